/* Polygon faces into triangles, each keeping its input face and line.
 *
 *  1. Vector area N: the sum of the fan triangles' cross products
 *     (v0, vk-1, vk), which equals Newell's normal (twice the area vector).
 *  2. If no fan triangle points against N, the fan (0,1,2), (0,2,3), ... is
 *     a triangulation of the polygon: its triangles sweep monotonically
 *     around v0.  Convex polygons always take this branch, so their
 *     triangles are the fan in input order.  Zero-area and collinear
 *     polygons take it too: their degenerate triangles reach scene_finish's
 *     degeneracy check, which names the face.
 *  3. Otherwise ear clipping [eberly2002] in the polygon's own plane: project
 *     along N's dominant axis (orientation such that the polygon winds
 *     counter-clockwise), drop consecutive repeated corners, then repeatedly
 *     cut off an ear (a convex corner whose triangle holds no other corner,
 *     on its boundary included; failing that, strictly inside) and emit it in
 *     input winding.  Every cut removes one corner, so there are at most n-3
 *     cuts, each searching at most the remaining corners: the loop ends, and
 *     a budget of point-in-triangle tests bounds its time.
 *  4. If no corner is an ear (a self-intersecting polygon, or a zero net
 *     area with non-degenerate triangles, as a figure eight), the face is an
 *     input error naming file:line or the face. */
#include <math.h>
#include <stdlib.h>

#include "rad_geom.h"
#include "scene_internal.h"

static rad_vec3 vertex(const rad_scene *s, int i)
{
    const double *p = s->xyz + 3 * (size_t)i;
    return rad_vec3_make(p[0], p[1], p[2]);
}

static rad_status face_error(const rad_scene *s, int face, int line, const char *what)
{
    if (line > 0)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: face %d %s", s->source, line, face, what);
    return RAD_ERROR(RAD_EINPUT, "%s: face %d %s", s->source, face, what);
}

