/* radkit solve: a scene in, radiosities out (dense Galerkin radiosity, or
 * hierarchical radiosity with --method hier: solve_hier below).
 *
 * The data flow of DESIGN.md, one step per function below: load and validate
 * the scene; build its mesh and refine it; decide the effects plan; check the
 * dense size; build visibility only if the plan says something can occlude;
 * assemble G = A F V; solve for B per channel; write the outputs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "solve.h"
#include "rad_dense.h"
#include "rad_dense_solve.h"
#include "rad_ff.h"
#include "rad_geom.h"
#include "rad_hier.h"
#include "rad_io.h"
#include "rad_mesh.h"
#include "rad_radiosity.h"
#include "rad_render.h"
#include "rad_scene.h"
#include "rad_sys.h"
#include "rad_version.h"
#include "rad_vis.h"

static const char help_head[] =
    "usage: radkit solve SCENE [--method dense|hier|mc] [--rule RULE] [--tol T] [--solver S]\n"
    "                    [--oracle bf|error] [--eps E] [--min-area A] [--edges]\n"
    "                    [--samples N] [--seed S]\n"
    "                    [--refine K] [--threads N] [--out faces.tsv] [--ply out.ply]\n"
    "                    [--png out.png] [--image-size WxH] [--exposure X]\n"
    "                    [--stats stats.json] [--quiet]\n"
    "                    [--solver-tol T] [--max-iter N] [--vis-strata K]\n"
    "                    [scene options]\n"
    "\n"
    "Solve B = E + rho F B on the triangles of SCENE by Galerkin radiosity with\n"
    "piecewise-constant elements, dense or hierarchical, or estimate it by Monte\n"
    "Carlo path tracing, and print one row per input triangle.\n"
    "\n"
    "  --method M       dense (default), mc or hier.  mc: Monte Carlo, the\n"
    "                   independent reference: per input triangle the area-average\n"
    "                   radiosity and its standard error (columns se_r se_g se_b)\n"
    "                   by path tracing from stratified points of the triangle,\n"
    "                   next-event estimation and cosine continuation combined by\n"
    "                   multiple importance sampling, Russian roulette; no form\n"
    "                   factors, no mesh.  hier: hierarchical radiosity (Hanrahan,\n"
    "                   Salzman, Aupperle 1991): element quadtrees over the input\n"
    "                   triangles, links between elements at the level their\n"
    "                   error allows, refined by an oracle; a link's F from point\n"
    "                   values with exact visibility on both elements, touching\n"
    "                   elements by ss:5 or the exact rule (a given --rule gives\n"
    "                   every link's unoccluded F instead); --refine, --solver and\n"
    "                   --vis-strata do not apply; --solver-tol stops\n"
    "                   gather/push-pull at a step change of T max B.  The table\n"
    "                   header reports error_estimate: a bound on the worst input\n"
    "                   triangle's error relative to the mean reflected radiosity\n"
    "                   (also _l1, the area-weighted mean, and _leaf_max, the worst\n"
    "                   element), and error_target_met: whether it is within --eps\n"
    "  --oracle O       hier: error (default: refine the links whose share of an\n"
    "                   input triangle's error bound is largest, until every\n"
    "                   triangle's bound meets --eps or --min-area stops it) or bf\n"
    "                   (refine a link when the radiosity it brings, rho F B,\n"
    "                   exceeds eps times the mean reflected radiosity; HSA 1991)\n"
    "  --eps E          hier: the error target: each input triangle's radiosity\n"
    "                   error (a row of the table) within E times the\n"
    "                   area-weighted mean reflected radiosity (B - E, channels\n"
    "                   averaged); > 0, default 0.1.  The bound is conservative\n"
    "                   (the Cornell box at 0.01: estimate 8.6%, error 1.4% worst\n"
    "                   face; 2.7% and 0.14% area-weighted)\n"
    "  --min-area A     hier: never split an element into children smaller than A\n"
    "                   (scene units squared, >= 0; default: total area times\n"
    "                   min(1e-4, 0.01 eps^2), so it binds only below eps 0.1;\n"
    "                   where it binds the table says links_bound > 0)\n"
    "  --samples N      mc: paths per input triangle, >= 2 (default 4096; rounded\n"
    "                   up to a multiple of the 32 batches the standard error is\n"
    "                   estimated from)\n"
    "  --seed S         mc: the random seed, a whole number >= 0 (default 1); a\n"
    "                   seed gives the same table for any --threads\n"
    "  --edges          draw element edges (dense: elements; hier: leaves) on --png\n"
    "  --rule RULE      form-factor scheme per pair: vertex, centroid, gauss:P,\n"
    "                   analytic:P, ss:N, exact or auto (default auto)\n"
    "  --tol T          the relative accuracy auto aims for per pair (default 1e-6)\n"
    "  --solver S       lu (default), cholesky, jacobi, gauss-seidel, southwell\n"
    "  --solver-tol T   iterative solvers stop at residual T ||E|| (default 1e-10)\n"
    "  --max-iter N     iterative solvers' sweep cap (default 10000)\n"
    "  --refine K       split every triangle 1 -> 4, K times, before solving (default 0)\n"
    "  --threads N      OpenMP threads for the assembly (hier: for the link\n"
    "                   estimates; mc: for the paths; default: all cores)\n"
    "  --vis-strata K   where a pair's visibility is too complex to clip exactly\n"
    "                   (too many possible blockers): K^2 points per triangle,\n"
    "                   K^4 rays (default 8)\n"
    "  --out FILE       write the table to FILE instead of standard output\n"
    "  --ply FILE       the (refined) mesh as ASCII PLY with per-vertex colours: the\n"
    "                   area-weighted radiosity of the faces around each vertex,\n"
    "                   tone-mapped like the image\n"
    "  --png FILE       an image from the scene's camera (or the default view),\n"
    "                   Embree primary rays, smooth (Gouraud) shading of vertex\n"
    "                   radiosity; tone map: display = 255 (exposure B)^(1/2.2),\n"
    "                   clipped at white\n"
    "  --image-size WxH image size in pixels (default 512x512)\n"
    "  --exposure X     tone-map exposure (default: the 95th percentile of element\n"
    "                   radiosity maps to white)\n"
    "  --stats FILE     JSON with method, faces, elements, links, rays, kernel_evals,\n"
    "                   time_s (per phase and total), memory_peak_bytes, effects,\n"
    "                   solver {name, iterations, residual}\n"
    "  --quiet          no progress on standard error\n";

static const char help_tail[] =
    "\n"
    "Output: '#' lines with the parameters, the effects plan (effect_<name> and\n"
    "effect_<name>_reason), the work done (elements, pairs, rays, kernel_evals),\n"
    "the solver's figures and the phase times; then columns face (input\n"
    "triangle, 0-based, in input order), area, B_r, B_g, B_b.  With --refine the\n"
    "value of a face is the area average over its elements.\n"
    "\n"
    "Files (--out, --ply, --png, --stats; '-' is standard output) are checked\n"
    "before any work: an empty path, a directory, a missing directory, two\n"
    "outputs naming one file (without --out the table is '-') or an output\n"
    "naming the scene is a usage error (exit 2).  Each is written to a temporary file beside it and renamed onto\n"
    "it once complete: a failed write (exit 1) leaves the old file, or none.\n"
    "Devices and pipes (/dev/null) are written in place and never removed.\n"
    "\n"
    "example: radkit solve scenes/cornell/cornell.obj --refine 1 --out cornell.tsv\n";

static void solver_progress(int channel, int iteration, double residual, void *ctx)
{
    (void)ctx;
    fprintf(stderr, "\rradkit: solving channel %d: sweep %d, residual %.2e   ", channel, iteration,
            residual);
    fflush(stderr);
}

static void progress_line(double done, void *ctx)
{
    (void)ctx;
    fprintf(stderr, "\rradkit: assembling %5.1f%%", 100.0 * done);
    fflush(stderr);
}

/* --ply, --png (the elements are the display mesh) and --stats. */
static rad_status write_outputs(const solve_options *o, const rad_scene *scene, const rad_mesh *mesh,
                                const int *element_material, const double *E, const double *B,
                                const rad_effects_plan *plan, const rad_radiosity_stats *as,
                                const rad_dense_report *report, int n, int faces, double t_start,
                                const double phase_s[4])
{
    rad_status st = RAD_OK;
    double *corners = NULL, t_render = 0.0;
    if (o->edges) {
        corners = malloc((size_t)n * 9 * sizeof *corners);
        if (!corners)
            return RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d element outlines", n);
        const double *xyz = rad_mesh_vertices(mesh);
        const int *tri = rad_mesh_triangles(mesh);
        for (int i = 0; i < n; i++)
            for (int v = 0; v < 3; v++)
                memcpy(corners + 9 * (size_t)i + 3 * v, xyz + 3 * (size_t)tri[3 * i + v],
                       3 * sizeof *xyz);
    }
    solve_display d = {(size_t)rad_mesh_vertex_count(mesh), (size_t)n, rad_mesh_vertices(mesh),
                       rad_mesh_triangles(mesh), element_material, E, B, corners};
    st = solve_write_display(o, scene, &d, &t_render);
    free(corners);
    if (st == RAD_OK && o->stats) {
        rad_io_effect effects[RAD_EFFECT_COUNT];
        solve_effects_json(plan, effects);
        rad_io_phase phases[5] = {{"setup", phase_s[0]}, {"visibility", phase_s[1]},
                                  {"assemble", phase_s[2]}, {"solve", phase_s[3]},
                                  {"render", t_render}};
        rad_io_stats js = {
            .method = "dense", .faces = faces, .elements = n, .links = as->pairs - as->pairs_not_facing,
            .rays = (long long)as->rays, .kernel_evals = as->kernel_evals, .phases = phases,
            .nphases = 5, .total_seconds = rad_sys_seconds() - t_start,
            .memory_peak_bytes = rad_sys_peak_rss_bytes(), .effects = effects, .neffects = RAD_EFFECT_COUNT,
            .solver_name = rad_dense_method_name(report->method),
            .solver_iterations = report->iterations, .solver_residual = report->residual,
        };
        st = rad_io_write_stats_json(o->stats, &js);
    }
    return st;
}

