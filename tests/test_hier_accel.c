/* Anderson mixing's projection (core/hier/accel.c): a mixed state is put
 * back into the set the fixed point lies in, B >= 0 and T >= q.  The steps
 * here are played by the test, not by the solver: each leaf's value
 * contracts towards the set's edge at its own rate (0.95, 0.2, 0.6, 0.5),
 * a map that a one-column mix overshoots: without the projection the
 * mixed B reach 0.040 below 0 and the mixed T 0.036 below q. */
#include <math.h>
#include <stdio.h>

#include "harness.h"
#include "hier_internal.h"
#include "rad_hier.h"
#include "rad_vis.h"
#include "squares.h"

static const double rate[4] = {0.95, 0.2, 0.6, 0.5};

/* The facing squares' hierarchy, its four leaves (nothing refined). */
static rad_hier *four_leaves(rad_vis **vis)
{
    rad_hier_params p;
    rad_hier_params_default(&p);
    p.anderson = 1;
    rad_hier *h = facing_squares(&p, vis);
    if (h && rad_hier_leaf_count(h) != 4) {
        CHECK_MSG(0, "%zu leaves, not the four triangles", rad_hier_leaf_count(h));
        rad_hier_destroy(h);
        h = NULL;
    }
    return h;
}

/* Sixteen steps of carry (CARRY_B: B -> rate B, towards 0; CARRY_T: T ->
 * q + rate (T - q), towards q = 0.1), each mixed.  Returns the lowest
 * value any mix left above the edge (negative: below it), and *mixed
 * whether a mix moved any value away from its step's output. */
static double lowest_after_mixing(rad_hier *h, int carry, int *mixed)
{
    double lowest = INFINITY;
    *mixed = 0;
    for (int e = 0; e < 4; e++)
        for (int c = 0; c < 3; c++) {
            h->el[e].B[c] = h->el[e].T[c] = 1.0;
            h->el[e].q[c] = 0.1;
            h->el[e].gB[c] = rad_vec3_make(0.0, 0.0, 0.0);
        }
    /* a test far below the changes: the solve is never near its end */
    hier_accel_begin(h, carry, 1e-12);
    double change = -1.0;
    for (int it = 0; it < 16; it++) {
        CHECK(hier_accel_save(h, change) == RAD_OK);
        double g[4][3];
        change = 0.0;
        for (int e = 0; e < 4; e++)
            for (int c = 0; c < 3; c++) {
                hier_elem *x = &h->el[e];
                double was = carry == CARRY_B ? x->B[c] : x->T[c];
                if (carry == CARRY_B)
                    g[e][c] = x->B[c] = rate[e] * x->B[c];
                else
                    g[e][c] = x->T[c] = x->q[c] + rate[e] * (x->T[c] - x->q[c]);
                change = fmax(change, fabs(g[e][c] - was));
            }
        hier_accel_mix(h);
        for (int e = 0; e < 4; e++)
            for (int c = 0; c < 3; c++) {
                const hier_elem *x = &h->el[e];
                double v = carry == CARRY_B ? x->B[c] : x->T[c] - x->q[c];
                *mixed |= (carry == CARRY_B ? x->B[c] : x->T[c]) != g[e][c];
                lowest = fmin(lowest, v);
            }
    }
    return lowest;
}

TEST(anderson_mixing_keeps_B_non_negative_and_T_above_q)
{
    rad_vis *vis = NULL;
    rad_hier *h = four_leaves(&vis);
    if (h) {
        int mixed = 0;
        double low = lowest_after_mixing(h, CARRY_B, &mixed);
        printf("# B: mixed %d, lowest %.3g\n", mixed, low);
        CHECK(mixed);
        CHECK_MSG(low >= 0.0, "a mixed B of %.3g", low);
        low = lowest_after_mixing(h, CARRY_T, &mixed);
        printf("# T - q: mixed %d, lowest %.3g\n", mixed, low);
        CHECK(mixed);
        CHECK_MSG(low >= 0.0, "a mixed T below q by %.3g", -low);
    }
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
}