/* Twice the signed area of the 2D triangle abc (positive counter-clockwise). */
static double orient2(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Is p inside triangle abc (counter-clockwise)?  `closed` counts the boundary. */
static int in_triangle(const double *p, const double *a, const double *b, const double *c,
                       int closed)
{
    double d1 = orient2(a, b, p), d2 = orient2(b, c, p), d3 = orient2(c, a, p);
    return closed ? (d1 >= 0.0 && d2 >= 0.0 && d3 >= 0.0) : (d1 > 0.0 && d2 > 0.0 && d3 > 0.0);
}

static int same2(const double *a, const double *b) { return a[0] == b[0] && a[1] == b[1]; }

/* Point-in-triangle tests one polygon may use (a few seconds at most): a
 * polygon of many thousands of corners whose ears are hard to find is refused
 * rather than ground through in O(n^3). */
static const long long POLYGON_MAX_TESTS = 1LL << 30;

/* Is corner `i` of the ring (prev/next links) an ear?  Adds the corners
 * tested to *tests. */
static int is_ear(const double *uv, const int *prev, const int *next, int i, int closed,
                  long long *tests)
{
    int a = prev[i], c = next[i];
    const double *pa = uv + 2 * a, *pb = uv + 2 * i, *pc = uv + 2 * c;
    if (!(orient2(pa, pb, pc) > 0.0))
        return 0;
    for (int j = next[c]; j != a; j = next[j]) {
        const double *p = uv + 2 * j;
        ++*tests;
        /* A corner repeated elsewhere on the ring (a hole's bridge) may touch the ear. */
        if (same2(p, pa) || same2(p, pb) || same2(p, pc))
            continue;
        if (in_triangle(p, pa, pb, pc, closed))
            return 0;
    }
    return 1;
}

static rad_status ear_clip(rad_scene *s, const int *idx, int n, rad_vec3 N, int mat, int face,
                           int line)
{
    rad_status st = RAD_OK;
    double *uv = malloc(2 * (size_t)n * sizeof *uv);
    int *ring = malloc(3 * (size_t)n * sizeof *ring);
    if (!uv || !ring) {
        free(uv);
        free(ring);
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory for a polygon of %d corners", s->source, n);
    }
    int *prev = ring, *next = ring + n, *keep = ring + 2 * n;
    /* Drop the dominant axis; swap the other two when N points down it so the
     * polygon winds counter-clockwise in (u, v). */
    double ax = fabs(N.x), ay = fabs(N.y), az = fabs(N.z);
    int drop = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
    double sign = drop == 0 ? N.x : drop == 1 ? N.y : N.z;
    int iu = (drop + 1) % 3, iv = (drop + 2) % 3;
    if (sign < 0.0) {
        int t = iu;
        iu = iv;
        iv = t;
    }
    int m = 0;
    for (int k = 0; k < n; k++) {
        const double *p = s->xyz + 3 * (size_t)idx[k];
        uv[2 * m] = p[iu];
        uv[2 * m + 1] = p[iv];
        keep[m] = idx[k];
        if (m > 0 && same2(uv + 2 * m, uv + 2 * (m - 1)))
            continue; /* a repeated corner adds nothing to the area */
        m++;
    }
    while (m > 1 && same2(uv, uv + 2 * (m - 1)))
        m--;
    for (int k = 0; k < m; k++) {
        prev[k] = (k + m - 1) % m;
        next[k] = (k + 1) % m;
    }
    int i = 0;
    long long tests = 0;
    while (m > 3 && st == RAD_OK) {
        int ear = -1;
        for (int pass = 0; pass < 2 && ear < 0; pass++) {
            int j = i;
            for (int tries = 0; tries < m; tries++, j = next[j])
                if (is_ear(uv, prev, next, j, pass == 0, &tests)) {
                    ear = j;
                    break;
                }
        }
        if (tests > POLYGON_MAX_TESTS) {
            st = face_error(s, face, line, "is a non-convex polygon too large to split into "
                            "triangles here; split it before import");
            break;
        }
        if (ear < 0) {
            st = face_error(s, face, line,
                            "is a self-intersecting polygon (no way to split it into triangles)");
            break;
        }
        st = scene_add_triangle(s, keep[prev[ear]], keep[ear], keep[next[ear]], mat, face, line);
        next[prev[ear]] = next[ear];
        prev[next[ear]] = prev[ear];
        i = next[ear];
        m--;
    }
    if (st == RAD_OK) {
        if (m == 3)
            st = scene_add_triangle(s, keep[prev[i]], keep[i], keep[next[i]], mat, face, line);
        else
            st = face_error(s, face, line, "has fewer than 3 distinct corners");
    }
    free(uv);
    free(ring);
    return st;
}

rad_status scene_add_polygon(rad_scene *s, const int *idx, int n, int mat, int face, int line)
{
    if (n < 3)
        return face_error(s, face, line, "needs at least 3 corners");
    for (int k = 0; k < n; k++)
        if (idx[k] < 0 || idx[k] >= s->nv)
            return face_error(s, face, line, "has a corner index out of range");
    if (n == 3)
        return scene_add_triangle(s, idx[0], idx[1], idx[2], mat, face, line);
    rad_vec3 o = vertex(s, idx[0]), N = rad_vec3_make(0, 0, 0);
    double total = 0.0;
    for (int k = 2; k < n; k++) {
        rad_vec3 c = rad_vec3_cross(rad_vec3_sub(vertex(s, idx[k - 1]), o),
                                    rad_vec3_sub(vertex(s, idx[k]), o));
        N = rad_vec3_add(N, c);
        total += rad_vec3_norm(c);
    }
    /* A net area that vanishes against the triangles' own (a figure eight)
     * leaves no plane to triangulate in. */
    if (total > 0.0 && !(rad_vec3_norm(N) > 1e-12 * total))
        return face_error(s, face, line,
                          "is a self-intersecting polygon (its parts cancel each other's area)");
    int folds = 0;
    for (int k = 2; k < n && !folds; k++) {
        rad_vec3 c = rad_vec3_cross(rad_vec3_sub(vertex(s, idx[k - 1]), o),
                                    rad_vec3_sub(vertex(s, idx[k]), o));
        folds = rad_vec3_dot(c, N) < 0.0;
    }
    if (!folds) {
        for (int k = 2; k < n; k++) {
            rad_status st = scene_add_triangle(s, idx[0], idx[k - 1], idx[k], mat, face, line);
            if (st != RAD_OK)
                return st;
        }
        return RAD_OK;
    }
    return ear_clip(s, idx, n, N, mat, face, line);
}
