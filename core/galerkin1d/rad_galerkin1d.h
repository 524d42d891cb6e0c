/* rad_galerkin1d: the 1D model problem of the seed notes,
 *
 *     y(x) = f(x) + int_0^1 k(x,t) y(t) dt   on (0,1),
 *
 * discretised by Galerkin's method with piecewise-constant (P0) or continuous
 * piecewise-linear (P1) elements on n equal cells of width h = 1/n.
 *
 * Numbering (0-based throughout): cell c is [c h, (c+1) h].  P0 has n unknowns,
 * one per cell; P1 has n+1, one per node x_i = i h, with hat basis functions.
 * The Galerkin system is (M - A) y = b with
 *     M_ij = int phi_i phi_j                  (mass matrix, tridiagonal)
 *     A_ij = int int phi_i(x) k(x,t) phi_j(t) dt dx   (row i: test, column j: trial)
 *     b_i  = int f phi_i
 * For the seed kernel A is symmetric and equals the notes' A; the notes write
 * the same system as h y = A y + f (P0, M = h I).
 * Dense matrices are column-major: A[i + j*dim]. */
#ifndef RAD_GALERKIN1D_H
#define RAD_GALERKIN1D_H

#include <stddef.h>

#include "rad_error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum rad_galerkin1d_basis {
    RAD_GALERKIN1D_P0, /* piecewise constants: one unknown per cell */
    RAD_GALERKIN1D_P1  /* continuous piecewise linears: one unknown per node */
} rad_galerkin1d_basis;

/* A model problem: kernel, right-hand side, and what is known in closed form. */
typedef struct rad_galerkin1d_problem {
    const char *name;
    const char *description;
    double (*kernel)(double x, double t);
    int kernel_kink;     /* nonzero: k has a derivative jump on the diagonal x = t */
    int kernel_is_green; /* nonzero: k(x,t) = min(x,t) (1 - max(x,t)), the seed kernel,
                            whose Galerkin matrices have the closed forms below */
    double (*f)(double x);
    double (*exact)(double x); /* exact solution; NULL if unknown */
    /* Closed-form load moments over the cell [p, p+h], with u = (x-p)/h:
     *   out[0] = int f(x) (1-u) dx,   out[1] = int f(x) u dx.
     * NULL when there is no closed form. */
    void (*f_moments)(double p, double h, double out[2]);
} rad_galerkin1d_problem;

/* The built-in problems: "seed" (the notes' f; exact solution y = x) and "exp"
 * (manufactured: y = e^x, f = 2 e^x - 1 - (e-1) x).  NULL if no such name. */
const rad_galerkin1d_problem *rad_galerkin1d_problem_find(const char *name);
/* The names of the built-in problems, NULL-terminated. */
const char *const *rad_galerkin1d_problem_names(void);

/* How the kernel matrix and load vector are computed. */
typedef enum rad_galerkin1d_assembly_kind {
    RAD_GALERKIN1D_EXACT,      /* closed forms (needs kernel_is_green and f_moments) */
    RAD_GALERKIN1D_GAUSS,      /* tensor Gauss-Legendre, `points` per cell per direction;
                           points = 1 is the midpoint rule */
    RAD_GALERKIN1D_GAUSS_SPLIT /* as GAUSS, but diagonal cells are split along the kink
                           x = t into two triangles (collapsed Gauss rules) */
} rad_galerkin1d_assembly_kind;

typedef struct rad_galerkin1d_assembly {
    rad_galerkin1d_assembly_kind kind;
    int points;
} rad_galerkin1d_assembly;

/* Parse "exact", "midpoint", "gauss:K", "gauss-split:K" (K >= 1). */
rad_status rad_galerkin1d_assembly_parse(const char *text, rad_galerkin1d_assembly *out);
/* Canonical text of an assembly ("exact", "midpoint", "gauss:4", ...). */
void rad_galerkin1d_assembly_format(rad_galerkin1d_assembly assembly, char *buf, size_t size);
/* Parse "p0" or "p1". */
rad_status rad_galerkin1d_basis_parse(const char *text, rad_galerkin1d_basis *out);
const char *rad_galerkin1d_basis_name(rad_galerkin1d_basis basis);

/* Number of unknowns: n for P0, n+1 for P1 (0 if n < 1). */
size_t rad_galerkin1d_dim(rad_galerkin1d_basis basis, int n);

/* Closed forms for the seed kernel (derived in papers/galerkin-1d.md):
 * P0 entry A_ij for cells i (test) and j (trial), 0-based. */
double rad_galerkin1d_green_p0(int n, int i, int j);
/* P1 local matrix of the cell pair (a: test cell in x, c: trial cell in t):
 * out[alpha][beta] = int_{cell a} int_{cell c} psi_alpha(x) k(x,t) psi_beta(t),
 * with psi_0 = 1-u, psi_1 = u the cell's local shape functions. */
void rad_galerkin1d_green_p1_local(int n, int a, int c, double out[2][2]);

/* Mass matrix: diag[dim] and off[dim-1] (the sub/super diagonal). */
void rad_galerkin1d_mass(rad_galerkin1d_basis basis, int n, double *diag, double *off);

/* Fill A (dim x dim, column-major) and b (dim).  RAD_EINVAL when the problem has
 * no closed forms for EXACT, or the assembly is malformed. */
rad_status rad_galerkin1d_assemble(const rad_galerkin1d_problem *problem,
                                   rad_galerkin1d_basis basis, rad_galerkin1d_assembly assembly,
                                   int n, double *A, double *b);

/* Overwrite A by M - A, solve (M - A) y = b, write y (dim).  A is destroyed.
 * rcond (may be NULL) receives LAPACK's estimate of 1/cond_1(M - A). */
rad_status rad_galerkin1d_solve(rad_galerkin1d_basis basis, int n, double *A, const double *b,
                                double *y, double *rcond);

/* The discrete solution at x in [0,1]. */
double rad_galerkin1d_eval(rad_galerkin1d_basis basis, int n, const double *y, double x);

/* Errors of a discrete solution against the problem's exact solution. */
typedef struct rad_galerkin1d_error_norms {
    double l2;    /* || y_h - y ||_L2(0,1), 16-point Gauss per cell */
    double linf;  /* max |y_h - y|: 33 samples per cell, then golden-section refinement */
    double nodal; /* P0: max over cells |y_c - y(midpoint)|; P1: max over nodes */
} rad_galerkin1d_error_norms;

rad_status rad_galerkin1d_errors(const rad_galerkin1d_problem *problem,
                                 rad_galerkin1d_basis basis, int n, const double *y,
                                 rad_galerkin1d_error_norms *out);

/* Independent check of a solution: the Galerkin residual
 *     r_i = (M y)_i - int phi_i (K y_h) - int phi_i f
 * computed from the kernel and f functions alone (nested Gauss rules, the inner
 * one split at the kink t = x), never from the closed forms.  Writes
 * max_i |r_i| / max_i |b_i|.  Exact to round-off for kernels that are
 * polynomial on each side of the diagonal (both built-in problems); costs 16 n^2
 * kernel evaluations. */
rad_status rad_galerkin1d_residual(const rad_galerkin1d_problem *problem,
                                   rad_galerkin1d_basis basis, int n, const double *y,
                                   double *relative_residual);

#ifdef __cplusplus
}
#endif
#endif
