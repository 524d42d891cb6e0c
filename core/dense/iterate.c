/* Iterative solvers of the radiosity system B = E + R F B, one sweep per step.
 *
 * Notation: R = diag(rho), F_ij = G_ij / A_i, K = I - R F, r = E - K B.
 * 1. Start from B = E (the direct light); r = R F E.
 * 2. Jacobi: B <- B + r (= E + R F B), then r = E + R F B - B.  The error
 *    obeys e <- R F e, so with rho_i sum_j F_ij <= rho_max < 1 every sweep
 *    shrinks ||e||_inf and ||r||_inf by at least rho_max (r <- R F r as well).
 * 3. Gauss-Seidel: for i = 0..n-1 in order,
 *    B_i <- (E_i + rho_i sum_{j != i} F_ij B_j) / (1 - rho_i F_ii), using the
 *    B_j already updated in this sweep; then r from its definition.
 * 4. Southwell (progressive radiosity, "shooting"): r is the unshot
 *    radiosity.  n times per step: pick i maximising the unshot power A_i |r_i|,
 *    B_i += d = r_i / K_ii, and every r_j += rho_j F_ji d (j != i), r_i = 0:
 *    O(n) per shot, reading column i of G.  Then r from its definition.
 * 5. Test: ||r||_inf <= tol ||E||_inf.
 * References: \cite{cohen1988progressive} (progressive refinement = Southwell),
 * \cite{gortler1994relaxation}'s discussion of Jacobi / Gauss-Seidel / Southwell
 * for radiosity, and \cite{cohen1993} chapter 5.
 * The products with F are OpenMP loops over rows, each row summed in a fixed
 * order, so results do not depend on the number of threads. */
#include "rad_dense_solve.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Below this many faces an OpenMP region costs more than the O(n^2) loop it
 * splits (waking threads on a loaded 2-core machine took ~0.1 ms a region). */
enum { DENSE_PARALLEL_MIN = 256 };

struct rad_dense_iter {
    int n;
    const double *G, *area;
    double *rho, *E, *B, *r, *work;
    rad_dense_method method;
    rad_dense_params params;
    double enorm;
    int count;
    double *history;
    int history_cap;
};

/* r = E + R F B - B; returns ||r||_inf. */
static double residual(const rad_dense_iter *it)
{
    int n = it->n;
    double rmax = 0.0;
#pragma omp parallel for schedule(static) reduction(max : rmax) if (n >= DENSE_PARALLEL_MIN)
    for (int i = 0; i < n; i++) {
        const double *g = it->G + (size_t)i * (size_t)n;
        double s = 0.0;
        for (int j = 0; j < n; j++)
            s += g[j] * it->B[j];
        double ri = it->E[i] + it->rho[i] * (s / it->area[i]) - it->B[i];
        it->r[i] = ri;
        rmax = fmax(rmax, fabs(ri));
    }
    return rmax;
}

static rad_status record(rad_dense_iter *it, double rmax)
{
    double rel = it->enorm > 0.0 ? rmax / it->enorm : rmax;
    if (!isfinite(rel))
        return RAD_ERROR(RAD_ENUMERIC, "%s: the residual is not finite after %d sweeps",
                         rad_dense_method_name(it->method), it->count);
    if (it->count + 1 > it->history_cap) {
        int cap = it->history_cap ? 2 * it->history_cap : 64;
        double *h = realloc(it->history, (size_t)cap * sizeof *h);
        if (!h)
            return RAD_ERROR(RAD_ENOMEM, "%s: no memory for the residual history",
                             rad_dense_method_name(it->method));
        it->history = h;
        it->history_cap = cap;
    }
    it->history[it->count] = rel;
    return RAD_OK;
}

void rad_dense_iter_destroy(rad_dense_iter *it)
{
    if (!it)
        return;
    free(it->rho);
    free(it->history);
    free(it);
}

