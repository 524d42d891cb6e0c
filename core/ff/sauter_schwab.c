/* ss:N: Sauter-Schwab quadrature for edge- and vertex-adjacent pairs.
 *
 * Both triangles are mapped from the reference triangle
 * K = {(x1, x2) : 0 <= x2 <= x1 <= 1} by x = A + x1 (B - A) + x2 (C - B)
 * (|Jacobian| = 2 area), with the shared vertices first: for a common edge AB
 * the points (t, 0) of both maps coincide, for a common vertex (0, 0) does.
 * 1. Common edge: K x K is split into 5 regions and each is mapped from the
 *    unit 4-cube (xi, eta1, eta2, eta3) so that the distance |x - y| factors as
 *    xi eta1 times a function bounded away from 0; the Jacobians xi^3 eta1^2
 *    (region 1) and xi^3 eta1^2 eta2 (regions 2-5) cancel the 1/r^2 of the
 *    kernel, leaving an integrand that is smooth (analytic when no cosine
 *    clamp is active inside the pair) \cite{sauter2011}, Section 5.2.
 * 2. Common vertex: 2 regions, x = (xi, xi eta1), y = xi eta2 (1, eta3) and
 *    the swap, Jacobian xi^3 eta2.
 * 3. The radial variable xi is integrated in closed form: for flat
 *    triangles k depends on y - x only and is homogeneous of degree -2, and
 *    y - x = xi D(eta) in every region, so int xi^3 k(xi D) dxi = k(D) / 2
 *    (see ss_edge).  The remaining three eta directions use an N-point
 *    Gauss-Legendre rule each: 5 N^3 kernel evaluations for an edge pair,
 *    2 N^3 for a vertex pair (the generic 4D form would cost N times more
 *    for the same accuracy).
 * 4. Disjoint pairs (and pairs whose vertices coincide only within a loose
 *    tolerance) use the collapsed Gauss product rule with N points per
 *    direction on each triangle: N^4 evaluations.
 * The test suite checks the regions by integrating polynomials over K x K. */
#include <math.h>

#include "ff_internal.h"
#include "rad_quad.h"

typedef struct ss_geom {
    rad_vec3 a, e1[2], e2[2]; /* x = a + x1 e1 + x2 e2 for triangle k */
    rad_vec3 n[2];
} ss_geom;

static inline rad_vec3 ss_point(const ss_geom *g, int k, double x1, double x2)
{
    return rad_vec3_add(g->a, rad_vec3_add(rad_vec3_scale(g->e1[k], x1), rad_vec3_scale(g->e2[k], x2)));
}

static inline double ss_k(const ss_geom *g, double x1, double x2, double y1, double y2, long *guard)
{
    return ff_kernel(ss_point(g, 0, x1, x2), g->n[0], ss_point(g, 1, y1, y2), g->n[1], guard);
}

/* The radial variable xi in closed form.  For flat triangles the kernel
 * depends on d = y - x only and is positively homogeneous of degree -2
 * (k(xi d) = k(d) / xi^2, the clamps included), and in every region
 * y - x = xi D(eta) because both points are xi times a point of K mapped
 * from the shared vertex A.  Hence int_0^1 xi^3 k(xi D) dxi = k(D) / 2 and
 * each region is a 3D integral over eta: N^3 points per region. */
static double ss_edge(const ss_geom *g, int n, const double *x, const double *w, long *guard)
{
    double sum = 0.0;
    for (int j = 0; j < n; j++) {
        double e1 = x[j], wj = w[j] * e1 * e1;
        for (int k = 0; k < n; k++) {
            double e2 = x[k], wk = wj * w[k];
            for (int l = 0; l < n; l++) {
                double e3 = x[l], wl = wk * w[l];
                double r1 = ss_k(g, 1.0, e1 * e3, 1 - e1 * e2, e1 * (1 - e2), guard);
                double r2 = ss_k(g, 1.0, e1, 1 - e1 * e2 * e3, e1 * e2 * (1 - e3), guard);
                double r3 = ss_k(g, 1 - e1 * e2, e1 * (1 - e2), 1.0, e1 * e2 * e3, guard);
                double r4 = ss_k(g, 1 - e1 * e2 * e3, e1 * e2 * (1 - e3), 1.0, e1, guard);
                double r5 = ss_k(g, 1 - e1 * e2 * e3, e1 * (1 - e2 * e3), 1.0, e1 * e2, guard);
                sum += wl * (r1 + e2 * (r2 + r3 + r4 + r5));
            }
        }
    }
    return 0.5 * sum;
}

