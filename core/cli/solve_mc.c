/* radkit solve --method mc: Monte Carlo radiosity (rad_mc), the independent
 * reference.  The table is dense's (per input triangle, area-average B) with
 * three more columns, the standard errors se_r, se_g, se_b, and '#' lines for
 * the sampling figures; --ply and --png show the input triangles' values. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <omp.h>
#include <unistd.h>

#include "rad_geom.h"
#include "rad_io.h"
#include "rad_mc.h"
#include "rad_mesh.h"
#include "rad_sys.h"
#include "rad_version.h"
#include "solve.h"

/* The options of the deterministic methods that mean nothing here. */
static rad_status refuse_other_options(const solve_options *o)
{
    const char *other[10][2] = {{"--rule", o->rule},         {"--tol", o->tol},
                                {"--solver", o->solver},     {"--solver-tol", o->solver_tol},
                                {"--max-iter", o->max_iter}, {"--refine", o->refine},
                                {"--vis-strata", o->strata}, {"--eps", o->eps},
                                {"--min-area", o->min_area}, {"--oracle", o->oracle}};
    for (int k = 0; k < 10; k++)
        if (other[k][1])
            return RAD_ERROR(RAD_EINVAL, "solve: %s does not apply to --method mc", other[k][0]);
    return RAD_OK;
}

