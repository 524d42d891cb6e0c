/* radkit solve --method mc end to end: the furnace within its standard
 * errors, the table's se columns and '#' lines, a seed reproducing the table
 * for any --threads, the stats JSON, and bad options. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"

/* The rows of a table (after its header row), '#' lines and timing aside. */
static const char *rows_of(const char *out)
{
    const char *p = strstr(out, "\nface\t");
    return p ? p + 1 : "";
}

TEST(mc_cli_furnace_within_standard_errors)
{
    char *out = NULL, *err = NULL, buf[64];
    CHECK(harness_radkit_run("solve", (const char *[]){harness_path("scenes/furnace_room/room_box.obj"),
                             "--method", "mc", "--samples", "2000", "--rho", "0.9", "--quiet", NULL},
                             &out, &err) == 0);
    if (!out)
        return;
    double B[3 * 24], se[3 * 24];
    int rows = harness_face_table_se(out, B, se, 24);
    CHECK(rows == 24);
    if (rows != 24)
        rows = 0;
    double exact = 2.385 / (1.0 - 0.9);
    for (int k = 0; k < 3 * rows; k++) {
        CHECK_MSG(fabs(B[k] - exact) <= 5.0 * se[k], "row %d: B %.5g, se %.3g", k / 3, B[k], se[k]);
        CHECK_MSG(se[k] > 0.0 && se[k] < 0.03 * exact, "row %d: se %.3g", k / 3, se[k]);
    }
    CHECK(harness_header(out, "method", buf, sizeof buf) && strcmp(buf, "mc") == 0);
    /* 2000 rounded up to a multiple of the 32 batches */
    CHECK(harness_header(out, "samples", buf, sizeof buf) && atoll(buf) == 2016);
    CHECK(harness_header(out, "paths", buf, sizeof buf) && atoll(buf) == 2016 * 24);
    CHECK(harness_header(out, "rays", buf, sizeof buf) && atoll(buf) > 2016 * 24);
    CHECK(harness_header(out, "effect_occlusion", buf, sizeof buf) && strcmp(buf, "on") == 0);
    CHECK(harness_header(out, "se_rel_l1", buf, sizeof buf) && atof(buf) > 0.003 && atof(buf) < 0.03);
    free(out);
    free(err);
}

TEST(mc_cli_seed_reproduces_for_any_thread_count)
{
    const char *cornell = harness_path("scenes/cornell/cornell.obj");
    char *out[3] = {NULL, NULL, NULL}, *err = NULL;
    const char *threads[3] = {"1", "2", "2"}, *seeds[3] = {"17", "17", "18"};
    for (int k = 0; k < 3; k++) {
        CHECK(harness_radkit_run("solve", (const char *[]){cornell, "--method", "mc", "--samples",
                                 "300", "--seed", seeds[k], "--threads", threads[k], "--quiet", NULL},
                                 &out[k], &err) == 0);
        free(err);
        err = NULL;
    }
    if (out[0] && out[1] && out[2]) {
        CHECK_MSG(strcmp(rows_of(out[0]), rows_of(out[1])) == 0, "1 and 2 threads differ");
        CHECK_MSG(strcmp(rows_of(out[1]), rows_of(out[2])) != 0, "seeds 17 and 18 agree");
        CHECK(strlen(rows_of(out[0])) > 38 * 40);
    }
    for (int k = 0; k < 3; k++)
        free(out[k]);
}

TEST(mc_cli_writes_stats_and_images)
{
    char dir[] = "/tmp/radkit-mc-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(0);
        return;
    }
    char stats[256], png[256], table[256];
    snprintf(stats, sizeof stats, "%s/stats.json", dir);
    snprintf(png, sizeof png, "%s/image.png", dir);
    snprintf(table, sizeof table, "%s/faces.tsv", dir);
    char *out = NULL, *err = NULL;
    CHECK(harness_radkit_run("solve", (const char *[]){harness_path("scenes/cornell/cornell.obj"),
                             "--method", "mc", "--samples", "64", "--stats", stats, "--png", png,
                             "--image-size", "64x64", "--out", table, "--quiet", NULL},
                             &out, &err) == 0);
    char *json = harness_read_file(stats);
    CHECK(json && strstr(json, "\"method\": \"mc\"") != NULL);
    CHECK(json && strstr(json, "\"paths\"") != NULL && strstr(json, "\"se_rel_l1\"") != NULL);
    CHECK(json && strstr(json, "\"rays\"") != NULL && strstr(json, "\"total\"") != NULL);
    free(json);
    CHECK(access(png, R_OK) == 0);
    char *text = harness_read_file(table);
    double B[3 * 38], se[3 * 38];
    CHECK(text && harness_face_table_se(text, B, se, 38) == 38);
    free(text);
    CHECK(out && out[0] == '\0'); /* the table went to --out */
    remove(stats);
    remove(png);
    remove(table);
    rmdir(dir);
    free(out);
    free(err);
}

