/* auto: the cheapest scheme expected to reach a relative tolerance T, chosen
 * per pair, with an a-posteriori check.
 *
 * 1. Classify the pair: adjacency (shared vertex or edge), relative distance
 *    rho = dist(T_i, T_j) / longest edge, and whether a cosine clamp is active
 *    inside the pair (a vertex of one triangle behind or on the other's plane:
 *    the kernel then has a kink and no fixed rule converges fast).
 * 2. Well separated (disjoint, rho >= auto_near_ratio, no clamp active): the
 *    kernel is analytic on the pair and symmetric rules converge
 *    geometrically.  Evaluate gauss:P for P = 2, 4, 6, 8, 10, 14, 20 in turn
 *    and accept the first P whose value differs from the previous one by at
 *    most auto_safety T (0.1 T) relative; that difference, which overestimates the error of the
 *    higher rule when convergence is geometric, is the reported estimate.
 *    The ladder costs at most twice the evaluations of the accepted rule.
 * 3. Near (disjoint, auto_min_ratio <= rho < auto_near_ratio, no clamp
 *    active): the same ladder with analytic:P, whose closed-form inner integral
 *    absorbs the near-singularity (measured: 64 closed-form evaluations reach
 *    1e-6 at rho = 0.17, where gauss:P needs 28561 kernel evaluations).
 * 4. Adjacent, no clamp active: ss:N with N = ceil(2 + 1.35 log10(1/(0.1 T)))
 *    (the experiment's adjacent pairs gain at least 0.7 decade per N), checked
 *    against ss:N+1 and accepted when they agree to 0.1 T; tried only when
 *    the two together cost at most auto_exact_cost kernel evaluations, the
 *    time exact takes on an adjacent pair (bench/ff.tsv: about 230 us, i.e.
 *    35000 evaluations at 6.5 ns).
 * 5. Disjoint with an active clamp (one triangle straddles or touches the
 *    other's plane): clip each triangle to the open half-space in front of
 *    the other (the clamped kernel vanishes outside it), fan the clipped
 *    polygons into pieces, and run the gauss ladder of step 2 on every pair
 *    of pieces, whose kernel has no kink (it only vanishes on the clip line).
 *    The sum is accepted when every piece pair is well separated (rho >=
 *    auto_near_ratio, measured on the pieces) and settles.  Near pieces are
 *    left to exact: the analytic ladder on clipped pieces accepted two
 *    agreeing orders 2.5x outside the tolerance on 2 of 80 random straddling
 *    pairs (tests/test_ff.c).  Straddling pairs are common in rooms, which
 *    is why they get this step rather than exact (papers/quadrature.md,
 *    section 6).
 * 6. Everything else (near-touching, tighter tolerances on adjacent pairs,
 *    pieces that touch, a ladder that did not settle): exact, whose own error
 *    estimate is reported.  Measured cost (bench/ff.tsv): exact on an
 *    adjacent pair costs about as much time as ss:8 and is accurate to
 *    1e-13, so ss:N with larger N is never the cheaper choice for T < 1e-3.
 * The evaluations of every attempt are counted in the result. */
#include <math.h>

#include "ff_internal.h"

static int clamp_active(const ff_pair *pr, double tol)
{
    for (int k = 0; k < 2; k++)
        for (int v = 0; v < 3; v++)
            if (!(rad_vec3_dot(pr->n[1 - k], rad_vec3_sub(pr->p[k][v], pr->p[1 - k][0])) > tol))
                return 1;
    return 0;
}

/* Steps 2-3: the gauss (far) or analytic (near) ladder on a disjoint pair
 * with no active clamp.  Returns 1 with *v and *used set when two successive
 * orders agree to auto_safety * tol, 0 when the pair is too close for it or
 * the ladder did not settle.  Evaluations are added to *spent either way. */
