/* radkit solve --method hier end to end: the furnace cube's exact answer
 * through the CLI, the table's shape and '#' lines, and bad options. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>
#include <unistd.h>

#include "harness.h"

/* Furnace cube (rho 0.375, E 2.385): B = 3.816.  --eps 1e-9 asks for
 * refinement until min_area stops it; --min-area 0.19 lets each face
 * triangle (area 0.78125) split at most once (children 0.195 >= 0.19,
 * grandchildren 0.049 < 0.19).  With the exact rule every row sums to 1 to
 * ~1e-13 (see test_hier.c): 1e-6 is the brief's tolerance, with a wide
 * margin. */
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
    /* sealed (a closed convex scene): every row is scaled to 1, the bound is
       0 at once, and min_area allows at most one split */
    CHECK(harness_header(out, "elements", buf, sizeof buf) && (atoi(buf) == 12 || atoi(buf) == 48));
    CHECK(harness_header(out, "error_target_met", buf, sizeof buf) && strcmp(buf, "yes") == 0);
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
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--solver", "lu", NULL}, "--solver");
}

/* Read an 8-bit RGB PNG (libpng's simplified API); NULL on failure. */
static unsigned char *read_png(const char *path, int *w, int *h)
{
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&image, path))
        return NULL;
    image.format = PNG_FORMAT_RGB;
    unsigned char *rgb = malloc(PNG_IMAGE_SIZE(image));
    if (!rgb || !png_image_finish_read(&image, NULL, rgb, 0, NULL)) {
        free(rgb);
        png_image_free(&image);
        return NULL;
    }
    *w = (int)image.width;
    *h = (int)image.height;
    return rgb;
}

/* The occluded Cornell box through --method hier with every output: the
 * table, a PLY of the leaves' conforming mesh whose triangles add up to the
 * scene's area (the table's area column, an independent sum), at least as
 * many display triangles as leaves, the stats JSON with the hierarchy's
 * figures, and --edges drawing dark lines on an otherwise identical image. */
