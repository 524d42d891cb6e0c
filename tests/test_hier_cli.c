/* radkit solve --method hier end to end: the furnace cube's exact answer
 * through the CLI, the table's shape and '#' lines, and bad options. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>
#include <unistd.h>

#include "harness.h"
#include "rad_ff.h"
#include "rad_geom.h"

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

/* One run's table (NULL after a failure, reported). */
static char *solve_table(const char *const *args)
{
    char *out = NULL, *err = NULL;
    CHECK_MSG(harness_radkit_run("solve", args, &out, &err) == 0, "%s", err ? err : "");
    free(err);
    return out;
}

/* The time breakdown's figures lie inside the phases they are part of: the
 * link estimates inside linking and refining, the error transport inside
 * solving (each printed to 1e-4 s); the transport takes at least a step;
 * every run estimates element links, only a cluster run cluster links. */
TEST(hier_cli_reports_where_the_time_goes)
{
    const char *cornell = harness_path("scenes/cornell/cornell.obj");
    const char *runs[][5] = {{"--method", "hier", NULL},
                             {"--method", "cluster", NULL},
                             {"--method", "hier", "--basis", "p1", NULL}};
    for (int r = 0; r < 3; r++) {
        const char *args[8] = {cornell};
        int n = 1;
        for (int k = 0; runs[r][k]; k++)
            args[n++] = runs[r][k];
        args[n++] = "--quiet";
        args[n] = NULL;
        char *out = solve_table(args);
        if (!out)
            continue;
        double cl = harness_header_number(out, "time_estimate_cluster_s");
        double el = harness_header_number(out, "time_estimate_element_s");
        double bound = harness_header_number(out, "time_bound_s");
        double steps = harness_header_number(out, "iterations_bound");
        double made = harness_header_number(out, "time_link_s") + harness_header_number(out, "time_refine_s");
        double solve = harness_header_number(out, "time_solve_s");
        CHECK_MSG(el > 0.0 && (r == 1 ? cl > 0.0 : cl == 0.0), "run %d: %g %g", r, cl, el);
        CHECK_MSG(cl + el <= made + 3e-4, "run %d: estimates %g + %g, linking and refining %g", r,
                  cl, el, made);
        CHECK_MSG(bound > 0.0 && bound <= solve + 2e-4, "run %d: bound %g, solve %g", r, bound,
                  solve);
        CHECK_MSG(steps >= 1.0, "run %d: %g transport steps", r, steps);
        free(out);
    }
}

/* Where the bound comes from: error_local_cluster, the share of the
 * leaves' local errors of F that cluster links bring.  Left unrefined
 * (eps 1e6) the 64 boxes keep the tree's first links, nearly all of them
 * cluster links, and nearly all the error is theirs; refinement replaces
 * cluster links by element links, and their share falls; where no cluster
 * link is left (the Cornell box at eps 0.01) it is 0; without clusters the
 * table has no such line. */
TEST(cluster_cli_reports_where_the_bound_comes_from)
{
    const char *boxes = harness_path("scenes/many_objects/many_64.obj");
    const char *cornell = harness_path("scenes/cornell/cornell.obj");
    double share[2] = {NAN, NAN};
    const char *eps[2] = {"1e6", "1"};
    for (int k = 0; k < 2; k++) {
        char *out = solve_table((const char *[]){boxes, "--method", "cluster", "--eps", eps[k],
                                                 "--quiet", NULL});
        if (out)
            share[k] = harness_header_number(out, "error_local_cluster");
        printf("# many_64, eps %s: error_local_cluster %.4f\n", eps[k], share[k]);
        free(out);
    }
    CHECK_MSG(share[0] >= 0.9 && share[0] <= 1.0, "unrefined: %g", share[0]);
    CHECK_MSG(share[1] > 0.0 && share[1] < share[0], "eps 1: %g, unrefined %g", share[1],
              share[0]);
    char *out = solve_table((const char *[]){cornell, "--method", "cluster", "--eps", "0.01",
                                             "--quiet", NULL});
    if (out) {
        CHECK(harness_header_number(out, "links_cluster") == 0.0);
        CHECK(harness_header_number(out, "error_local_cluster") == 0.0);
    }
    free(out);
    out = solve_table((const char *[]){cornell, "--method", "hier", "--quiet", NULL});
    char buf[64];
    CHECK(out && !harness_header(out, "error_local_cluster", buf, sizeof buf));
    free(out);
}

