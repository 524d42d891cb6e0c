/* End to end: radkit solve on the shipped scenes: the furnace identity, rho
 * near 1, every solver agreeing, the outputs, and bad input. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"

/* Closed, convex, uniform rho = 0.375 and E = 2.385: B = E / (1 - rho) = 3.816. */
TEST(cli_solve_furnace_is_exact)
{
    const char *scenes[] = {"scenes/furnace_cube/cube.obj", "scenes/tetrahedron/tetrahedron.obj",
                            "scenes/sphere/sphere_1.obj"};
    for (int s = 0; s < 3; s++) {
        char *out, *err;
        double B[3 * 200];
        CHECK(harness_radkit_run("solve", (const char *[]){harness_path(scenes[s]), "--rule", "exact", "--quiet", NULL}, &out, &err) == 0);
        int rows = harness_face_table(out, B, 200);
        CHECK(rows > 0);
        for (int k = 0; k < 3 * rows; k++)
            CHECK_NEAR(B[k], 2.385 / (1.0 - 0.375), 1e-9, 0.0);
        CHECK(strstr(out, "# effect_occlusion = off") != NULL); /* convex: no rays */
        CHECK(harness_header_number(out, "rays") == 0.0);
        free(out);
        free(err);
    }
}

/* The default rule (auto, tol 1e-6) on the furnace: the row sums are only as
 * good as the tolerance, and so is B. */
TEST(cli_solve_furnace_default_rule)
{
    char *out, *err;
    double B[3 * 100];
    CHECK(harness_radkit_run("solve", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--refine", "1", "--quiet", NULL}, &out, &err) == 0);
    int rows = harness_face_table(out, B, 100);
    CHECK(rows == 12);
    for (int k = 0; k < 3 * rows; k++)
        CHECK_NEAR(B[k], 2.385 / (1.0 - 0.375), 1e-5, 0.0);
    free(out);
    free(err);
}

TEST(cli_solve_rho_near_one_stays_accurate)
{
    const char *rhos[] = {"0.99", "0.999"};
    for (int k = 0; k < 2; k++) {
        char *out, *err;
        double B[3 * 20], rho = atof(rhos[k]);
        CHECK(harness_radkit_run("solve", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--rule", "exact", "--rho", rhos[k],
                                     "--quiet", NULL}, &out, &err) == 0);
        CHECK(harness_face_table(out, B, 20) == 12);
        for (int i = 0; i < 36; i++)
            CHECK_NEAR(B[i], 2.385 / (1.0 - rho), 1e-9, 0.0);
        double rcond = harness_header_number(out, "rcond");
        CHECK_MSG(rcond > 0.0 && rcond < 0.5 * (1.0 - rho) * 10.0, "rcond %g for rho %g", rcond, rho);
        free(out);
        free(err);
    }
}

TEST(cli_solve_every_solver_agrees)
{
    const char *solvers[] = {"lu", "cholesky", "jacobi", "gauss-seidel", "southwell"};
    double ref[3 * 200], B[3 * 200];
    int rows_ref = 0;
    for (int s = 0; s < 5; s++) {
        char *out, *err;
        CHECK(harness_radkit_run("solve", (const char *[]){harness_path("scenes/cornell/cornell.obj"), "--refine", "1", "--rule", "gauss:2",
                                     "--solver", solvers[s], "--solver-tol", "1e-12", "--quiet", NULL},
                    &out, &err) == 0);
        int rows = harness_face_table(out, s ? B : ref, 200);
        if (s == 0)
            rows_ref = rows;
        CHECK(rows == rows_ref && rows == 38);
        for (int k = 0; s && k < 3 * rows; k++)
            CHECK_NEAR(B[k], ref[k], 1e-9, 1e-12);
        free(out);
        free(err);
    }
}

TEST(cli_solve_writes_its_outputs)
{
    char png[] = "/tmp/radkit-test-XXXXXX";
    int fd = mkstemp(png);
    if (fd >= 0)
        close(fd);
    char ply[64], stats[64], tsv[64];
    snprintf(ply, sizeof ply, "%s.ply", png);
    snprintf(stats, sizeof stats, "%s.json", png);
    snprintf(tsv, sizeof tsv, "%s.tsv", png);
    char *out, *err;
    CHECK(harness_radkit_run("solve", (const char *[]){harness_path("scenes/cornell/cornell.obj"), "--png", png, "--ply", ply, "--stats", stats,
                                 "--out", tsv, "--image-size", "64x48", "--quiet", NULL}, &out, &err) == 0);
    CHECK(strcmp(out, "") == 0); /* the table went to --out */
    FILE *f = fopen(png, "rb");
    unsigned char sig[8] = {0};
    CHECK(f && fread(sig, 1, 8, f) == 8 && memcmp(sig, "\x89PNG\r\n\x1a\n", 8) == 0);
    if (f)
        fclose(f);
    f = fopen(stats, "r");
    char json[8192] = {0};
    CHECK(f && fread(json, 1, sizeof json - 1, f) > 0);
    if (f)
        fclose(f);
    const char *keys[] = {"\"method\"", "\"faces\"", "\"elements\"", "\"links\"", "\"rays\"", "\"kernel_evals\"",
                          "\"time_s\"", "\"total\"", "\"memory_peak_bytes\"", "\"effects\"", "\"solver\"",
                          "\"iterations\"", "\"residual\""};
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
        CHECK_MSG(strstr(json, keys[k]) != NULL, "stats JSON lacks %s", keys[k]);
    f = fopen(ply, "r");
    char head[256] = {0};
    CHECK(f && fread(head, 1, sizeof head - 1, f) > 0 && strncmp(head, "ply\n", 4) == 0);
    if (f)
        fclose(f);
    f = fopen(tsv, "r");
    CHECK(f != NULL);
    if (f)
        fclose(f);
    remove(png);
    remove(ply);
    remove(stats);
    remove(tsv);
    free(out);
    free(err);
}

TEST(cli_solve_rejects_bad_input)
{
    const char *cube = harness_path("scenes/furnace_cube/cube.obj");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){NULL}, "scene");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){"/nonexistent/scene.obj", NULL}, "nonexistent");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/bad/nan_vertex.obj"), NULL}, "nan_vertex.obj:");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/bad/zero_area.obj"), "--strict", NULL}, "zero_area.obj:9: degenerate");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/bad/rho_too_big.obj"), NULL}, "rho_too_big");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/bad/negative_emission.obj"), NULL}, "negative");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--rule", "simpson", NULL}, "simpson");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--solver", "magic", NULL}, "magic");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "clustered", NULL}, "clustered");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--refine", "-1", NULL}, "--refine");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--tol", "0", NULL}, "--tol");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--image-size", "0x5", NULL}, "--image-size");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--rho", "1.0", NULL}, "--rho");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, cube, NULL}, "more than one");
    /* Coordinates so large that products of four lengths overflow. */
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--scale", "1e150", NULL}, "scale the scene down");
}

