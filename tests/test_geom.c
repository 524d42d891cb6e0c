/* Triangle basics against hand values. */
#include "harness.h"
#include "rad_geom.h"

#include <float.h>
#include <stdint.h>
#include <stdio.h>

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

/* rad_geom_angle against libm's atan2 (correctly rounded) within 2 ulp: the
 * whole half-plane s >= 0 at random angles and magnitudes, both sides of each
 * of the arctangent's reduction boundaries (tan of the angle 0.4375, 0.6875,
 * 1.1875, 2.4375), the axes and a NaN. */
TEST(geom_angle_matches_atan2_within_two_ulp)
{
    double worst = 0.0;
    uint64_t state = 12345;
    for (int k = 0; k < 200000; k++) {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        double u = (double)(state >> 11) * 0x1.0p-53;
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        double v = (double)(state >> 11) * 0x1.0p-53;
        double theta = u * RAD_PI, r = pow(10.0, 600.0 * v - 300.0);
        double s = fabs(r * sin(theta)), c = r * cos(theta);
        double want = atan2(s, c), got = rad_geom_angle(s, c);
        worst = fmax(worst, fabs(got - want) / (DBL_EPSILON * fmax(want, DBL_MIN)));
    }
    const double edges[4] = {0.4375, 0.6875, 1.1875, 2.4375};
    for (int e = 0; e < 4; e++)
        for (int k = -4; k <= 4; k++) {
            double t = edges[e] + k * DBL_EPSILON * edges[e];
            for (int side = 0; side < 2; side++) {
                double c = side ? -1.0 : 1.0, want = atan2(t, c), got = rad_geom_angle(t, c);
                worst = fmax(worst, fabs(got - want) / (DBL_EPSILON * want));
            }
        }
    CHECK_MSG(worst <= 2.0, "largest difference %.3g ulp", worst);
    CHECK(rad_geom_angle(0.0, 1.0) == 0.0 && rad_geom_angle(0.0, -2.0) == atan2(0.0, -2.0));
    CHECK(rad_geom_angle(3.0, 0.0) == atan2(3.0, 0.0) && rad_geom_angle(0.0, 0.0) == 0.0);
    CHECK(rad_geom_angle(1e300, 1e-300) == atan2(1e300, 1e-300));
    CHECK(isnan(rad_geom_angle(NAN, 1.0)) && isnan(rad_geom_angle(1.0, NAN)));
    printf("# rad_geom_angle against atan2: largest difference %.2f ulp\n", worst);
}
