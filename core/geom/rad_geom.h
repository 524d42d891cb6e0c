/* rad_geom: 3D vectors and triangle basics shared by every module.
 * Small vector operations are static inline so hot loops pay nothing for them.
 * Triangles are one-sided: the front is the side the counter-clockwise winding's
 * normal (b - a) x (c - a) points to. */
#ifndef RAD_GEOM_H
#define RAD_GEOM_H

#include <math.h>

#ifdef __cplusplus
extern "C" {
#endif

/* pi to double precision: the one definition every module uses. */
#define RAD_PI 3.14159265358979323846

typedef struct rad_vec3 {
    double x, y, z;
} rad_vec3;

/* fmin/fmax are calls into libm unless -ffinite-math-only; these inline to one
 * instruction.  For finite inputs only: with a NaN they return b, where fmax
 * would return the other argument. */
static inline double rad_dmin(double a, double b) { return a < b ? a : b; }
static inline double rad_dmax(double a, double b) { return a > b ? a : b; }

static inline rad_vec3 rad_vec3_make(double x, double y, double z) { rad_vec3 v = {x, y, z}; return v; }
static inline rad_vec3 rad_vec3_add(rad_vec3 a, rad_vec3 b) { return rad_vec3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline rad_vec3 rad_vec3_sub(rad_vec3 a, rad_vec3 b) { return rad_vec3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline rad_vec3 rad_vec3_scale(rad_vec3 a, double s) { return rad_vec3_make(a.x * s, a.y * s, a.z * s); }
static inline double rad_vec3_dot(rad_vec3 a, rad_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline rad_vec3 rad_vec3_cross(rad_vec3 a, rad_vec3 b)
{
    return rad_vec3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double rad_vec3_norm(rad_vec3 a) { return sqrt(rad_vec3_dot(a, a)); }
static inline int rad_vec3_is_finite(rad_vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/* The angle between two vectors, atan2(s, c) in [0, pi], from the norm of
 * their cross product s >= 0 (finite) and their dot product c (finite):
 * within 2 ulp of libm's atan2 (angle.c). */
double rad_geom_angle(double s, double c);

/* The largest coordinate magnitude radkit accepts.  Form factors multiply up
 * to four lengths (r^4 in the kernel, A_i A_j in the couplings): beyond 1e75
 * such products can overflow double precision; rescale the scene instead. */
#define RAD_GEOM_MAX_COORD 1e75
static inline int rad_vec3_in_range(rad_vec3 a)
{
    return fabs(a.x) <= RAD_GEOM_MAX_COORD && fabs(a.y) <= RAD_GEOM_MAX_COORD &&
           fabs(a.z) <= RAD_GEOM_MAX_COORD;
}

/* Area of triangle abc (>= 0). */
double rad_geom_triangle_area(rad_vec3 a, rad_vec3 b, rad_vec3 c);
/* Unit normal of the counter-clockwise winding; (0,0,0) for a degenerate triangle. */
rad_vec3 rad_geom_triangle_normal(rad_vec3 a, rad_vec3 b, rad_vec3 c);
rad_vec3 rad_geom_triangle_centroid(rad_vec3 a, rad_vec3 b, rad_vec3 c);
/* Length of the longest edge of t[0..2]. */
double rad_geom_triangle_longest_edge(const rad_vec3 t[3]);
/* Point of the triangle at barycentric-like coordinates: a + s (b - a) + t (c - a). */
rad_vec3 rad_geom_triangle_point(rad_vec3 a, rad_vec3 b, rad_vec3 c, double s, double t);
/* Stratified sampling of a triangle: the lattice a + (p/k)(b - a) + (q/k)(c - a),
 * p + q <= k, cuts it into k^2 congruent cells of area A/k^2, numbered row by
 * row (row p holds 2(k - p) - 1 cells, alternately "up" and "down").  Cell
 * `cell` (0 <= cell < k^2) and (w1, w2) uniform on the unit square give
 * (s, t) for rad_geom_triangle_point, uniform on that cell.  Hashing w1, w2
 * per cell gives jittered stratified samples. */
void rad_geom_triangle_stratum(int k, long long cell, double w1, double w2, double *s, double *t);
/* A triangle is degenerate when its area is below rel_tol times the square of
 * its longest edge (zero-area, collinear or sliver beyond use), or it has a
 * non-finite coordinate.  rel_tol = 1e-12 is the library's default.  A test of
 * shape, not size: a triangle scaled by 1e-200 is degenerate exactly when the
 * unscaled one is (area, normal and longest edge are likewise computed
 * without underflow; the area itself underflows only below sizes of 1e-154). */
int rad_geom_triangle_is_degenerate(rad_vec3 a, rad_vec3 b, rad_vec3 c, double rel_tol);

#ifdef __cplusplus
}
#endif
#endif
