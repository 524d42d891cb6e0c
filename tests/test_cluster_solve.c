/* Clustered hierarchical radiosity (rad_hier with params.cluster, radkit
 * solve --method cluster): the table and stats, bad options refused, the
 * same answer on any thread count, and linking that starts linear in the
 * input triangles (hier's starts with every pair).  Its answers against the
 * furnaces and the Monte Carlo reference are in test_furnace.c and
 * test_hier.c, beside hier's; here, a cluster link's visibility between
 * two slabs against the closed form. */
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "rad_ff.h"
#include "rad_hier.h"
#include "rad_solve.h"
#include "rad_sys.h"
#include "rad_vis.h"

TEST(cluster_cli_table_and_stats)
{
    char dir[] = "/tmp/radkit-cluster-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK(0);
        return;
    }
    char stats[256], ply[256];
    snprintf(stats, sizeof stats, "%s/stats.json", dir);
    snprintf(ply, sizeof ply, "%s/leaves.ply", dir);
    const char *models[2] = {NULL, "iso"};
    for (int m = 0; m < 2; m++) {
        char *out = NULL, *err = NULL, buf[64];
        const char *args[16];
        int n = 0;
        args[n++] = harness_path("scenes/cornell/cornell.obj");
        args[n++] = "--method";
        args[n++] = "cluster";
        if (models[m]) {
            args[n++] = "--cluster-model";
            args[n++] = models[m];
        }
        /* the input triangles uncut, so that they are the tree's leaves */
        args[n++] = "--contact";
        args[n++] = "off";
        args[n++] = "--stats";
        args[n++] = stats;
        args[n++] = "--ply";
        args[n++] = ply;
        args[n++] = "--quiet";
        args[n] = NULL;
        CHECK_MSG(harness_radkit_run("solve", args, &out, &err) == 0, "%s", err ? err : "");
        if (!out) {
            free(err);
            continue;
        }
        double B[3 * 38];
        CHECK(harness_face_table(out, B, 38) == 38);
        CHECK(harness_header(out, "method", buf, sizeof buf) && strcmp(buf, "cluster") == 0);
        CHECK(harness_header(out, "cluster_model", buf, sizeof buf) &&
              strcmp(buf, models[m] ? models[m] : "oriented") == 0);
        /* a binary tree with one triangle per leaf: 2 n - 1 nodes */
        CHECK(harness_header(out, "clusters", buf, sizeof buf) && atoi(buf) == 2 * 38 - 1);
        CHECK(harness_header(out, "links_cluster", buf, sizeof buf) && atoi(buf) >= 0);
        CHECK(harness_header(out, "error_estimate", buf, sizeof buf) && atof(buf) > 0.0);
        char *text = harness_read_file(stats);
        CHECK(text && strstr(text, "\"method\": \"cluster\"") != NULL);
        CHECK(text && strstr(text, "\"clusters\": 75") != NULL);
        CHECK(text && strstr(text, "\"links_cluster\"") != NULL);
        free(text);
        CHECK(access(ply, R_OK) == 0);
        free(out);
        free(err);
    }
    remove(stats);
    remove(ply);
    rmdir(dir);
}

TEST(cluster_cli_rejects_bad_options)
{
    const char *cube = harness_path("scenes/furnace_cube/cube.obj");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--cluster-model", "fancy", NULL}, "fancy");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--cluster-model", "iso", NULL}, "--method cluster");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--cluster-model", "iso", NULL}, "--method cluster");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--basis", "p1", NULL}, "--basis");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--oracle", "bf", NULL}, "--oracle");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--rule", "exact", NULL}, "--rule");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--refine", "1", NULL}, "--refine");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--eps", "0", NULL}, "--eps");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){harness_path("scenes/bad/rho_too_big.obj"), "--method", "cluster", NULL}, "rho_too_big");
}

/* A hierarchy that would outgrow the machine's memory is refused as too big
 * (exit 2), naming the memory and what makes it smaller, before the kernel
 * kills the process: at the first check when the memory is less than the
 * process holds already (1 MB), for hier (p0 and p1) and cluster alike,
 * and part way through the refinement of 343 boxes at the defaults (whose
 * links take far more than 100 MB) when the memory is what the test holds
 * now and 100 MB more. */
TEST(cluster_refuses_a_hierarchy_beyond_the_machines_memory)
{
    const char *room = harness_path("scenes/many_objects/many_343.obj");
    const char *cornell = harness_path("scenes/cornell/cornell.obj");
    setenv("RADKIT_MEMORY_LIMIT", "1000000", 1);
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){room, "--method", "cluster", "--quiet", NULL}, "RADKIT_MEMORY_LIMIT");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cornell, "--method", "hier", "--quiet", NULL}, "--method cluster");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cornell, "--method", "hier", "--basis", "p1", "--quiet", NULL}, "--basis");
    rad_scene *scene = harness_scene_load("scenes/many_objects/many_343.obj", NULL);
    char limit[64];
    snprintf(limit, sizeof limit, "%.0f", rad_sys_rss_bytes() + 100e6);
    setenv("RADKIT_MEMORY_LIMIT", limit, 1);
    if (scene) {
        rad_solve_params p;
        rad_solve_params_default(&p);
        p.method = RAD_SOLVE_CLUSTER;
        rad_solution *s = NULL;
        rad_status st = rad_solve_run(scene, &p, &s);
        const char *msg = rad_error_message();
        CHECK_MSG(st == RAD_ETOOBIG && !s, "status %d: %s", (int)st, msg);
        size_t links = 0, clinks = 0;
        const char *with = strstr(msg, "GiB (RADKIT_MEMORY_LIMIT sets it), with ");
        CHECK_MSG(with && sscanf(with, "GiB (RADKIT_MEMORY_LIMIT sets it), with %zu links, %zu",
                                 &links, &clinks) == 2 && clinks > 0,
                  "%s", msg);
        CHECK_MSG(strstr(msg, "--eps") != NULL, "%s", msg);
        rad_solution_destroy(s);
        rad_scene_destroy(scene);
    }
    unsetenv("RADKIT_MEMORY_LIMIT");
}

/* The peak resident memory since the last reset (VmHWM; writing 5 to
 * clear_refs resets it, Linux 4.0 and later); 0 where it cannot be read. */
static double peak_since_reset(int reset)
{
    if (reset) {
        FILE *f = fopen("/proc/self/clear_refs", "w");
        int ok = f && fputs("5", f) >= 0;
        if (f && fclose(f) != 0)
            ok = 0;
        return ok ? 1.0 : 0.0;
    }
    FILE *f = fopen("/proc/self/status", "r");
    char line[256];
    double kb = 0.0;
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, "VmHWM:", 6) == 0)
            kb = atof(line + 6);
    if (f)
        fclose(f);
    return 1024.0 * kb;
}

/* Under the address sanitizer the resident memory holds its shadow and the
 * quarantine of freed blocks, which no forecast of radkit's arrays counts:
 * there the peaks are printed, not held to the share. */