static int ladder(const ff_pair *pr, const rad_ff_params *params, double longest, double min_ratio,
                  ff_value *v, rad_ff_rule *used, long *spent, rad_status *st)
{
    /* Local copies: GCC's -fsanitize build misreads the array bounds of
     * pr->p[1] (a -Wstringop-overread false positive). */
    rad_vec3 ti[3] = {pr->p[0][0], pr->p[0][1], pr->p[0][2]};
    rad_vec3 tj[3] = {pr->p[1][0], pr->p[1][1], pr->p[1][2]};
    double rho = rad_ff_triangle_distance(ti, tj) / longest;
    if (!(rho >= min_ratio))
        return 0;
    static const int orders[] = {2, 4, 6, 8, 10, 14, 20};
    int analytic = rho < params->auto_near_ratio;
    ff_value prev = {0}, cur = {0};
    for (int k = 0; k < (int)(sizeof orders / sizeof orders[0]); k++) {
        *st = analytic ? ff_analytic(pr, orders[k], &cur) : ff_gauss(pr, orders[k], &cur);
        if (*st != RAD_OK)
            return 0;
        *spent += cur.evals;
        if (k > 0 && cur.G > 0.0 && fabs(cur.G - prev.G) <= params->auto_safety * params->tol * cur.G) {
            *v = cur;
            v->rel_error = fabs(cur.G - prev.G) / cur.G;
            used->scheme = analytic ? RAD_FF_ANALYTIC : RAD_FF_GAUSS;
            used->order = orders[k];
            return 1;
        }
        prev = cur;
    }
    return 0;
}

/* Step 5: clip, split into pieces, run the ladder on every pair of pieces. */
static int clipped_ladder(const ff_pair *pr, const rad_ff_params *params, ff_value *v,
                          rad_ff_rule *used, long *spent, rad_status *st)
{
    rad_vec3 poly[2][4];
    int nv[2];
    nv[0] = ff_clip(pr->p[0], 3, pr->n[1], pr->p[1][0], poly[0]);
    nv[1] = ff_clip(pr->p[1], 3, pr->n[0], pr->p[0][0], poly[1]);
    ff_value sum = {0};
    rad_ff_rule highest = {RAD_FF_GAUSS, 0};
    if (nv[0] == 0 || nv[1] == 0) { /* nothing in front: the kernel vanishes */
        *v = sum;
        *used = highest;
        return 1;
    }
    double err = 0.0;
    for (int a = 1; a + 1 < nv[0]; a++)
        for (int b = 1; b + 1 < nv[1]; b++) {
            ff_pair sub = *pr;
            sub.p[0][0] = poly[0][0];
            sub.p[0][1] = poly[0][a];
            sub.p[0][2] = poly[0][a + 1];
            sub.p[1][0] = poly[1][0];
            sub.p[1][1] = poly[1][b];
            sub.p[1][2] = poly[1][b + 1];
            for (int k = 0; k < 2; k++) {
                rad_vec3 c = rad_vec3_cross(rad_vec3_sub(sub.p[k][1], sub.p[k][0]),
                                            rad_vec3_sub(sub.p[k][2], sub.p[k][0]));
                sub.A[k] = 0.5 * rad_vec3_norm(c);
            }
            sub.map[0] = sub.map[1] = sub.map[2] = -1;
            sub.adj = RAD_FF_DISJOINT;
            /* A sliver cut off at a vertex carries no measurable coupling. */
            if (!(sub.A[0] > 1e-14) || !(sub.A[1] > 1e-14))
                continue;
            double longest = fmax(rad_geom_triangle_longest_edge(sub.p[0]), rad_geom_triangle_longest_edge(sub.p[1]));
            ff_value piece;
            rad_ff_rule r;
            if (!ladder(&sub, params, longest, params->auto_near_ratio, &piece, &r, spent, st))
                return 0;
            sum.G += piece.G;
            err += piece.rel_error * piece.G;
            sum.guarded += piece.guarded;
            if (r.scheme == RAD_FF_ANALYTIC || r.order > highest.order)
                highest = r;
        }
    sum.rel_error = sum.G > 0.0 ? err / sum.G : 0.0;
    *v = sum;
    *used = highest;
    return 1;
}

