/* rad_basis: the orthonormal polynomials q_k on the unit triangle (rad_basis.h).
 * Gram-Schmidt of 1, s, t, s^2, st, t^2 in the mean over the triangle, with
 * the moments mean(s^a t^b) = 2 a! b! / (a + b + 2)!, in exact arithmetic;
 * the squared norms before normalization are 1, 1/18, 1/24, 1/300, 1/900 and
 * 1/540 (hence the square roots below). */
#include "rad_basis.h"

#include <math.h>
#include <string.h>

#include "rad_quad.h"

rad_status rad_basis_parse(const char *text, int *order)
{
    static const char *const names[RAD_BASIS_MAX_ORDER + 1] = {"p0", "p1", "p2"};
    for (int p = 0; p <= RAD_BASIS_MAX_ORDER; p++)
        if (text && strcmp(text, names[p]) == 0) {
            *order = p;
            return RAD_OK;
        }
    return RAD_ERROR(RAD_EINVAL, "basis must be p0, p1 or p2, got '%s'", text ? text : "");
}

int rad_basis_size(int order)
{
    return order == 0 ? 1 : order == 1 ? 3 : order == 2 ? 6 : 0;
}

void rad_basis_eval(int order, double s, double t, double *q)
{
    q[0] = 1.0;
    if (order < 1)
        return;
    q[1] = sqrt(2.0) * (3.0 * s - 1.0);
    q[2] = sqrt(6.0) * (s + 2.0 * t - 1.0);
    if (order < 2)
        return;
    q[3] = sqrt(3.0) * (1.0 - 8.0 * s + 10.0 * s * s);
    q[4] = 3.0 * (1.0 - 6.0 * s - 2.0 * t + 5.0 * s * s + 10.0 * s * t);
    q[5] = sqrt(15.0) * (1.0 - 2.0 * s - 6.0 * t + s * s + 6.0 * s * t + 6.0 * t * t);
}

double rad_basis_value(int order, double area, const double *coef, double s, double t)
{
    double q[RAD_BASIS_MAX_SIZE], v = 0.0;
    rad_basis_eval(order, s, t, q);
    for (int k = 0; k < rad_basis_size(order); k++)
        v += coef[k] * q[k];
    return area > 0.0 ? v / sqrt(area) : 0.0;
}

rad_status rad_basis_project(int order, const rad_vec3 tri[3], double (*f)(rad_vec3 x, void *ctx),
                             void *ctx, int degree, double *coef)
{
    int n = rad_basis_size(order), np = 0;
    if (n == 0)
        return RAD_ERROR(RAD_EINVAL, "basis order %d is not 0, 1 or 2", order);
    double s[RAD_QUAD_TRI_MAX_POINTS], t[RAD_QUAD_TRI_MAX_POINTS], w[RAD_QUAD_TRI_MAX_POINTS];
    rad_status st = rad_quad_tri_symmetric(degree, s, t, w, &np);
    if (st != RAD_OK)
        return st;
    double area = rad_geom_triangle_area(tri[0], tri[1], tri[2]);
    for (int k = 0; k < n; k++)
        coef[k] = 0.0;
    for (int i = 0; i < np; i++) {
        double q[RAD_BASIS_MAX_SIZE];
        rad_basis_eval(order, s[i], t[i], q);
        double fx = f(rad_geom_triangle_point(tri[0], tri[1], tri[2], s[i], t[i]), ctx);
        for (int k = 0; k < n; k++)
            coef[k] += w[i] * fx * q[k];
    }
    /* int_T f phi_k = A mean(f q_k / sqrt(A)) = sqrt(A) mean(f q_k) */
    for (int k = 0; k < n; k++)
        coef[k] *= sqrt(area);
    return RAD_OK;
}
