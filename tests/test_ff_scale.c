/* rad_ff and rad_geom at the extremes of scale and separation: decisions
 * (degenerate, coplanar, coincident) are relative to the triangles' own size
 * and rounding, never absolute, so a pair scaled by 1e-100 gives the same F,
 * and facing triangles a tiny gap apart give F near its limit (1 for identical
 * triangles) instead of jumping to 0.  A pair that coincides within rounding
 * with opposite normals is flagged (the CLI refuses it). */
#include "harness.h"

#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_error.h"
#include "rad_ff.h"
#include "rad_geom.h"

#define V(x, y, z) rad_vec3_make(x, y, z)

/* A well-shaped triangle of size about 2 in the plane z = 0.1, normal +z, and
 * its mirror (same corners, opposite winding) lifted by gap: the two face
 * each other. */
static void facing_pair(double gap, double scale, rad_vec3 a[3], rad_vec3 b[3])
{
    const double base[3][3] = {{0.3, -0.2, 0.1}, {2.685, -0.1, 0.1}, {0.7, 1.5, 0.1}};
    for (int v = 0; v < 3; v++) {
        a[v] = V(base[v][0] * scale, base[v][1] * scale, base[v][2] * scale);
        int w = v == 0 ? 0 : 3 - v; /* reversed winding */
        b[v] = V(base[w][0] * scale, base[w][1] * scale, (base[w][2] + gap) * scale);
    }
}

static rad_status ff_rule(const rad_vec3 a[3], const rad_vec3 b[3], const char *rule,
                          rad_ff_result *r)
{
    rad_ff_rule rr;
    rad_ff_rule_parse(rule, &rr);
    return rad_ff_compute(a, b, rr, NULL, r);
}

TEST(ff_facing_gap_tends_to_one_continuously)
{
    /* gaps relative to the longest edge (about 2.4) */
    const double gaps[] = {1e-3, 1e-6, 1e-9, 1e-11, 1e-12, 1e-13};
    const char *rules[] = {"exact", "auto"};
    for (int r = 0; r < 2; r++) {
        double prev = 0.0;
        for (size_t k = 0; k < sizeof gaps / sizeof gaps[0]; k++) {
            rad_vec3 a[3], b[3];
            facing_pair(gaps[k] * 2.4, 1.0, a, b);
            rad_ff_result res;
            CHECK(ff_rule(a, b, rules[r], &res) == RAD_OK);
            CHECK_MSG(!(res.flags & RAD_FF_FLAG_NOT_FACING), "%s gap %g: not facing", rules[r],
                      gaps[k]);
            CHECK_MSG(res.F12 > prev && res.F12 <= 1.0 + 1e-12, "%s gap %g: F12 %.17g after %.17g",
                      rules[r], gaps[k], res.F12, prev);
            /* 1 - F is about perimeter x gap / (pi area) log-corrected: below 10 gaps */
            CHECK_MSG(1.0 - res.F12 < 10.0 * gaps[k] * 2.4 + 1e-12, "%s gap %g: F12 %.17g",
                      rules[r], gaps[k], res.F12);
            prev = res.F12;
        }
    }
}

TEST(ff_coincident_pair_is_flagged_not_silent)
{
    rad_vec3 a[3], b[3];
    rad_ff_result res;
    /* the same corners, opposite windings, gap 0 and within rounding */
    const double gaps[] = {0.0, 1e-17, -1e-17};
    for (int k = 0; k < 3; k++) {
        facing_pair(gaps[k], 1.0, a, b);
        CHECK(ff_rule(a, b, "exact", &res) == RAD_OK);
        CHECK_MSG(res.flags & RAD_FF_FLAG_COINCIDENT, "gap %g: flags %u", gaps[k], res.flags);
        CHECK(res.F12 == 0.0);
    }
    /* the same plane and orientation (one triangle twice): 0, not coincident */
    facing_pair(0.0, 1.0, a, b);
    CHECK(ff_rule(a, a, "exact", &res) == RAD_OK);
    CHECK(res.F12 == 0.0 && (res.flags & RAD_FF_FLAG_NOT_FACING) &&
          !(res.flags & RAD_FF_FLAG_COINCIDENT));
    /* opposite windings side by side in one plane: no overlap, F = 0 is the limit */
    for (int v = 0; v < 3; v++)
        b[v].x += 5.0;
    CHECK(ff_rule(a, b, "exact", &res) == RAD_OK);
    CHECK(res.F12 == 0.0 && !(res.flags & RAD_FF_FLAG_COINCIDENT));
}

