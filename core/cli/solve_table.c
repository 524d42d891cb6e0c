/* radkit solve: a solution as the table ('#' lines, then one row per input
 * triangle) and as the --stats JSON.  The '#' lines follow one order for
 * every method: the parameters used, the scene's warnings, the effects plan,
 * the work done, the solver's figures, the phase times. */
#include <stdio.h>

#include "rad_dense.h"
#include "rad_ff.h"
#include "rad_io.h"
#include "rad_sys.h"
#include "rad_version.h"
#include "solve.h"

static void print_params(FILE *out, const rad_solution *s)
{
    const rad_solve_params *u = &s->used;
    char rule[64];
    switch (s->method) {
    case RAD_SOLVE_DENSE:
        rad_ff_rule_format(u->assembly.rule, rule, sizeof rule);
        fprintf(out, "# rule = %s\n# tol = %g\n# solver = %s\n", rule, u->assembly.ff.tol,
                rad_dense_method_name(u->dense.method));
        fprintf(out, "# basis = p%d\n# faces = %d\n# elements = %zu\n# refine = %d\n", u->basis,
                s->faces, s->elements, u->refine);
        break;
    case RAD_SOLVE_HIER:
    case RAD_SOLVE_CLUSTER:
        rad_ff_rule_format(u->hier.rule, rule, sizeof rule);
        fprintf(out, "# oracle = %s\n# rule = %s\n# tol = %g\n# eps = %g\n# min_area = %g\n"
                     "# max_tighten = %d\n# max_links = %zu\n# clip_blockers = %d\n"
                     "# solver_tol = %g\n",
                rad_hier_oracle_name(u->hier.oracle), rule, u->hier.ff.tol, u->hier.eps,
                u->hier.min_area, u->hier.max_tighten, u->hier.max_links, u->hier.clip_blockers,
                u->hier.tol);
        fprintf(out, "# basis = p%d\n# faces = %d\n# elements = %zu\n# nodes = %zu\n"
                     "# max_depth = %d\n",
                u->basis, s->faces, s->hier.elements, s->hier.nodes, s->hier.max_depth);
        if (s->hier.clusters > 0)
            fprintf(out, "# cluster_model = %s\n# clusters = %zu\n",
                    rad_hier_cluster_model_name(u->hier.cluster_model), s->hier.clusters);
        break;
    case RAD_SOLVE_MC:
        fprintf(out, "# samples = %lld\n# seed = %llu\n# batches = %d\n# faces = %d\n"
                     "# elements = %d\n",
                s->mc.samples_per_face, u->mc.seed, s->mc.batches, s->faces, s->faces);
        break;
    }
}