TEST(hier_cli_occluded_cornell_with_all_outputs)
{
    char base[] = "/tmp/radkit-hier-XXXXXX";
    int fd = mkstemp(base);
    if (fd >= 0)
        close(fd);
    char png[64], png_edges[64], ply[64], stats[64];
    snprintf(png, sizeof png, "%s.png", base);
    snprintf(png_edges, sizeof png_edges, "%s-edges.png", base);
    snprintf(ply, sizeof ply, "%s.ply", base);
    snprintf(stats, sizeof stats, "%s.json", base);
    const char *cornell = harness_path("scenes/cornell/cornell.obj");
    char *out = NULL, *err = NULL, *out2 = NULL, *err2 = NULL, buf[64];
    CHECK(harness_radkit_run("solve", (const char *[]){cornell, "--method", "hier", "--oracle",
                             "error", "--eps", "0.3", "--png", png, "--ply", ply, "--stats", stats,
                             "--image-size", "96x96", "--quiet", NULL}, &out, &err) == 0);
    CHECK(harness_radkit_run("solve", (const char *[]){cornell, "--method", "hier", "--oracle",
                             "error", "--eps", "0.3", "--png", png_edges, "--edges",
                             "--image-size", "96x96", "--quiet", "--out", "/dev/null", NULL},
                             &out2, &err2) == 0);
    free(out2);
    free(err2);
    if (!out)
        return;
    CHECK(harness_header(out, "oracle", buf, sizeof buf) && strcmp(buf, "error") == 0);
    CHECK(harness_header(out, "effect_occlusion", buf, sizeof buf) && strcmp(buf, "on") == 0);
    long leaves = harness_header(out, "elements", buf, sizeof buf) ? atol(buf) : -1;
    CHECK(harness_header(out, "links_partial", buf, sizeof buf) && atol(buf) > 0);
    CHECK(harness_header(out, "error_estimate", buf, sizeof buf) && atof(buf) > 0.0);
    CHECK(leaves > 38); /* refinement happened */
    /* the scene's area from the table */
    double total = 0.0;
    const char *row = strstr(out, "\nface\t");
    for (row = row ? strchr(row + 1, '\n') : NULL; row && row[1]; row = strchr(row + 1, '\n')) {
        int face;
        double area;
        if (sscanf(row + 1, "%d\t%lf", &face, &area) == 2)
            total += area;
    }
    CHECK(total > 1.0);
    /* the PLY: vertices, then faces as "3 i j k" */
    FILE *f = fopen(ply, "r");
    long nv = -1, nf = -1;
    double ply_area = 0.0;
    if (f) {
        char line[256];
        while (fgets(line, sizeof line, f) && strncmp(line, "end_header", 10) != 0) {
            sscanf(line, "element vertex %ld", &nv);
            sscanf(line, "element face %ld", &nf);
        }
        double *v = nv > 0 ? malloc((size_t)nv * 3 * sizeof *v) : NULL;
        for (long k = 0; v && k < nv; k++)
            if (fscanf(f, "%lf %lf %lf %*d %*d %*d", v + 3 * k, v + 3 * k + 1, v + 3 * k + 2) != 3)
                break;
        for (long k = 0; v && k < nf; k++) {
            int n3, a, b, c;
            if (fscanf(f, "%d %d %d %d", &n3, &a, &b, &c) != 4 || n3 != 3 || a < 0 || b < 0 ||
                c < 0 || a >= nv || b >= nv || c >= nv)
                break;
            double e1[3], e2[3];
            for (int d = 0; d < 3; d++) {
                e1[d] = v[3 * b + d] - v[3 * a + d];
                e2[d] = v[3 * c + d] - v[3 * a + d];
            }
            double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2],
                   cz = e1[0] * e2[1] - e1[1] * e2[0];
            ply_area += 0.5 * sqrt(cx * cx + cy * cy + cz * cz);
        }
        free(v);
        fclose(f);
    }
    CHECK_MSG(nf >= leaves, "PLY has %ld faces for %ld leaves", nf, leaves);
    /* float coordinates in the PLY: 1e-5 relative */
    CHECK_MSG(fabs(ply_area - total) <= 1e-5 * total, "PLY area %.9g, table %.9g", ply_area, total);
    f = fopen(stats, "r");
    char json[8192] = {0};
    CHECK(f && fread(json, 1, sizeof json - 1, f) > 0);
    if (f)
        fclose(f);
    const char *keys[] = {"\"method\": \"hier\"", "\"details\"", "\"links_partial\"",
                          "\"links_blocked\"", "\"max_depth\"", "\"refine\"", "\"link\""};
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
        CHECK_MSG(strstr(json, keys[k]) != NULL, "stats JSON lacks %s", keys[k]);
    int w1 = 0, h1 = 0, w2 = 0, h2 = 0;
    unsigned char *plain = read_png(png, &w1, &h1), *edges = read_png(png_edges, &w2, &h2);
    CHECK(plain && edges && w1 == 96 && h1 == 96 && w2 == 96 && h2 == 96);
    if (plain && edges) {
        int changed = 0, dark = 0;
        for (int k = 0; k < 96 * 96; k++)
            if (memcmp(plain + 3 * k, edges + 3 * k, 3) != 0) {
                changed++;
                /* the line colour, 0.05 of white */
                dark += edges[3 * k] <= 14 && edges[3 * k + 1] <= 14 && edges[3 * k + 2] <= 14;
            }
        CHECK_MSG(changed > 200 && dark == changed, "%d pixels changed, %d of them dark", changed,
                  dark);
    }
    free(plain);
    free(edges);
    remove(base);
    remove(png);
    remove(png_edges);
    remove(ply);
    remove(stats);
    free(out);
    free(err);
}

TEST(hier_cli_oracle_option)
{
    const char *cube = harness_path("scenes/furnace_cube/cube.obj");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--oracle", "fast", NULL}, "oracle");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--oracle", "bf", NULL}, "--method hier");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--refine", "1", NULL}, "--refine");
}