#if defined(__SANITIZE_ADDRESS__)
enum { PEAK_HELD = 0 };
#else
enum { PEAK_HELD = 1 };
#endif

/* Under limits of the resident memory before the run plus 50%, 95% and
 * 105% of what the run took unchecked, in process: the run finishes or is
 * refused, and its peak (VmHWM, reset before each run) stays within the
 * limit's share but for the pages the kernel backs in 2 MB (a few arrays'
 * last huge page).  Then through the program (a process of its own, no
 * heap left by other runs): a limit 30% above the peak the run reports
 * unchecked lets it finish within the share, so the forecast bounds what
 * is made and does not refuse everything.  Each run in process starts from
 * a trimmed heap: free memory that earlier tests left resident would take
 * part of a run's arrays without growing the resident set, and the growth
 * measured unchecked would then fall short of what a later run needs. */
static void memory_check_holds(const char *scene_path, rad_solve_params p, const char *const args[])
{
    rad_scene *scene = harness_scene_load(scene_path, NULL);
    if (!scene)
        return;
    unsetenv("RADKIT_MEMORY_LIMIT");
    malloc_trim(0);
    double base = rad_sys_rss_bytes(), grown = 0.0;
    if (peak_since_reset(1)) {
        rad_solution *s = NULL;
        CHECK_MSG(rad_solve_run(scene, &p, &s) == RAD_OK, "%s", rad_error_message());
        grown = peak_since_reset(0) - base;
        rad_solution_destroy(s);
    } else {
        printf("# /proc/self/clear_refs not writable: no peak per run in process\n");
    }
    const double share[3] = {0.5, 0.95, 1.05};
    for (int k = 0; k < 3 && grown > 0.0; k++) {
        malloc_trim(0);
        base = rad_sys_rss_bytes();
        double limit = (base + share[k] * grown) / RAD_SYS_MEMORY_SHARE;
        char text[64];
        snprintf(text, sizeof text, "%.0f", limit);
        setenv("RADKIT_MEMORY_LIMIT", text, 1);
        peak_since_reset(1);
        rad_solution *s = NULL;
        rad_status st = rad_solve_run(scene, &p, &s);
        double peak = peak_since_reset(0);
        CHECK_MSG(st == RAD_OK || st == RAD_ETOOBIG, "status %d: %s", (int)st, rad_error_message());
        printf("# %s, limit for %.0f%% of the run: %s, peak %.1f MB, share %.1f MB\n", scene_path,
               100.0 * share[k], st == RAD_OK ? "finished" : "refused", (peak - base) / 1e6,
               (RAD_SYS_MEMORY_SHARE * limit - base) / 1e6);
        CHECK_MSG(!PEAK_HELD || peak <= RAD_SYS_MEMORY_SHARE * limit + 8e6,
                  "%s, limit for %.0f%% of the run: peak %.1f MB past the share %.1f MB (%s)",
                  scene_path, 100.0 * share[k], peak / 1e6, RAD_SYS_MEMORY_SHARE * limit / 1e6,
                  st == RAD_OK ? "finished" : "refused");
        rad_solution_destroy(s);
    }
    unsetenv("RADKIT_MEMORY_LIMIT");
    rad_scene_destroy(scene);
    /* through the program: the table's memory_peak_bytes */
    const char *argv[16] = {harness_path(scene_path), "--quiet"};
    int n = 2;
    while (args[n - 2] && n < 15) {
        argv[n] = args[n - 2];
        n++;
    }
    argv[n] = NULL;
    char *out = NULL, *err = NULL, buf[64];
    CHECK(harness_radkit_run("solve", argv, &out, &err) == 0);
    double peak = out && harness_header(out, "memory_peak_bytes", buf, sizeof buf) ? atof(buf) : 0.0;
    free(out);
    free(err);
    CHECK_MSG(peak > 0.0, "no memory_peak_bytes in the table");
    if (peak > 0.0) {
        double limit = 1.3 * peak / RAD_SYS_MEMORY_SHARE;
        snprintf(buf, sizeof buf, "%.0f", limit);
        setenv("RADKIT_MEMORY_LIMIT", buf, 1);
        int code = harness_radkit_run("solve", argv, &out, &err);
        unsetenv("RADKIT_MEMORY_LIMIT");
        CHECK_MSG(code == 0, "%s, limit 30%% above the peak: exit %d: %s", scene_path, code,
                  err ? err : "");
        double again = out && harness_header(out, "memory_peak_bytes", buf, sizeof buf) ? atof(buf)
                                                                                          : INFINITY;
        CHECK_MSG(!PEAK_HELD || again <= RAD_SYS_MEMORY_SHARE * limit,
                  "%s: peak %.1f MB past the share %.1f MB",
                  scene_path, again / 1e6, RAD_SYS_MEMORY_SHARE * limit / 1e6);
        free(out);
        free(err);
    }
}

/* The memory check forecasts what a hierarchy will hold before it makes it,
 * the solve's arrays included (a round's new link ends are built by the
 * solve after the round's last check of links), so under any limit a run
 * either finishes or is refused before its resident memory passes the
 * limit's share: 64 boxes through the cluster layer at the defaults, and
 * P1 elements (hierp's own arrays) on the Cornell box at eps 0.01, whose
 * reruns in process mostly reuse the heap the first run left, so that its
 * run through the program is what tests it. */
TEST(memory_check_keeps_the_run_within_its_limit)
{
    rad_solve_params p;
    rad_solve_params_default(&p);
    p.method = RAD_SOLVE_CLUSTER;
    memory_check_holds("scenes/many_objects/many_64.obj", p,
                       (const char *[]){"--method", "cluster", NULL});
    rad_solve_params_default(&p);
    p.method = RAD_SOLVE_HIER;
    p.basis = 1;
    p.hier.eps = 0.01;
    memory_check_holds("scenes/cornell/cornell.obj", p,
                       (const char *[]){"--method", "hier", "--basis", "p1", "--eps", "0.01", NULL});
}

/* --max-links caps each kind of link, and a hierarchy past it is refused
 * (exit 2) with a message naming the option: the room of 343 boxes needs
 * far more than 2 000 cluster links at any eps; the furnace cube's 12
 * triangles make 66 pairs, more than 50; the Cornell box's initial pairs fit
 * in 2 000 (its table says so) but its refinement at the defaults, P0 and
 * P1, does not.  A cap that is not reached changes nothing. */
