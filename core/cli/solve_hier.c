/* radkit solve --method hier: hierarchical radiosity (rad_hier) on the input
 * triangles.  The same table as dense (per input triangle, the area average
 * of its leaves) with '#' lines for the hierarchy's figures; --ply and --png
 * show the leaves through their conforming mesh (rad_mesh_conform_leaves:
 * T-vertices resolved, so vertex colours are smooth), --edges draws the
 * leaves' edges, --stats adds the hierarchy's figures under "details".
 * Visibility is built over the input triangles when the plan says something
 * can occlude. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <omp.h>
#include <unistd.h>

#include "rad_ff.h"
#include "rad_hier.h"
#include "rad_io.h"
#include "rad_mesh.h"
#include "rad_sys.h"
#include "rad_version.h"
#include "solve.h"

/* The options of the dense path that mean nothing here. */
static rad_status refuse_dense_options(const solve_options *o)
{
    const char *dense_only[3][2] = {{"--solver", o->solver}, {"--refine", o->refine},
                                    {"--vis-strata", o->strata}};
    for (int k = 0; k < 3; k++)
        if (dense_only[k][1])
            return RAD_ERROR(RAD_EINVAL, "solve: %s applies to --method dense only",
                             dense_only[k][0]);
    return RAD_OK;
}

static rad_status parse_hier_params(const solve_options *o, rad_hier_params *hp, int *min_area_given)
{
    rad_status st = RAD_OK;
    rad_hier_params_default(hp);
    if (o->rule && (st = rad_ff_rule_parse(o->rule, &hp->rule)) != RAD_OK)
        return st;
    if (o->rule) { /* an explicit rule gives every link's unoccluded F */
        hp->use_rule = 1;
        hp->far_ratio = 0.0;
    }
    if (o->tol && (st = solve_parse_double("--tol", o->tol, 0.0, &hp->ff.tol)) != RAD_OK)
        return st;
    if (o->eps && (st = solve_parse_double("--eps", o->eps, 0.0, &hp->eps)) != RAD_OK)
        return st;
    if (o->oracle && (st = rad_hier_oracle_parse(o->oracle, &hp->oracle)) != RAD_OK)
        return st;
    *min_area_given = 0;
    if (o->min_area) {
        char *end = NULL;
        double v = strtod(o->min_area, &end);
        if (end == o->min_area || *end != '\0' || !isfinite(v) || v < 0.0)
            return RAD_ERROR(RAD_EINVAL, "solve: --min-area must be a number >= 0, got '%s'",
                             o->min_area);
        hp->min_area = v;
        *min_area_given = 1;
    }
    if (o->solver_tol &&
        (st = solve_parse_double("--solver-tol", o->solver_tol, 0.0, &hp->tol)) != RAD_OK)
        return st;
    if (o->max_iter && (st = cli_parse_positive_int("solve: --max-iter", o->max_iter, 100000000,
                                                    &hp->max_iterations)) != RAD_OK)
        return st;
    int threads = 0;
    if (o->threads &&
        (st = cli_parse_positive_int("solve: --threads", o->threads, 1024, &threads)) != RAD_OK)
        return st;
    /* rad_hier estimates new links on OpenMP's threads; results do not depend on their number */
    if (threads > 0)
        omp_set_num_threads(threads);
    return RAD_OK;
}

/* Progress on a terminal: one line per refinement round (rad_hier_params). */
static void hier_progress(int round, size_t leaves, size_t links, void *ctx)
{
    (void)ctx;
    fprintf(stderr, "\rradkit: hier round %d: %zu leaves, %zu links   ", round, leaves, links);
    fflush(stderr);
}

/* The leaves' conforming mesh as a display (solve.h); the arrays belong to *a
 * (hier_display_free). */
typedef struct hier_display_arrays {
    double *corners, *xyz, *E, *B;
    int *tri, *leaf, *material;
} hier_display_arrays;

