/* radkit solve --method hier end to end: the furnace cube's exact answer
 * through the CLI, the table's shape and '#' lines, and bad options. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

/* Furnace cube (rho 0.375, E 2.385): B = 3.816.  --eps 1e-9 refines every
 * link until min_area stops it; --min-area 0.19 lets each face triangle
 * (area 0.78125) split exactly once (children 0.195 >= 0.19, grandchildren
 * 0.049 < 0.19), so every link joins leaves and, with the exact rule, every
 * row sums to 1 to ~1e-13 (see test_hier.c): 1e-6 is the brief's tolerance,
 * with a wide margin. */
TEST(hier_cli_furnace_cube)
{
    char *out = NULL, *err = NULL, buf[64];
    CHECK(harness_radkit_run("solve", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"),
                             "--method", "hier", "--eps", "1e-9", "--min-area", "0.19",
                             "--rule", "exact", "--quiet", NULL}, &out, &err) == 0);
    if (!out)
        return;
    double B[3 * 12];
    CHECK(harness_face_table(out, B, 12) == 12);
    for (int k = 0; k < 36; k++)
        CHECK_NEAR(B[k], 2.385 / (1.0 - 0.375), 1e-6, 0.0);
    CHECK(harness_header(out, "method", buf, sizeof buf) && strcmp(buf, "hier") == 0);
    CHECK(harness_header(out, "elements", buf, sizeof buf) && atoi(buf) == 48);
    CHECK(harness_header(out, "links", buf, sizeof buf) && atoi(buf) > 0);
    CHECK(harness_header(out, "iterations", buf, sizeof buf) && atoi(buf) > 0);
    free(out);
    free(err);
}

TEST(hier_cli_rejects_bad_options)
{
    const char *cube = harness_path("scenes/furnace_cube/cube.obj");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--eps", "0", NULL}, "--eps");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--eps", "-1", NULL}, "--eps");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--eps", "x", NULL}, "--eps");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--min-area", "-1", NULL}, "--min-area");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--eps", "1e-3", NULL}, "--method hier");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--png", "x.png", NULL}, "--png");
}

/* Until hierarchical visibility agrees with dense on the Cornell box, hier
 * refuses occluded scenes (exit 2, naming the reason) instead of answering
 * 5% dark; --occlusion off is the explicit way to solve without visibility. */
TEST(cli_hier_refuses_occluded_scenes)
{
    const char *cornell = harness_path("scenes/cornell/cornell.obj");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cornell, "--method", "hier", NULL}, "occlusion");
    char *out, *err;
    CHECK(harness_radkit_run("solve", (const char *[]){cornell, "--method", "hier", "--eps", "1e-2",
                                                       "--occlusion", "off", "--quiet", NULL},
                             &out, &err) == 0);
    CHECK(strstr(out, "\nface\tarea\tB_r\tB_g\tB_b\n") != NULL);
    free(out);
    free(err);
}
