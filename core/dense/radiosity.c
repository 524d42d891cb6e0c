/* Direct solvers of the radiosity system and the driver over three channels.
 *
 * LU: K = I - R F with F_ij = G_ij / A_i, solved by dgesv (rad_dense_lu_solve).
 *
 * Cholesky on the symmetric form.  Row i of K B = E reads
 *     B_i - rho_i sum_j (G_ij / A_i) B_j = E_i.
 * For rho_i > 0 multiply it by A_i / rho_i:
 *     (A_i / rho_i) B_i - sum_j G_ij B_j = (A_i / rho_i) E_i,
 * i.e. S B = diag(A/rho) E with S = diag(A/rho) - G, symmetric because G is.
 * S is positive definite: its diagonal A_i/rho_i - G_ii is positive and
 *     (A_i/rho_i - G_ii) - sum_{j != i} |G_ij| = A_i/rho_i - A_i sum_j F_ij
 *                                            >= A_i (1/rho_i - 1) > 0
 * when sum_j F_ij <= 1 and 0 < rho_i < 1 (G >= 0 off the diagonal; a closed
 * row's negative G_ii, rad_radiosity_close_rows, adds |G_ii| to both sides
 * while its row sums to A_i), so S is strictly diagonally
 * dominant with a positive diagonal, and by Gershgorin's theorem a symmetric
 * such matrix has only positive eigenvalues.
 * Faces with rho_i = 0 reflect nothing: B_i = E_i exactly.  They are eliminated:
 * their B is known, so their columns move to the right-hand side,
 *     S_aa B_a = diag(A/rho)_a E_a + G_az E_z   (a: rho > 0, z: rho = 0),
 * and the factorization covers the reflecting faces only.
 * Steps: 1. per channel (once when grey), gather the reflecting faces;
 * 2. build S_aa (lower triangle suffices) and the right-hand sides;
 * 3. dpotrf, dpotrs, dpocon; 4. scatter B.  A failed dpotrf means the input
 * violated the row-sum bound (F sums above 1): RAD_ESINGULAR, use LU.
 * References: \cite{golub2013matrix} (Cholesky, Gershgorin), \cite{lapack1999} (dpotrf, dpocon). */
#include "rad_dense_solve.h"

#include <lapacke.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Below this many faces an OpenMP region costs more than the O(n^2) loop it
 * splits (waking threads on a loaded 2-core machine took ~0.1 ms a region). */
enum { DENSE_PARALLEL_MIN = 256 };

#include "rad_dense.h"

static const char *const method_names[RAD_DENSE_METHOD_COUNT] = {
    "lu", "cholesky", "jacobi", "gauss-seidel", "southwell",
};

const char *rad_dense_method_name(rad_dense_method method)
{
    return (unsigned)method < RAD_DENSE_METHOD_COUNT ? method_names[method] : "unknown";
}

rad_status rad_dense_method_parse(const char *text, rad_dense_method *out)
{
    for (int m = 0; m < RAD_DENSE_METHOD_COUNT; m++)
        if (text && strcmp(text, method_names[m]) == 0) {
            *out = (rad_dense_method)m;
            return RAD_OK;
        }
    return RAD_ERROR(RAD_EINVAL, "unknown solver '%s' (use lu, cholesky, jacobi, gauss-seidel "
                     "or southwell)", text ? text : "(null)");
}

void rad_dense_params_default(rad_dense_params *params)
{
    memset(params, 0, sizeof *params); /* every field a later one adds starts at 0 */
    params->method = RAD_DENSE_LU;
    params->tol = 1e-10;
    params->max_iter = 10000;
    params->share_channels = 1;
    params->progress = NULL;
    params->progress_ctx = NULL;
}

static int is_direct(rad_dense_method m) { return m == RAD_DENSE_LU || m == RAD_DENSE_CHOLESKY; }

rad_status rad_dense_radiosity_check_size(size_t n, rad_dense_method method)
{
    rad_status status = rad_dense_check_size(n, is_direct(method) ? 2 : 1, "dense radiosity");
    if (status == RAD_ETOOBIG) {
        char msg[512];
        snprintf(msg, sizeof msg, "%s", rad_error_message());
        return RAD_ERROR(RAD_ETOOBIG, "%s; use --method hier for a scene this large", msg);
    }
    return status;
}

