/* scene_add_polygon: convex polygons keep the fan in input order; non-convex
 * simple polygons are ear-clipped into triangles that cover exactly the
 * polygon's area (the shoelace formula, worked independently) and all face the
 * polygon's way; degenerate and self-intersecting input ends. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "scene_internal.h"

/* A scene holding the 2D points (x, y) placed in the plane through `o`
 * spanned by unit vectors e1, e2 (so the polygons are tilted in 3D). */
static rad_scene *planar_scene(const double (*xy)[2], int n, const double o[3], const double e1[3],
                               const double e2[3])
{
    rad_scene *s = scene_new("polygon-test");
    for (int k = 0; k < n; k++)
        CHECK(scene_add_vertex(s, o[0] + xy[k][0] * e1[0] + xy[k][1] * e2[0],
                               o[1] + xy[k][0] * e1[1] + xy[k][1] * e2[1],
                               o[2] + xy[k][0] * e1[2] + xy[k][1] * e2[2]) == RAD_OK);
    return s;
}

static const double O[3] = {0.3, -1.7, 2.385};
/* An orthonormal pair tilted off every axis; e1 x e2 has a dominant -z part
 * for E2B below, so the projection's orientation swap is exercised too. */
static const double E1[3] = {0.8, 0.6, 0.0};
static const double E2[3] = {-0.36, 0.48, 0.8};
static const double E2B[3] = {0.36, -0.48, -0.8};

static double shoelace(const double (*xy)[2], int n)
{
    double a = 0.0;
    for (int k = 0; k < n; k++)
        a += xy[k][0] * xy[(k + 1) % n][1] - xy[(k + 1) % n][0] * xy[k][1];
    return 0.5 * a;
}