TEST(cluster_and_hier_refuse_more_links_than_max_links)
{
    const char *room = harness_path("scenes/many_objects/many_343.obj");
    const char *cube = harness_path("scenes/furnace_cube/cube.obj");
    const char *cornell = harness_path("scenes/cornell/cornell.obj");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){room, "--method", "cluster", "--eps", "1", "--max-links", "2000", "--quiet", NULL}, "more than 2000 cluster links");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--max-links", "50", "--quiet", NULL}, "--max-links");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cornell, "--method", "hier", "--max-links", "2000", "--quiet", NULL}, "more than 2000 links (max_links, --max-links)");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cornell, "--method", "hier", "--basis", "p1", "--max-links", "2000", "--quiet", NULL}, "more than 2000 links (max_links, --max-links)");
    char *out[2] = {NULL, NULL}, *err = NULL, buf[64];
    double B[2][3 * 12];
    for (int k = 0; k < 2; k++) {
        CHECK(harness_radkit_run("solve", (const char *[]){cube, "--method", "hier", "--quiet", k ? "--max-links" : NULL, "66", NULL}, &out[k], &err) == 0);
        free(err);
        err = NULL;
    }
    CHECK(out[1] && harness_header(out[1], "max_links", buf, sizeof buf) && atol(buf) == 66);
    CHECK(out[0] && out[1] && harness_face_table(out[0], B[0], 12) == 12 &&
          harness_face_table(out[1], B[1], 12) == 12 && memcmp(B[0], B[1], sizeof B[0]) == 0);
    free(out[0]);
    free(out[1]);
}

/* Estimates run in parallel, each into its own slot, in job order, and the
 * cluster links' intensities, and their terms of the error bound, are
 * computed in parallel and summed in link order: the table and the bound are
 * the same to the bit on one thread and on two.  The
 * Cornell box ends with element links only; 64 boxes at eps 3 keep some
 * 28 000 cluster links, enough for the gather to run on both threads. */
static void same_answer_on_one_and_two_threads(const char *path, double eps, size_t min_cluster)
{
    rad_scene *scene = harness_scene_load(path, NULL);
    if (!scene)
        return;
    double *B[2] = {NULL, NULL};
    size_t links[2] = {0, 0}, clinks = 0;
    double bound[2][3] = {{0}};
    int faces = 0;
    for (int t = 0; t < 2; t++) {
        rad_solve_params p;
        rad_solve_params_default(&p);
        p.method = RAD_SOLVE_CLUSTER;
        p.threads = t + 1;
        if (eps > 0.0)
            p.hier.eps = eps;
        rad_solution *s = NULL;
        CHECK_MSG(rad_solve_run(scene, &p, &s) == RAD_OK, "%s", rad_error_message());
        if (!s)
            continue;
        faces = s->faces;
        links[t] = s->hier.links;
        clinks = s->hier.links_cluster;
        bound[t][0] = s->hier.bound_leaf_max;
        bound[t][1] = s->hier.bound_face_max;
        bound[t][2] = s->hier.bound_mean;
        B[t] = malloc(3 * (size_t)faces * sizeof *B[t]);
        memcpy(B[t], s->face_B, 3 * (size_t)faces * sizeof *B[t]);
        rad_solution_destroy(s);
    }
    CHECK_MSG(links[0] == links[1] && links[0] > 0, "%s: links %zu and %zu", path, links[0],
              links[1]);
    CHECK_MSG(clinks >= min_cluster, "%s: %zu cluster links", path, clinks);
    CHECK_MSG(memcmp(bound[0], bound[1], sizeof bound[0]) == 0 && bound[0][1] > 0.0,
              "%s: bounds %.17g and %.17g", path, bound[0][1], bound[1][1]);
    if (B[0] && B[1])
        CHECK_MSG(memcmp(B[0], B[1], 3 * (size_t)faces * sizeof *B[0]) == 0, "%s", path);
    free(B[0]);
    free(B[1]);
    rad_scene_destroy(scene);
}

TEST(cluster_same_answer_on_any_thread_count)
{
    same_answer_on_one_and_two_threads("scenes/cornell/cornell.obj", 0.0, 0);
    same_answer_on_one_and_two_threads("scenes/many_objects/many_64.obj", 3.0, 2048);
}

/* A closed 10 m room (inward) holding k^3 unit-ish cubes (outward) on a
 * grid: 12 + 12 k^3 triangles. */
static int room_of_boxes(int k, double **xyz, int **tri)
{
    int nb = k * k * k, nt = 12 * (nb + 1);
    *xyz = malloc((size_t)8 * (size_t)(nb + 1) * 3 * sizeof **xyz);
    *tri = malloc((size_t)nt * 3 * sizeof **tri);
    static const int quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    int t = 0;
    for (int b = 0; b <= nb; b++) {
        double lo[3], hi[3];
        if (b == 0) {
            for (int a = 0; a < 3; a++) {
                lo[a] = 0.0;
                hi[a] = 10.0;
            }
        } else {
            int g[3] = {(b - 1) % k, ((b - 1) / k) % k, (b - 1) / (k * k)};
            for (int a = 0; a < 3; a++) {
                lo[a] = 10.0 * (g[a] + 0.35) / k;
                hi[a] = 10.0 * (g[a] + 0.65) / k;
            }
        }
        for (int v = 0; v < 8; v++) {
            (*xyz)[24 * b + 3 * v] = v & 1 ? hi[0] : lo[0];
            (*xyz)[24 * b + 3 * v + 1] = v & 2 ? hi[1] : lo[1];
            (*xyz)[24 * b + 3 * v + 2] = v & 4 ? hi[2] : lo[2];
        }
        for (int q = 0; q < 6; q++) {
            /* the quads above face outward; the room's are flipped */
            int c[4];
            for (int i = 0; i < 4; i++)
                c[i] = 8 * b + quads[q][b == 0 ? 3 - i : i];
            int tris[2][3] = {{c[0], c[1], c[2]}, {c[0], c[2], c[3]}};
            for (int h = 0; h < 2; h++, t++)
                for (int i = 0; i < 3; i++)
                    (*tri)[3 * t + i] = tris[h][i];
        }
    }
    return nt;
}

/* A room of k^3 boxes (room_of_boxes), every reflectance 0.5, with its
 * visibility and a cluster hierarchy of parameters p; emit: every triangle
 * emits 1, else the room's first two. */
typedef struct room {
    double *xyz, *rho, *E;
    int *tri, n;
    rad_vis *vis;
    rad_hier *h;
} room;

static void room_open(room *r, int k, int emit, const rad_hier_params *p)
{
    memset(r, 0, sizeof *r);
    r->n = room_of_boxes(k, &r->xyz, &r->tri);
    size_t n = (size_t)r->n, nv = 8 * (size_t)(k * k * k + 1);
    r->rho = malloc(3 * n * sizeof *r->rho);
    r->E = calloc(3 * n, sizeof *r->E);
    for (size_t i = 0; i < 3 * n; i++) {
        r->rho[i] = 0.5;
        r->E[i] = emit || i % n < 2 ? 1.0 : 0.0;
    }
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    CHECK(rad_vis_create(r->xyz, nv, r->tri, n, &vp, &r->vis) == RAD_OK);
    CHECK_MSG(rad_hier_create(r->xyz, nv, r->tri, n, r->rho, r->E, r->vis, p, &r->h) == RAD_OK,
              "%s", rad_error_message());
}