rad_status rad_dense_system_matrix(int n, const double *G, const double *area, const double *rho,
                                   double *K)
{
    if (n < 1 || !G || !area || !rho || !K)
        return RAD_ERROR(RAD_EINVAL, "system matrix: bad arguments (n = %d)", n);
    size_t nn = (size_t)n;
    /* K_ij = delta_ij - rho_i G_ij / A_i: column j of K from column j of G. */
#pragma omp parallel for schedule(static) if (n >= DENSE_PARALLEL_MIN)
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            size_t k = (size_t)i + (size_t)j * nn;
            K[k] = (i == j ? 1.0 : 0.0) - rho[i] * G[k] / area[i];
        }
    return RAD_OK;
}

static rad_status check_input(int n, const double *G, const double *area, const double *rho,
                              const double *E, int signed_couplings)
{
    for (int i = 0; i < n; i++) {
        if (!(area[i] > 0.0) || !isfinite(area[i]))
            return RAD_ERROR(RAD_EINPUT, "dense solve: face %d has area %g", i, area[i]);
        for (int c = 0; c < 3; c++) {
            double r = rho[i + (size_t)c * n], e = E[i + (size_t)c * n];
            if (!(r >= 0.0 && r < 1.0))
                return RAD_ERROR(RAD_EINPUT, "dense solve: face %d has reflectance %g in channel "
                                 "%d, outside [0, 1)", i, r, c);
            if (!(e >= 0.0 || signed_couplings) || !isfinite(e))
                return RAD_ERROR(RAD_EINPUT, "dense solve: face %d has emission %g in channel %d",
                                 i, e, c);
        }
    }
    size_t nn = (size_t)n * (size_t)n;
    for (size_t k = 0; k < nn; k++) {
        size_t i = k % (size_t)n;
        /* a closed row's diagonal may be negative (rad_radiosity_close_rows) */
        double least = i == k / (size_t)n ? -area[i] : 0.0;
        if (!isfinite(G[k]) || (G[k] < least && !signed_couplings))
            return RAD_ERROR(RAD_EINPUT, "dense solve: coupling entry (%zu, %zu) is %g",
                             k % (size_t)n, k / (size_t)n, G[k]);
    }
    return RAD_OK;
}

static int channel_equal(int n, const double *rho, int c, int d)
{
    for (int i = 0; i < n; i++)
        if (rho[i + (size_t)c * n] != rho[i + (size_t)d * n])
            return 0;
    return 1;
}

/* LU for the channels in `chans` (nc of them) sharing reflectance rho_c. */
static rad_status solve_lu(int n, const double *G, const double *area, const double *rho_c,
                           const double *E, double *B, const int *chans, int nc, double *K,
                           double *rcond)
{
    rad_status status = rad_dense_system_matrix(n, G, area, rho_c, K);
    if (status != RAD_OK)
        return status;
    double *rhs = malloc((size_t)n * (size_t)nc * sizeof *rhs);
    if (!rhs)
        return RAD_ERROR(RAD_ENOMEM, "LU: no memory for %d right-hand sides", nc);
    for (int k = 0; k < nc; k++)
        memcpy(rhs + (size_t)k * n, E + (size_t)chans[k] * n, (size_t)n * sizeof *rhs);
    status = rad_dense_lu_solve(n, K, nc, rhs, rcond);
    if (status == RAD_OK)
        for (int k = 0; k < nc; k++)
            memcpy(B + (size_t)chans[k] * n, rhs + (size_t)k * n, (size_t)n * sizeof *rhs);
    free(rhs);
    return status;
}