static void print_work(FILE *out, const rad_solution *s)
{
    const rad_radiosity_stats *as = &s->assembly;
    const rad_hier_stats *hs = &s->hier;
    switch (s->method) {
    case RAD_SOLVE_DENSE:
        fprintf(out, "# pairs = %lld\n# pairs_not_facing = %lld\n# pairs_occlusion_tested = %lld\n"
                     "# pairs_visibility_sampled = %lld\n# visibility_error = %.3e\n",
                as->pairs, as->pairs_not_facing, as->pairs_occlusion_tested, as->pairs_sampled,
                as->visibility_error);
        fprintf(out, "# pairs_out_of_range = %lld\n# rows_closed = %.3e\n# rays = %llu\n"
                     "# kernel_evals = %lld\n",
                as->pairs_out_of_range, as->rows_closed, as->rays, as->kernel_evals);
        fprintf(out, "# systems = %d\n# solver_factorizations = %d\n# solver_iterations = %d\n"
                     "# solver_residual = %.3e\n# rcond = %.3e\n",
                s->systems, s->dense.factorizations, s->dense.iterations, s->dense.residual,
                s->dense.rcond);
        break;
    case RAD_SOLVE_HIER:
    case RAD_SOLVE_CLUSTER:
        if (hs->clusters > 0)
            fprintf(out, "# links_cluster = %zu\n", hs->links_cluster);
        fprintf(out, "# links = %zu\n# links_leaf = %zu\n# links_clear = %zu\n"
                     "# links_visible = %zu\n# links_partial = %zu\n# links_blocked = %zu\n"
                     "# links_unknown = %zu\n# links_sampled = %zu\n# links_constant = %zu\n",
                hs->links, hs->links_leaf, hs->links_clear, hs->links_visible, hs->links_partial,
                hs->links_blocked, hs->links_unknown, hs->links_sampled, hs->links_constant);
        fprintf(out, "# iterations = %lld\n# refinements = %lld\n# rounds = %d\n"
                     "# residual = %.3e\n",
                hs->iterations, hs->refinements, hs->rounds, hs->residual);
        fprintf(out, "# error_estimate = %.3e\n# error_estimate_l1 = %.3e\n"
                     "# error_estimate_leaf_max = %.3e\n# error_target_met = %s\n"
                     "# links_bound = %lld\n# tightenings = %d\n# tightened_share = %.4f\n",
                hs->bound_face_max, hs->bound_mean, hs->bound_leaf_max,
                hs->target_met ? "yes" : "no", hs->links_bound, hs->tightenings,
                hs->tightened_share);
        if (hs->clusters > 0)
            fprintf(out, "# error_local_cluster = %.4f\n", hs->local_cluster);
        if (hs->gain > 0.0)
            fprintf(out, "# gain = %.6f\n", hs->gain);
        fprintf(out, "# rays = %llu\n# kernel_evals = %lld\n", hs->rays, hs->kernel_evals);
        fprintf(out, "# iterations_bound = %lld\n# time_estimate_cluster_s = %.4f\n"
                     "# time_estimate_element_s = %.4f\n# time_bound_s = %.4f\n",
                hs->iterations_bound, hs->time_estimate_cluster_s, hs->time_estimate_element_s,
                hs->time_bound_s);
        break;
    case RAD_SOLVE_MC:
        fprintf(out, "# paths = %lld\n# rays = %lld\n# bounces = %lld\n# rays_per_path = %.4f\n",
                s->mc.paths, s->mc.rays, s->mc.bounces,
                s->mc.paths ? (double)s->mc.rays / (double)s->mc.paths : 0.0);
        fprintf(out, "# se_rel_l1 = %.3e\n# se_rel_max = %.3e\n", s->se_rel_l1, s->se_rel_max);
        break;
    }
}

void solve_print_table(FILE *out, const solve_options *o, const rad_scene *scene,
                       const rad_solution *s)
{
    fprintf(out, "# radkit %s solve\n# scene = %s\n# method = %s\n", RAD_VERSION, o->scene,
            rad_solve_method_name(s->method));
    print_params(out, s);
    for (int w = 0; w < rad_scene_warning_count(scene); w++)
        fprintf(out, "# warning = %s\n", rad_scene_warning(scene, w));
    solve_print_effects(out, &s->plan);
    print_work(out, s);
    for (int k = 0; k < s->nphases; k++)
        fprintf(out, "# time_%s_s = %.4f\n", s->phases[k].name, s->phases[k].seconds);
    fprintf(out, "# time_total_s = %.4f\n", s->total_seconds);
    if (s->method == RAD_SOLVE_MC) {
        double paths_s = s->nphases > 2 ? s->phases[2].seconds : 0.0;
        fprintf(out, "# paths_per_s = %.4g\n", paths_s > 0.0 ? (double)s->mc.paths / paths_s : 0.0);
    }
    fprintf(out, "# memory_peak_bytes = %.0f\n", rad_sys_peak_rss_bytes());
    if (s->face_se)
        rad_io_print_faces_se(out, (size_t)s->faces, s->face_area, s->face_B, s->face_se);
    else
        rad_io_print_faces(out, (size_t)s->faces, s->face_area, s->face_B);
}

rad_status solve_write_stats(const char *path, const rad_solution *s, double render_s)
{
    return solve_write_stats_ranks(path, s, render_s, 0, 0.0);
}