TEST(ff_pairs_are_scale_invariant_or_refused)
{
    rad_vec3 a[3], b[3];
    rad_ff_result ref, res;
    facing_pair(0.37, 1.0, a, b);
    CHECK(ff_rule(a, b, "exact", &ref) == RAD_OK);
    CHECK(ref.F12 > 0.1);
    const double scales[] = {1e-100, 1e-140, 1e-60, 1e50};
    for (size_t k = 0; k < sizeof scales / sizeof scales[0]; k++) {
        double s = scales[k];
        facing_pair(0.37, s, a, b);
        CHECK_MSG(!rad_geom_triangle_is_degenerate(a[0], a[1], a[2], 1e-12), "scale %g: degenerate",
                  s);
        rad_status st = ff_rule(a, b, "exact", &res);
        CHECK_MSG(st == RAD_OK, "scale %g: %s", s, rad_error_message());
        CHECK_NEAR(res.F12, ref.F12, 1e-12, 0.0);
        CHECK_NEAR(res.F21, ref.F21, 1e-12, 0.0);
        CHECK_NEAR(res.A1, ref.A1 * s * s, 1e-12, 0.0);
        CHECK_NEAR(res.G, ref.G * s * s, 1e-12, 0.0);
        CHECK(ff_rule(a, b, "auto", &res) == RAD_OK);
        CHECK_NEAR(res.F12, ref.F12, 1e-6, 0.0);
    }
    /* at 1e-160 the areas (1e-320) leave double precision's normal range:
       refused, naming the reason */
    facing_pair(0.37, 1e-160, a, b);
    CHECK(!rad_geom_triangle_is_degenerate(a[0], a[1], a[2], 1e-12));
    CHECK(ff_rule(a, b, "exact", &res) == RAD_EINPUT);
    CHECK_MSG(strstr(rad_error_message(), "scale the pair up") != NULL, "message: %s",
              rad_error_message());
}

TEST(geom_tiny_triangles_keep_their_shape)
{
    const double scales[] = {1e-100, 1e-160, 1e-200, 1e60};
    for (size_t k = 0; k < sizeof scales / sizeof scales[0]; k++) {
        double s = scales[k];
        rad_vec3 a = V(0.3 * s, -0.2 * s, 0.1 * s), b = V(2.685 * s, -0.1 * s, 0.1 * s),
                 c = V(0.7 * s, 1.5 * s, 0.1 * s);
        CHECK_MSG(!rad_geom_triangle_is_degenerate(a, b, c, 1e-12), "scale %g: degenerate", s);
        rad_vec3 n = rad_geom_triangle_normal(a, b, c);
        CHECK_NEAR(n.z, 1.0, 1e-15, 0.0);
        rad_vec3 t[3] = {a, b, c};
        CHECK_NEAR(rad_geom_triangle_longest_edge(t) / s, sqrt(1.985 * 1.985 + 1.6 * 1.6), 1e-15,
                   0.0); /* the edge b -> c */
        if (s >= 1e-150) /* the area itself is representable */
            CHECK_NEAR(rad_geom_triangle_area(a, b, c) / (s * s),
                       0.5 * (2.385 * 1.7 - 0.1 * 0.4), 1e-14, 0.0);
        /* a sliver stays degenerate at every scale */
        rad_vec3 d = V(1.0 * s, 1e-14 * s, 0.0);
        CHECK(rad_geom_triangle_is_degenerate(V(0, 0, 0), V(2.0 * s, 0, 0), d, 1e-12));
    }
}