TEST(hier_cli_rejects_bad_options)
{
    const char *cube = harness_path("scenes/furnace_cube/cube.obj");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--eps", "0", NULL}, "--eps");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--eps", "-1", NULL}, "--eps");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--eps", "x", NULL}, "--eps");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--min-area", "-1", NULL}, "--min-area");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--max-tighten", "-1", NULL}, "--max-tighten");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--max-tighten", "31", NULL}, "--max-tighten");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--max-tighten", "1.5", NULL}, "--max-tighten");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--max-tighten", "2", NULL}, "--method hier or cluster");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--oracle", "bf", "--max-tighten", "1", NULL}, "--oracle error");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--max-links", "0", NULL}, "--max-links");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--max-links", "-5", NULL}, "--max-links");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--max-links", "1e6", NULL}, "--max-links");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "mc", "--max-links", "100", NULL}, "--method hier or cluster");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--clip-blockers", "257", NULL}, "--clip-blockers");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--clip-blockers", "-1", NULL}, "--clip-blockers");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--clip-blockers", "8x", NULL}, "--clip-blockers");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "dense", "--clip-blockers", "8", NULL}, "--method hier or cluster");
    /* the largest K is taken (the cube's bound meets eps before any tightening) */
    char *out = NULL, *err = NULL, buf[64];
    CHECK(harness_radkit_run("solve", (const char *[]){cube, "--method", "hier", "--max-tighten", "30", "--quiet", NULL}, &out, &err) == 0);
    CHECK(out && harness_header(out, "max_tighten", buf, sizeof buf) && atoi(buf) == 30);
    free(out);
    free(err);
    CHECK(harness_radkit_run("solve", (const char *[]){cube, "--method", "cluster", "--clip-blockers", "0", "--quiet", NULL}, &out, &err) == 0);
    CHECK(out && harness_header(out, "clip_blockers", buf, sizeof buf) && atoi(buf) == 0);
    free(out);
    free(err);
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

/* Where a link's clipping would exceed its budget it takes rays
 * (rad_vis_point_visible_limited, link.c): a floor (rho 0.5) lit by a ceiling
 * (E 1, rho 0) through a black screen of 72 small squares on a checkerboard
 * (144 triangles) halfway between.  The floor's radiosity is 0.5 F_vis(x,
 * ceiling); from any x the squares' shadows on the ceiling are disjoint
 * squares twice their size about x, so F_vis is the open form factor minus
 * theirs (clipped to the ceiling), and a midpoint rule over each floor
 * triangle gives its reference.  hier with its defaults (eps 0.1) must use
 * rays here, keep each floor triangle within eps R of its reference (R the
 * mean reflected radiosity) and within its own error estimate; without
 * visibility the floor would be 2.6 times too bright. */