int cli_solve(int argc, char **argv)
{
    solve_options o;
    memset(&o, 0, sizeof o);
    cli_scene_options_init(&o.scene_opts);
    /* the command's own options, the shared scene options and the terminator */
    enum { SOLVE_OWN_OPTIONS = 25 };
    cli_option table[SOLVE_OWN_OPTIONS + CLI_SCENE_OPTION_COUNT + 1] = {
        {"", &o.scene, NULL, "scene"},
        {"--method", &o.method, NULL, NULL},
        {"--rule", &o.rule, NULL, NULL},
        {"--tol", &o.tol, NULL, NULL},
        {"--solver", &o.solver, NULL, NULL},
        {"--solver-tol", &o.solver_tol, NULL, NULL},
        {"--max-iter", &o.max_iter, NULL, NULL},
        {"--refine", &o.refine, NULL, NULL},
        {"--threads", &o.threads, NULL, NULL},
        {"--vis-strata", &o.strata, NULL, NULL},
        {"--out", &o.out, NULL, NULL},
        {"--ply", &o.ply, NULL, NULL},
        {"--png", &o.png, NULL, NULL},
        {"--image-size", &o.size, NULL, NULL},
        {"--exposure", &o.exposure, NULL, NULL},
        {"--stats", &o.stats, NULL, NULL},
        {"--quiet", NULL, &o.quiet, NULL},
        {"--help", NULL, &o.help, NULL},
        {"-h", NULL, &o.help, NULL},
        {"--eps", &o.eps, NULL, NULL},
        {"--min-area", &o.min_area, NULL, NULL},
        {"--oracle", &o.oracle, NULL, NULL},
        {"--edges", NULL, &o.edges, NULL},
        {"--samples", &o.samples, NULL, NULL},
        {"--seed", &o.seed, NULL, NULL},
    };
    int nopt = SOLVE_OWN_OPTIONS;
    nopt += cli_scene_options_add(&o.scene_opts, table + nopt);
    table[nopt] = (cli_option){NULL, NULL, NULL, NULL};

    rad_status st = cli_parse("solve", argc, argv, 2, table);
    if (st != RAD_OK)
        return cli_fail(st);
    if (o.help) {
        printf("%s%s%s", help_head, cli_scene_options_help, help_tail);
        return 0;
    }
    if (!o.scene)
        return cli_fail(RAD_ERROR(RAD_EINVAL, "solve: no scene given (see 'radkit solve --help')"));
    /* every output path now, before the work: a typo must not cost a solve */
    if ((st = solve_check_outputs(&o)) != RAD_OK)
        return cli_fail(st);

    /* ---- parameters ---- */
    rad_scene_params sp;
    rad_effects_params ep;
    rad_scene_params_default(&sp);
    rad_scene_effects_params_default(&ep);
    sp.no_cross_check = 1; /* 'radkit info' cross-checks a file with Assimp; solve spares the 50 ms */
    if ((st = cli_scene_options_apply("solve", &o.scene_opts, &sp, &ep)) != RAD_OK)
        return cli_fail(st);
    if (o.method && strcmp(o.method, "mc") == 0)
        return solve_mc(&o, &sp, &ep);
    if (o.samples || o.seed)
        return cli_fail(RAD_ERROR(RAD_EINVAL, "solve: --samples and --seed need --method mc"));
    if (o.method && strcmp(o.method, "hier") == 0)
        return solve_hier(&o, &sp, &ep);
    if (o.eps || o.min_area || o.oracle)
        return cli_fail(RAD_ERROR(RAD_EINVAL, "solve: --eps, --min-area and --oracle need "
                                              "--method hier"));
    if (o.method && strcmp(o.method, "dense") != 0) {
        if (strcmp(o.method, "cluster") == 0)
            return cli_fail(RAD_ERROR(RAD_EINVAL, "solve: --method %s is not available yet; use dense",
                                  o.method));
        return cli_fail(RAD_ERROR(RAD_EINVAL, "solve: unknown method '%s' (expected dense, hier or mc)", o.method));
    }
    rad_radiosity_params ap;
    rad_radiosity_params_default(&ap);
    if (o.rule && (st = rad_ff_rule_parse(o.rule, &ap.rule)) != RAD_OK)
        return cli_fail(st);
    if (o.tol && (st = solve_parse_double("--tol", o.tol, 0.0, &ap.ff.tol)) != RAD_OK)
        return cli_fail(st);
    rad_dense_params dp;
    rad_dense_params_default(&dp);
    if (o.solver && (st = rad_dense_method_parse(o.solver, &dp.method)) != RAD_OK)
        return cli_fail(st);
    if (o.solver_tol && (st = solve_parse_double("--solver-tol", o.solver_tol, 0.0, &dp.tol)) != RAD_OK)
        return cli_fail(st);
    int refine = 0, threads = 0, strata = 8;
    if (o.max_iter && (st = cli_parse_positive_int("solve: --max-iter", o.max_iter, 100000000, &dp.max_iter)) != RAD_OK)
        return cli_fail(st);
    if (o.refine && strcmp(o.refine, "0") != 0 &&
        (st = cli_parse_positive_int("solve: --refine", o.refine, 12, &refine)) != RAD_OK)
        return cli_fail(st);
    if (o.threads && (st = cli_parse_positive_int("solve: --threads", o.threads, 1024, &threads)) != RAD_OK)
        return cli_fail(st);
    if (o.strata && (st = cli_parse_positive_int("solve: --vis-strata", o.strata, 16, &strata)) != RAD_OK)
        return cli_fail(st);
    int width, height;
    double exposure;
    /* checked now, before the heavy work; solve_write_display reads them again */
    if ((st = solve_parse_image(&o, &width, &height, &exposure)) != RAD_OK)
        return cli_fail(st);
    ap.threads = threads;
    int show_progress = !o.quiet && isatty(2);
    if (show_progress) {
        ap.progress = progress_line;
        dp.progress = solver_progress;
    }

    /* ---- scene, mesh, plan ---- */
    double t_start = rad_sys_seconds();
    rad_scene *scene = NULL;
    rad_mesh *base = NULL, *mesh = NULL;
    rad_vis *vis = NULL;
    double *G = NULL, *work = NULL;
    int *element_material = NULL;
    rad_io_output table_out = {0};
    if ((st = rad_scene_load(o.scene, &sp, &scene)) != RAD_OK)
        return cli_fail(st);
    int faces = rad_scene_triangle_count(scene);
    /* The scene's warnings (no emitter, duplicate faces, ...) go to stderr and
     * into the table's header: a scene without light solves to zeros. */
    if (!o.quiet)
        for (int w = 0; w < rad_scene_warning_count(scene); w++)
            fprintf(stderr, "radkit: warning: %s\n", rad_scene_warning(scene, w));
    if ((st = rad_mesh_create(rad_scene_vertices(scene), rad_scene_vertex_count(scene),
                              rad_scene_triangles(scene), faces, NULL, &base)) != RAD_OK)
        goto done;
    rad_effects_plan plan;
    if ((st = rad_scene_effects_plan(scene, base, &ep, &plan)) != RAD_OK)
        goto done;
    if (plan.refusal[0]) {
        st = RAD_ERROR(RAD_ENUMERIC, "solve: %s", plan.refusal);
        goto done;
    }
    /* Reflectance near 1: the defaults' tolerances tightened (effects.c, 6). */
    if (!o.tol)
        ap.ff.tol *= plan.tighten;
    if (!o.solver_tol)
        dp.tol *= plan.tighten;
    ap.visible.tol *= plan.tighten;
    /* The dense limit in elements, before refining into something too big. */
    size_t max_elements = 46340;
    if (refine > 0) {
        if ((st = rad_mesh_refine_uniform(base, refine, max_elements, &mesh)) != RAD_OK) {
            if (st == RAD_ETOOBIG)
                st = RAD_ERROR(RAD_ETOOBIG, "solve: --refine %d makes %.0f elements, beyond what a "
                                            "dense solve can hold; use fewer levels or --method hier",
                               refine, (double)faces * pow(4.0, refine));
            goto done;
        }
    } else {
        mesh = base;
        base = NULL;
    }
    int n = rad_mesh_face_count(mesh);
    if ((st = rad_dense_radiosity_check_size((size_t)n, dp.method)) != RAD_OK)
        goto done;
    double t_setup = rad_sys_seconds();

    /* ---- per-element reflectance and emission (n x 3, column-major) ---- */
    const int *parent = rad_mesh_input_faces(mesh);
    const int *tri_mat = rad_scene_triangle_materials(scene);
    const rad_scene_material *mats = rad_scene_materials(scene);
    work = malloc((size_t)n * 10 * sizeof *work);
    if (!work) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d elements", n);
        goto done;
    }
    double *rho = work, *E = work + 3 * (size_t)n, *B = work + 6 * (size_t)n, *areas = work + 9 * (size_t)n;
    element_material = malloc((size_t)n * sizeof *element_material);
    if (!element_material) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d elements", n);
        goto done;
    }
    for (int i = 0; i < n; i++) {
        element_material[i] = tri_mat[parent[i]];
        const rad_scene_material *m = &mats[tri_mat[parent[i]]];
        for (int c = 0; c < 3; c++) {
            rho[i + c * n] = m->rho[c];
            E[i + c * n] = m->emission[c];
        }
    }

    /* ---- visibility, only where the plan says something can occlude ---- */
    /* Over the input triangles: an element lies on its input triangle, which
     * cannot block it; the visible integral of a pair of elements takes the
     * blockers from the shaft of the two elements. */
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    vp.strata_per_edge = strata;
    if (plan.occlusion.on &&
        (st = rad_vis_create(rad_scene_vertices(scene), (size_t)rad_scene_vertex_count(scene),
                             rad_scene_triangles(scene), (size_t)faces, &vp, &vis)) != RAD_OK)
        goto done;
    ap.face_of = parent;
    ap.visible.sample_strata = strata;
    double t_vis = rad_sys_seconds();

    /* ---- assembly and solve ---- */
    G = malloc((size_t)n * (size_t)n * sizeof *G);
    if (!G) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for the %d x %d coupling matrix", n, n);
        goto done;
    }
    rad_radiosity_stats as;
    st = rad_radiosity_assemble(rad_mesh_vertices(mesh), rad_mesh_triangles(mesh), n, vis, &ap, G,
                                areas, &as);
    if (show_progress)
        fputc('\n', stderr);
    if (st != RAD_OK)
        goto done;
    double t_assembled = rad_sys_seconds();
    rad_dense_report report;
    st = rad_dense_radiosity_solve(n, G, areas, rho, E, B, &dp, &report);
    if (show_progress && dp.method != RAD_DENSE_LU && dp.method != RAD_DENSE_CHOLESKY)
        fputc('\n', stderr);
    if (st != RAD_OK)
        goto done;
    double t_solved = rad_sys_seconds();

    /* ---- per input triangle: area average over its elements ---- */
    double *face_area = calloc((size_t)faces * 4, sizeof *face_area);
    if (!face_area) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d faces", faces);
        goto done;
    }
    double *face_B = face_area + faces;
    if ((st = rad_io_face_averages((size_t)n, parent, areas, B, (size_t)faces, face_area, face_B)) != RAD_OK) {
        free(face_area);
        goto done;
    }
    if ((st = solve_check_answer("dense", (size_t)faces, face_B)) != RAD_OK) {
        free(face_area);
        goto done;
    }

    if ((st = rad_io_output_open(o.out ? o.out : "-", 0, &table_out)) != RAD_OK) {
        free(face_area);
        goto done;
    }
    FILE *out = table_out.f;
    char rule_text[64];
    rad_ff_rule_format(ap.rule, rule_text, sizeof rule_text);
    fprintf(out, "# radkit %s solve\n# scene = %s\n# method = dense\n", RAD_VERSION, o.scene);
    fprintf(out, "# rule = %s\n# tol = %g\n# solver = %s\n", rule_text, ap.ff.tol,
            rad_dense_method_name(dp.method));
    fprintf(out, "# faces = %d\n# elements = %d\n# refine = %d\n", faces, n, refine);
    for (int w = 0; w < rad_scene_warning_count(scene); w++)
        fprintf(out, "# warning = %s\n", rad_scene_warning(scene, w));
    solve_print_effects(out, &plan);
    fprintf(out, "# pairs = %lld\n# pairs_not_facing = %lld\n# pairs_occlusion_tested = %lld\n"
                 "# pairs_visibility_sampled = %lld\n# visibility_error = %.3e\n",
            as.pairs, as.pairs_not_facing, as.pairs_occlusion_tested, as.pairs_sampled,
            as.visibility_error);
    fprintf(out, "# pairs_out_of_range = %lld\n# rays = %llu\n# kernel_evals = %lld\n",
            as.pairs_out_of_range, as.rays, as.kernel_evals);
    fprintf(out, "# solver_factorizations = %d\n# solver_iterations = %d\n# solver_residual = %.3e\n",
            report.factorizations, report.iterations, report.residual);
    fprintf(out, "# rcond = %.3e\n", report.rcond);
    fprintf(out, "# time_setup_s = %.4f\n# time_visibility_s = %.4f\n# time_assemble_s = %.4f\n"
                 "# time_solve_s = %.4f\n# time_total_s = %.4f\n# memory_peak_bytes = %.0f\n",
            t_setup - t_start, t_vis - t_setup - 0.0, t_assembled - t_vis, t_solved - t_assembled,
            rad_sys_seconds() - t_start, rad_sys_peak_rss_bytes());
    rad_io_print_faces(out, (size_t)faces, face_area, face_B);
    free(face_area);
    st = rad_io_output_commit(&table_out);
    if (st == RAD_OK)
        st = write_outputs(&o, scene, mesh, element_material, E, B, &plan, &as, &report, n, faces,
                           t_start,
                           (double[4]){t_setup - t_start, t_vis - t_setup, t_assembled - t_vis,
                                       t_solved - t_assembled});

done:
    rad_io_output_discard(&table_out);
    free(G);
    free(work);
    free(element_material);
    rad_vis_destroy(vis);
    rad_mesh_destroy(mesh);
    rad_mesh_destroy(base);
    rad_scene_destroy(scene);
    return st == RAD_OK ? 0 : cli_fail(st);
}