static rad_status hier_display(const rad_hier *h, const rad_scene *scene, size_t n,
                               const int *leaf_face, const double *leaf_B,
                               hier_display_arrays *a, solve_display *d)
{
    memset(a, 0, sizeof *a);
    a->corners = malloc(n * 9 * sizeof *a->corners);
    if (!a->corners)
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu leaves", n);
    rad_hier_leaves(h, NULL, NULL, a->corners, NULL);
    size_t nv = 0, nt = 0;
    rad_status st = rad_mesh_conform_leaves(a->corners, n, &a->xyz, &nv, &a->tri, &a->leaf, &nt);
    if (st != RAD_OK)
        return st;
    a->material = malloc(nt * sizeof *a->material);
    a->E = malloc(nt * 3 * sizeof *a->E);
    a->B = malloc(nt * 3 * sizeof *a->B);
    double *outline = malloc(nt * 9 * sizeof *outline);
    if (!a->material || !a->E || !a->B || !outline) {
        free(outline);
        return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu display triangles", nt);
    }
    const int *tri_mat = rad_scene_triangle_materials(scene);
    const rad_scene_material *mats = rad_scene_materials(scene);
    for (size_t t = 0; t < nt; t++) {
        size_t l = (size_t)a->leaf[t];
        int f = leaf_face[l];
        a->material[t] = tri_mat[f];
        memcpy(outline + 9 * t, a->corners + 9 * l, 9 * sizeof *outline);
        for (int c = 0; c < 3; c++) {
            a->E[t + c * nt] = mats[tri_mat[f]].emission[c];
            a->B[t + c * nt] = leaf_B[l + c * n];
        }
    }
    /* the outlines replace the leaf corners (same size per leaf, now per triangle) */
    free(a->corners);
    a->corners = outline;
    *d = (solve_display){nv, nt, a->xyz, a->tri, a->material, a->E, a->B, a->corners};
    return RAD_OK;
}

static void hier_display_free(hier_display_arrays *a)
{
    free(a->corners);
    free(a->xyz);
    free(a->E);
    free(a->B);
    free(a->tri);
    free(a->leaf);
    free(a->material);
}

