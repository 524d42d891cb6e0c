/* rad_mc: one path, the estimator of the irradiance H(x) at a surface point.
 *
 * With L = B / pi leaving every diffuse point and B = E + rho H,
 *
 *   H(x) = int_hemisphere (E(y) + rho(y) H(y)) / pi  cos(theta_x) dw,
 *
 * y = y(x, w) the first point a ray from x in direction w meets (its front
 * side; the back of a triangle is black).  At each path vertex p on triangle t,
 * with throughput beta (the product of the reflectances met so far, divided
 * by the roulette's survival probabilities):
 *
 * 1. Next-event estimation: an emitter triangle e drawn with probability
 *    proportional to A_e |E_e| (|E| = sum of channels), a point y uniform on
 *    it (area density p_A = |E_e| / sum A |E|), one shadow ray p -> y
 *    ignoring t and e.  Its term: beta E_e cos_p cos_y / (pi r^2 p_A), times
 *    the MIS weight p_l^2 / (p_l^2 + p_c^2), where p_l = p_A r^2 / cos_y is
 *    the light density in solid angle and p_c = cos_p / pi the cosine
 *    density.
 * 2. Continuation: w cosine-weighted about the normal, the closest hit y on
 *    triangle j beyond the ray epsilon (hits on t itself are also rejected
 *    by id, for grazing rays whose float origin lies behind t's plane).
 *    No hit, or the back of j: the path ends.  If j emits, its emission
 *    counts with weight p_c^2 / (p_c^2 + p_l^2) (cos / p_c = pi cancels the
 *    1/pi of L: the term is beta E_j w).
 * 3. beta *= rho_j; Russian roulette: survive with q = max channel of beta
 *    over rr_weight (if below 1), then beta /= q.  Unbiased: a path goes on
 *    without roulette while its throughput is above rr_weight, and below it
 *    survivors carry about rr_weight; a path ends where nothing reflects.
 * The first vertex may take its direction and its emitter point from the
 * caller (stratified over a batch, mc.c); deeper vertices draw their own.
 * The power heuristic: \cite{veach1995mis}; cosine sampling by Malley's
 * method \cite{pharr2016pbrt}; the branchless frame of \cite{duff2017onb}. */
#include "mc_internal.h"

#include <math.h>


static rad_vec3 point_on(const mc_tri *t, double s, double r)
{
    return rad_vec3_add(t->a, rad_vec3_add(rad_vec3_scale(t->ab, s), rad_vec3_scale(t->ac, r)));
}

/* cos and sin of 2 pi u for u in [0, 1): Taylor polynomials on the octant
 * |x| <= pi/4 (truncation below 1e-11), libm's sincos costing 7% of a path. */
static void sincos_2pi(double u, double *s, double *c)
{
    double q = u * 4.0;             /* quadrants */
    int k = (int)(q + 0.5);         /* nearest multiple of pi/2 */
    double x = (q - k) * (RAD_PI / 2); /* |x| <= pi/4 */
    double x2 = x * x;
    double sn = x * (1 + x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800))))));
    double cs = 1 + x2 * (-0.5 + x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 + x2 * (-1.0 / 3628800 + x2 * (1.0 / 479001600))))));
    switch (k & 3) {
    case 0: *s = sn; *c = cs; break;
    case 1: *s = cs; *c = -sn; break;
    case 2: *s = -sn; *c = -cs; break;
    default: *s = -cs; *c = sn; break;
    }
}

