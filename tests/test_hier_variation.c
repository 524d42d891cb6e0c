/* The variation the error estimate gives a leaf for what its links' linear
 * fits leave out (core/hier/solve.c, hier_inner_spread with residuals): at
 * most rho times the range of its sources' B (from 0, unsealed), the
 * furthest a mean of them can move the leaf's irradiance; below that, the
 * residuals count in full.  The residuals are set by the test: large ones
 * (10, where a fit's residual is a fraction of its form factor) give the
 * sum of rho r w far above the range, small ones (1e-6) far below it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "harness.h"
#include "hier_internal.h"
#include "rad_hier.h"
#include "rad_vis.h"
#include "squares.h"

/* The facing squares solved at eps 0.01: a refined hierarchy whose leaves
 * have links at several levels. */
static rad_hier *two_squares(rad_vis **vis)
{
    rad_hier_params p;
    rad_hier_params_default(&p);
    p.eps = 0.01;
    rad_hier *h = facing_squares(&p, vis);
    if (h && rad_hier_solve(h) != RAD_OK) {
        CHECK_MSG(0, "the two squares did not solve");
        rad_hier_destroy(h);
        h = NULL;
    }
    return h;
}

/* Every link's residuals set to r. */
static void set_residuals(rad_hier *h, double r)
{
    for (size_t k = 0; k < h->nln; k++)
        h->ln[k].ra = h->ln[k].rb = r;
}

/* rho times the range of the B of leaf e's sources (its links' and its
 * ancestors' other ends), from 0 when the scene is not sealed; channel c. */
static double range_cap(const rad_hier *h, int e, int c)
{
    double lo = h->p.sealed ? INFINITY : 0.0, hi = -INFINITY;
    for (int a = e; a >= 0; a = h->el[a].parent)
        for (size_t k = 0; k < h->nln; k++) {
            const hier_link *l = &h->ln[k];
            int s = l->a == a ? l->b : l->b == a ? l->a : -1;
            if (l->a < 0 || s < 0)
                continue;
            lo = fmin(lo, h->el[s].B[c]);
            hi = fmax(hi, h->el[s].B[c]);
        }
    const hier_elem *x = &h->el[e];
    return hi >= lo ? h->rho[(size_t)x->face + (size_t)c * h->nroots] * (hi - lo) : INFINITY;
}

TEST(residual_variation_within_the_sources_range)
{
    rad_vis *vis = NULL;
    rad_hier *h = two_squares(&vis);
    if (!h) {
        rad_vis_destroy(vis);
        return;
    }
    CHECK_MSG(h->ncln == 0, "%zu cluster links: the range would take every leaf's B", h->ncln);
    double *slope = calloc(3 * h->nel, sizeof *slope);
    CHECK(slope != NULL);
    CHECK(hier_inner_spread(h, 0) == RAD_OK);
    for (size_t e = 0; slope && e < h->nel; e++)
        for (int c = 0; c < 3; c++)
            slope[3 * e + (size_t)c] = h->el[e].var[c];
    int leaves = 0, capped = 0, added = 0;
    double worst_over = 0.0;
    /* large residuals: the sum of rho r w would exceed the range */
    set_residuals(h, 10.0);
    CHECK(hier_inner_spread(h, 1) == RAD_OK);
    for (size_t e = 0; slope && e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        leaves++;
        for (int c = 0; c < 3; c++) {
            double s = slope[3 * e + (size_t)c], cap = range_cap(h, (int)e, c);
            double allowed = fmax(s, cap);
            worst_over = fmax(worst_over, x->var[c] - allowed);
            capped += x->var[c] > s && fabs(x->var[c] - allowed) <= 1e-12 * fmax(1.0, allowed);
        }
    }
    printf("# %d leaves, %zu links: with residuals 10, %d leaf channels at the range, "
           "the largest excess over it %.3g\n",
           leaves, h->nln, capped, worst_over);
    CHECK(leaves > 4);
    CHECK_MSG(worst_over <= 1e-12, "a leaf's var exceeds rho times its sources' range by %.3g",
              worst_over);
    CHECK_MSG(capped > 0, "no leaf's var reached the range: the test does not reach the cap");
    /* small residuals: they count in full */
    set_residuals(h, 1e-6);
    CHECK(hier_inner_spread(h, 1) == RAD_OK);
    for (size_t e = 0; slope && e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child < 0 && x->var[0] > slope[3 * e])
            added++;
    }
    printf("# with residuals 1e-6, %d of %d leaves' var above their slope's\n", added, leaves);
    CHECK_MSG(added == leaves, "only %d of %d leaves count the small residuals", added, leaves);
    free(slope);
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
}