int solve_hier(const solve_options *o, const rad_scene_params *sp, const rad_effects_params *ep)
{
    rad_hier_params hp;
    int min_area_given = 0, width, height;
    double exposure;
    rad_status st = refuse_dense_options(o);
    if (st == RAD_OK)
        st = parse_hier_params(o, &hp, &min_area_given);
    if (st == RAD_OK)
        st = solve_parse_image(o, &width, &height, &exposure);
    if (st != RAD_OK)
        return cli_fail(st);

    double t_start = rad_sys_seconds();
    rad_scene *scene = NULL;
    rad_mesh *base = NULL;
    rad_vis *vis = NULL;
    rad_hier *h = NULL;
    double *work = NULL, *leaf = NULL, *face_area = NULL;
    int *leaf_face = NULL;
    hier_display_arrays disp_arrays;
    memset(&disp_arrays, 0, sizeof disp_arrays);
    rad_io_output table = {0};
    if ((st = rad_scene_load(o->scene, sp, &scene)) != RAD_OK)
        return cli_fail(st);
    if (!o->quiet)
        for (int w = 0; w < rad_scene_warning_count(scene); w++)
            fprintf(stderr, "radkit: warning: %s\n", rad_scene_warning(scene, w));
    int faces = rad_scene_triangle_count(scene);
    if ((st = rad_mesh_create(rad_scene_vertices(scene), rad_scene_vertex_count(scene),
                              rad_scene_triangles(scene), faces, NULL, &base)) != RAD_OK)
        goto done;
    rad_effects_plan plan;
    if ((st = rad_scene_effects_plan(scene, base, ep, &plan)) != RAD_OK)
        goto done;
    if (plan.refusal[0]) {
        st = RAD_ERROR(RAD_ENUMERIC, "solve: %s", plan.refusal);
        goto done;
    }
    rad_scene_summary sum;
    rad_scene_summarize(scene, &sum);
    /* The default minimum area follows eps (an element's P0 error is about
     * its size times the gradient: area ~ eps^2), so that it does not cap the
     * accuracy asked for; where it does bind, the stats say so. */
    if (!min_area_given)
        hp.min_area = sum.total_area * fmin(1e-4, fmax(1e-10, 1e-2 * hp.eps * hp.eps));
    hp.sealed = plan.sealed;
    /* Reflectance near 1: the solver's stopping tests tightened (effects plan) */
    hp.tol *= plan.tighten;
    hp.bound_tol *= plan.tighten;
    work = malloc((size_t)faces * 6 * sizeof *work);
    if (!work) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d faces", faces);
        goto done;
    }
    double *rho = work, *E = work + 3 * (size_t)faces;
    const int *tri_mat = rad_scene_triangle_materials(scene);
    const rad_scene_material *mats = rad_scene_materials(scene);
    for (int i = 0; i < faces; i++)
        for (int c = 0; c < 3; c++) {
            rho[i + c * faces] = mats[tri_mat[i]].rho[c];
            E[i + c * faces] = mats[tri_mat[i]].emission[c];
        }
    double t_setup = rad_sys_seconds();
    /* Visibility over the input triangles: a link's samples lie on its two
     * elements, and rad_vis ignores hits on the input triangles they lie on. */
    if (plan.occlusion.on) {
        rad_vis_params vp;
        rad_vis_params_default(&vp);
        if ((st = rad_vis_create(rad_scene_vertices(scene), (size_t)rad_scene_vertex_count(scene),
                                 rad_scene_triangles(scene), (size_t)faces, &vp, &vis)) != RAD_OK)
            goto done;
    }
    double t_vis = rad_sys_seconds();
    int show_progress = !o->quiet && isatty(2);
    if (show_progress)
        hp.progress = hier_progress;
    st = rad_hier_create(rad_scene_vertices(scene), (size_t)rad_scene_vertex_count(scene),
                         rad_scene_triangles(scene), (size_t)faces, rho, E, vis, &hp, &h);
    if (st == RAD_OK)
        st = rad_hier_solve(h);
    if (show_progress)
        fputc('\n', stderr);
    if (st != RAD_OK)
        goto done;
    rad_hier_stats hs;
    rad_hier_get_stats(h, &hs);
    if (!hs.target_met && !o->quiet) {
        fprintf(stderr, "radkit: warning: the error estimate %.3g (worst input triangle, "
                        "relative to the mean reflected radiosity) exceeds --eps %g", hs.bound_face_max,
                hp.eps);
        if (hs.links_bound > 0)
            fprintf(stderr, ": %lld links could not be refined further (--min-area or the depth "
                            "limit binds)\n", hs.links_bound);
        else
            fprintf(stderr, " after the oracle tightened its thresholds 64-fold (the estimate "
                            "is conservative: see error_estimate_l1)\n");
    }
    size_t n = rad_hier_leaf_count(h);
    leaf = malloc(n * 4 * sizeof *leaf);
    leaf_face = malloc(n * sizeof *leaf_face);
    face_area = calloc((size_t)faces * 4, sizeof *face_area);
    if (!leaf || !leaf_face || !face_area) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %zu elements", n);
        goto done;
    }
    double *area = leaf, *B = leaf + n, *face_B = face_area + faces;
    rad_hier_leaves(h, leaf_face, area, NULL, B);
    if ((st = rad_io_face_averages(n, leaf_face, area, B, (size_t)faces, face_area, face_B)) !=
        RAD_OK)
        goto done;
    if ((st = solve_check_answer("hier", (size_t)faces, face_B)) != RAD_OK)
        goto done;
    if ((st = rad_io_output_open(o->out ? o->out : "-", 0, &table)) != RAD_OK)
        goto done;
    FILE *out = table.f;
    char rule_text[64];
    rad_ff_rule_format(hp.rule, rule_text, sizeof rule_text);
    fprintf(out, "# radkit %s solve\n# scene = %s\n# method = hier\n# oracle = %s\n",
            RAD_VERSION, o->scene, rad_hier_oracle_name(hp.oracle));
    fprintf(out, "# rule = %s\n# tol = %g\n# eps = %g\n# min_area = %g\n# solver_tol = %g\n",
            rule_text, hp.ff.tol, hp.eps, hp.min_area, hp.tol);
    fprintf(out, "# faces = %d\n# elements = %zu\n# nodes = %zu\n# max_depth = %d\n", faces,
            hs.elements, hs.nodes, hs.max_depth);
    fprintf(out, "# links = %zu\n# links_leaf = %zu\n# links_clear = %zu\n# links_visible = %zu\n"
                 "# links_partial = %zu\n# links_blocked = %zu\n# links_unknown = %zu\n",
            hs.links, hs.links_leaf, hs.links_clear, hs.links_visible, hs.links_partial,
            hs.links_blocked, hs.links_unknown);
    fprintf(out, "# iterations = %lld\n# refinements = %lld\n# rounds = %d\n# residual = %.3e\n",
            hs.iterations, hs.refinements, hs.rounds, hs.residual);
    fprintf(out, "# error_estimate = %.3e\n# error_estimate_l1 = %.3e\n"
                 "# error_estimate_leaf_max = %.3e\n# error_target_met = %s\n"
                 "# links_bound = %lld\n",
            hs.bound_face_max, hs.bound_mean, hs.bound_leaf_max, hs.target_met ? "yes" : "no",
            hs.links_bound);
    for (int w = 0; w < rad_scene_warning_count(scene); w++)
        fprintf(out, "# warning = %s\n", rad_scene_warning(scene, w));
    solve_print_effects(out, &plan);
    fprintf(out, "# rays = %llu\n# kernel_evals = %lld\n", hs.rays, hs.kernel_evals);
    fprintf(out, "# time_setup_s = %.4f\n# time_visibility_s = %.4f\n# time_link_s = %.4f\n"
                 "# time_refine_s = %.4f\n# time_solve_s = %.4f\n# time_total_s = %.4f\n"
                 "# memory_peak_bytes = %.0f\n",
            t_setup - t_start, t_vis - t_setup, hs.time_link_s, hs.time_refine_s,
            hs.time_solve_s, rad_sys_seconds() - t_start, rad_sys_peak_rss_bytes());
    rad_io_print_faces(out, (size_t)faces, face_area, face_B);
    if ((st = rad_io_output_commit(&table)) != RAD_OK)
        goto done;

    double t_render = 0.0;
    if (o->ply || o->png) {
        solve_display d;
        if ((st = hier_display(h, scene, n, leaf_face, B, &disp_arrays, &d)) != RAD_OK ||
            (st = solve_write_display(o, scene, &d, &t_render)) != RAD_OK)
            goto done;
    }
    if (o->stats) {
        rad_io_effect effects[RAD_EFFECT_COUNT];
        solve_effects_json(&plan, effects);
        rad_io_phase phases[6] = {{"setup", t_setup - t_start}, {"visibility", t_vis - t_setup},
                                  {"link", hs.time_link_s},     {"refine", hs.time_refine_s},
                                  {"solve", hs.time_solve_s},   {"render", t_render}};
        rad_io_figure details[18] = {
            {"nodes", (double)hs.nodes},
            {"max_depth", hs.max_depth},
            {"links_leaf", (double)hs.links_leaf},
            {"links_clear", (double)hs.links_clear},
            {"links_visible", (double)hs.links_visible},
            {"links_partial", (double)hs.links_partial},
            {"links_blocked", (double)hs.links_blocked},
            {"links_unknown", (double)hs.links_unknown},
            {"refinements", (double)hs.refinements},
            {"rounds", hs.rounds},
            {"eps", hp.eps},
            {"min_area", hp.min_area},
            {"oracle_error", hp.oracle == RAD_HIER_ORACLE_ERROR},
            {"error_estimate", hs.bound_face_max},
            {"error_estimate_l1", hs.bound_mean},
            {"error_estimate_leaf_max", hs.bound_leaf_max},
            {"error_target_met", hs.target_met},
            {"links_bound", (double)hs.links_bound}};
        rad_io_stats js = {
            .method = "hier", .faces = faces, .elements = (long long)hs.elements,
            .links = (long long)hs.links, .rays = (long long)hs.rays,
            .kernel_evals = hs.kernel_evals, .phases = phases, .nphases = 6,
            .total_seconds = rad_sys_seconds() - t_start,
            .memory_peak_bytes = rad_sys_peak_rss_bytes(), .effects = effects, .neffects = RAD_EFFECT_COUNT,
            .solver_name = "jacobi-push-pull", .solver_iterations = hs.iterations,
            .solver_residual = hs.residual, .details = details, .ndetails = 18};
        st = rad_io_write_stats_json(o->stats, &js);
    }
done:
    rad_io_output_discard(&table);
    hier_display_free(&disp_arrays);
    free(work);
    free(leaf);
    free(leaf_face);
    free(face_area);
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
    rad_mesh_destroy(base);
    rad_scene_destroy(scene);
    return st == RAD_OK ? 0 : cli_fail(st);
}
