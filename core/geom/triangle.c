/* Triangle area, normal, centroid and degeneracy.  The cross product is taken
 * from the vertex opposite the longest edge, which keeps the area accurate for
 * slivers (the two shorter edges have the least cancellation).
 *
 * Every result depends on the triangle's shape and scale only, at any scale:
 * squares of lengths (1e-100 squared is 1e-200, its square underflows) are
 * formed directly only while they stay in double precision's normal range;
 * outside it the edges are first divided by their largest component, so a
 * well-shaped triangle of size 1e-200 is as well-shaped as one of size 1.
 * Inside the range the arithmetic is the plain one (no extra cost, same bits). */
#include "rad_geom.h"

/* Squares within [lo, hi] are formed and rooted without loss. */
#define SQ_LO 1e-280
#define SQ_HI 1e280

/* The triangle translated to a = 0 and divided by the largest edge
 * component m (returned; 0 for a point, non-finite for non-finite input). */
static double rescale(rad_vec3 *a, rad_vec3 *b, rad_vec3 *c)
{
    rad_vec3 ab = rad_vec3_sub(*b, *a), ac = rad_vec3_sub(*c, *a);
    double m = rad_dmax(rad_dmax(fabs(ab.x), fabs(ab.y)), fabs(ab.z));
    m = rad_dmax(m, rad_dmax(rad_dmax(fabs(ac.x), fabs(ac.y)), fabs(ac.z)));
    if (!(m > 0.0) || !isfinite(m))
        return m;
    *a = rad_vec3_make(0.0, 0.0, 0.0);
    *b = rad_vec3_make(ab.x / m, ab.y / m, ab.z / m); /* division: 1/m may overflow */
    *c = rad_vec3_make(ac.x / m, ac.y / m, ac.z / m);
    return m;
}

static rad_vec3 stable_cross(rad_vec3 a, rad_vec3 b, rad_vec3 c)
{
    rad_vec3 ab = rad_vec3_sub(b, a), bc = rad_vec3_sub(c, b), ca = rad_vec3_sub(a, c);
    double lab = rad_vec3_dot(ab, ab), lbc = rad_vec3_dot(bc, bc), lca = rad_vec3_dot(ca, ca);
    /* (b-a) x (c-a) = (c-b) x (a-b) = (a-c) x (b-c): all equal the CCW normal. */
    if (lab >= lbc && lab >= lca)
        return rad_vec3_cross(ca, rad_vec3_scale(bc, -1.0)); /* from c: (a-c) x (b-c) */
    if (lbc >= lab && lbc >= lca)
        return rad_vec3_cross(ab, rad_vec3_scale(ca, -1.0)); /* from a */
    return rad_vec3_cross(bc, rad_vec3_scale(ab, -1.0)); /* from b: (c-b) x (a-b) */
}

double rad_geom_triangle_area(rad_vec3 a, rad_vec3 b, rad_vec3 c)
{
    rad_vec3 n = stable_cross(a, b, c);
    double sq = rad_vec3_dot(n, n);
    if (sq >= SQ_LO && sq <= SQ_HI)
        return 0.5 * sqrt(sq);
    double m = rescale(&a, &b, &c);
    if (!(m > 0.0) || !isfinite(m))
        return 0.5 * sqrt(sq);
    /* the area of the rescaled triangle times m^2, in two steps so that
       neither overflows nor underflows before the result does */
    return 0.5 * rad_vec3_norm(stable_cross(a, b, c)) * m * m;
}

rad_vec3 rad_geom_triangle_normal(rad_vec3 a, rad_vec3 b, rad_vec3 c)
{
    rad_vec3 n = stable_cross(a, b, c);
    double sq = rad_vec3_dot(n, n);
    if (!(sq >= SQ_LO && sq <= SQ_HI)) {
        double m = rescale(&a, &b, &c);
        if (!(m > 0.0) || !isfinite(m))
            return rad_vec3_make(0.0, 0.0, 0.0);
        n = stable_cross(a, b, c);
        sq = rad_vec3_dot(n, n);
    }
    double len = sqrt(sq);
    if (!(len > 0.0) || !isfinite(len))
        return rad_vec3_make(0.0, 0.0, 0.0);
    return rad_vec3_scale(n, 1.0 / len);
}

