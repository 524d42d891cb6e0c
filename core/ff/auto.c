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
 * 4. Adjacent, no clamp active, T >= auto_ss_min_tol (1e-5): ss:N for
 *    N = 3, 4, ... up to auto_ss_max (7), accepted when two consecutive N
 *    agree to 0.1 T; the whole ladder costs about as much time as one exact
 *    evaluation of an adjacent pair, so beyond it exact is cheaper.
 * 5. Everything else (near-touching, tighter tolerances on adjacent pairs,
 *    active clamps, a ladder that did not settle): exact, whose own error
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

rad_status ff_auto(const ff_pair *pr, const rad_ff_params *params, ff_value *v, rad_ff_rule *used)
{
    double tol = params->tol;
    long spent = 0;
    /* Adjacent pairs touch: the shared vertex is on both planes, which does
     * not count as an active clamp. */
    int clamped = pr->adj == RAD_FF_DISJOINT && clamp_active(pr, params->plane_rel_tol);
    if (pr->adj == RAD_FF_DISJOINT && !clamped) {
        /* Local copies: GCC's -fsanitize build misreads the array bounds of
         * pr->p[1] (a -Wstringop-overread false positive). */
        rad_vec3 ti[3] = {pr->p[0][0], pr->p[0][1], pr->p[0][2]};
        rad_vec3 tj[3] = {pr->p[1][0], pr->p[1][1], pr->p[1][2]};
        double rho = rad_ff_triangle_distance(ti, tj); /* longest edge is 1 */
        if (rho >= params->auto_min_ratio) {
            static const int ladder[] = {2, 4, 6, 8, 10, 14, 20};
            int analytic = rho < params->auto_near_ratio;
            ff_value prev = {0}, cur = {0};
            for (int k = 0; k < (int)(sizeof ladder / sizeof ladder[0]); k++) {
                rad_status st = analytic ? ff_analytic(pr, ladder[k], &cur) : ff_gauss(pr, ladder[k], &cur);
                if (st != RAD_OK)
                    return st;
                spent += cur.evals;
                if (k > 0 && cur.G > 0.0 && fabs(cur.G - prev.G) <= params->auto_safety * tol * cur.G) {
                    *v = cur;
                    v->rel_error = fabs(cur.G - prev.G) / cur.G;
                    v->evals = spent;
                    used->scheme = analytic ? RAD_FF_ANALYTIC : RAD_FF_GAUSS;
                    used->order = ladder[k];
                    return RAD_OK;
                }
                prev = cur;
            }
        }
    }
    if (pr->adj != RAD_FF_DISJOINT && pr->adj != RAD_FF_SHARE_ALL && tol >= params->auto_ss_min_tol) {
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
            /* Consecutive N: Sauter-Schwab converges geometrically (an order of
             * magnitude per step near N = 5 in the experiment), so the
             * difference of two neighbours bounds the error of the higher. */
            ff_value prev = {0}, cur = {0};
            for (int n = 3; n <= params->auto_ss_max; n++) {
                rad_status st = ff_ss(pr, n, &cur);
                if (st != RAD_OK)
                    return st;
                spent += cur.evals;
                if (n > 3 && cur.G > 0.0 && fabs(cur.G - prev.G) <= params->auto_safety * tol * cur.G) {
                    *v = cur;
                    v->rel_error = fabs(cur.G - prev.G) / cur.G;
                    v->evals = spent;
                    used->scheme = RAD_FF_SS;
                    used->order = n;
                    return RAD_OK;
                }
                prev = cur;
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
