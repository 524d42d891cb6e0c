/* Two unit squares facing each other 1 apart: four triangles, the upper
 * square emitting 1, both reflecting 0.5.  For the tests that work on a
 * hierarchy's internals (test_hier_accel.c, test_hier_variation.c). */
#ifndef RADKIT_TESTS_SQUARES_H
#define RADKIT_TESTS_SQUARES_H

#include "rad_hier.h"
#include "rad_vis.h"

/* The hierarchy with params p, unsolved (*vis its visibility, for the
 * caller to destroy after it); NULL after a failed CHECK. */
rad_hier *facing_squares(const rad_hier_params *p, rad_vis **vis);

#endif