rad_vec3 rad_geom_triangle_centroid(rad_vec3 a, rad_vec3 b, rad_vec3 c)
{
    return rad_vec3_scale(rad_vec3_add(rad_vec3_add(a, b), c), 1.0 / 3.0);
}

double rad_geom_triangle_longest_edge(const rad_vec3 t[3])
{
    double l = 0.0;
    for (int k = 0; k < 3; k++) {
        rad_vec3 d = rad_vec3_sub(t[(k + 1) % 3], t[k]);
        l = rad_dmax(l, rad_vec3_dot(d, d));
    }
    if (l >= SQ_LO && l <= SQ_HI)
        return sqrt(l); /* sqrt is monotone and correctly rounded: the longest length exactly */
    rad_vec3 a = t[0], b = t[1], c = t[2];
    double m = rescale(&a, &b, &c);
    if (!(m > 0.0) || !isfinite(m))
        return sqrt(l);
    rad_vec3 u[3] = {a, b, c};
    return rad_geom_triangle_longest_edge(u) * m; /* rescaled: within range now */
}

rad_vec3 rad_geom_triangle_point(rad_vec3 a, rad_vec3 b, rad_vec3 c, double s, double t)
{
    return rad_vec3_add(a, rad_vec3_add(rad_vec3_scale(rad_vec3_sub(b, a), s),
                                        rad_vec3_scale(rad_vec3_sub(c, a), t)));
}

void rad_geom_triangle_stratum(int k, long long cell, double w1, double w2, double *s, double *t)
{
    /* Row p starts at cell p (2k - p): p = floor(k - sqrt(k^2 - cell)), corrected
     * for rounding of the square root. */
    long long kk = k;
    long long p = (long long)floor((double)kk - sqrt((double)(kk * kk - cell)));
    if (p < 0)
        p = 0;
    while (p > 0 && p * (2 * kk - p) > cell)
        p--;
    while (p + 1 < kk && (p + 1) * (2 * kk - p - 1) <= cell)
        p++;
    long long q = cell - p * (2 * kk - p);
    if (w1 + w2 > 1.0) { /* fold the unit square onto the unit triangle */
        w1 = 1.0 - w1;
        w2 = 1.0 - w2;
    }
    /* Lattice corners of the cell (along a->b, along a->c). */
    double s0, r0, s1, r1, s2, r2;
    if (q % 2 == 0) { /* up: (p, j), (p, j+1), (p+1, j) in (row, column) */
        double j = (double)(q / 2);
        r0 = (double)p; s0 = j; r1 = (double)p; s1 = j + 1; r2 = (double)p + 1; s2 = j;
    } else { /* down: (p, j+1), (p+1, j+1), (p+1, j) */
        double j = (double)(q / 2);
        r0 = (double)p; s0 = j + 1; r1 = (double)p + 1; s1 = j + 1; r2 = (double)p + 1; s2 = j;
    }
    *s = (s0 + w1 * (s1 - s0) + w2 * (s2 - s0)) / (double)k;
    *t = (r0 + w1 * (r1 - r0) + w2 * (r2 - r0)) / (double)k;
}

int rad_geom_triangle_is_degenerate(rad_vec3 a, rad_vec3 b, rad_vec3 c, double rel_tol)
{
    if (!rad_vec3_is_finite(a) || !rad_vec3_is_finite(b) || !rad_vec3_is_finite(c))
        return 1;
    rad_vec3 ab = rad_vec3_sub(b, a), bc = rad_vec3_sub(c, b), ca = rad_vec3_sub(a, c);
    double longest = fmax(rad_vec3_dot(ab, ab), fmax(rad_vec3_dot(bc, bc), rad_vec3_dot(ca, ca)));
    if (!(longest >= SQ_LO && longest <= SQ_HI)) {
        /* a shape test: on the rescaled triangle, whatever its size */
        double m = rescale(&a, &b, &c);
        if (!(m > 0.0) || !isfinite(m))
            return 1;
        ab = rad_vec3_sub(b, a), bc = rad_vec3_sub(c, b), ca = rad_vec3_sub(a, c);
        longest = fmax(rad_vec3_dot(ab, ab), fmax(rad_vec3_dot(bc, bc), rad_vec3_dot(ca, ca)));
    }
    double area = rad_geom_triangle_area(a, b, c);
    return !(longest > 0.0) || !(area > rel_tol * longest);
}