static void room_close(room *r)
{
    rad_hier_destroy(r->h);
    rad_vis_destroy(r->vis);
    free(r->xyz);
    free(r->tri);
    free(r->rho);
    free(r->E);
}

/* Linking starts from the sibling clusters and splits only where bounding
 * boxes meet, which the tree's splits between objects leave rare: the
 * links made at creation grow no faster than the triangles (8 to 216
 * boxes: 108 to 2604 triangles), where hier's initial linking couples
 * every pair that faces. */
TEST(cluster_links_start_linear_in_triangles)
{
    double per[3] = {0, 0, 0};
    int sizes[3] = {2, 4, 6};
    rad_hier_params p;
    rad_hier_params_default(&p);
    p.cluster = 1;
    for (int s = 0; s < 3; s++) {
        room r;
        room_open(&r, sizes[s], 1, &p);
        if (r.h) {
            rad_hier_stats st;
            rad_hier_get_stats(r.h, &st);
            per[s] = (double)st.links / r.n;
            printf("# room with %d boxes: %d triangles, %zu clusters, %zu links at creation (%zu "
                   "cluster), %.1f per triangle (all pairs: %d)\n",
                   sizes[s] * sizes[s] * sizes[s], r.n, st.clusters, st.links, st.links_cluster,
                   per[s], r.n * (r.n - 1) / 2);
            CHECK(st.clusters == 2 * (size_t)r.n - 1);
        }
        room_close(&r);
    }
    /* 24 times the triangles, and no more links per triangle (pairs would
       grow by the factor 24) */
    CHECK_MSG(per[0] > 0.0 && per[2] <= per[0], "links per triangle %.1f -> %.1f", per[0],
              per[2]);
}

/* The room's walls are larger than whole groups of boxes: the cluster layer
 * splits a wall, not only the boxes' clusters, where it is the larger end,
 * so a wall is linked piece by piece to clusters of boxes instead of to
 * each of their triangles, whose shafts would cross the whole room between
 * ever more boxes.  At a coarse setting (eps 1, no tightening) the point
 * evaluations of all estimates per input triangle then stay about the same
 * from 64 to 216 boxes; linking a wall to every triangle would make them
 * grow with the boxes in the way. */
static double evals_per_triangle(int k)
{
    rad_hier_params p;
    rad_hier_params_default(&p);
    p.cluster = 1;
    p.eps = 1.0;
    p.max_tighten = 0;
    p.min_area = 100.0 / (k * k * k); /* about a box face's area (solve/ sets one too) */
    room r;
    room_open(&r, k, 0, &p);
    double per = 0.0;
    if (r.h && rad_hier_solve(r.h) == RAD_OK) {
        rad_hier_stats st;
        rad_hier_get_stats(r.h, &st);
        per = (double)st.kernel_evals / r.n;
        printf("# room with %d boxes, eps 1: %zu links (%zu cluster), %lld evaluations, %.0f per "
               "triangle\n",
               k * k * k, st.links, st.links_cluster, st.kernel_evals, per);
    }
    room_close(&r);
    return per;
}

TEST(cluster_walls_link_to_clusters_not_to_each_triangle)
{
    double small = evals_per_triangle(4), large = evals_per_triangle(6);
    CHECK_MSG(small > 0.0 && large < 1.25 * small, "evaluations per triangle %.0f -> %.0f", small,
              large);
}

/* A room of 27 boxes lit by two of its triangles at eps 0.3: the leaves'
 * radiosity and bounds, three channels each ([0] B, [1] bounds), with
 * the blue reflectance of one box triangle raised by blue_step. */
static size_t room_leaves(double blue_step, double *out[2])
{
    rad_hier_params p;
    rad_hier_params_default(&p);
    p.cluster = 1;
    p.eps = 0.3;
    room r;
    room_open(&r, 3, 0, &p);
    rad_hier_destroy(r.h); /* made again with the changed reflectance */
    r.h = NULL;
    r.rho[2 * (size_t)r.n + 20] += blue_step;
    size_t n = 0;
    out[0] = out[1] = NULL;
    if (rad_hier_create(r.xyz, 8 * 28, r.tri, (size_t)r.n, r.rho, r.E, r.vis, &p, &r.h) ==
            RAD_OK &&
        rad_hier_solve(r.h) == RAD_OK) {
        n = rad_hier_leaf_count(r.h);
        out[0] = malloc(3 * n * sizeof **out);
        out[1] = malloc(3 * n * sizeof **out);
        rad_hier_leaves(r.h, NULL, NULL, NULL, out[0]);
        rad_hier_leaf_bounds(r.h, out[1]);
    }
    room_close(&r);
    return n;
}

/* Where every reflectance and emission is grey the cluster gather carries
 * one channel for the three: the answer and its bound must be those of
 * three channels carried, which a blue reflectance 1e-12 off grey forces
 * (the same links; values within 1e-9). */
TEST(cluster_grey_scene_carries_one_channel_for_three)
{
    double *grey[2], *colour[2];
    size_t n = room_leaves(0.0, grey), m = room_leaves(1e-12, colour);
    CHECK_MSG(n > 0 && n == m, "leaves %zu and %zu", n, m);
    double worst = 0.0, top = 0.0;
    for (size_t i = 0; n == m && i < 3 * n; i++)
        for (int k = 0; k < 2; k++) {
            worst = fmax(worst, fabs(grey[k][i] - colour[k][i]));
            top = fmax(top, fabs(colour[k][i]));
        }
    CHECK_MSG(top > 0.0 && worst <= 1e-9 * top, "largest difference %.3g of %.3g", worst, top);
    for (int k = 0; k < 2; k++) {
        free(grey[k]);
        free(colour[k]);
    }
}

/* The effects plan decides clustering for hier from the pairs of input
 * triangles that face each other and whether anything can block them
 * (effects.c); on, the 1280-triangle sphere's hier links 2 559 clusters
 * instead of 818 560 pairs and the furnace stays exact;
 * forced either way by --clustering, refused where nothing has a cluster
 * layer or where it contradicts the method. */