TEST(cli_ff_coincident_pair_is_refused_and_tiny_pairs_work)
{
    HARNESS_EXPECT_USAGE_ERROR("ff", (const char *[]){"--tri", "0 0 0 1 0 0 0 1 0", "--tri",
                                                     "0 0 0 0 1 0 1 0 0", NULL},
                               "coincide");
    char *out1, *err1, *out2, *err2;
    const char *unit[] = {"--tri", "0 0 0 1 0 0 0 1 0", "--tri", "0 0 0.5 0 1 0.5 1 0 0.5", NULL};
    const char *tiny[] = {"--tri", "0 0 0 1e-100 0 0 0 1e-100 0", "--tri",
                          "0 0 0.5e-100 0 1e-100 0.5e-100 1e-100 0 0.5e-100", NULL};
    CHECK(harness_radkit_run("ff", unit, &out1, &err1) == 0);
    CHECK_MSG(harness_radkit_run("ff", tiny, &out2, &err2) == 0, "%s", err2);
    const char *r1 = strstr(out1, "\nexact\t"), *r2 = strstr(out2, "\nexact\t");
    CHECK(r1 && r2);
    if (r1 && r2)
        CHECK_NEAR(strtod(r2 + 7, NULL), strtod(r1 + 7, NULL), 1e-12, 0.0);
    free(out1);
    free(err1);
    free(out2);
    free(err2);
}

/* A whole scene scaled by 1e-100: dense and hier (double precision
 * throughout) give the same radiosities; Monte Carlo traces rays in Embree's
 * single precision, where such coordinates vanish: refused, not wrong. */
TEST(solve_tiny_scene_is_scale_invariant_or_refused)
{
    const char *scene = harness_path("scenes/tetrahedron/tetrahedron.obj");
    const char *methods[2] = {"dense", "hier"};
    for (int m = 0; m < 2; m++) {
        const char *unit[] = {scene, "--method", methods[m], "--quiet", NULL};
        const char *tiny[] = {scene, "--method", methods[m], "--quiet", "--scale", "1e-100", NULL};
        char *o1, *e1, *o2, *e2;
        CHECK(harness_radkit_run("solve", unit, &o1, &e1) == 0);
        CHECK_MSG(harness_radkit_run("solve", tiny, &o2, &e2) == 0, "%s: %s", methods[m], e2);
        double B1[12], B2[12];
        CHECK(harness_face_table(o1, B1, 4) == 4 && harness_face_table(o2, B2, 4) == 4);
        for (int k = 0; k < 12; k++)
            CHECK_NEAR(B2[k], B1[k], 1e-9, 0.0);
        free(o1);
        free(e1);
        free(o2);
        free(e2);
    }
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--method", "mc", "--scale",
                                                        "1e-100", NULL},
                               "single precision");
}

/* Scaling a scene by a power of two scales every coordinate exactly, so
 * whatever depends on the size alone (tolerances, minimum areas, contact
 * reaches, shaft planes) must come out the same and the table must not move
 * at all: any absolute length left in hier, its contact cut, its clipping or
 * cluster's rays would show here.  (A decimal scale rounds every coordinate
 * differently, which may flip a refinement decision sitting on its
 * threshold; that is no test of the units.) */
TEST(hier_and_cluster_are_scale_invariant_at_powers_of_two)
{
    const char *scene = harness_path("scenes/cornell/cornell.obj");
    /* method options; cluster takes no --basis */
    const char *methods[3][4] = {{"--method", "hier", NULL},
                                 {"--method", "hier", "--basis", "p1"},
                                 {"--method", "cluster", NULL}};
    const char *scales[3] = {NULL, "1048576", "9.5367431640625e-07"}; /* 1, 2^20, 2^-20 */
    enum { N = 38 };
    for (int m = 0; m < 3; m++) {
        double B[3][3 * N];
        for (int s = 0; s < 3; s++) {
            const char *argv[10] = {scene, "--quiet"};
            int n = 2;
            for (int k = 0; k < 4 && methods[m][k]; k++)
                argv[n++] = methods[m][k];
            if (scales[s]) {
                argv[n++] = "--scale";
                argv[n++] = scales[s];
            }
            char *out, *err;
            CHECK_MSG(harness_radkit_run("solve", argv, &out, &err) == 0, "%s", err);
            CHECK(harness_face_table(out, B[s], N) == N);
            free(out);
            free(err);
        }
        for (int s = 1; s < 3; s++) {
            double worst = 0.0;
            for (int k = 0; k < 3 * N; k++)
                worst = fmax(worst, fabs(B[s][k] - B[0][k]) / B[0][k]);
            CHECK_MSG(worst <= 1e-14, "%s %s at scale %s: a face moved by %.3g relative",
                      methods[m][1], methods[m][3] ? methods[m][3] : "", scales[s], worst);
        }
    }
}
