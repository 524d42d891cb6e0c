/* The point rules: the notes' vertex average, the centroid rule, symmetric
 * Gauss rules on both triangles, and the analytic-inner rule.
 *
 * vertex   G = (A_i A_j / 9) sum_k sum_l k(v_ik, v_jl), the notes' Riemann sum
 *          (their H is pi k, their rho reads albedo/pi; DESIGN.md).  At a
 *          shared vertex r = 0 and the kernel is 0/0: that term is taken as 0
 *          and counted (guarded).  Vertices on the other triangle's plane give
 *          cos = 0, so an edge-adjacent pair sees only the two opposite
 *          vertices: the rule is blind to most of the coupling near the edge.
 * centroid G = A_i A_j k(c_i, c_j).
 * gauss:P  G = A_i A_j sum_a sum_b w_a w_b k(x_a, y_b), the same degree-P rule
 *          on both triangles (Witherden-Vincent up to degree 10, collapsed
 *          Gauss beyond; rad_quad) \cite{witherden2015}.
 * analytic:P  G = A_i sum_a w_a F(dA(x_a) -> T_j), the inner integral by the
 *          point-to-polygon contour formula (Howell B-3) on T_j clipped to the
 *          half-space in front of x_a, which is exactly the clamped kernel's
 *          support \cite{howell}.  The inner integral is exact, so the rule
 *          only has to integrate a function of x that is smooth away from
 *          T_j's plane: it converges fast for every pair but edge/vertex
 *          adjacent ones, where F(dA -> T_j) has a log-type singularity at the
 *          shared edge or vertex. */
#include <math.h>
#include <string.h>

#include "ff_internal.h"
#include "rad_quad.h"

ff_value ff_vertex(const ff_pair *pr)
{
    ff_value v = {0};
    double sum = 0.0;
    for (int k = 0; k < 3; k++)
        for (int l = 0; l < 3; l++)
            sum += ff_kernel(pr->p[0][k], pr->n[0], pr->p[1][l], pr->n[1], &v.guarded);
    v.G = pr->A[0] * pr->A[1] / 9.0 * sum;
    v.evals = 9;
    v.rel_error = NAN;
    return v;
}

ff_value ff_centroid(const ff_pair *pr)
{
    ff_value v = {0};
    rad_vec3 c0 = rad_geom_triangle_centroid(pr->p[0][0], pr->p[0][1], pr->p[0][2]);
    rad_vec3 c1 = rad_geom_triangle_centroid(pr->p[1][0], pr->p[1][1], pr->p[1][2]);
    v.G = pr->A[0] * pr->A[1] * ff_kernel(c0, pr->n[0], c1, pr->n[1], &v.guarded);
    v.evals = 1;
    v.rel_error = NAN;
    return v;
}

rad_status ff_tri_rule(int degree, double *s, double *t, double *w, int *n)
{
    if (degree <= RAD_QUAD_TRI_MAX_DEGREE)
        return rad_quad_tri_symmetric(degree, s, t, w, n);
    int k = (degree + 3) / 2; /* collapsed Gauss with k points: degree 2k - 2 >= degree */
    *n = k * k;
    return rad_quad_tri_duffy(k, s, t, w);
}

rad_status ff_gauss(const ff_pair *pr, int degree, ff_value *v)
{
    double s[FF_RULE_MAX_POINTS], t[FF_RULE_MAX_POINTS], w[FF_RULE_MAX_POINTS];
    rad_vec3 x[2][FF_RULE_MAX_POINTS];
    int n = 0;
    rad_status st = ff_tri_rule(degree, s, t, w, &n);
    if (st != RAD_OK)
        return st;
    for (int k = 0; k < 2; k++)
        for (int a = 0; a < n; a++)
            x[k][a] = rad_geom_triangle_point(pr->p[k][0], pr->p[k][1], pr->p[k][2], s[a], t[a]);
    double sum = 0.0;
    long guarded = 0;
    for (int a = 0; a < n; a++) {
        double inner = 0.0;
        for (int b = 0; b < n; b++)
            inner += w[b] * ff_kernel(x[0][a], pr->n[0], x[1][b], pr->n[1], &guarded);
        sum += w[a] * inner;
    }
    v->G = pr->A[0] * pr->A[1] * sum;
    v->evals = (long)n * n;
    v->guarded = guarded;
    v->rel_error = NAN;
    v->flags = 0;
    return RAD_OK;
}