rad_status solve_write_stats_ranks(const char *path, const rad_solution *s, double render_s,
                                   int ranks, double memory_per_rank)
{
    rad_io_effect effects[RAD_EFFECT_COUNT];
    solve_effects_json(&s->plan, effects);
    rad_io_phase phases[RAD_SOLVE_MAX_PHASES + 1];
    for (int k = 0; k < s->nphases; k++)
        phases[k] = (rad_io_phase){s->phases[k].name, s->phases[k].seconds};
    phases[s->nphases] = (rad_io_phase){"render", render_s};
    const rad_hier_stats *hs = &s->hier;
    rad_io_figure hier_details[] = {
        {"nodes", (double)hs->nodes},
        {"max_depth", hs->max_depth},
        {"links_leaf", (double)hs->links_leaf},
        {"links_clear", (double)hs->links_clear},
        {"links_visible", (double)hs->links_visible},
        {"links_partial", (double)hs->links_partial},
        {"links_blocked", (double)hs->links_blocked},
        {"links_sampled", (double)hs->links_sampled},
        {"links_unknown", (double)hs->links_unknown},
        {"links_constant", (double)hs->links_constant},
        {"refinements", (double)hs->refinements},
        {"rounds", hs->rounds},
        {"eps", s->used.hier.eps},
        {"min_area", s->used.hier.min_area},
        {"max_tighten", s->used.hier.max_tighten},
        {"max_links", (double)s->used.hier.max_links},
        {"clip_blockers", s->used.hier.clip_blockers},
        {"oracle_error", s->used.hier.oracle == RAD_HIER_ORACLE_ERROR},
        {"error_estimate", hs->bound_face_max},
        {"error_estimate_l1", hs->bound_mean},
        {"error_estimate_leaf_max", hs->bound_leaf_max},
        {"error_target_met", hs->target_met},
        {"links_bound", (double)hs->links_bound},
        {"tightenings", hs->tightenings},
        {"tightened_share", hs->tightened_share},
        {"gain", hs->gain},
        {"error_local_cluster", hs->local_cluster},
        {"clusters", (double)hs->clusters},
        {"links_cluster", (double)hs->links_cluster},
        {"iterations_bound", (double)hs->iterations_bound},
        {"time_estimate_cluster_s", hs->time_estimate_cluster_s},
        {"time_estimate_element_s", hs->time_estimate_element_s},
        {"time_bound_s", hs->time_bound_s}};
    rad_io_figure mc_details[] = {
        {"samples_per_face", (double)s->mc.samples_per_face},
        {"batches", s->mc.batches},
        {"paths", (double)s->mc.paths},
        {"bounces", (double)s->mc.bounces},
        {"se_rel_l1", s->se_rel_l1},
        {"se_rel_max", s->se_rel_max}};
    rad_io_figure dense_details[] = {{"systems", s->systems},
                                     {"pairs_not_facing", (double)s->assembly.pairs_not_facing}};
    rad_io_stats js = {
        .method = rad_solve_method_name(s->method), .faces = s->faces,
        .elements = (long long)s->elements, .links = s->links, .rays = (long long)s->rays,
        .kernel_evals = s->kernel_evals, .phases = phases, .nphases = (size_t)s->nphases + 1,
        .total_seconds = s->total_seconds + render_s,
        .memory_peak_bytes = rad_sys_peak_rss_bytes(), .effects = effects,
        .neffects = RAD_EFFECT_COUNT, .solver_name = s->solver_name,
        .solver_iterations = s->solver_iterations, .solver_residual = s->solver_residual,
        .ranks = ranks, .memory_peak_bytes_per_rank = memory_per_rank};
    if (s->method == RAD_SOLVE_HIER || s->method == RAD_SOLVE_CLUSTER) {
        js.details = hier_details;
        js.ndetails = sizeof hier_details / sizeof hier_details[0];
    } else if (s->method == RAD_SOLVE_MC) {
        js.details = mc_details;
        js.ndetails = sizeof mc_details / sizeof mc_details[0];
    } else {
        js.details = dense_details;
        js.ndetails = sizeof dense_details / sizeof dense_details[0];
    }
    return rad_io_write_stats_json(path, &js);
}