static double ss_vertex(const ss_geom *g, int n, const double *x, const double *w, long *guard)
{
    double sum = 0.0;
    for (int j = 0; j < n; j++)
        for (int k = 0; k < n; k++) {
            double e1 = x[j], e2 = x[k], wk = w[j] * w[k] * e2;
            for (int l = 0; l < n; l++) {
                double e3 = x[l];
                double r1 = ss_k(g, 1.0, e1, e2, e2 * e3, guard);
                double r2 = ss_k(g, e2, e2 * e3, 1.0, e1, guard);
                sum += wk * w[l] * (r1 + r2);
            }
        }
    return 0.5 * sum;
}

rad_status ff_ss(const ff_pair *pr, int n, ff_value *v)
{
    double x[RAD_FF_SS_MAX], w[RAD_FF_SS_MAX];
    rad_status st = rad_quad_gauss_legendre(n, x, w);
    if (st != RAD_OK)
        return st;
    v->guarded = 0;
    v->flags = 0;
    v->rel_error = NAN;
    if (pr->adj == RAD_FF_SHARE_EDGE || pr->adj == RAD_FF_SHARE_VERTEX) {
        /* Order the vertices: shared ones first, in the same order on both. */
        int oi[3], oj[3], ns = 0, ui = 0, uj = 0;
        int used_j[3] = {0, 0, 0};
        for (int a = 0; a < 3; a++)
            if (pr->map[a] >= 0) {
                oi[ns] = a;
                oj[ns] = pr->map[a];
                used_j[pr->map[a]] = 1;
                ns++;
            }
        ui = ns;
        uj = ns;
        for (int a = 0; a < 3; a++) {
            if (pr->map[a] < 0)
                oi[ui++] = a;
            if (!used_j[a])
                oj[uj++] = a;
        }
        ss_geom g;
        /* Shared points are taken from triangle i on both sides, so the
         * singular point or edge of the two maps coincides exactly. */
        rad_vec3 A = pr->p[0][oi[0]];
        rad_vec3 Bi = pr->p[0][oi[1]], Ci = pr->p[0][oi[2]];
        rad_vec3 Bj = ns == 2 ? Bi : pr->p[1][oj[1]], Cj = pr->p[1][oj[2]];
        g.a = A;
        g.e1[0] = rad_vec3_sub(Bi, A);
        g.e2[0] = rad_vec3_sub(Ci, Bi);
        g.e1[1] = rad_vec3_sub(Bj, A);
        g.e2[1] = rad_vec3_sub(Cj, Bj);
        g.n[0] = pr->n[0];
        g.n[1] = pr->n[1];
        double I = ns == 2 ? ss_edge(&g, n, x, w, &v->guarded) : ss_vertex(&g, n, x, w, &v->guarded);
        /* dA = 2 A dx on each side. */
        v->G = 4.0 * pr->A[0] * pr->A[1] * I;
        long n3 = (long)n * n * n;
        v->evals = (ns == 2 ? 5 : 2) * n3;
        return RAD_OK;
    }
    /* Disjoint (or identical, which the facing test already made zero). */
    double s[RAD_FF_SS_MAX * RAD_FF_SS_MAX], t[RAD_FF_SS_MAX * RAD_FF_SS_MAX],
        wt[RAD_FF_SS_MAX * RAD_FF_SS_MAX];
    if ((st = rad_quad_tri_duffy(n, s, t, wt)) != RAD_OK)
        return st;
    int m = n * n;
    double sum = 0.0;
    for (int a = 0; a < m; a++) {
        rad_vec3 xa = rad_geom_triangle_point(pr->p[0][0], pr->p[0][1], pr->p[0][2], s[a], t[a]);
        double inner = 0.0;
        for (int b = 0; b < m; b++) {
            rad_vec3 yb = rad_geom_triangle_point(pr->p[1][0], pr->p[1][1], pr->p[1][2], s[b], t[b]);
            inner += wt[b] * ff_kernel(xa, pr->n[0], yb, pr->n[1], &v->guarded);
        }
        sum += wt[a] * inner;
    }
    v->G = pr->A[0] * pr->A[1] * sum;
    v->evals = (long)m * m;
    return RAD_OK;
}
