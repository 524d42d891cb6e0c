/* rad_basis: discontinuous polynomial bases on triangles, orthonormal in L2.
 *
 * On a triangle abc of area A, with local coordinates (s, t) of the point
 * a + s (b - a) + t (c - a) (s, t >= 0, s + t <= 1), the basis of order p
 * (p = 0, 1, 2: 1, 3, 6 functions) is
 *
 *   phi_k(x) = q_k(s, t) / sqrt(A),
 *
 * where q_0 = 1, q_1, q_2 (linear), q_3, q_4, q_5 (quadratic) are the
 * Gram-Schmidt orthonormalization of the monomials 1, s, t, s^2, st, t^2 in
 * the mean over the triangle (mean(q_k q_l) = delta_kl), so that
 * int_T phi_k phi_l dA = delta_kl.  The orders are nested (order p's
 * functions are the first of order p + 1's), the constant is in every space,
 * and q_0 = 1 makes a function's first coefficient sqrt(A) times its mean:
 * the per-face average of a solution is its first coefficient over sqrt(A).
 * Orthonormal, nested polynomial bases are those of Zatz 1993 (Legendre
 * products on quadrilaterals) and of Bekaert and Willems' hierarchical
 * Galerkin radiosity; on triangles the orthonormalization is done once, in
 * exact arithmetic, and written below in closed form (tests/test_basis.c
 * checks it against quadrature).
 *
 * With an orthonormal basis the Galerkin mass matrix is the identity: the
 * radiosity system for coefficients b is b = e + rho K b, K the couplings
 * int int phi_ik(x) k(x, y) V(x, y) phi_jl(y). */
#ifndef RAD_BASIS_H
#define RAD_BASIS_H

#include "rad_error.h"
#include "rad_geom.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RAD_BASIS_MAX_ORDER 2
#define RAD_BASIS_MAX_SIZE 6 /* functions of the highest order */

/* "p0", "p1" or "p2" -> 0, 1, 2; RAD_EINVAL naming the text otherwise. */
rad_status rad_basis_parse(const char *text, int *order);

/* Functions of order p: 1, 3, 6 (0 for an order out of range). */
int rad_basis_size(int order);

/* q_k(s, t) for k < rad_basis_size(order) (the area-free part of phi_k). */
void rad_basis_eval(int order, double s, double t, double *q);

/* The value at (s, t) of the function with coefficients coef on a triangle
 * of area `area`: sum_k coef[k] q_k(s, t) / sqrt(area). */
double rad_basis_value(int order, double area, const double *coef, double s, double t);

/* The L2 projection of f onto the basis of order p on triangle tri:
 * coef[k] = int_T f phi_k dA, by the symmetric rule of degree `degree`
 * (>= 2 p: exact for f of degree up to degree - p).  RAD_EINVAL for an order
 * or degree out of range. */
rad_status rad_basis_project(int order, const rad_vec3 tri[3], double (*f)(rad_vec3 x, void *ctx),
                             void *ctx, int degree, double *coef);

#ifdef __cplusplus
}
#endif
#endif