static rad_status solve_cholesky(int n, const double *G, const double *area, const double *rho_c,
                                 const double *E, double *B, const int *chans, int nc, double *S,
                                 double *rcond)
{
    rad_status status = RAD_OK;
    int *act = malloc((size_t)n * sizeof *act);
    double *rhs = malloc((size_t)n * (size_t)nc * sizeof *rhs);
    if (!act || !rhs) {
        status = RAD_ERROR(RAD_ENOMEM, "Cholesky: no memory for %d faces", n);
        goto done;
    }
    int na = 0;
    for (int i = 0; i < n; i++)
        if (rho_c[i] > 0.0)
            act[na++] = i;
    /* Non-reflecting faces: B = E. */
    for (int k = 0; k < nc; k++)
        memcpy(B + (size_t)chans[k] * n, E + (size_t)chans[k] * n, (size_t)n * sizeof *B);
    *rcond = 1.0;
    if (na == 0)
        goto done;
    size_t m = (size_t)na;
#pragma omp parallel for schedule(static) if (n >= DENSE_PARALLEL_MIN)
    for (int b = 0; b < na; b++)
        for (int a = b; a < na; a++) { /* lower triangle of S_aa */
            double g = G[(size_t)act[a] + (size_t)act[b] * (size_t)n];
            S[(size_t)a + (size_t)b * m] = a == b ? area[act[a]] / rho_c[act[a]] - g : -g;
        }
    for (int k = 0; k < nc; k++) {
        const double *e = E + (size_t)chans[k] * n;
        double *y = rhs + (size_t)k * m;
        for (int a = 0; a < na; a++)
            y[a] = area[act[a]] / rho_c[act[a]] * e[act[a]];
        if (na < n) /* move the known B_z = E_z of non-reflecting faces across */
            for (int z = 0; z < n; z++)
                if (!(rho_c[z] > 0.0) && e[z] != 0.0)
                    for (int a = 0; a < na; a++)
                        y[a] += G[(size_t)act[a] + (size_t)z * (size_t)n] * e[z];
    }
    double anorm = LAPACKE_dlansy(LAPACK_COL_MAJOR, '1', 'L', na, S, na);
    lapack_int info = LAPACKE_dpotrf(LAPACK_COL_MAJOR, 'L', na, S, na);
    if (info > 0) {
        status = RAD_ERROR(RAD_ESINGULAR, "Cholesky: the symmetric form is not positive definite "
                           "(minor %d); the coupling's row sums probably exceed the face areas "
                           "(sum_j F_ij > 1); use the LU solver", (int)info);
        goto done;
    }
    if (info == 0)
        info = LAPACKE_dpotrs(LAPACK_COL_MAJOR, 'L', na, nc, S, na, rhs, na);
    if (info == 0)
        info = LAPACKE_dpocon(LAPACK_COL_MAJOR, 'L', na, S, na, anorm, rcond);
    if (info != 0) {
        status = RAD_ERROR(RAD_EDEP, "Cholesky: LAPACK returned %d", (int)info);
        goto done;
    }
    for (int k = 0; k < nc; k++)
        for (int a = 0; a < na; a++)
            B[(size_t)act[a] + (size_t)chans[k] * n] = rhs[(size_t)a + (size_t)k * m];
done:
    free(act);
    free(rhs);
    rad_dense_blas_idle();
    return status;
}

static rad_status solve_iterative(int n, const double *G, const double *area, const double *rho,
                                  const double *E, double *B, const rad_dense_params *p,
                                  rad_dense_report *rep)
{
    for (int c = 0; c < 3; c++) {
        rad_dense_iter *it = NULL;
        rad_status status = rad_dense_iter_create(n, G, area, rho + (size_t)c * n,
                                                  E + (size_t)c * n, p->method, p, &it);
        while (status == RAD_OK && (status = rad_dense_iter_test(it)) == RAD_CONTINUE) {
            status = rad_dense_iter_step(it);
            if (status == RAD_OK && p->progress)
                p->progress(c, rad_dense_iter_count(it), rad_dense_iter_residual(it), p->progress_ctx);
        }
        if (status == RAD_OK) {
            memcpy(B + (size_t)c * n, rad_dense_iter_solution(it), (size_t)n * sizeof *B);
            if (rad_dense_iter_count(it) > rep->iterations)
                rep->iterations = rad_dense_iter_count(it);
            rep->residual = fmax(rep->residual, rad_dense_iter_residual(it));
        }
        rad_dense_iter_destroy(it);
        if (status != RAD_OK)
            return status;
    }
    return RAD_OK;
}

/* Radiosity is never negative (B = E + rho F B with nothing negative in it).
 * A solution whose entries are non-finite, or negative beyond rounding
 * (1e-9 of the largest), comes from a system too ill-conditioned to solve:
 * RAD_ENUMERIC.  Negatives within rounding are set to 0.  Coefficients of a
 * polynomial basis (signed couplings) may be negative: only finiteness. */