rad_status rad_dense_iter_create(int n, const double *G, const double *area, const double *rho,
                                 const double *E, rad_dense_method method,
                                 const rad_dense_params *params, rad_dense_iter **out)
{
    if (!out || n < 1 || !G || !area || !rho || !E)
        return RAD_ERROR(RAD_EINVAL, "iterative solve: bad arguments (n = %d)", n);
    *out = NULL;
    if (method != RAD_DENSE_JACOBI && method != RAD_DENSE_GAUSS_SEIDEL &&
        method != RAD_DENSE_SOUTHWELL)
        return RAD_ERROR(RAD_EINVAL, "iterative solve: %s is not an iterative method",
                         rad_dense_method_name(method));
    rad_dense_params p;
    if (params)
        p = *params;
    else
        rad_dense_params_default(&p);
    if (!(p.tol > 0.0) || p.max_iter < 1)
        return RAD_ERROR(RAD_EINVAL, "iterative solve: tolerance %g and iteration cap %d must be "
                         "positive", p.tol, p.max_iter);
    for (int i = 0; i < n; i++) {
        if (!(area[i] > 0.0) || !isfinite(area[i]))
            return RAD_ERROR(RAD_EINPUT, "iterative solve: face %d has area %g", i, area[i]);
        if (!(rho[i] >= 0.0 && rho[i] < 1.0))
            return RAD_ERROR(RAD_EINPUT, "iterative solve: face %d has reflectance %g, outside "
                             "[0, 1)", i, rho[i]);
        if (!(E[i] >= 0.0) || !isfinite(E[i]))
            return RAD_ERROR(RAD_EINPUT, "iterative solve: face %d has emission %g", i, E[i]);
    }
    rad_dense_iter *it = calloc(1, sizeof *it);
    if (!it)
        return RAD_ERROR(RAD_ENOMEM, "iterative solve: no memory");
    /* One block for rho, E, B, r and work (n each). */
    it->rho = malloc(5 * (size_t)n * sizeof *it->rho);
    if (!it->rho) {
        free(it);
        return RAD_ERROR(RAD_ENOMEM, "iterative solve: no memory for %d faces", n);
    }
    it->E = it->rho + n;
    it->B = it->E + n;
    it->r = it->B + n;
    it->work = it->r + n;
    it->n = n;
    it->G = G;
    it->area = area;
    it->method = method;
    it->params = p;
    memcpy(it->rho, rho, (size_t)n * sizeof *rho);
    memcpy(it->E, E, (size_t)n * sizeof *E);
    memcpy(it->B, E, (size_t)n * sizeof *E);
    it->enorm = 0.0;
    for (int i = 0; i < n; i++)
        it->enorm = fmax(it->enorm, E[i]);
    rad_status status = record(it, residual(it));
    if (status != RAD_OK) {
        rad_dense_iter_destroy(it);
        return status;
    }
    *out = it;
    return RAD_OK;
}

static void gauss_seidel_sweep(rad_dense_iter *it)
{
    int n = it->n;
    for (int i = 0; i < n; i++) {
        const double *g = it->G + (size_t)i * (size_t)n;
        double s = 0.0;
        for (int j = 0; j < n; j++)
            if (j != i)
                s += g[j] * it->B[j];
        double kii = 1.0 - it->rho[i] * g[i] / it->area[i];
        it->B[i] = (it->E[i] + it->rho[i] * s / it->area[i]) / kii;
    }
}

static void southwell_shots(rad_dense_iter *it)
{
    int n = it->n;
    for (int shot = 0; shot < n; shot++) {
        int best = 0;
        double power = -1.0;
        for (int i = 0; i < n; i++) {
            double pw = it->area[i] * fabs(it->r[i]);
            if (pw > power) {
                power = pw;
                best = i;
            }
        }
        if (!(power > 0.0))
            return; /* nothing left to shoot: B is exact */
        const double *g = it->G + (size_t)best * (size_t)n; /* column: G_j,best */
        double kii = 1.0 - it->rho[best] * g[best] / it->area[best];
        double d = it->r[best] / kii;
        it->B[best] += d;
        for (int j = 0; j < n; j++)
            it->r[j] += it->rho[j] * (g[j] / it->area[j]) * d;
        it->r[best] = 0.0;
    }
}

rad_status rad_dense_iter_step(rad_dense_iter *it)
{
    if (!it)
        return RAD_ERROR(RAD_EINVAL, "iterative solve: NULL iterator");
    if (it->count >= it->params.max_iter)
        return RAD_ERROR(RAD_ENUMERIC, "%s: no convergence in %d sweeps (relative residual %.3g, "
                         "tolerance %.3g)", rad_dense_method_name(it->method), it->count,
                         rad_dense_iter_residual(it), it->params.tol);
    switch (it->method) {
    case RAD_DENSE_JACOBI:
        for (int i = 0; i < it->n; i++)
            it->B[i] += it->r[i];
        break;
    case RAD_DENSE_GAUSS_SEIDEL:
        gauss_seidel_sweep(it);
        break;
    default:
        southwell_shots(it);
        break;
    }
    it->count++;
    return record(it, residual(it));
}

double rad_dense_iter_residual(const rad_dense_iter *it)
{
    return it ? it->history[it->count] : INFINITY;
}

rad_status rad_dense_iter_test(const rad_dense_iter *it)
{
    if (!it)
        return RAD_ERROR(RAD_EINVAL, "iterative solve: NULL iterator");
    return rad_dense_iter_residual(it) <= it->params.tol ? RAD_OK : RAD_CONTINUE;
}

int rad_dense_iter_count(const rad_dense_iter *it) { return it ? it->count : 0; }

const double *rad_dense_iter_history(const rad_dense_iter *it, int *length)
{
    if (length)
        *length = it ? it->count + 1 : 0;
    return it ? it->history : NULL;
}

const double *rad_dense_iter_solution(const rad_dense_iter *it) { return it ? it->B : NULL; }