TEST(mc_cli_rejects_bad_options)
{
    const char *cube = harness_path("scenes/furnace_cube/cube.obj");
    const char *bad_samples[] = {"0", "1", "-5", "abc", "1e3", "10x", "", "2199023255553"};
    for (size_t k = 0; k < sizeof bad_samples / sizeof bad_samples[0]; k++)
        HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "mc", "--samples",
                                   bad_samples[k], NULL}, "--samples");
    const char *bad_seeds[] = {"-1", "x", "1.5", "18446744073709551616", ""};
    for (size_t k = 0; k < sizeof bad_seeds / sizeof bad_seeds[0]; k++)
        HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "mc", "--seed",
                                   bad_seeds[k], NULL}, "--seed");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--samples", "100", NULL}, "--method mc");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--seed", "3", NULL},
                               "--method mc");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "mc", "--rule", "exact", NULL},
                               "--rule");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "mc", "--eps", "0.1", NULL},
                               "--eps");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "mc", "--refine", "1", NULL},
                               "--refine");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "mcc", NULL}, "mcc");
}

/* radkit compare: a dense furnace solve (exact to rounding) against a Monte
 * Carlo table of the same furnace differs by about the Monte Carlo's own
 * standard error; tables of another scene, missing files and missing
 * arguments are refused. */
TEST(mc_cli_compare_against_a_reference)
{
    char dir[] = "/tmp/radkit-cmp-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(0);
        return;
    }
    char dense[256], mc[256], buf[64];
    snprintf(dense, sizeof dense, "%s/dense.tsv", dir);
    snprintf(mc, sizeof mc, "%s/mc.tsv", dir);
    const char *room = harness_path("scenes/furnace_room/room_box.obj");
    char *out = NULL, *err = NULL;
    CHECK(harness_radkit_run("solve", (const char *[]){room, "--rule", "exact", "--refine", "1",
                             "--out", dense, "--quiet", NULL}, &out, &err) == 0);
    free(out);
    free(err);
    CHECK(harness_radkit_run("solve", (const char *[]){room, "--method", "mc", "--samples", "1024",
                             "--out", mc, "--quiet", NULL}, &out, &err) == 0);
    free(out);
    free(err);
    CHECK(harness_radkit_run("compare", (const char *[]){room, dense, mc, NULL}, &out, &err) == 0);
    if (out) {
        double l1 = -1, se = -1, worst = -1;
        if (harness_header(out, "error_l1", buf, sizeof buf))
            l1 = atof(buf);
        if (harness_header(out, "reference_se_l1", buf, sizeof buf))
            se = atof(buf);
        if (harness_header(out, "error_worst", buf, sizeof buf))
            worst = atof(buf);
        /* |B - B_ref| averages about 0.8 se for normal errors */
        CHECK_MSG(se > 0 && l1 > 0.3 * se && l1 < 2.0 * se, "l1 %g, reference se %g", l1, se);
        CHECK(worst >= l1 && worst < 0.1);
        CHECK(harness_header(out, "mean_reflected", buf, sizeof buf) &&
              fabs(atof(buf) - (2.385 / 0.625 - 2.385)) < 0.05);
        CHECK(harness_count_lines(out) > 24);
    }
    free(out);
    free(err);
    /* a table against itself: no error at all */
    CHECK(harness_radkit_run("compare", (const char *[]){room, dense, dense, NULL}, &out, &err) == 0);
    CHECK(out && harness_header(out, "error_worst", buf, sizeof buf) && atof(buf) == 0.0);
    free(out);
    free(err);
    HARNESS_EXPECT_USAGE_ERROR("compare", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"),
                               dense, mc, NULL}, "24 faces, the scene 12");
    HARNESS_EXPECT_USAGE_ERROR("compare", (const char *[]){room, dense, NULL}, "SCENE TABLE REFERENCE");
    HARNESS_EXPECT_USAGE_ERROR("compare", (const char *[]){room, dense, "/nonexistent.tsv", NULL},
                               "/nonexistent.tsv");
    HARNESS_EXPECT_USAGE_ERROR("compare", (const char *[]){room, dense, mc, mc, NULL}, "more than one");
    remove(dense);
    remove(mc);
    rmdir(dir);
}