TEST(hier_rays_past_the_clipping_budget_stay_within_eps)
{
    enum { N = 12, MAXF = 256 };
    const double side = 0.4 / N, h = 1.0;
    /* the temporary files carry the process id: the OBJ names its MTL by that name */
    const char *mtl = harness_write_file("screen.mtl", "newmtl floor\nKd 0.5 0.5 0.5\n"
                                                       "newmtl light\nKd 0 0 0\nKe 1 1 1\n"
                                                       "newmtl black\nKd 0 0 0\n");
    char obj[32768], *w = obj;
    size_t room = sizeof obj;
    int n = snprintf(w, room, "mtllib %s\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                              "v 0 0 %g\nv 1 0 %g\nv 1 1 %g\nv 0 1 %g\n"
                              "usemtl floor\nf 1 2 3\nf 1 3 4\nusemtl light\nf 5 7 6\nf 5 8 7\n"
                              "usemtl black\n", strrchr(mtl, '/') + 1, h, h, h, h);
    w += n;
    room -= (size_t)n;
    int nv = 8;
    double lo[N * N][2];
    int sq = harness_checkerboard(N, 0.3, side, lo);
    for (int s = 0; s < sq; s++) {
        double x0 = lo[s][0], y0 = lo[s][1];
        n = snprintf(w, room,
                     "v %.17g %.17g %g\nv %.17g %.17g %g\nv %.17g %.17g %g\nv %.17g %.17g %g\n"
                     "f %d %d %d\nf %d %d %d\n",
                     x0, y0, h / 2, x0 + side, y0, h / 2, x0 + side, y0 + side, h / 2, x0,
                     y0 + side, h / 2, nv + 1, nv + 3, nv + 2, nv + 1, nv + 4, nv + 3);
        w += n;
        room -= (size_t)n;
        nv += 4;
    }
    const char *scene = harness_write_file("screen.obj", obj);
    /* the references: 0.5 x each floor triangle's mean of F_vis(x, ceiling)
       (face 0 below the diagonal y = x, face 1 above it); polygons wound
       counter-clockwise seen from the floor */
    enum { Q = 120 };
    rad_vec3 nx = rad_vec3_make(0, 0, 1);
    rad_vec3 ceiling[4] = {rad_vec3_make(0, 0, h), rad_vec3_make(0, 1, h), rad_vec3_make(1, 1, h),
                           rad_vec3_make(1, 0, h)};
    double sum[2] = {0, 0}, weight[2] = {0, 0}, open = 0.0;
    for (int a = 0; a < Q; a++)
        for (int b = 0; b < Q; b++) {
            rad_vec3 x = rad_vec3_make((a + 0.5) / Q, (b + 0.5) / Q, 0.0);
            double F = rad_ff_point_polygon(x, nx, ceiling, 4);
            open += F / (Q * Q);
            for (int s = 0; s < sq; s++) {
                /* the shadow 2 p - x of the square, clipped to the unit square */
                double x0 = fmax(0.0, 2 * lo[s][0] - x.x), x1 = fmin(1.0, 2 * (lo[s][0] + side) - x.x);
                double y0 = fmax(0.0, 2 * lo[s][1] - x.y), y1 = fmin(1.0, 2 * (lo[s][1] + side) - x.y);
                if (!(x1 > x0) || !(y1 > y0))
                    continue;
                rad_vec3 shadow[4] = {rad_vec3_make(x0, y0, h), rad_vec3_make(x0, y1, h),
                                      rad_vec3_make(x1, y1, h), rad_vec3_make(x1, y0, h)};
                F -= rad_ff_point_polygon(x, nx, shadow, 4);
            }
            double part0 = a > b ? 1.0 : a == b ? 0.5 : 0.0; /* on the diagonal: half each */
            sum[0] += part0 * F;
            weight[0] += part0;
            sum[1] += (1.0 - part0) * F;
            weight[1] += 1.0 - part0;
        }
    double ref[2] = {0.5 * sum[0] / weight[0], 0.5 * sum[1] / weight[1]};
    /* R: the area-weighted mean of B - E over every face (the screen's is 0,
       the ceiling's B - E is 0) */
    double R = 0.5 * (ref[0] + ref[1]) / (2.0 + sq * side * side);
    char *out = NULL, *err = NULL, rays[64], est[64];
    CHECK(harness_radkit_run("solve", (const char *[]){scene, "--method", "hier", "--quiet", NULL},
                             &out, &err) == 0);
    double B[3 * MAXF];
    CHECK_MSG(ref[0] > 0.05 && ref[1] > 0.05 && ref[0] < 0.5 * open, "references %g %g (open %g)",
              ref[0], ref[1], 0.5 * open);
    if (out && harness_face_table(out, B, MAXF) == 2 + 2 * sq + 2) {
        CHECK(harness_header(out, "rays", rays, sizeof rays) && atof(rays) > 0);
        CHECK(harness_header(out, "error_estimate", est, sizeof est));
        for (int f = 0; f < 2; f++) {
            double e = fabs(B[3 * f] - ref[f]) / R;
            CHECK_MSG(e <= 0.1 && e <= atof(est), "floor face %d: %.6g against %.6g: %.3g R "
                      "(eps 0.1, estimate %s)", f, B[3 * f], ref[f], e, est);
            printf("# floor face %d: %.6g, reference %.6g (open %.6g): error %.3f R, estimate %s; "
                   "%s rays\n", f, B[3 * f], ref[f], 0.5 * open, e, est, rays);
        }
    } else {
        CHECK_MSG(0, "no table of %d faces", 2 + 2 * sq + 2);
    }
    free(out);
    free(err);
    remove(scene);
    remove(mtl);
}