static double mis2(double a, double b)
{
    double a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

static void next_event(const mc_scene *s, int t, rad_vec3 p, mc_rng *rng, const double *ul,
                       const double beta[3], double H[3], mc_counts *counts)
{
    int e = s->emitters[mc_pick_emitter(s, mc_uniform(rng))];
    double u1 = ul ? ul[0] : mc_uniform(rng), u2 = ul ? ul[1] : mc_uniform(rng);
    if (e == t)
        return; /* a plane sees nothing of itself */
    const mc_tri *te = &s->tris[e], *tp = &s->tris[t];
    if (u1 + u2 > 1.0) {
        u1 = 1.0 - u1;
        u2 = 1.0 - u2;
    }
    rad_vec3 y = point_on(te, u1, u2);
    rad_vec3 d = rad_vec3_sub(y, p);
    double r2 = rad_vec3_dot(d, d);
    if (!(r2 > 0.0))
        return;
    double r = sqrt(r2);
    double cos_p = rad_vec3_dot(tp->n, d) / r, cos_y = -rad_vec3_dot(te->n, d) / r;
    if (!(cos_p > 0.0 && cos_y > 0.0))
        return;
    if (s->occlusion) {
        counts->rays++;
        double pa[3] = {p.x, p.y, p.z}, ya[3] = {y.x, y.y, y.z};
        if (rad_vis_segment_blocked(s->vis, pa, ya, t, e))
            return;
    }
    double p_l = te->light_pdf * r2 / cos_y, p_c = cos_p / RAD_PI;
    double f = mis2(p_l, p_c) * cos_p * cos_y / (RAD_PI * r2 * te->light_pdf);
    for (int c = 0; c < 3; c++)
        H[c] += beta[c] * te->E[c] * f;
}

void mc_path_irradiance(const mc_scene *s, int t, rad_vec3 x, mc_rng *rng, const double *first,
                        double H[3], mc_counts *counts)
{
    double beta[3] = {1.0, 1.0, 1.0};
    H[0] = H[1] = H[2] = 0.0;
    rad_vec3 p = x;
    for (int depth = 0;; depth++) {
        if (depth >= s->max_depth) {
            counts->too_long++;
            return;
        }
        const mc_tri *tp = &s->tris[t];
        if (s->next_event && s->nemitters)
            next_event(s, t, p, rng, depth == 0 && first ? first + 2 : NULL, beta, H, counts);

        /* cosine-weighted direction (Malley) in the frame (t1, t2, n) */
        double u1 = depth == 0 && first ? first[0] : mc_uniform(rng);
        double u2 = depth == 0 && first ? first[1] : mc_uniform(rng);
        double rad = sqrt(u1), sphi, cphi;
        sincos_2pi(u2, &sphi, &cphi);
        double cos_p = sqrt(1.0 - u1);
        rad_vec3 w = rad_vec3_add(rad_vec3_add(rad_vec3_scale(tp->t1, rad * cphi),
                                               rad_vec3_scale(tp->t2, rad * sphi)),
                                  rad_vec3_scale(tp->n, cos_p));
        double org[3] = {p.x, p.y, p.z}, dir[3] = {w.x, w.y, w.z};
        rad_vis_hit hit;
        counts->rays++;
        if (!rad_vis_ray_closest(s->vis, org, dir, s->tnear, t, &hit))
            return;
        const mc_tri *tj = &s->tris[hit.tri];
        double cos_y = -rad_vec3_dot(tj->n, w);
        if (!(cos_y > 0.0))
            return; /* the back of a triangle: black */
        if (tj->light_pdf > 0.0) {
            double weight = 1.0;
            if (s->next_event) {
                double r = hit.t * rad_vec3_norm(w);
                weight = mis2(cos_p / RAD_PI, tj->light_pdf * r * r / cos_y);
            }
            for (int c = 0; c < 3; c++)
                H[c] += beta[c] * tj->E[c] * weight;
        }
        double q = 0.0;
        for (int c = 0; c < 3; c++) {
            beta[c] *= tj->rho[c];
            q = rad_dmax(q, beta[c]);
        }
        if (!(q > 0.0))
            return;
        q /= s->rr_weight;
        if (q < 1.0) {
            if (mc_uniform(rng) >= q)
                return;
            for (int c = 0; c < 3; c++)
                beta[c] /= q;
        }
        /* the next vertex from the hit's barycentrics, exactly on triangle j */
        double bu = rad_dmin(rad_dmax(hit.u, 0.0), 1.0), bv = rad_dmin(rad_dmax(hit.v, 0.0), 1.0);
        if (bu + bv > 1.0) {
            double sum = bu + bv;
            bu /= sum;
            bv /= sum;
        }
        p = point_on(tj, bu, bv);
        t = hit.tri;
        counts->bounces++;
    }
}
