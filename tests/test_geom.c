/* Triangle basics against hand values. */
#include "harness.h"
#include "rad_geom.h"

TEST(geom_triangle_area_normal_centroid)
{
    rad_vec3 a = {0.3, -1.2, 2.385}, b = {2.3, -1.2, 2.385}, c = {0.3, 1.8, 2.385};
    CHECK_NEAR(rad_geom_triangle_area(a, b, c), 3.0, 1e-15, 0.0);
    rad_vec3 n = rad_geom_triangle_normal(a, b, c);
    CHECK_NEAR(n.z, 1.0, 1e-15, 0.0);
    CHECK_NEAR(rad_geom_triangle_normal(a, c, b).z, -1.0, 1e-15, 0.0); /* winding flips it */
    rad_vec3 g = rad_geom_triangle_centroid(a, b, c);
    CHECK_NEAR(g.x, 2.9 / 3.0, 1e-15, 0.0);
    rad_vec3 p = rad_geom_triangle_point(a, b, c, 0.25, 0.5);
    CHECK_NEAR(p.x, 0.8, 1e-15, 0.0);
    CHECK_NEAR(p.y, 0.3, 1e-14, 0.0);
}

TEST(geom_sliver_area_is_accurate)
{
    /* Far from the origin, aspect 1e6: area = 0.5 * 1 * 1e-6. */
    rad_vec3 a = {1e4, 1e4, 1e4}, b = {1e4 + 1.0, 1e4, 1e4}, c = {1e4 + 0.5, 1e4 + 1e-6, 1e4};
    CHECK_NEAR(rad_geom_triangle_area(a, b, c), 0.5e-6, 1e-5, 0.0); /* coordinates carry ~2e-12 */
    CHECK(!rad_geom_triangle_is_degenerate(a, b, c, 1e-12));
}

TEST(geom_degenerate_triangles)
{
    rad_vec3 a = {0, 0, 0}, b = {1, 1, 1}, c = {2, 2, 2}, nan = {NAN, 0, 0};
    CHECK(rad_geom_triangle_is_degenerate(a, b, c, 1e-12));
    CHECK(rad_geom_triangle_is_degenerate(a, a, a, 1e-12));
    CHECK(rad_geom_triangle_is_degenerate(a, b, nan, 1e-12));
    rad_vec3 n = rad_geom_triangle_normal(a, b, c);
    CHECK(n.x == 0.0 && n.y == 0.0 && n.z == 0.0);
}

TEST(geom_normal_follows_winding_whichever_edge_is_longest)
{
    /* The cross product is taken at a different vertex depending on which edge
     * is longest; every choice must give the plain (b-a) x (c-a) direction. */
    rad_vec3 tris[3][3] = {
        {{0, 0, 0}, {5.3, 0, 0}, {2.1, 1.7, 0}},   /* ab longest */
        {{0, 0, 0}, {1.2, 0, 0}, {-2.9, 3.4, 0}},  /* bc longest */
        {{0, 0, 0}, {2.2, 0.4, 0}, {0.3, 4.6, 0}}, /* ca longest */
    };
    for (int k = 0; k < 3; k++) {
        rad_vec3 *t = tris[k];
        rad_vec3 plain = rad_vec3_cross(rad_vec3_sub(t[1], t[0]), rad_vec3_sub(t[2], t[0]));
        rad_vec3 n = rad_geom_triangle_normal(t[0], t[1], t[2]);
        CHECK_MSG(n.z > 0.999 && plain.z > 0.0, "case %d: normal z = %g", k, n.z);
        CHECK_NEAR(rad_geom_triangle_area(t[0], t[1], t[2]), 0.5 * rad_vec3_norm(plain), 1e-14, 0.0);
        rad_vec3 flipped = rad_geom_triangle_normal(t[0], t[2], t[1]);
        CHECK_MSG(flipped.z < -0.999, "case %d flipped: normal z = %g", k, flipped.z);
    }
}
