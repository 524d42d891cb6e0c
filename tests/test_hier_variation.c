/* The variation the error estimate gives a leaf for what its links' linear
 * fits leave out (core/hier/solve.c, hier_inner_spread with residuals): at
 * most rho times the range of its sources' B (from 0, unsealed), the
 * furthest a mean of them can move the leaf's irradiance; below that, the
 * residuals count in full.  The residuals are set by the test: large ones
 * (10, where a fit's residual is a fraction of its form factor) give the
 * sum of rho r w far above the range, small ones (1e-6) far below it; on
 * two facing squares (open: the range from 0), inside a closed cube
 * (sealed: from the smallest source B), and inside it through clusters at
 * a coarse eps, where cluster links remain and the range spans every
 * leaf's B (some leaves then pass what their element links' sources alone
 * allow; the test fails if that wider range is not taken). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "harness.h"
#include "hier_internal.h"
#include "rad_hier.h"
#include "rad_vis.h"
#include "squares.h"

/* h solved at eps 0.01 (NULL, h destroyed, if it does not solve). */
static rad_hier *solved(rad_hier *h)
{
    if (h && rad_hier_solve(h) != RAD_OK) {
        CHECK_MSG(0, "did not solve: %s", rad_error_message());
        rad_hier_destroy(h);
        h = NULL;
    }
    return h;
}

static rad_vec3 vertex(const double *xyz, int v)
{
    return rad_vec3_make(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
}

/* The inside of the unit cube, its top emitting 1, every face reflecting
 * 0.5: a sealed scene (every point sees only front faces), so a leaf's
 * irradiance is a mean of its sources' B and the range starts at the
 * smallest of them, not at 0. */
static rad_hier *closed_cube(rad_vis **vis, const rad_hier_params *p)
{
    static const int quad[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                   {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    double xyz[24], rho[36], E[36];
    int tri[36];
    for (int v = 0; v < 8; v++)
        for (int a = 0; a < 3; a++)
            xyz[3 * v + a] = (v >> a) & 1;
    rad_vec3 centre = rad_vec3_make(0.5, 0.5, 0.5);
    for (int f = 0; f < 6; f++) {
        const int *q = quad[f];
        int t[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
        for (int k = 0; k < 2; k++) {
            rad_vec3 p0 = vertex(xyz, t[k][0]), p1 = vertex(xyz, t[k][1]),
                     p2 = vertex(xyz, t[k][2]);
            rad_vec3 n = rad_vec3_cross(rad_vec3_sub(p1, p0), rad_vec3_sub(p2, p0));
            int in = rad_vec3_dot(n, rad_vec3_sub(centre, p0)) > 0.0; /* wound towards the centre */
            int *out = tri + 3 * (2 * f + k);
            out[0] = t[k][0];
            out[1] = in ? t[k][1] : t[k][2];
            out[2] = in ? t[k][2] : t[k][1];
        }
    }
    for (int k = 0; k < 36; k++) {
        rho[k] = 0.5;
        E[k] = k % 12 == 10 || k % 12 == 11 ? 1.0 : 0.0; /* the top, z = 1 */
    }
    return test_hier_of(xyz, 8, tri, 12, rho, E, p, vis);
}

/* Every link's residuals set to r. */
static void set_residuals(rad_hier *h, double r)
{
    for (size_t k = 0; k < h->nln; k++)
        h->ln[k].ra = h->ln[k].rb = r;
}

/* rho times the range of the B of leaf e's sources (its links' and its
 * ancestors' other ends, and with every_leaf each leaf's: where cluster
 * links exist they may bring any), from 0 when the scene is not sealed;
 * channel c. */
static double range_cap(const rad_hier *h, int e, int c, int every_leaf)
{
    double lo = h->p.sealed ? INFINITY : 0.0, hi = -INFINITY;
    for (size_t k = 0; every_leaf && k < h->nel; k++)
        if (h->el[k].first_child < 0) {
            lo = fmin(lo, h->el[k].B[c]);
            hi = fmax(hi, h->el[k].B[c]);
        }
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

/* The checks on a solved hierarchy h (what: its name in the messages). */
static void cap_holds(rad_hier *h, const char *what)
{
    double *slope = calloc(3 * h->nel, sizeof *slope);
    CHECK(slope != NULL);
    CHECK(hier_inner_spread(h, 0) == RAD_OK);
    for (size_t e = 0; slope && e < h->nel; e++)
        for (int c = 0; c < 3; c++)
            slope[3 * e + (size_t)c] = h->el[e].var[c];
    int leaves = 0, capped = 0, added = 0, wider = 0;
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
            double s = slope[3 * e + (size_t)c], cap = range_cap(h, (int)e, c, h->ncln > 0);
            double allowed = fmax(s, cap);
            worst_over = fmax(worst_over, x->var[c] - allowed);
            capped += x->var[c] > s && fabs(x->var[c] - allowed) <= 1e-12 * fmax(1.0, allowed);
            /* beyond what its element links' sources alone would allow */
            wider += x->var[c] > fmax(s, range_cap(h, (int)e, c, 0)) * (1.0 + 1e-12) + 1e-15;
        }
    }
    printf("# %s: %d leaves, %zu links, %zu cluster links: with residuals 10, %d leaf channels "
           "at the range (%d beyond their element links' sources'), the largest excess over "
           "it %.3g\n",
           what, leaves, h->nln, h->ncln, capped, wider, worst_over);
    CHECK_MSG(h->ncln == 0 ? wider == 0 : wider > 0,
              "%s: %d leaf channels beyond their element links' sources' range with %zu cluster "
              "links", what, wider, h->ncln);
    CHECK(leaves > 4);
    CHECK_MSG(worst_over <= 1e-12, "%s: a leaf's var exceeds rho times its sources' range by %.3g",
              what, worst_over);
    CHECK_MSG(capped > 0, "%s: no leaf's var reached the range: the test does not reach the cap",
              what);
    /* small residuals: they count in full */
    set_residuals(h, 1e-6);
    CHECK(hier_inner_spread(h, 1) == RAD_OK);
    for (size_t e = 0; slope && e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child < 0 && x->var[0] > slope[3 * e])
            added++;
    }
    printf("# %s: with residuals 1e-6, %d of %d leaves' var above their slope's\n", what, added,
           leaves);
    CHECK_MSG(added == leaves, "%s: only %d of %d leaves count the small residuals", what, added,
              leaves);
    free(slope);
}

TEST(residual_variation_within_the_sources_range)
{
    rad_hier_params p;
    rad_hier_params_default(&p);
    p.eps = 0.01;
    rad_vis *vis = NULL;
    rad_hier *h = solved(facing_squares(&p, &vis));
    if (h)
        cap_holds(h, "facing squares (open)");
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
    p.sealed = 1;
    h = solved(closed_cube(&vis, &p));
    if (h)
        cap_holds(h, "closed cube (sealed)");
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
    /* through clusters at a coarse eps, so that cluster links remain: the
       range then spans every leaf's B */
    p.cluster = 1;
    p.eps = 1.0;
    h = solved(closed_cube(&vis, &p));
    if (h) {
        CHECK_MSG(h->ncln > 0, "no cluster link left: the test does not reach that range");
        cap_holds(h, "closed cube through clusters (sealed)");
    }
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
}
