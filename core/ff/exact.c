/* exact: the unoccluded form factor by a double contour integral.
 *
 * 1. Support.  x lies on plane P_i, so n_i . (y - x) > 0 says only that y is in
 *    front of P_i; likewise cos_j > 0 says x is in front of P_j.  The clamped
 *    kernel is therefore nonzero exactly on T_i' x T_j', T_i' = T_i clipped to
 *    the open half-space in front of P_j and T_j' = T_j clipped in front of P_i
 *    (convex polygons of 3 or 4 vertices), and there it equals the unclamped
 *    kernel, to which Stokes' theorem applies twice.
 * 2. Contour form (Sparrow; Siegel & Howell \cite{siegel2002}):
 *      G = (1/2pi) sum_a sum_b (u_a . v_b) int_0^La int_0^Lb ln(r / D) dt ds
 *    over edges a of T_i' and b of T_j' (unit directions u_a, v_b, with each
 *    polygon counter-clockwise about its own normal), the sign fixed by the
 *    test against Howell C-11.  D is any length: the double sum of
 *    (u_a . v_b) La Lb over two closed contours is 0; D = max(1, centroid
 *    distance) keeps the terms small for far pairs, which limits cancellation.
 * 3. Inner integral in closed form: with w = x(s) - q_b, tau = w . v_b,
 *    h = |w - tau v_b| and z = t - tau,
 *      int ln sqrt(z^2 + h^2) dz = z ln sqrt(z^2 + h^2) - z + h atan(z / h).
 * 4. Outer integral by adaptive Gauss-Kronrod (rad_quad_adapt) with
 *    breakpoints where x(s) is closest to the endpoints of edge b and to the
 *    line of b: there the integrand has its log-type kinks (shared vertices,
 *    collinear or crossing edges, common edges after clipping).
 * 5. Error estimate: the sum of the adaptive error bounds, relative to |G|.
 * 6. Far pairs.  The contour terms are of size La Lb ln(r/D) while G shrinks
 *    like 1/D^2, so for centroid distance D > exact_far_ratio times the size
 *    the cancellation costs digits (measured: 1e-13 at D = 10, 1e-10 at 100).
 *    There, when no clamp is active (both clipped polygons are the whole
 *    triangles), the kernel is analytic on the pair and a collapsed Gauss
 *    product rule converges geometrically: exact returns the degree-20 rule
 *    when it agrees with the degree-16 rule to 1e-14 (their difference is the
 *    error estimate), and falls back to the contour integral otherwise.
 * 7. Slivers and other pairs whose G is tiny against the contour terms lose
 *    digits the same way; when the estimate of step 5 exceeds
 *    exact_retry_rel on an unclamped disjoint pair, analytic:40 checked
 *    against analytic:28 replaces the contour value if it is better.
 * Cost: counted as inner closed-form evaluations.  Relative accuracy is near
 * 1e-14 for touching pairs; for pairs far apart it degrades like
 * eps * D / size because of cancellation between edge pairs.
 * The closed form Schroeder-Hanrahan (1993) derived for this integral
 * \cite{schroeder1993} needs dilogarithms; the adaptive outer integral of a
 * closed-form inner one reaches the same accuracy with much less code. */
#include <math.h>

#include "ff_internal.h"
#include "rad_quad.h"

typedef struct edge_ctx {
    rad_vec3 p, u; /* outer edge: p + s u */
    rad_vec3 q, v; /* inner edge: q + t v, t in [0, Lb] */
    double Lb, lnD;
    long evals;
} edge_ctx;

/* Antiderivative in z of ln sqrt(z^2 + h^2), h >= 0. */
static double phi(double z, double h)
{
    double r2 = z * z + h * h;
    double lg = r2 > 0.0 ? 0.5 * z * log(r2) : 0.0;
    double at = h > 0.0 ? h * atan(z / h) : 0.0;
    return lg - z + at;
}

double ff_log_segment(double z0, double z1, double h)
{
    return phi(z1, h) - phi(z0, h);
}

static double inner(double s, void *vctx)
{
    edge_ctx *c = vctx;
    c->evals++;
    rad_vec3 w = rad_vec3_sub(rad_vec3_add(c->p, rad_vec3_scale(c->u, s)), c->q);
    double tau = rad_vec3_dot(w, c->v);
    double h = rad_vec3_norm(rad_vec3_sub(w, rad_vec3_scale(c->v, tau)));
    return phi(c->Lb - tau, h) - phi(-tau, h) - c->Lb * c->lnD;
}