static rad_status check_solution(int n, double *B, int signed_couplings)
{
    double bmax = 0.0;
    for (size_t k = 0; k < 3 * (size_t)n; k++) {
        if (!isfinite(B[k]))
            return RAD_ERROR(RAD_ENUMERIC, "dense solve: element %zu has a non-finite radiosity "
                                           "(the system is singular to working precision)",
                             k % (size_t)n);
        bmax = fmax(bmax, fabs(B[k]));
    }
    for (size_t k = 0; k < 3 * (size_t)n && !signed_couplings; k++) {
        if (B[k] < -1e-9 * bmax)
            return RAD_ERROR(RAD_ENUMERIC, "dense solve: element %zu has a negative radiosity "
                                           "%.3g (the system is too ill-conditioned; is a "
                                           "reflectance too close to 1?)", k % (size_t)n, B[k]);
        if (B[k] < 0.0)
            B[k] = 0.0;
    }
    return RAD_OK;
}

rad_status rad_dense_radiosity_solve(int n, const double *G, const double *area, const double *rho,
                                     const double *E, double *B, const rad_dense_params *params,
                                     rad_dense_report *report)
{
    if (n < 1 || !G || !area || !rho || !E || !B)
        return RAD_ERROR(RAD_EINVAL, "dense solve: bad arguments (n = %d)", n);
    rad_dense_params p;
    if (params)
        p = *params;
    else
        rad_dense_params_default(&p);
    if ((unsigned)p.method >= RAD_DENSE_METHOD_COUNT)
        return RAD_ERROR(RAD_EINVAL, "dense solve: unknown method %d", (int)p.method);
    rad_status status = rad_dense_radiosity_check_size((size_t)n, p.method);
    if (status != RAD_OK)
        return status;
    if ((status = check_input(n, G, area, rho, E, p.signed_couplings)) != RAD_OK)
        return status;
    rad_dense_report rep = {p.method, 0, 0, 0.0, 1.0};
    if (!is_direct(p.method)) {
        status = solve_iterative(n, G, area, rho, E, B, &p, &rep);
    } else {
        double *K = malloc((size_t)n * (size_t)n * sizeof *K);
        if (!K)
            return RAD_ERROR(RAD_ENOMEM, "dense solve: no memory for the %d x %d matrix", n, n);
        /* Group channels with identical reflectance: one factorization each. */
        int done[3] = {0, 0, 0};
        for (int c = 0; c < 3 && status == RAD_OK; c++) {
            if (done[c])
                continue;
            int chans[3], nc = 0;
            for (int d = c; d < 3; d++)
                if (!done[d] && (d == c || (p.share_channels && channel_equal(n, rho, c, d)))) {
                    chans[nc++] = d;
                    done[d] = 1;
                }
            double rc = 1.0;
            const double *rho_c = rho + (size_t)c * n;
            if (p.method == RAD_DENSE_LU)
                status = solve_lu(n, G, area, rho_c, E, B, chans, nc, K, &rc);
            else
                status = solve_cholesky(n, G, area, rho_c, E, B, chans, nc, K, &rc);
            rep.factorizations++;
            rep.rcond = fmin(rep.rcond, rc);
        }
        free(K);
        if (status == RAD_OK) {
            /* The relative residual of the answer, from its definition. */
            for (int c = 0; c < 3; c++) {
                const double *b = B + (size_t)c * n, *e = E + (size_t)c * n;
                const double *r = rho + (size_t)c * n;
                double rmax = 0.0, emax = 0.0;
#pragma omp parallel for schedule(static) reduction(max : rmax, emax) if (n >= DENSE_PARALLEL_MIN)
                for (int i = 0; i < n; i++) {
                    const double *g = G + (size_t)i * (size_t)n;
                    double s = 0.0;
                    for (int j = 0; j < n; j++)
                        s += g[j] * b[j];
                    rmax = fmax(rmax, fabs(e[i] + r[i] * s / area[i] - b[i]));
                    emax = fmax(emax, e[i]);
                }
                rep.residual = fmax(rep.residual, emax > 0.0 ? rmax / emax : rmax);
            }
        }
    }
    if (status == RAD_OK)
        status = check_solution(n, B, p.signed_couplings);
    if (report)
        *report = rep;
    return status;
}