TEST(cluster_effects_plan_decides_for_hier)
{
    /* by the pairs facing each other: where nothing can block (the spheres
       seen from inside: 190, 3 160, 51 040 and 818 560 pairs) from 2e4, among
       occluders (rooms of 64, 343 and 1 000 boxes: 74 948, 2 064 192 and
       17.5 million pairs) from 2.5e5 */
    struct { const char *scene; const char *want; } info[] = {
        {"scenes/sphere/sphere_0.obj", "off"}, {"scenes/sphere/sphere_1.obj", "off"},
        {"scenes/sphere/sphere_2.obj", "on"},  {"scenes/sphere/sphere_3.obj", "on"},
        {"scenes/many_objects/many_64.obj", "off"}, {"scenes/many_objects/many_343.obj", "on"},
        {"scenes/many_objects/many_1000.obj", "on"}};
    for (size_t k = 0; k < sizeof info / sizeof info[0]; k++) {
        char *out = NULL, *err = NULL, buf[512];
        CHECK(harness_radkit_run("info", (const char *[]){harness_path(info[k].scene), NULL},
                                 &out, &err) == 0);
        CHECK_MSG(out && harness_header(out, "effect_clustering", buf, sizeof buf) &&
                      strcmp(buf, info[k].want) == 0,
                  "%s: effect_clustering '%s'", info[k].scene, out ? buf : "");
        free(out);
        free(err);
    }
    /* the solve decides as info does, without the tightening too: the room
       of 343 boxes at the preview setting */
    char *out = NULL, *err = NULL, buf[512];
    CHECK(harness_radkit_run("solve", (const char *[]){harness_path(
                             "scenes/many_objects/many_343.obj"), "--method", "hier", "--eps",
                             "1", "--max-tighten", "0", "--quiet", NULL}, &out, &err) == 0);
    CHECK_MSG(out && harness_header(out, "effect_clustering", buf, sizeof buf) &&
                  strcmp(buf, "on") == 0,
              "many_343, --max-tighten 0: effect_clustering '%s'", out ? buf : "");
    free(out);
    free(err);
    /* auto on: the sphere furnace (rho 0.9, E 1: B = 10) through clusters */
    CHECK(harness_radkit_run("solve", (const char *[]){harness_path("scenes/sphere/sphere_3.obj"),
                             "--method", "hier", "--rho", "0.9", "--emission", "1", "--quiet",
                             NULL}, &out, &err) == 0);
    CHECK(out && harness_header(out, "effect_clustering", buf, sizeof buf) &&
          strcmp(buf, "on") == 0);
    CHECK(out && harness_header(out, "clusters", buf, sizeof buf) && atoi(buf) == 2 * 1280 - 1);
    static double B[3 * 1280];
    CHECK(out && harness_face_table(out, B, 1280) == 1280);
    double worst = 0.0;
    for (int i = 0; i < 3 * 1280; i++)
        worst = fmax(worst, fabs(B[i] - 10.0) / 10.0);
    /* exact up to the last solve's distance from its fixed point: within
       eps/100 R by default (eps 0.1, R = 9 = 0.9 B) */
    CHECK_MSG(worst < 1e-6 + 0.01 * 0.1 * 0.9, "sphere furnace through clusters: worst %g",
              worst);
    free(out);
    free(err);
    /* forced on below the threshold: the Cornell box's 38 triangles */
    CHECK(harness_radkit_run("solve", (const char *[]){harness_path("scenes/cornell/cornell.obj"),
                             "--method", "hier", "--clustering", "on", "--contact", "off",
                             "--quiet", NULL},
                             &out, &err) == 0);
    CHECK(out && harness_header(out, "clusters", buf, sizeof buf) && atoi(buf) == 75);
    CHECK(out && harness_header(out, "effect_clustering_reason", buf, sizeof buf) &&
          strstr(buf, "forced on") != NULL);
    free(out);
    free(err);
    const char *cube = harness_path("scenes/furnace_cube/cube.obj");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--clustering", "on", NULL}, "--clustering");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "mc", "--clustering", "on", NULL}, "--clustering");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--basis", "p1", "--clustering", "on", NULL}, "--clustering");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "cluster", "--clustering", "off", NULL}, "--clustering off");
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){cube, "--method", "hier", "--clustering", "maybe", NULL}, "maybe");
}

/* Howell's C-11: the form factor between directly opposed equal squares of
 * side a at distance c. */
static double opposed_squares(double a, double c)
{
    double X = a / c, q = sqrt(1.0 + X * X);
    return 2.0 / (RAD_PI * X * X) *
           (log((1.0 + X * X) / sqrt(1.0 + 2.0 * X * X)) + 2.0 * X * q * atan(X / q) -
            2.0 * X * atan(X));
}

/* The box [lo, hi] as 8 vertices (xyz, 24 doubles) and 12 outward triangles
 * (vertex indices from base); its +z face is triangles 10 and 11, its -z
 * face 8 and 9. */