/* Sum of the triangles' areas, and whether every one faces along `n`. */
static double triangles_area(const rad_scene *s, const double n[3], int *all_facing)
{
    double area = 0.0;
    *all_facing = 1;
    for (int t = 0; t < s->nt; t++) {
        const double *a = s->xyz + 3 * s->tri[3 * t], *b = s->xyz + 3 * s->tri[3 * t + 1],
                     *c = s->xyz + 3 * s->tri[3 * t + 2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double x[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        double d = x[0] * n[0] + x[1] * n[1] + x[2] * n[2];
        if (!(d > 0.0))
            *all_facing = 0;
        area += 0.5 * sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
    }
    return area;
}

static void check_polygon(const double (*xy)[2], int n, const double e2[3], const char *what)
{
    rad_scene *s = planar_scene(xy, n, O, E1, e2);
    int idx[64];
    for (int k = 0; k < n; k++)
        idx[k] = k;
    rad_status st = scene_add_polygon(s, idx, n, 0, 7, 42);
    CHECK_MSG(st == RAD_OK, "%s: %s", what, rad_error_message());
    CHECK_MSG(s->nt == n - 2, "%s: %d triangles, want %d", what, s->nt, n - 2);
    double normal[3] = {E1[1] * e2[2] - E1[2] * e2[1], E1[2] * e2[0] - E1[0] * e2[2],
                        E1[0] * e2[1] - E1[1] * e2[0]};
    double want = shoelace(xy, n);
    if (want < 0) {
        want = -want;
        for (int k = 0; k < 3; k++)
            normal[k] = -normal[k];
    }
    int facing = 0;
    CHECK_NEAR(triangles_area(s, normal, &facing), want, 1e-13, 0.0);
    CHECK_MSG(facing, "%s: a triangle faces against the polygon", what);
    for (int t = 0; t < s->nt; t++)
        CHECK(s->tri_face[t] == 7 && s->tri_line[t] == 42 && s->tri_mat[t] == 0);
    rad_scene_destroy(s);
}

TEST(polygon_convex_keeps_the_fan_in_order)
{
    static const double quad[4][2] = {{0, 0}, {2.385, 0.1}, {2.2, 1.3}, {-0.2, 1.1}};
    rad_scene *s = planar_scene(quad, 4, O, E1, E2);
    int idx[4] = {2, 3, 0, 1};
    CHECK(scene_add_polygon(s, idx, 4, 0, 0, 0) == RAD_OK);
    CHECK(s->nt == 2);
    int want[6] = {2, 3, 0, 2, 0, 1};
    CHECK(s->nt == 2 && memcmp(s->tri, want, sizeof want) == 0);
    rad_scene_destroy(s);
    /* A regular 11-gon: fan order, 9 triangles. */
    double ring[11][2];
    for (int k = 0; k < 11; k++) {
        ring[k][0] = 1.7 * cos(2 * RAD_PI * k / 11);
        ring[k][1] = 1.7 * sin(2 * RAD_PI * k / 11);
    }
    s = planar_scene((const double(*)[2])ring, 11, O, E1, E2);
    int id11[11];
    for (int k = 0; k < 11; k++)
        id11[k] = k;
    CHECK(scene_add_polygon(s, id11, 11, 0, 0, 0) == RAD_OK);
    CHECK(s->nt == 9);
    for (int t = 0; t < s->nt; t++)
        CHECK(s->tri[3 * t] == 0 && s->tri[3 * t + 1] == t + 1 && s->tri[3 * t + 2] == t + 2);
    rad_scene_destroy(s);
    check_polygon((const double(*)[2])ring, 11, E2, "11-gon");
}

TEST(polygon_non_convex_is_ear_clipped)
{
    /* An L whose fan from corner 0 folds (corner 0 sees the notch from outside). */
    static const double ell[6][2] = {{2, 1}, {1, 1}, {1, 3}, {0, 3}, {0, 0}, {2, 0}};
    check_polygon(ell, 6, E2, "L");
    check_polygon(ell, 6, E2B, "L, plane facing down");
    /* The same L wound clockwise. */
    static const double ell_cw[6][2] = {{2, 1}, {2, 0}, {0, 0}, {0, 3}, {1, 3}, {1, 1}};
    check_polygon(ell_cw, 6, E2, "L clockwise");
    /* A five-pointed star (10 corners, inner radius 0.4), starting at an inner corner. */
    double star[10][2];
    for (int k = 0; k < 10; k++) {
        double r = k % 2 ? 1.3 : 0.4, a = 2 * RAD_PI * k / 10 + 0.1;
        star[k][0] = r * cos(a);
        star[k][1] = r * sin(a);
    }
    check_polygon((const double(*)[2])star, 10, E2, "star");
    /* A comb: a spine with four teeth, 19 corners, the last one on the straight
     * left edge (a corner at 180 degrees). */
    double comb[20][2];
    int m = 0;
    comb[m][0] = 0, comb[m++][1] = 0;
    comb[m][0] = 8, comb[m++][1] = 0;
    for (int t = 3; t >= 0; t--) {
        comb[m][0] = 2 * t + 2, comb[m++][1] = 3.5;
        comb[m][0] = 2 * t + 1.2, comb[m++][1] = 3.5;
        comb[m][0] = 2 * t + 1.2, comb[m++][1] = 0.7;
        comb[m][0] = 2 * t + 0.6, comb[m++][1] = 0.7;
    }
    comb[m - 1][0] = 0, comb[m - 1][1] = 0.7;
    comb[m][0] = 0, comb[m++][1] = 0.35;
    check_polygon((const double(*)[2])comb, m, E2, "comb");
}

TEST(polygon_degenerate_input_ends)
{
    static const double pts[6][2] = {{0, 0}, {1, 0}, {2, 0}, {3, 0}, {1, 1}, {0, 1}};
    rad_scene *s = planar_scene(pts, 6, O, E1, E2);
    int two[2] = {0, 1};
    CHECK(scene_add_polygon(s, two, 2, 0, 5, 9) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "polygon-test:9: face 5") != NULL);
    int bad[3] = {0, 1, 6};
    CHECK(scene_add_polygon(s, bad, 3, 0, 5, 0) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "out of range") != NULL);
    /* All corners on one line: the fan, whose zero-area triangles are left to
     * scene_finish's degeneracy check. */
    int line4[4] = {0, 1, 2, 3};
    CHECK(scene_add_polygon(s, line4, 4, 0, 1, 0) == RAD_OK && s->nt == 2);
    /* A square with a repeated corner: still convex, the fan as given. */
    int rep[5] = {0, 1, 1, 4, 5};
    int nt = s->nt;
    CHECK(scene_add_polygon(s, rep, 5, 0, 2, 0) == RAD_OK && s->nt == nt + 3);
    /* A figure eight (bow tie, equal lobes): refused, not looped over. */
    static const double bow[4][2] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
    rad_scene *b = planar_scene(bow, 4, O, E1, E2);
    int id4[4] = {0, 1, 2, 3};
    CHECK(scene_add_polygon(b, id4, 4, 0, 3, 11) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "self-intersecting") != NULL);
    rad_scene_destroy(b);
    /* A pentagram (self-intersecting, all turns alike): ends either way. */
    double pg[5][2];
    for (int k = 0; k < 5; k++) {
        double a = 2 * RAD_PI * (2 * k % 5) / 5;
        pg[k][0] = cos(a);
        pg[k][1] = sin(a);
    }
    rad_scene *p = planar_scene((const double(*)[2])pg, 5, O, E1, E2);
    int id5[5] = {0, 1, 2, 3, 4};
    rad_status st = scene_add_polygon(p, id5, 5, 0, 4, 0);
    CHECK(st == RAD_OK || st == RAD_EINPUT);
    rad_scene_destroy(p);
    /* A non-convex polygon with a repeated corner and a doubled-back spike. */
    static const double spike[8][2] = {{2, 1}, {1, 1}, {1, 1}, {1, 3}, {0, 3}, {0, 0}, {2, 0}, {2, 0}};
    rad_scene *q = planar_scene(spike, 8, O, E1, E2);
    int id8[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    st = scene_add_polygon(q, id8, 8, 0, 4, 0);
    CHECK_MSG(st == RAD_OK, "%s", rad_error_message());
    CHECK(q->nt == 4);
    rad_scene_destroy(q);
    rad_scene_destroy(s);
}