int ff_clip(const rad_vec3 *in, int n, rad_vec3 nrm, rad_vec3 o, rad_vec3 *out)
{
    if (n < 1 || n > FF_CLIP_MAX)
        return 0;
    double side[FF_CLIP_MAX];
    int front = 0;
    for (int k = 0; k < n; k++) {
        side[k] = rad_vec3_dot(nrm, rad_vec3_sub(in[k], o));
        front += side[k] > 0.0;
    }
    /* The common case: every vertex in front, nothing to cut (hier's
     * point-to-element closed forms meet it on most calls).  A polygon with
     * repeated vertices keeps them here; its zero-length edges add nothing
     * to the contour integral. */
    if (front == n) {
        memcpy(out, in, (size_t)n * sizeof *out);
        return n >= 3 ? n : 0;
    }
    int m = 0;
    for (int k = 0; k < n; k++) {
        int k1 = k + 1 < n ? k + 1 : 0;
        rad_vec3 a = in[k], b = in[k1];
        double da = side[k], db = side[k1];
        if (da > 0.0)
            out[m++] = a;
        /* An edge that crosses the plane contributes its crossing point; an
         * endpoint exactly on the plane is reached as the crossing (t = 0 or 1). */
        if ((da > 0.0 && db <= 0.0) || (da <= 0.0 && db > 0.0)) {
            double t = da / (da - db);
            out[m++] = rad_vec3_add(a, rad_vec3_scale(rad_vec3_sub(b, a), t));
        }
    }
    /* Drop consecutive duplicates (a vertex on the plane reached twice). */
    int q = 0;
    for (int k = 0; k < m; k++) {
        rad_vec3 d = rad_vec3_sub(out[k], q > 0 ? out[q - 1] : out[m - 1]);
        if (q > 0 && rad_vec3_dot(d, d) == 0.0)
            continue;
        out[q++] = out[k];
    }
    if (q > 1) {
        rad_vec3 d = rad_vec3_sub(out[0], out[q - 1]);
        if (rad_vec3_dot(d, d) == 0.0)
            q--;
    }
    return q >= 3 ? q : 0;
}

/* The contour formula on a polygon already known to lie in front of x and to
 * face it; the caller clips. */
static double contour_point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *poly, int nv)
{
    double sum = 0.0;
    for (int k = 0; k < nv; k++) {
        rad_vec3 r0 = rad_vec3_sub(poly[k], x), r1 = rad_vec3_sub(poly[k + 1 < nv ? k + 1 : 0], x);
        rad_vec3 c = rad_vec3_cross(r0, r1);
        double cn = rad_vec3_norm(c);
        if (!(cn > 0.0))
            continue; /* x on the edge's line: the edge subtends no angle */
        double gamma = rad_geom_angle(cn, rad_vec3_dot(r0, r1));
        sum += gamma * rad_vec3_dot(n, c) / cn;
    }
    return -sum / (2.0 * RAD_PI);
}

double rad_ff_point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *poly, int nv)
{
    if (nv < 3 || nv > FF_CLIP_MAX)
        return 0.0;
    /* The polygon's own normal by Newell's method (any planar polygon). */
    rad_vec3 np = {0, 0, 0};
    for (int k = 0; k < nv; k++)
        np = rad_vec3_add(np, rad_vec3_cross(poly[k], poly[k + 1 < nv ? k + 1 : 0]));
    if (!(rad_vec3_dot(np, rad_vec3_sub(x, poly[0])) > 0.0))
        return 0.0;
    rad_vec3 clipped[16];
    int m = ff_clip(poly, nv, n, x, clipped);
    return m ? contour_point_polygon(x, n, clipped, m) : 0.0;
}

rad_status ff_analytic(const ff_pair *pr, int degree, ff_value *v)
{
    double s[FF_RULE_MAX_POINTS], t[FF_RULE_MAX_POINTS], w[FF_RULE_MAX_POINTS];
    int n = 0;
    rad_status st = ff_tri_rule(degree, s, t, w, &n);
    if (st != RAD_OK)
        return st;
    double sum = 0.0;
    for (int a = 0; a < n; a++) {
        rad_vec3 x = rad_geom_triangle_point(pr->p[0][0], pr->p[0][1], pr->p[0][2], s[a], t[a]);
        /* x must be in front of T_j (cos_j > 0); then clip T_j to x's front. */
        if (!(rad_vec3_dot(pr->n[1], rad_vec3_sub(x, pr->p[1][0])) > 0.0))
            continue;
        rad_vec3 clipped[4];
        int m = ff_clip(pr->p[1], 3, pr->n[0], x, clipped);
        if (m)
            sum += w[a] * contour_point_polygon(x, pr->n[0], clipped, m);
    }
    v->G = pr->A[0] * sum;
    v->evals = n;
    v->guarded = 0;
    v->rel_error = NAN;
    v->flags = 0;
    return RAD_OK;
}