TEST(cli_solve_refuses_what_dense_cannot_hold)
{
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/cornell/cornell.obj"), "--refine", "8", NULL}, "--method hier");
    setenv("RADKIT_MEMORY_LIMIT", "4000000", 1); /* 4 MB: 608 elements need ~6 MB */
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/cornell/cornell.obj"), "--refine", "2", NULL}, "--method hier");
    unsetenv("RADKIT_MEMORY_LIMIT");
}

TEST(cli_solve_help_explains_every_option)
{
    char *out, *err;
    CHECK(harness_radkit_run("solve", (const char *[]){"--help", NULL}, &out, &err) == 0);
    const char *opts[] = {"--method", "--rule", "--tol", "--solver", "--solver-tol", "--max-iter",
                          "--refine", "--threads", "--vis-strata", "--out", "--ply", "--png",
                          "--image-size", "--exposure", "--stats", "--quiet", "--scale",
                          "--drop-degenerate", "--rho", "--emission", "--occlusion", "--colour",
                          "--facing-away", "--singular", "--reflectance", "cholesky", "southwell",
                          "exact", "auto"};
    for (size_t k = 0; k < sizeof opts / sizeof opts[0]; k++)
        CHECK_MSG(strstr(out, opts[k]) != NULL, "solve --help does not mention %s", opts[k]);
    free(out);
    free(err);
}

TEST(cli_solve_warns_when_nothing_emits)
{
    const char *path = harness_write_file("noemit.obj",
                                          "v 0 0 0\nv 1.3 0 0\nv 0 0.7 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\n");
    char *out, *err, buf[256];
    CHECK(harness_radkit_run("solve", (const char *[]){path, NULL}, &out, &err) == 0);
    CHECK_MSG(strstr(err, "radkit: warning: no emitter") != NULL, "stderr: %s", err);
    CHECK(harness_header(out, "warning", buf, sizeof buf) != NULL);
    free(out);
    free(err);
    CHECK(harness_radkit_run("solve", (const char *[]){path, "--quiet", NULL}, &out, &err) == 0);
    CHECK(strcmp(err, "") == 0);
    free(out);
    free(err);
    remove(path);
}
