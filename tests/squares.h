/* Small hierarchies for the tests that work on a hierarchy's internals
 * (test_hier_accel.c, test_hier_variation.c). */
#ifndef RADKIT_TESTS_SQUARES_H
#define RADKIT_TESTS_SQUARES_H

#include <stddef.h>

#include "rad_hier.h"
#include "rad_vis.h"

/* The hierarchy of the nt triangles tri over the nv vertices xyz (rho, E:
 * 3 nt each, channel-major) with params p, unsolved; *vis its visibility,
 * for the caller to destroy after it.  NULL after a failed CHECK. */
rad_hier *test_hier_of(const double *xyz, size_t nv, const int *tri, size_t nt, const double *rho,
                       const double *E, const rad_hier_params *p, rad_vis **vis);

/* Two unit squares facing each other 1 apart: four triangles, the upper
 * square emitting 1, both reflecting 0.5. */
rad_hier *facing_squares(const rad_hier_params *p, rad_vis **vis);

#endif