rad_status ff_auto(const ff_pair *pr, const rad_ff_params *params, ff_value *v, rad_ff_rule *used)
{
    double tol = params->tol;
    long spent = 0;
    /* Adjacent pairs touch: the shared vertex is on both planes, which does
     * not count as an active clamp. */
    if (pr->adj != RAD_FF_DISJOINT && !params->singular_rules) {
        /* as if the pair were apart: the Gauss ladder whatever the distance */
        rad_ff_params regular = *params;
        regular.auto_near_ratio = 0.0;
        rad_status st = RAD_OK;
        if (ladder(pr, &regular, 1.0, -1.0, v, used, &spent, &st)) {
            v->evals = spent;
        } else if (st == RAD_OK) {
            st = ff_gauss(pr, 20, v);
            v->evals += spent;
            v->flags |= RAD_FF_FLAG_NOT_CONVERGED;
            used->scheme = RAD_FF_GAUSS;
            used->order = 20;
        }
        return st;
    }
    int clamped = pr->adj == RAD_FF_DISJOINT && clamp_active(pr, params->plane_rel_tol);
    if (pr->adj == RAD_FF_DISJOINT) {
        rad_status st = RAD_OK;
        int settled = clamped ? clipped_ladder(pr, params, v, used, &spent, &st)
                              : ladder(pr, params, 1.0 /* longest edge, normalised */,
                                       params->auto_min_ratio, v, used, &spent, &st);
        if (st != RAD_OK)
            return st;
        if (settled) {
            v->evals = spent;
            return RAD_OK;
        }
    }
    if (pr->adj != RAD_FF_DISJOINT && pr->adj != RAD_FF_SHARE_ALL) {
        /* Shared vertices lie on both planes; a clamp is active only if a
         * non-shared vertex is behind or on the other plane. */
        int active = 0;
        for (int k = 0; k < 2; k++)
            for (int a = 0; a < 3; a++) {
                int shared = 0;
                for (int b = 0; b < 3; b++)
                    shared |= k == 0 ? pr->map[a] >= 0 : pr->map[b] == a;
                if (!shared &&
                    !(rad_vec3_dot(pr->n[1 - k], rad_vec3_sub(pr->p[k][a], pr->p[1 - k][0])) >
                      params->plane_rel_tol))
                    active = 1;
            }
        if (!active) {
            /* Predict N from the measured convergence (at least 0.7 decade
             * per N on the experiment's adjacent pairs), check it against
             * N + 1, and do so only when the two cost less than exact. */
            int n = (int)ceil(2.0 + 1.35 * log10(1.0 / (params->auto_safety * tol)));
            if (n < 3)
                n = 3;
            long per = pr->adj == RAD_FF_SHARE_EDGE ? 5 : 2;
            long cost = per * ((long)n * n * n + (long)(n + 1) * (n + 1) * (n + 1));
            if (n + 1 <= RAD_FF_SS_MAX && cost <= params->auto_exact_cost) {
                ff_value lo, hi;
                rad_status st;
                if ((st = ff_ss(pr, n, &lo)) != RAD_OK || (st = ff_ss(pr, n + 1, &hi)) != RAD_OK)
                    return st;
                spent += lo.evals + hi.evals;
                if (hi.G > 0.0 && fabs(hi.G - lo.G) <= params->auto_safety * tol * hi.G) {
                    *v = hi;
                    v->rel_error = fabs(hi.G - lo.G) / hi.G;
                    v->evals = spent;
                    used->scheme = RAD_FF_SS;
                    used->order = n + 1;
                    return RAD_OK;
                }
            }
        }
    }
    *v = ff_exact(pr, params);
    v->evals += spent;
    used->scheme = RAD_FF_EXACT;
    used->order = 0;
    if (!(v->rel_error <= tol))
        v->flags |= RAD_FF_FLAG_NOT_CONVERGED;
    return RAD_OK;
}
