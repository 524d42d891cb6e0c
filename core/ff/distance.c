/* Distance between two triangles: the minimum over the 6 vertex-to-triangle
 * and 9 edge-to-edge distances (Ericson, Real-Time Collision Detection, 5.1),
 * which covers every configuration of two closed triangles that do not
 * intersect; intersecting triangles (which the facing test usually zeroes
 * anyway) are reported at distance of their closest edge features, 0 when an
 * edge pierces the other triangle is not detected. */
#include <math.h>

#include "ff_internal.h"

static double clamp01(double x) { return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x; }

static double segment_segment(rad_vec3 p1, rad_vec3 q1, rad_vec3 p2, rad_vec3 q2)
{
    rad_vec3 d1 = rad_vec3_sub(q1, p1), d2 = rad_vec3_sub(q2, p2), r = rad_vec3_sub(p1, p2);
    double a = rad_vec3_dot(d1, d1), e = rad_vec3_dot(d2, d2), f = rad_vec3_dot(d2, r);
    double s, t;
    double c = rad_vec3_dot(d1, r), b = rad_vec3_dot(d1, d2), den = a * e - b * b;
    s = den > 1e-300 ? clamp01((b * f - c * e) / den) : 0.0;
    t = (b * s + f) / e;
    if (t < 0.0) {
        t = 0.0;
        s = clamp01(-c / a);
    } else if (t > 1.0) {
        t = 1.0;
        s = clamp01((b - c) / a);
    }
    rad_vec3 c1 = rad_vec3_add(p1, rad_vec3_scale(d1, s)), c2 = rad_vec3_add(p2, rad_vec3_scale(d2, t));
    return rad_vec3_norm(rad_vec3_sub(c1, c2));
}

static double point_triangle(rad_vec3 p, const rad_vec3 t[3])
{
    rad_vec3 n = rad_vec3_cross(rad_vec3_sub(t[1], t[0]), rad_vec3_sub(t[2], t[0]));
    double nn = rad_vec3_dot(n, n);
    double best = INFINITY;
    if (nn > 0.0) {
        double h = rad_vec3_dot(n, rad_vec3_sub(p, t[0])) / nn;
        rad_vec3 f = rad_vec3_sub(p, rad_vec3_scale(n, h)); /* foot on the plane */
        int inside = 1;
        for (int k = 0; k < 3; k++) {
            rad_vec3 e = rad_vec3_sub(t[(k + 1) % 3], t[k]);
            if (rad_vec3_dot(rad_vec3_cross(e, rad_vec3_sub(f, t[k])), n) < 0.0)
                inside = 0;
        }
        if (inside)
            best = fabs(h) * sqrt(nn);
    }
    for (int k = 0; k < 3; k++)
        best = fmin(best, segment_segment(p, p, t[k], t[(k + 1) % 3]));
    return best;
}

double rad_ff_triangle_distance(const rad_vec3 ti[3], const rad_vec3 tj[3])
{
    double best = INFINITY;
    for (int k = 0; k < 3; k++) {
        best = fmin(best, point_triangle(ti[k], tj));
        best = fmin(best, point_triangle(tj[k], ti));
        for (int l = 0; l < 3; l++)
            best = fmin(best, segment_segment(ti[k], ti[(k + 1) % 3], tj[l], tj[(l + 1) % 3]));
    }
    return best;
}

/* 1 when the bounding boxes of ti and tj are more than gap apart along an
 * axis: then so are the triangles. */
static int boxes_apart(const rad_vec3 ti[3], const rad_vec3 tj[3], double gap)
{
    for (int axis = 0; axis < 3; axis++) {
        double lo_i = INFINITY, hi_i = -INFINITY, lo_j = INFINITY, hi_j = -INFINITY;
        for (int k = 0; k < 3; k++) {
            double a = axis == 0 ? ti[k].x : axis == 1 ? ti[k].y : ti[k].z;
            double b = axis == 0 ? tj[k].x : axis == 1 ? tj[k].y : tj[k].z;
            lo_i = fmin(lo_i, a);
            hi_i = fmax(hi_i, a);
            lo_j = fmin(lo_j, b);
            hi_j = fmax(hi_j, b);
        }
        if (lo_j - hi_i > gap || lo_i - hi_j > gap)
            return 1;
    }
    return 0;
}

int rad_ff_triangles_touch(const rad_vec3 ti[3], rad_vec3 ci, double si, const rad_vec3 tj[3],
                           rad_vec3 cj, double sj)
{
    double tol = 1e-9 * rad_dmax(si, sj);
    return rad_vec3_norm(rad_vec3_sub(ci, cj)) <= 1.001 * (si + sj) && !boxes_apart(ti, tj, tol) &&
           rad_ff_triangle_distance(ti, tj) <= tol;
}