static void slab(const double lo[3], const double hi[3], int base, double *xyz, int *tri)
{
    for (int v = 0; v < 8; v++) {
        xyz[3 * v] = v & 1 ? hi[0] : lo[0];
        xyz[3 * v + 1] = v & 2 ? hi[1] : lo[1];
        xyz[3 * v + 2] = v & 4 ? hi[2] : lo[2];
    }
    static const int quad[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                   {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (int f = 0; f < 6; f++) {
        const int *q = quad[f];
        int t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        for (int k = 0; k < 6; k++)
            tri[6 * f + k] = base + t[k];
    }
}

/* xyz (nv vertices) and tri (nt triangles) solved by cluster at eps with
 * no tightening, the final solve to convergence where converged is set
 * (final_share 0: the bound is then the links' terms, not what a coarse
 * eps lets the iteration leave); NULL (after a failed check) when it could
 * not be.  *vis is the scene's visibility, for the caller to destroy. */
static rad_hier *cluster_solved(const double *xyz, size_t nv, const int *tri, size_t nt,
                                const double *rho, const double *E, double eps, int converged,
                                rad_vis **vis)
{
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    CHECK(rad_vis_create(xyz, nv, tri, nt, &vp, vis) == RAD_OK);
    rad_hier_params p;
    rad_hier_params_default(&p);
    p.cluster = 1;
    p.eps = eps;
    p.max_tighten = 0;
    if (converged)
        p.final_share = 0.0;
    rad_hier *h = NULL;
    CHECK(*vis && rad_hier_create(xyz, nv, tri, nt, rho, E, *vis, &p, &h) == RAD_OK);
    if (h && rad_hier_solve(h) != RAD_OK) {
        CHECK_MSG(0, "solve: %s", rad_error_message());
        rad_hier_destroy(h);
        h = NULL;
    }
    return h;
}

/* The area-weighted mean B (channel 0) of h's leaves on input triangles f0
 * and f1. */
static double faces_mean_B(const rad_hier *h, int f0, int f1)
{
    size_t n = rad_hier_leaf_count(h);
    int *face = malloc(n * sizeof *face);
    double *area = malloc(n * sizeof *area), *B = malloc(3 * n * sizeof *B);
    double a = 0.0, ab = 0.0;
    if (face && area && B) {
        rad_hier_leaves(h, face, area, NULL, B);
        for (size_t k = 0; k < n; k++)
            if (face[k] == f0 || face[k] == f1) {
                a += area[k];
                ab += area[k] * B[k];
            }
    }
    free(face);
    free(area);
    free(B);
    return a > 0.0 ? ab / a : 0.0;
}

/* Two boxes (1 x 1 x t) face each other across D: the lower one's +z face
 * reflects 0.5, the upper one's -z face emits 1, nothing else reflects or
 * emits, so the reflector's mean radiosity is 0.5 F with F the opposed
 * squares' form factor (closed form, checked here against rad_ff's exact
 * rule).  Linking starts with one cluster link between the boxes (the
 * root's children).  Solved with eps and no tightening; returns the
 * reflector's F as solved (-1 after a failure), and *bound_ok whether the
 * reported bound of the worst face covers the reflector's error. */
static double opposed_boxes(double t, double D, double eps, int *bound_ok, size_t *links,
                            size_t *cluster_links)
{
    double xyz[48];
    int tri[72];
    slab((double[3]){0, 0, 0}, (double[3]){1, 1, t}, 0, xyz, tri);
    slab((double[3]){0, 0, t + D}, (double[3]){1, 1, 2 * t + D}, 8, xyz + 24, tri + 36);
    double rho[72] = {0}, E[72] = {0};
    for (int c = 0; c < 3; c++) {
        rho[10 + 24 * c] = rho[11 + 24 * c] = 0.5; /* the reflector's +z face */
        E[12 + 8 + 24 * c] = E[12 + 9 + 24 * c] = 1.0; /* the emitter's -z face */
    }
    double F = opposed_squares(1.0, D), G = 0.0;
    rad_ff_rule exact = {RAD_FF_EXACT, 0};
    rad_ff_params fp;
    rad_ff_params_default(&fp);
    for (int i = 10; i < 12; i++)
        for (int j = 20; j < 22; j++) {
            rad_vec3 ti[3], tj[3];
            for (int k = 0; k < 3; k++) {
                const double *a = xyz + 3 * tri[3 * i + k], *b = xyz + 3 * tri[3 * j + k];
                ti[k] = rad_vec3_make(a[0], a[1], a[2]);
                tj[k] = rad_vec3_make(b[0], b[1], b[2]);
            }
            rad_ff_result r;
            CHECK(rad_ff_compute(ti, tj, exact, &fp, &r) == RAD_OK);
            G += r.G;
        }
    CHECK_MSG(fabs(G - F) <= 1e-9 * F, "closed form %.12g, exact rule %.12g", F, G);
    double got = -1.0;
    *bound_ok = 0;
    rad_vis *vis = NULL;
    rad_hier *h = cluster_solved(xyz, 16, tri, 24, rho, E, eps, 0, &vis);
    if (h) {
        rad_hier_stats st;
        rad_hier_get_stats(h, &st);
        got = faces_mean_B(h, 10, 11) / 0.5;
        double err = 0.5 * fabs(got - F) / st.reflected;
        *bound_ok = err <= st.bound_face_max;
        printf("# boxes 1 x 1 x %g across %g, eps %g: F %.5f, through %zu links (%zu cluster): "
               "%.5f (%+.1f%%), error %.3g R, bound %.3g R\n",
               t, D, eps, F, st.links, st.links_cluster, got, 100.0 * (got / F - 1.0), err,
               st.bound_face_max);
        if (links)
            *links = st.links;
        if (cluster_links)
            *cluster_links = st.links_cluster;
    }
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
    return got;
}

/* The reflector's F within tol (relative) of the closed form, the
 * reported bound covering its error, and, where eps leaves the first link
 * unrefined, that link a cluster link. */
static void opposed_boxes_within(double t, double D, double eps, double tol)
{
    int bound_ok = 0;
    size_t links = 0, cluster_links = 0;
    double got = opposed_boxes(t, D, eps, &bound_ok, &links, &cluster_links),
           F = opposed_squares(1.0, D);
    CHECK_MSG(fabs(got / F - 1.0) <= tol, "reflector's F %.5f, closed form %.5f", got, F);
    CHECK(bound_ok);
    if (eps >= 1e6)
        CHECK_MSG(links == 1 && cluster_links == 1, "%zu links, %zu cluster links", links,
                  cluster_links);
}

/* Thin slabs (t 0.02) across 4 at the preview setting (eps 1, no
 * tightening), and with eps so large that the one cluster link between
 * them stands.  A slab's back faces lie behind its front: a visibility ray
 * from one is blocked by its own slab, and with every sample there the four
 * rays would agree on "blocked", the link would carry nothing and flag
 * nothing (so the oracle would not refine it either), and the reflector
 * would stay black.  Rays must start on faces turned towards the other
 * end. */
TEST(cluster_link_sees_past_its_own_back_faces)
{
    opposed_boxes_within(0.02, 4.0, 1.0, 0.1);
    opposed_boxes_within(0.02, 4.0, 1e6, 0.1);
}

/* Unit cubes across 3, with eps so large that the one cluster link between
 * them is never refined: what it carries is its point kernel V / (pi d^2)
 * times the emitter's projected area, d the distance between where the
 * ends' projected areas lie: the facing faces' centres, 3 apart (5% above
 * F).  Between the cubes' centres, 4 apart, it would be 40% below F. */
TEST(cluster_link_kernel_between_the_projected_areas)
{
    opposed_boxes_within(1.0, 3.0, 1e6, 0.15);
}

/* Unit cubes across 0.5: their spheres (radius 0.87, centres 1.5 apart)
 * meet, their boxes do not.  With eps so large that nothing is refined, the
 * one cluster link between them stands, bounded by the gap alone (F <=
 * min(A / (pi gap^2), 1)), its error the whole bracket, and the reported
 * bound covers the reflector's error (the point kernel across the gap,
 * 1 / (pi 0.5^2) = 1.27 towards a unit face, against the exact 0.415).
 * A link refined wherever spheres meet would make more than one. */
TEST(cluster_link_between_meeting_spheres_is_bounded_by_the_gap)
{
    int bound_ok = 0;
    size_t links = 0;
    double got = opposed_boxes(1.0, 0.5, 1e6, &bound_ok, &links, NULL),
           F = opposed_squares(1.0, 0.5);
    CHECK_MSG(links == 1, "%zu links", links);
    CHECK_MSG(got > 0.0, "reflector's F %.5f (exact %.5f)", got, F);
    CHECK(bound_ok);
}

/* A square of side a centred on (0, 0, z), facing +z (up) or -z, as two
 * triangles, or as four around its centre (fan), into xyz (4 or 5
 * vertices, from base) and tri. */
static void square(double a, double z, int up, int fan, int base, double *xyz, int *tri)
{
    for (int v = 0; v < 5; v++) {
        xyz[3 * v] = v == 4 ? 0.0 : (v == 1 || v == 2 ? 0.5 : -0.5) * a;
        xyz[3 * v + 1] = v == 4 ? 0.0 : (v >= 2 ? 0.5 : -0.5) * a;
        xyz[3 * v + 2] = z;
    }
    static const int two[6] = {0, 1, 2, 0, 2, 3}, four[12] = {4, 0, 1, 4, 1, 2, 4, 2, 3, 4, 3, 0};
    int n = fan ? 12 : 6;
    for (int k = 0; k < n; k += 3)
        for (int j = 0; j < 3; j++)
            tri[k + j] = base + (fan ? four : two)[k + (up ? j : 2 - j)];
}

/* A cluster link whose point kernel is taken farther than the ends'
 * centres: X is a column 2.1 tall holding a square of side 0.2 at its foot
 * and one of side 0.02 at its top, both facing up; Y, 40 above the top, a
 * square of side 0.05 facing down that emits 1.  X's projected area lies
 * almost all at its foot, so the link takes the kernel at rho = 42.08,
 * while the centres lie r = 41.05 apart and the small square sees Y from
 * the gap, 40: it receives about 10% more than the link brings.  Nothing else
 * reflects, so the small square's B is 0.5 F towards Y exactly (F by
 * rad_ff's exact rule), and the reported bound of its leaves must cover
 * that error: a kernel spread taken at the centres' distance,
 * (r / (r - R))^2 (1 + sin beta) - 1 = 8.4%, would not; the one at rho,
 * (rho / gap)^2 (1 + sin beta) - 1 = 13.6%, does.  eps is so large that
 * the one link between X and Y stands. */
TEST(cluster_link_kernel_spread_covers_a_kernel_taken_beyond_the_centres)
{
    double xyz[39];
    int tri[24];
    square(0.2, -2.1, 1, 0, 0, xyz, tri);          /* X's foot: triangles 0, 1 */
    square(0.02, 0.0, 1, 0, 4, xyz + 12, tri + 6);  /* X's top: triangles 2, 3 */
    square(0.05, 40.0, 0, 1, 8, xyz + 24, tri + 12); /* Y: triangles 4 to 7 */
    double rho[24] = {0}, E[24] = {0};
    for (int c = 0; c < 3; c++) {
        rho[2 + 8 * c] = rho[3 + 8 * c] = 0.5;
        for (int j = 4; j < 8; j++)
            E[j + 8 * c] = 1.0;
    }
    rad_ff_rule exact = {RAD_FF_EXACT, 0};
    rad_ff_params fp;
    rad_ff_params_default(&fp);
    double truth[2] = {0.0, 0.0};
    rad_vec3 t[8][3];
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 3; k++) {
            const double *v = xyz + 3 * tri[3 * i + k];
            t[i][k] = rad_vec3_make(v[0], v[1], v[2]);
        }
    for (int i = 0; i < 2; i++)
        for (int j = 4; j < 8; j++) {
            rad_ff_result r;
            CHECK(rad_ff_compute(t[2 + i], t[j], exact, &fp, &r) == RAD_OK);
            truth[i] += 0.5 * r.G / rad_geom_triangle_area(t[2 + i][0], t[2 + i][1], t[2 + i][2]);
        }
    rad_vis *vis = NULL;
    rad_hier *h = cluster_solved(xyz, 13, tri, 8, rho, E, 1e6, 1, &vis);
    if (h) {
        rad_hier_stats st;
        rad_hier_get_stats(h, &st);
        CHECK_MSG(st.links == 1 && st.links_cluster == 1, "%zu links", st.links);
        size_t n = rad_hier_leaf_count(h);
        int *face = malloc(n * sizeof *face);
        double *B = malloc(3 * n * sizeof *B), *bound = malloc(3 * n * sizeof *bound);
        rad_hier_leaves(h, face, NULL, NULL, B);
        rad_hier_leaf_bounds(h, bound);
        int seen = 0;
        for (size_t k = 0; k < n; k++) {
            if (face[k] != 2 && face[k] != 3)
                continue;
            seen++;
            double want = truth[face[k] - 2], err = fabs(B[k] - want);
            printf("# small square, triangle %d: B %.6g, exact %.6g (%+.1f%%), bound %.6g\n",
                   face[k], B[k], want, 100.0 * (B[k] / want - 1.0), bound[k]);
            CHECK_MSG(err >= 0.08 * want, "the link should bring %.1f%% too little",
                      100.0 * (1.0 - B[k] / want));
            CHECK_MSG(err <= bound[k], "error %.4g above the bound %.4g", err, bound[k]);
        }
        CHECK(seen == 2);
        free(face);
        free(B);
        free(bound);
    }
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
}

/* Whether the segment p -> q crosses the box [lo, hi] (slab test). */
static int segment_hits_box(const double p[3], const double q[3], const double lo[3],
                            const double hi[3])
{
    double t0 = 0.0, t1 = 1.0;
    for (int a = 0; a < 3; a++) {
        double d = q[a] - p[a];
        if (fabs(d) < 1e-300) {
            if (p[a] < lo[a] || p[a] > hi[a])
                return 0;
            continue;
        }
        double u = (lo[a] - p[a]) / d, v = (hi[a] - p[a]) / d;
        if (u > v) {
            double w = u;
            u = v;
            v = w;
        }
        t0 = rad_dmax(t0, u);
        t1 = rad_dmin(t1, v);
        if (t0 > t1)
            return 0;
    }
    return 1;
}

/* A unit square (z = 0, facing up, reflectance 0.5) under an emitting one
 * (z = 1, facing down, E = 1) with nine black cubes of side 0.15 between
 * (a 3 x 3 grid at height 0.4): the shaft of the two squares holds all 108
 * cube triangles.  Nothing else reflects, so the square's mean B is
 * 0.5 F_vis exactly, F_vis computed here without radkit's visibility: the
 * kernel at 48 x 48 midpoints of each square, each segment tested against
 * the cubes as boxes (slab test; within 0.05% of finer grids).  hier and
 * cluster must come within eps R of it (the square's mean is an input
 * triangle's row, R the mean reflected radiosity over the 3.2 m^2 of the
 * scene: 3.1% of the square's B at eps 0.1; the cubes' shadows take a
 * fifth of F) at their defaults (108 blockers, more than clip_blockers:
 * rays, then clipping where the oracle would refine), with rays only
 * (clip_blockers 0: a link whose rays all miss a narrow shadow must not be
 * kept for that) and clipping every shaft exactly (clip_blockers at its
 * maximum); papers/clustering.md §3. */
TEST(hier_links_seen_through_a_crowd_stay_accurate)
{
    double xyz[3 * (8 + 9 * 8)];
    int tri[3 * (4 + 9 * 12)];
    static const double sq[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                    {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    static const int sqt[12] = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6};
    memcpy(xyz, sq, sizeof sq);
    memcpy(tri, sqt, sizeof sqt);
    double lo[9][3], hi[9][3];
    for (int k = 0; k < 9; k++) {
        double cx = 0.2 + 0.3 * (k % 3), cy = 0.2 + 0.3 * (k / 3);
        lo[k][0] = cx - 0.075;
        lo[k][1] = cy - 0.075;
        lo[k][2] = 0.4;
        hi[k][0] = cx + 0.075;
        hi[k][1] = cy + 0.075;
        hi[k][2] = 0.55;
        slab(lo[k], hi[k], 8 + 8 * k, xyz + 24 + 24 * k, tri + 12 + 36 * k);
    }
    size_t nv = 8 + 9 * 8, nt = 4 + 9 * 12;
    double *rho = calloc(3 * nt, sizeof *rho), *E = calloc(3 * nt, sizeof *E);
    for (int c = 0; c < 3; c++) {
        rho[0 + nt * (size_t)c] = rho[1 + nt * (size_t)c] = 0.5;
        E[2 + nt * (size_t)c] = E[3 + nt * (size_t)c] = 1.0;
    }
    enum { N = 48 };
    double F = 0.0;
    for (int i = 0; i < N * N; i++) {
        double p[3] = {(i % N + 0.5) / N, (i / N + 0.5) / N, 0.0};
        for (int j = 0; j < N * N; j++) {
            double q[3] = {(j % N + 0.5) / N, (j / N + 0.5) / N, 1.0};
            int open = 1;
            for (int k = 0; k < 9 && open; k++)
                open = !segment_hits_box(p, q, lo[k], hi[k]);
            if (open) {
                double dx = q[0] - p[0], dy = q[1] - p[1], d2 = dx * dx + dy * dy + 1.0;
                F += 1.0 / (RAD_PI * d2 * d2);
            }
        }
    }
    F /= (double)N * N * N * N;
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, nv, tri, nt, &vp, &vis) == RAD_OK);
    static const char *mode[3] = {"at its defaults", "with rays only", "clipping exactly"};
    for (int run = 0; run < 6 && vis; run++) {
        int cl = run & 1, m = run >> 1;
        rad_hier_params p;
        rad_hier_params_default(&p);
        p.cluster = cl;
        CHECK(p.clip_blockers < 108);
        if (m > 0)
            p.clip_blockers = m == 1 ? 0 : RAD_HIER_CLIP_BLOCKERS_MAX;
        rad_hier *h = NULL;
        CHECK(rad_hier_create(xyz, nv, tri, nt, rho, E, vis, &p, &h) == RAD_OK);
        if (!h || rad_hier_solve(h) != RAD_OK) {
            CHECK_MSG(0, "%s: %s", cl ? "cluster" : "hier", rad_error_message());
            rad_hier_destroy(h);
            continue;
        }
        rad_hier_stats st;
        rad_hier_get_stats(h, &st);
        double got = faces_mean_B(h, 0, 1) / 0.5;
        printf("# %s %s under nine cubes: F_vis %.5f (midpoints, slab test), "
               "solved %.5f (%+.2f%%), %zu links, %llu rays\n",
               cl ? "cluster" : "hier", mode[m], F, got,
               100.0 * (got / F - 1.0), st.links, st.rays);
        /* R = 0.5 F / total area; the square's error |0.5 got - 0.5 F| within eps R */
        double total = 2.0 + 9.0 * 6.0 * 0.15 * 0.15;
        CHECK_MSG(fabs(got / F - 1.0) <= p.eps / total, "F_vis %.5f, solved %.5f", F, got);
        rad_hier_destroy(h);
    }
    rad_vis_destroy(vis);
    free(rho);
    free(E);
}