ff_value ff_exact(const ff_pair *pr, const rad_ff_params *params)
{
    ff_value v = {0};
    rad_vec3 pi[4], pj[4];
    int ni = ff_clip(pr->p[0], 3, pr->n[1], pr->p[1][0], pi);
    int nj = ff_clip(pr->p[1], 3, pr->n[0], pr->p[0][0], pj);
    if (!ni || !nj) {
        v.rel_error = 0.0;
        return v;
    }
    rad_vec3 ci = rad_geom_triangle_centroid(pr->p[0][0], pr->p[0][1], pr->p[0][2]);
    rad_vec3 cj = rad_geom_triangle_centroid(pr->p[1][0], pr->p[1][1], pr->p[1][2]);
    double D = fmax(1.0, rad_vec3_norm(rad_vec3_sub(ci, cj)));
    if (D > params->exact_far_ratio && ni == 3 && nj == 3) {
        ff_value lo, hi;
        if (ff_gauss(pr, 16, &lo) == RAD_OK && ff_gauss(pr, 20, &hi) == RAD_OK) {
            double diff = fabs(hi.G - lo.G);
            v.evals += lo.evals + hi.evals;
            if (diff <= 1e-14 * fabs(hi.G)) {
                v.G = hi.G;
                v.rel_error = hi.G > 0.0 ? diff / hi.G : 0.0;
                return v;
            }
        }
    }
    rad_quad_adapt_params ap;
    rad_quad_adapt_params_default(&ap);
    ap.rel_tol = params->exact_rel_tol;
    ap.max_intervals = 400;
    double sum = 0.0, err = 0.0;
    for (int a = 0; a < ni; a++) {
        rad_vec3 p = pi[a], pe = pi[(a + 1) % ni];
        double La = rad_vec3_norm(rad_vec3_sub(pe, p));
        if (!(La > 0.0))
            continue;
        rad_vec3 u = rad_vec3_scale(rad_vec3_sub(pe, p), 1.0 / La);
        for (int b = 0; b < nj; b++) {
            rad_vec3 q = pj[b], qe = pj[(b + 1) % nj];
            double Lb = rad_vec3_norm(rad_vec3_sub(qe, q));
            if (!(Lb > 0.0))
                continue;
            rad_vec3 vv = rad_vec3_scale(rad_vec3_sub(qe, q), 1.0 / Lb);
            double uv = rad_vec3_dot(u, vv);
            if (uv == 0.0)
                continue;
            edge_ctx c = {p, u, q, vv, Lb, log(D), 0};
            /* Breakpoints: closest approach of the outer edge to q, to qe and
             * to the inner edge's line. */
            double br[3];
            int nb = 0;
            br[nb++] = rad_vec3_dot(rad_vec3_sub(q, p), u);
            br[nb++] = rad_vec3_dot(rad_vec3_sub(qe, p), u);
            double den = 1.0 - uv * uv;
            if (den > 1e-12) {
                rad_vec3 d0 = rad_vec3_sub(p, q);
                double s = (uv * rad_vec3_dot(d0, vv) - rad_vec3_dot(d0, u)) / den;
                br[nb++] = s;
            }
            /* Absolute floor: rounding of O(1) terms over an O(La Lb) range. */
            ap.abs_tol = 1e-16 * La * Lb * (1.0 + fabs(log(D)));
            rad_quad_result r;
            rad_status st = rad_quad_adapt(inner, &c, 0.0, La, br, nb, &ap, &r);
            if (st != RAD_OK) {
                v.flags |= RAD_FF_FLAG_NOT_CONVERGED;
                rad_error_clear();
            }
            sum += uv * r.value;
            err += fabs(uv) * r.error;
            v.evals += c.evals;
        }
    }
    v.G = sum / (2.0 * RAD_PI);
    err /= 2.0 * RAD_PI;
    /* Rounding can leave a tiny negative value for a vanishing coupling;
     * within its own error bound that is zero, not a negative estimate. */
    if (v.G < 0.0 && -v.G <= err)
        v.G = 0.0;
    v.rel_error = fabs(v.G) > 0.0 ? err / fabs(v.G) : err;
    /* Step 7: cancellation left too few digits (slivers, G far below the
     * contour terms).  On an unclamped disjoint pair analytic:P converges
     * geometrically; take analytic:40 if it agrees with analytic:28 better
     * than the contour's own bound. */
    if (v.rel_error > params->exact_retry_rel && pr->adj == RAD_FF_DISJOINT && ni == 3 && nj == 3) {
        ff_value lo, hi;
        if (ff_analytic(pr, 28, &lo) == RAD_OK && ff_analytic(pr, 40, &hi) == RAD_OK) {
            v.evals += lo.evals + hi.evals;
            double diff = fabs(hi.G - lo.G);
            if (hi.G > 0.0 && diff < v.rel_error * hi.G) {
                v.G = hi.G;
                v.rel_error = diff / hi.G;
            }
        }
    }
    /* The estimate is a pessimistic bound (|K15 - G7| per interval): flag
     * only when even the bound is loose. */
    if (v.rel_error > params->exact_flag_rel)
        v.flags |= RAD_FF_FLAG_NOT_CONVERGED;
    return v;
}