/* A whole number in [lo, hi] (unsigned 64-bit range); RAD_EINVAL names the option. */
static rad_status parse_count(const char *option, const char *text, unsigned long long lo,
                              unsigned long long hi, unsigned long long *out)
{
    char *end = NULL;
    errno = 0;
    const char *p = text;
    while (*p == ' ')
        p++;
    unsigned long long v = *p == '-' ? 0 : strtoull(p, &end, 10);
    if (*p == '-' || end == p || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        return RAD_ERROR(RAD_EINVAL, "solve: %s must be a whole number in [%llu, %llu], got '%s'",
                         option, lo, hi, text);
    *out = v;
    return RAD_OK;
}

static rad_status parse_mc_params(const solve_options *o, rad_mc_params *mp)
{
    rad_status st = RAD_OK;
    rad_mc_params_default(mp);
    unsigned long long v;
    if (o->samples) {
        if ((st = parse_count("--samples", o->samples, 2, 1ull << 40, &v)) != RAD_OK)
            return st;
        mp->samples = (long long)v;
    }
    if (o->seed) {
        if ((st = parse_count("--seed", o->seed, 0, ~0ull, &v)) != RAD_OK)
            return st;
        mp->seed = v;
    }
    int threads = 0;
    if (o->threads &&
        (st = cli_parse_positive_int("solve: --threads", o->threads, 1024, &threads)) != RAD_OK)
        return st;
    if (threads > 0)
        omp_set_num_threads(threads);
    return RAD_OK;
}

static void mc_progress(double done, void *ctx)
{
    (void)ctx;
    fprintf(stderr, "\rradkit: mc paths %5.1f%%", 100.0 * done);
    fflush(stderr);
}

/* The reference's own error in the measure the studies use: area-weighted
 * standard error over the area-weighted mean reflected radiosity (B - E),
 * three channels summed; and the largest face's standard error on the same
 * scale. */
static void relative_errors(size_t n, const double *area, const double *B, const double *E,
                            const double *se, double *l1, double *worst)
{
    double num = 0.0, den = 0.0, total = 0.0, top = 0.0;
    for (size_t i = 0; i < n; i++) {
        total += area[i];
        for (int c = 0; c < 3; c++) {
            num += area[i] * se[i + c * n];
            den += area[i] * (B[i + c * n] - E[i + c * n]);
            top = rad_dmax(top, se[i + c * n]);
        }
    }
    *l1 = den > 0.0 ? num / den : 0.0;
    *worst = den > 0.0 ? top / (den / (3.0 * total)) : 0.0;
}

int solve_mc(const solve_options *o, const rad_scene_params *sp, const rad_effects_params *ep)
{
    rad_mc_params mp;
    int width, height;
    double exposure;
    rad_status st = refuse_other_options(o);
    if (st == RAD_OK)
        st = parse_mc_params(o, &mp);
    if (st == RAD_OK)
        st = solve_parse_image(o, &width, &height, &exposure);
    if (st != RAD_OK)
        return cli_fail(st);

    double t_start = rad_sys_seconds();
    rad_scene *scene = NULL;
    rad_mesh *mesh = NULL;
    rad_vis *vis = NULL;
    double *work = NULL, *corners = NULL;
    rad_io_output table = {0};
    if ((st = rad_scene_load(o->scene, sp, &scene)) != RAD_OK)
        return cli_fail(st);
    if (!o->quiet)
        for (int w = 0; w < rad_scene_warning_count(scene); w++)
            fprintf(stderr, "radkit: warning: %s\n", rad_scene_warning(scene, w));
    int faces = rad_scene_triangle_count(scene);
    size_t n = (size_t)faces;
    const double *xyz = rad_scene_vertices(scene);
    const int *tri = rad_scene_triangles(scene);
    size_t nv = (size_t)rad_scene_vertex_count(scene);
    if ((st = rad_mesh_create(xyz, (int)nv, tri, faces, NULL, &mesh)) != RAD_OK)
        goto done;
    rad_effects_plan plan;
    if ((st = rad_scene_effects_plan(scene, mesh, ep, &plan)) != RAD_OK)
        goto done;
    if (plan.refusal[0]) {
        st = RAD_ERROR(RAD_ENUMERIC, "solve: %s", plan.refusal);
        goto done;
    }
    work = malloc(n * 13 * sizeof *work);
    if (!work) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d faces", faces);
        goto done;
    }
    double *rho = work, *E = work + 3 * n, *B = work + 6 * n, *se = work + 9 * n,
           *area = work + 12 * n;
    const int *tri_mat = rad_scene_triangle_materials(scene);
    const rad_scene_material *mats = rad_scene_materials(scene);
    for (size_t i = 0; i < n; i++) {
        const double *a = xyz + 3 * (size_t)tri[3 * i], *b = xyz + 3 * (size_t)tri[3 * i + 1],
                     *c = xyz + 3 * (size_t)tri[3 * i + 2];
        area[i] = rad_geom_triangle_area(rad_vec3_make(a[0], a[1], a[2]),
                                         rad_vec3_make(b[0], b[1], b[2]),
                                         rad_vec3_make(c[0], c[1], c[2]));
        for (int ch = 0; ch < 3; ch++) {
            rho[i + ch * n] = mats[tri_mat[i]].rho[ch];
            E[i + ch * n] = mats[tri_mat[i]].emission[ch];
        }
    }
    double t_setup = rad_sys_seconds();
    /* Paths need closest hits in every scene; the plan decides only whether
     * shadow rays are needed.  A small ray epsilon: hits on a path vertex's own
     * triangle are rejected by id, the epsilon only guards the far end. */
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    vp.eps_rel = 1e-6;
    if ((st = rad_vis_create(xyz, nv, tri, n, &vp, &vis)) != RAD_OK)
        goto done;
    double t_vis = rad_sys_seconds();
    mp.occlusion = plan.occlusion.on;
    int show_progress = !o->quiet && isatty(2);
    if (show_progress)
        mp.progress = mc_progress;
    rad_mc_stats ms;
    st = rad_mc_solve(xyz, nv, tri, n, rho, E, vis, &mp, B, se, &ms);
    if (show_progress)
        fputc('\n', stderr);
    if (st != RAD_OK || (st = solve_check_answer("mc", (size_t)n, B)) != RAD_OK)
        goto done;
    double t_paths = rad_sys_seconds();
    double se_l1 = 0.0, se_worst = 0.0;
    relative_errors(n, area, B, E, se, &se_l1, &se_worst);

    if ((st = rad_io_output_open(o->out ? o->out : "-", 0, &table)) != RAD_OK)
        goto done;
    FILE *out = table.f;
    fprintf(out, "# radkit %s solve\n# scene = %s\n# method = mc\n", RAD_VERSION, o->scene);
    fprintf(out, "# samples = %lld\n# seed = %llu\n# batches = %d\n# faces = %d\n# elements = %d\n",
            ms.samples_per_face, mp.seed, ms.batches, faces, faces);
    for (int w = 0; w < rad_scene_warning_count(scene); w++)
        fprintf(out, "# warning = %s\n", rad_scene_warning(scene, w));
    solve_print_effects(out, &plan);
    fprintf(out, "# paths = %lld\n# rays = %lld\n# bounces = %lld\n# rays_per_path = %.4f\n",
            ms.paths, ms.rays, ms.bounces, ms.paths ? (double)ms.rays / (double)ms.paths : 0.0);
    fprintf(out, "# se_rel_l1 = %.3e\n# se_rel_max = %.3e\n", se_l1, se_worst);
    fprintf(out, "# time_setup_s = %.4f\n# time_visibility_s = %.4f\n# time_paths_s = %.4f\n"
                 "# time_total_s = %.4f\n# paths_per_s = %.4g\n# memory_peak_bytes = %.0f\n",
            t_setup - t_start, t_vis - t_setup, t_paths - t_vis, rad_sys_seconds() - t_start,
            t_paths > t_vis ? (double)ms.paths / (t_paths - t_vis) : 0.0,
            rad_sys_peak_rss_bytes());
    rad_io_print_faces_se(out, n, area, B, se);
    if ((st = rad_io_output_commit(&table)) != RAD_OK)
        goto done;

    double t_render = 0.0;
    if (o->ply || o->png) {
        if (o->edges) {
            corners = malloc(n * 9 * sizeof *corners);
            if (!corners) {
                st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu outlines", n);
                goto done;
            }
            for (size_t i = 0; i < n; i++)
                for (int v = 0; v < 3; v++)
                    memcpy(corners + 9 * i + 3 * v, xyz + 3 * (size_t)tri[3 * i + v],
                           3 * sizeof *xyz);
        }
        solve_display d = {nv, n, xyz, tri, tri_mat, E, B, corners};
        if ((st = solve_write_display(o, scene, &d, &t_render)) != RAD_OK)
            goto done;
    }
    if (o->stats) {
        rad_io_effect effects[RAD_EFFECT_COUNT];
        solve_effects_json(&plan, effects);
        rad_io_phase phases[4] = {{"setup", t_setup - t_start},
                                  {"visibility", t_vis - t_setup},
                                  {"paths", t_paths - t_vis},
                                  {"render", t_render}};
        rad_io_figure details[6] = {
            {"samples_per_face", (double)ms.samples_per_face},
            {"batches", ms.batches},
            {"paths", (double)ms.paths},
            {"bounces", (double)ms.bounces},
            {"se_rel_l1", se_l1},
            {"se_rel_max", se_worst}};
        rad_io_stats js = {
            .method = "mc", .faces = faces, .elements = faces, .links = 0,
            .rays = ms.rays, .kernel_evals = 0, .phases = phases, .nphases = 4,
            .total_seconds = rad_sys_seconds() - t_start,
            .memory_peak_bytes = rad_sys_peak_rss_bytes(), .effects = effects, .neffects = RAD_EFFECT_COUNT,
            .solver_name = "path-tracing", .solver_iterations = ms.paths,
            .solver_residual = se_l1, .details = details, .ndetails = 6};
        st = rad_io_write_stats_json(o->stats, &js);
    }
done:
    rad_io_output_discard(&table);
    free(work);
    free(corners);
    rad_vis_destroy(vis);
    rad_mesh_destroy(mesh);
    rad_scene_destroy(scene);
    return st == RAD_OK ? 0 : cli_fail(st);
}