/* A unit cube lit only from above, by two emitting slabs at different
 * angles (one over it, one over and beside it), eps so large that nothing
 * is refined: every link reaching the cube arrives from above, so its
 * bottom face (triangles 8 and 9) must receive nothing.  A small cluster
 * receives triangle by triangle, max(n.w, 0) of each link; the moments of
 * two directions would give the bottom the upper half of their bracket's
 * width instead (for n = -z: sqrt(C c_z) - c_z > 0). */
TEST(small_cluster_receives_nothing_from_behind_its_faces)
{
    double xyz[72];
    int tri[108];
    slab((double[3]){0, 0, 0}, (double[3]){1, 1, 1}, 0, xyz, tri);
    slab((double[3]){0, 0, 4}, (double[3]){1, 1, 4.02}, 8, xyz + 24, tri + 36);
    slab((double[3]){4, 0, 3}, (double[3]){5, 1, 3.02}, 16, xyz + 48, tri + 72);
    double rho[108] = {0}, E[108] = {0};
    for (int c = 0; c < 3; c++) {
        for (int t = 0; t < 12; t++)
            rho[t + 36 * c] = 0.5; /* the cube */
        E[12 + 8 + 36 * c] = E[12 + 9 + 36 * c] = 1.0; /* the slabs' -z faces */
        E[24 + 8 + 36 * c] = E[24 + 9 + 36 * c] = 1.0;
    }
    rad_vis *vis = NULL;
    rad_hier *h = cluster_solved(xyz, 24, tri, 36, rho, E, 1e6, 0, &vis);
    if (h) {
        size_t n = rad_hier_leaf_count(h);
        int *face = malloc(n * sizeof *face);
        double *B = malloc(3 * n * sizeof *B);
        double *area = malloc(n * sizeof *area);
        rad_hier_leaves(h, face, area, NULL, B);
        double a = 0.0, ab = 0.0, bottom = 0.0;
        for (size_t k = 0; k < n; k++) {
            if (face[k] == 10 || face[k] == 11) {
                a += area[k];
                ab += area[k] * B[k];
            }
            if (face[k] == 8 || face[k] == 9)
                bottom = rad_dmax(bottom, B[k]);
        }
        /* the top face sees both emitters whole and nothing else that
           emits: its mean B is 0.5 F, F by rad_ff's exact rule */
        double G = 0.0;
        rad_ff_rule exact = {RAD_FF_EXACT, 0};
        rad_ff_params fp;
        rad_ff_params_default(&fp);
        const int top[2] = {10, 11}, emit[4] = {20, 21, 32, 33};
        for (int i = 0; i < 2; i++)
            for (int j = 0; j < 4; j++) {
                rad_vec3 ti[3], tj[3];
                for (int k = 0; k < 3; k++) {
                    const double *u = xyz + 3 * tri[3 * top[i] + k], *v = xyz + 3 * tri[3 * emit[j] + k];
                    ti[k] = rad_vec3_make(u[0], u[1], u[2]);
                    tj[k] = rad_vec3_make(v[0], v[1], v[2]);
                }
                rad_ff_result r;
                CHECK(rad_ff_compute(ti, tj, exact, &fp, &r) == RAD_OK);
                G += r.G;
            }
        double want = 0.5 * G, got = a > 0.0 ? ab / a : 0.0;
        rad_hier_stats st;
        rad_hier_get_stats(h, &st);
        double err = fabs(got - want) / st.reflected;
        printf("# cube lit from above through %zu cluster links: top %.4g (exact %.4g, %+.1f%%), "
               "error %.3g R, bound %.3g R, bottom %.3g\n",
               st.links_cluster, got, want, 100.0 * (got / want - 1.0), err, st.bound_face_max,
               bottom);
        CHECK(st.links_cluster > 0);
        CHECK_MSG(got > 0.0, "the top face got nothing (exact %.4g)", want);
        CHECK_MSG(err <= st.bound_face_max, "top face %.4g, exact %.4g: error %.3g R past the "
                  "bound %.3g R", got, want, err, st.bound_face_max);
        CHECK_MSG(bottom == 0.0, "the bottom face got %.3g", bottom);
        free(face);
        free(area);
        free(B);
    }
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
}
