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
 *     input error naming file:line or the face.
 * A polygon with holes (scene_add_polygon_holes, MGF's `fh`):
 *  5. The outer contour's vector area N fixes the plane and the projection
 *     of step 3.  In it every hole must lie inside the outer contour and
 *     outside the other holes (each corner and each edge's midpoint tested,
 *     the boundary allowed, one of them strictly inside the outer contour),
 *     and no two contours may cross; else the face is
 *     an input error.  Holes may wind either way: each is taken clockwise.
 *  6. The holes are joined to the outer ring one at a time, the one reaching
 *     furthest in +u first [eberly2002]: a ray from the hole's rightmost
 *     corner M in +u leaves the ring through its nearest edge at I; the
 *     bridge goes to that edge's end P of larger u, unless corners of the
 *     ring lie in the triangle M I P, in which case to the one of those
 *     nearest the ray in angle (then in distance) whose corner opens towards
 *     M (a corner repeated by an earlier bridge has two).  The ring becomes
 *     ... P M (the hole) M P ..., a polygon whose boundary touches itself
 *     along the bridges, and step 3 splits it: a corner repeated elsewhere
 *     on the ring never stops an ear.  The work is that of step 3 plus
 *     O(corners x contours) for the bridges and O(corners^2) for the checks,
 *     within the same budget. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rad_geom.h"
#include "scene_internal.h"

static rad_vec3 vertex(const rad_scene *s, int i)
{
    const double *p = s->xyz + 3 * (size_t)i;
    return rad_vec3_make(p[0], p[1], p[2]);
}

/* The polygon's place: the file being read (scene_set_file) and the line. */
static rad_status face_error(const rad_scene *s, int face, int line, const char *what)
{
    const char *file = scene_file_name(s, s->cur_file);
    if (line > 0)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: face %d %s", file, line, face, what);
    return RAD_ERROR(RAD_EINPUT, "%s: face %d %s", file, face, what);
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

/* The coordinates (iu, iv) a polygon of vector area N is projected on: N's
 * dominant axis dropped, the other two swapped when N points down it, so the
 * polygon winds counter-clockwise in (u, v). */
static void plane_axes(rad_vec3 N, int *iu, int *iv)
{
    double ax = fabs(N.x), ay = fabs(N.y), az = fabs(N.z);
    int drop = ax >= ay && ax >= az ? 0 : ay >= az ? 1 : 2;
    double sign = drop == 0 ? N.x : drop == 1 ? N.y : N.z;
    *iu = (drop + 1) % 3;
    *iv = (drop + 2) % 3;
    if (sign < 0.0) {
        int t = *iu;
        *iu = *iv;
        *iv = t;
    }
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
    int iu, iv;
    plane_axes(N, &iu, &iv);
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

/* ---- polygons with holes (steps 5 and 6) --------------------------------- */

/* Where p lies against the closed ring of corners ids[0..n-1] (uv pairs):
 * -1 outside, 0 on its boundary, 1 inside (crossing number). */
static int classify(const double *p, const double *uv, const int *ids, int n)
{
    int inside = 0;
    for (int i = 0, j = n - 1; i < n; j = i++) {
        const double *a = uv + 2 * ids[j], *b = uv + 2 * ids[i];
        if (orient2(a, b, p) == 0.0 && fmin(a[0], b[0]) <= p[0] && p[0] <= fmax(a[0], b[0]) &&
            fmin(a[1], b[1]) <= p[1] && p[1] <= fmax(a[1], b[1]))
            return 0;
        if ((a[1] > p[1]) != (b[1] > p[1]) &&
            p[0] < a[0] + (p[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]))
            inside = !inside;
    }
    return inside ? 1 : -1;
}

/* Do segments ab and cd cross at a point interior to both? */
static int cross_properly(const double *a, const double *b, const double *c, const double *d)
{
    double o1 = orient2(a, b, c), o2 = orient2(a, b, d), o3 = orient2(c, d, a), o4 = orient2(c, d, b);
    return ((o1 > 0.0 && o2 < 0.0) || (o1 < 0.0 && o2 > 0.0)) &&
           ((o3 > 0.0 && o4 < 0.0) || (o3 < 0.0 && o4 > 0.0));
}

/* Is p inside the corner b of the counter-clockwise ring (a, b, c): left of
 * both edges at a convex corner, of either at a reflex one? */
static int in_corner(const double *a, const double *b, const double *c, const double *p)
{
    if (orient2(a, b, c) >= 0.0)
        return orient2(a, b, p) >= 0.0 && orient2(b, c, p) >= 0.0;
    return orient2(a, b, p) >= 0.0 || orient2(b, c, p) >= 0.0;
}

/* Step 5: every hole inside the outer contour and outside the others, no two
 * contours crossing; first[c] .. first[c + 1] - 1 are contour c's corners. */
static rad_status check_contours(const rad_scene *s, const double *uv, const int *first,
                                 int ncontours, int face, int line, long long *tests)
{
    int all = first[ncontours];
    int *ids = malloc((size_t)all * sizeof *ids);
    if (!ids)
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory for a polygon of %d corners", s->source, all);
    for (int k = 0; k < all; k++)
        ids[k] = k;
    const char *why = NULL;
    for (int h = 1; h < ncontours && !why; h++) {
        int inside = 0; /* points strictly inside the outer contour */
        for (int k = first[h]; k < first[h + 1] && !why; k++) {
            /* the corner and the middle of the edge that leaves it */
            int k2 = k + 1 < first[h + 1] ? k + 1 : first[h];
            double mid[2] = {0.5 * (uv[2 * k] + uv[2 * k2]), 0.5 * (uv[2 * k + 1] + uv[2 * k2 + 1])};
            for (int q = 0; q < 2 && !why; q++) {
                const double *p = q ? mid : uv + 2 * k;
                *tests += all;
                int where = classify(p, uv, ids, first[1]);
                inside += where > 0;
                if (where < 0)
                    why = "has a hole that is not inside its outer contour";
                for (int o = 1; o < ncontours && !why; o++)
                    if (o != h && classify(p, uv, ids + first[o], first[o + 1] - first[o]) > 0)
                        why = "has a hole inside another hole";
            }
            if (*tests > POLYGON_MAX_TESTS)
                why = "has too many corners to check its holes here; split it before import";
        }
        if (!why && !inside) /* all on the outer boundary: it would cut the face away */
            why = "has a hole that is not inside its outer contour";
    }
    for (int c = 0; c < ncontours && !why; c++)
        for (int i = first[c]; i < first[c + 1] && !why; i++) {
            int i2 = i + 1 < first[c + 1] ? i + 1 : first[c];
            for (int j = first[c + 1]; j < all && !why; j++) {
                int c2 = c + 1;
                while (first[c2 + 1] <= j)
                    c2++;
                int j2 = j + 1 < first[c2 + 1] ? j + 1 : first[c2];
                if (cross_properly(uv + 2 * i, uv + 2 * i2, uv + 2 * j, uv + 2 * j2))
                    why = "has contours that cross each other";
            }
            if ((*tests += all) > POLYGON_MAX_TESTS && !why)
                why = "has too many corners to check its holes here; split it before import";
        }
    free(ids);
    return why ? face_error(s, face, line, why) : RAD_OK;
}

/* Step 6: join hole corners uv ids hole[0..nh-1] (clockwise) to the ring
 * ring[0..*n-1] (room for nh + 2 more) by a bridge from its rightmost corner. */
static void bridge_hole(const double *uv, int *ring, int *n, const int *hole, int nh,
                        long long *tests)
{
    int m = 0;
    for (int k = 1; k < nh; k++)
        if (uv[2 * hole[k]] > uv[2 * hole[m]])
            m = k;
    const double *M = uv + 2 * hole[m];
    /* the nearest edge the ray M + t (1, 0) leaves the ring through: one that
     * runs upwards (the ring winds counter-clockwise, so its inside is on the
     * left) */
    int e = -1;
    double xe = 0.0;
    for (int i = 0; i < *n; i++) {
        const double *a = uv + 2 * ring[i], *b = uv + 2 * ring[(i + 1) % *n];
        if (!(a[1] <= M[1] && M[1] <= b[1] && a[1] < b[1]))
            continue;
        double x = b[1] == M[1] ? b[0]
                   : a[1] == M[1] ? a[0]
                                  : a[0] + (M[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
        if (x >= M[0] && (e < 0 || x < xe)) {
            e = i;
            xe = x;
        }
    }
    *tests += *n;
    int p = 0;
    if (e >= 0) {
        int e2 = (e + 1) % *n;
        const double *a = uv + 2 * ring[e], *b = uv + 2 * ring[e2];
        p = b[1] == M[1] ? e2 : a[1] == M[1] ? e : a[0] > b[0] ? e : e2;
        const double *P = uv + 2 * ring[p], I[2] = {xe, M[1]};
        if (!(P[0] == I[0] && P[1] == I[1])) {
            /* A corner of the ring inside the triangle M I P hides P: take the
             * one nearest the ray in angle, then in distance, whose corner
             * (for a corner repeated by an earlier bridge) opens towards M. */
            double best_du = P[0] - M[0], best_dv = fabs(P[1] - M[1]);
            const double *t0 = M, *t1 = I, *t2 = P;
            if (orient2(t0, t1, t2) < 0.0) {
                t1 = P;
                t2 = I;
            }
            for (int j = 0; j < *n; j++) {
                const double *R = uv + 2 * ring[j];
                if (j == p || !in_triangle(R, t0, t1, t2, 1))
                    continue;
                double du = R[0] - M[0], dv = fabs(R[1] - M[1]);
                double lhs = dv * best_du, rhs = best_dv * du;
                if (lhs > rhs || (lhs == rhs && du * du + dv * dv >= best_du * best_du + best_dv * best_dv))
                    continue;
                if (!in_corner(uv + 2 * ring[(j + *n - 1) % *n], R, uv + 2 * ring[(j + 1) % *n], M))
                    continue;
                p = j;
                best_du = du;
                best_dv = dv;
            }
            *tests += *n;
        }
    }
    /* ring[0..p], M, the hole around to M again, ring[p], ring[p+1..] */
    int tail = *n - (p + 1);
    memmove(ring + p + 1 + nh + 2, ring + p + 1, (size_t)tail * sizeof *ring);
    for (int k = 0; k <= nh; k++)
        ring[p + 1 + k] = hole[(m + k) % nh];
    ring[p + 2 + nh] = ring[p];
    *n += nh + 2;
}

rad_status scene_add_polygon_holes(rad_scene *s, const int *idx, const int *count, int ncontours,
                                   int mat, int face, int line)
{
    if (ncontours < 1)
        return face_error(s, face, line, "has no contour");
    if (ncontours == 1)
        return scene_add_polygon(s, idx, count[0], mat, face, line);
    int all = 0;
    for (int c = 0; c < ncontours; c++) {
        if (count[c] < 3)
            return face_error(s, face, line, c ? "has a hole of fewer than 3 corners"
                                               : "needs at least 3 corners");
        all += count[c];
    }
    for (int k = 0; k < all; k++)
        if (idx[k] < 0 || idx[k] >= s->nv)
            return face_error(s, face, line, "has a corner index out of range");
    /* the outer contour's vector area (step 1) */
    rad_vec3 o = vertex(s, idx[0]), N = rad_vec3_make(0, 0, 0);
    for (int k = 2; k < count[0]; k++)
        N = rad_vec3_add(N, rad_vec3_cross(rad_vec3_sub(vertex(s, idx[k - 1]), o),
                                           rad_vec3_sub(vertex(s, idx[k]), o)));
    if (!(rad_vec3_norm(N) > 0.0))
        return face_error(s, face, line, "has an outer contour without area");
    int iu, iv;
    plane_axes(N, &iu, &iv);
    rad_status st = RAD_OK;
    size_t cap = (size_t)all + 2 * (size_t)ncontours;
    double *uv = malloc(2 * (size_t)all * sizeof *uv);
    int *first = malloc(((size_t)ncontours + 1) * sizeof *first);
    int *ring = malloc(cap * sizeof *ring), *hole = malloc((size_t)all * sizeof *hole);
    int *order = malloc((size_t)ncontours * sizeof *order), *vring = malloc(cap * sizeof *vring);
    if (!uv || !first || !ring || !hole || !order || !vring) {
        st = RAD_ERROR(RAD_ENOMEM, "%s: no memory for a polygon of %d corners", s->source, all);
        goto done;
    }
    first[0] = 0;
    for (int c = 0; c < ncontours; c++)
        first[c + 1] = first[c] + count[c];
    for (int k = 0; k < all; k++) {
        const double *p = s->xyz + 3 * (size_t)idx[k];
        uv[2 * k] = p[iu];
        uv[2 * k + 1] = p[iv];
    }
    long long tests = 0;
    if ((st = check_contours(s, uv, first, ncontours, face, line, &tests)) != RAD_OK)
        goto done;
    /* holes from the rightmost, each joined to the ring made so far */
    int n = count[0];
    for (int k = 0; k < n; k++)
        ring[k] = k;
    for (int h = 1; h < ncontours; h++)
        order[h - 1] = h;
    for (int a = 0; a < ncontours - 1; a++) {
        double best = -INFINITY;
        int b = a;
        for (int c = a; c < ncontours - 1; c++)
            for (int k = first[order[c]]; k < first[order[c] + 1]; k++)
                if (uv[2 * k] > best) {
                    best = uv[2 * k];
                    b = c;
                }
        int h = order[b];
        order[b] = order[a];
        order[a] = h;
        /* clockwise: reversed when its signed area is positive */
        int nh = count[h];
        double area = 0.0;
        for (int k = 0; k < nh; k++) {
            const double *p = uv + 2 * (first[h] + k), *q = uv + 2 * (first[h] + (k + 1) % nh);
            area += p[0] * q[1] - q[0] * p[1];
        }
        for (int k = 0; k < nh; k++)
            hole[k] = area > 0.0 ? first[h] + nh - 1 - k : first[h] + k;
        bridge_hole(uv, ring, &n, hole, nh, &tests);
        if (tests > POLYGON_MAX_TESTS) {
            st = face_error(s, face, line, "has too many holes to join here; split it before import");
            goto done;
        }
    }
    for (int k = 0; k < n; k++)
        vring[k] = idx[ring[k]];
    st = ear_clip(s, vring, n, N, mat, face, line);
done:
    free(uv);
    free(first);
    free(ring);
    free(hole);
    free(order);
    free(vring);
    return st;
}
