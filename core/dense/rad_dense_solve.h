/* rad_dense_solve: the radiosity system on a dense symmetric coupling, and
 * its direct and iterative solvers (part of the rad_dense module).
 *
 * Convention (DESIGN.md): B_i = E_i + rho_i sum_j F_ij B_j with the symmetric
 * coupling G_ij = A_i F_ij (reciprocity), so F_ij = G_ij / A_i.  G is a dense
 * n x n column-major matrix, symmetric: the solvers read row i of F as column i
 * of G (G[j + i n], contiguous) and Cholesky reads the lower triangle.
 * Per-channel arrays (rho, E, B) are n x 3 column-major: channel c of face i is
 * x[i + c n].  Reflectance must lie in [0, 1), emission must be >= 0.
 * When every face has rho_r = rho_g = rho_b the channels share one matrix and
 * the direct solvers factor it once for all three right-hand sides. */
#ifndef RAD_DENSE_SOLVE_H
#define RAD_DENSE_SOLVE_H

#include <stddef.h>

#include "rad_error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum rad_dense_method {
    RAD_DENSE_LU,           /* (I - R F) B = E by LU with partial pivoting (dgesv) */
    RAD_DENSE_CHOLESKY,     /* the symmetric form (diag(A/rho) - G) B = diag(A/rho) E (dpotrf) */
    RAD_DENSE_JACOBI,       /* B <- E + R F B */
    RAD_DENSE_GAUSS_SEIDEL, /* the same, using each new B_i at once */
    RAD_DENSE_SOUTHWELL,    /* progressive shooting: relax the face of largest unshot power */
    RAD_DENSE_METHOD_COUNT
} rad_dense_method;

/* "lu", "cholesky", "jacobi", "gauss-seidel", "southwell".  RAD_EINVAL
 * (listing the names) for anything else. */
rad_status rad_dense_method_parse(const char *text, rad_dense_method *out);
const char *rad_dense_method_name(rad_dense_method method);

typedef struct rad_dense_params {
    rad_dense_method method; /* default RAD_DENSE_LU */
    /* Iterative solvers stop when ||r||_inf <= tol ||E||_inf, r = E + R F B - B.
     * Since ||B - B*||_inf <= ||r||_inf / (1 - max_i rho_i sum_j F_ij), this
     * bounds the error by about tol ||B||_inf.  Default 1e-10. */
    double tol;
    int max_iter; /* iteration (sweep) cap of the iterative solvers; default 10000 */
    /* Direct solvers: 1 (default) lets channels with identical reflectance
     * share one factorization (a grey scene: one system); 0 factors every
     * channel on its own (the effects plan's colour decision forced on). */
    int share_channels;
    /* 0 (default): couplings are form factors, every entry >= 0 (a diagonal
     * entry >= -A_i: a sealed scene's closed row, rad_radiosity_close_rows), and the
     * emission and the answer >= 0 (checked); 1: the couplings of a
     * polynomial basis (rad_basis), whose entries, emission coefficients and
     * solution coefficients may have either sign (only finiteness checked). */
    int signed_couplings;
    /* Called by the iterative solvers after every sweep of every channel with
     * its relative residual; NULL (the default) for none. */
    void (*progress)(int channel, int iteration, double residual, void *ctx);
    void *progress_ctx;
} rad_dense_params;

void rad_dense_params_default(rad_dense_params *params);

/* What a solve did. */
typedef struct rad_dense_report {
    rad_dense_method method;
    int factorizations; /* direct solvers: 1 for grey reflectance, 3 for coloured */
    int iterations;     /* iterative solvers: the most sweeps any channel needed */
    double residual;    /* the largest final relative residual ||r||_inf / ||E||_inf */
    double rcond;       /* direct solvers: the smallest LAPACK estimate of 1/cond_1 of the
                           matrix factored: K = I - R F for LU, the scaled symmetric
                           S = diag(A/rho) - G (reflecting faces only) for Cholesky */
} rad_dense_report;

/* Before allocating for n faces with `method`: RAD_ETOOBIG when G plus the
 * solver's work matrix (direct) would not fit, with the estimate and a pointer
 * to `--method hier`. */
rad_status rad_dense_radiosity_check_size(size_t n, rad_dense_method method);

/* K = I - diag(rho) F with F_ij = G_ij / A_i (one channel: rho has n entries).
 * K is n x n column-major, written by the caller's buffer. */
rad_status rad_dense_system_matrix(int n, const double *G, const double *area, const double *rho,
                                   double *K);

/* Solve all three channels.  rho, E: n x 3 inputs; B: n x 3 output. */
rad_status rad_dense_radiosity_solve(int n, const double *G, const double *area, const double *rho,
                                     const double *E, double *B, const rad_dense_params *params,
                                     rad_dense_report *report);

/* ---- iterative solvers, one step at a time (init / iterate / test) ---------- */

typedef struct rad_dense_iter rad_dense_iter;

/* One channel (rho, E: n entries, copied).  Borrows G and area, which must
 * outlive the iterator.  The start is B = E; its residual is history[0]. */
rad_status rad_dense_iter_create(int n, const double *G, const double *area, const double *rho,
                                 const double *E, rad_dense_method method,
                                 const rad_dense_params *params, rad_dense_iter **out);
void rad_dense_iter_destroy(rad_dense_iter *it);

/* One sweep: Jacobi (one product with F), Gauss-Seidel (one sweep in face
 * order, then the true residual: two passes over G), Southwell (n relaxations
 * of the face with the largest unshot power A_i |r_i|, then the true residual).
 * Afterwards the residual is recomputed from its definition, so rounding in
 * the updates never hides in the reported figure.  RAD_ENUMERIC if it is not
 * finite or when called past the iteration cap (max_iter sweeps). */
rad_status rad_dense_iter_step(rad_dense_iter *it);
/* RAD_OK when converged (see rad_dense_params.tol), RAD_CONTINUE otherwise. */
rad_status rad_dense_iter_test(const rad_dense_iter *it);
/* The relative residual ||r||_inf / ||E||_inf (absolute when E = 0). */
double rad_dense_iter_residual(const rad_dense_iter *it);
int rad_dense_iter_count(const rad_dense_iter *it);
/* Residual after 0, 1, ..., count steps (count + 1 values). */
const double *rad_dense_iter_history(const rad_dense_iter *it, int *length);
const double *rad_dense_iter_solution(const rad_dense_iter *it);

#ifdef __cplusplus
}
#endif
#endif
