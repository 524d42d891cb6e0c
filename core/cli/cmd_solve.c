/* radkit solve: a scene in, radiosities out (dense Galerkin radiosity).
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

#include "cli.h"
#include "rad_dense.h"
#include "rad_dense_solve.h"
#include "rad_ff.h"
#include "rad_mesh.h"
#include "rad_radiosity.h"
#include "rad_scene.h"
#include "rad_sys.h"
#include "rad_version.h"
#include "rad_vis.h"

static const char help_head[] =
    "usage: radkit solve SCENE [--method dense] [--rule RULE] [--tol T] [--solver S]\n"
    "                    [--refine K] [--threads N] [--out faces.tsv] [--quiet]\n"
    "                    [--solver-tol T] [--max-iter N] [--vis-strata K]\n"
    "                    [scene options]\n"
    "\n"
    "Solve B = E + rho F B on the triangles of SCENE by dense Galerkin radiosity\n"
    "(piecewise-constant elements) and print one row per input triangle.\n"
    "\n"
    "  --method M       dense (the only method so far; hier and cluster come later)\n"
    "  --rule RULE      form-factor scheme per pair: vertex, centroid, gauss:P,\n"
    "                   analytic:P, ss:N, exact or auto (default auto)\n"
    "  --tol T          the relative accuracy auto aims for per pair (default 1e-6)\n"
    "  --solver S       lu (default), cholesky, jacobi, gauss-seidel, southwell\n"
    "  --solver-tol T   iterative solvers stop at residual T ||E|| (default 1e-10)\n"
    "  --max-iter N     iterative solvers' sweep cap (default 10000)\n"
    "  --refine K       split every triangle 1 -> 4, K times, before solving (default 0)\n"
    "  --threads N      OpenMP threads for the assembly (default: all cores)\n"
    "  --vis-strata K   visibility samples: K^2 points per triangle, K^4 rays per\n"
    "                   pair that something might block (default 3)\n"
    "  --out FILE       write the table to FILE instead of standard output\n"
    "  --quiet          no progress on standard error\n";

static const char help_tail[] =
    "\n"
    "Output: '#' lines with the parameters, the effects plan (effect_<name> and\n"
    "effect_<name>_reason), the work done (elements, pairs, rays, kernel_evals),\n"
    "the solver's figures and the phase times; then columns face (input\n"
    "triangle, 0-based, in input order), area, B_r, B_g, B_b.  With --refine the\n"
    "value of a face is the area average over its elements.\n"
    "\n"
    "example: radkit solve scenes/cornell/cornell.obj --refine 1 --out cornell.tsv\n";

typedef struct solve_options {
    const char *scene, *method, *rule, *tol, *solver, *solver_tol, *max_iter, *refine;
    const char *threads, *out, *strata;
    int quiet, help;
    cli_scene_options scene_opts;
} solve_options;

static int fail(rad_status st)
{
    fprintf(stderr, "radkit: %s\n", rad_error_message());
    return rad_status_exit_code(st);
}

static rad_status parse_double(const char *option, const char *text, double lo, double *out)
{
    char *end = NULL;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || !isfinite(v) || !(v > lo))
        return RAD_ERROR(RAD_EINVAL, "solve: %s must be a number > %g, got '%s'", option, lo, text);
    *out = v;
    return RAD_OK;
}

static void progress_line(double done, void *ctx)
{
    (void)ctx;
    fprintf(stderr, "\rradkit: assembling %5.1f%%", 100.0 * done);
    fflush(stderr);
}

int cli_solve(int argc, char **argv)
{
    solve_options o;
    memset(&o, 0, sizeof o);
    cli_scene_options_init(&o.scene_opts);
    cli_option table[32] = {
        {"", &o.scene, NULL},
        {"--method", &o.method, NULL},
        {"--rule", &o.rule, NULL},
        {"--tol", &o.tol, NULL},
        {"--solver", &o.solver, NULL},
        {"--solver-tol", &o.solver_tol, NULL},
        {"--max-iter", &o.max_iter, NULL},
        {"--refine", &o.refine, NULL},
        {"--threads", &o.threads, NULL},
        {"--vis-strata", &o.strata, NULL},
        {"--out", &o.out, NULL},
        {"--quiet", NULL, &o.quiet},
        {"--help", NULL, &o.help},
        {"-h", NULL, &o.help},
    };
    int nopt = 14;
    nopt += cli_scene_options_add(&o.scene_opts, table + nopt);
    table[nopt] = (cli_option){NULL, NULL, NULL};

    rad_status st = cli_parse("solve", argc, argv, 2, table);
    if (st != RAD_OK)
        return fail(st);
    if (o.help) {
        printf("%s%s%s", help_head, cli_scene_options_help, help_tail);
        return 0;
    }
    if (!o.scene)
        return fail(RAD_ERROR(RAD_EINVAL, "solve: no scene given (see 'radkit solve --help')"));

    /* ---- parameters ---- */
    rad_scene_params sp;
    rad_effects_params ep;
    rad_scene_params_default(&sp);
    rad_scene_effects_params_default(&ep);
    if ((st = cli_scene_options_apply("solve", &o.scene_opts, &sp, &ep)) != RAD_OK)
        return fail(st);
    if (o.method && strcmp(o.method, "dense") != 0) {
        if (strcmp(o.method, "hier") == 0 || strcmp(o.method, "cluster") == 0)
            return fail(RAD_ERROR(RAD_EINVAL, "solve: --method %s is not available yet; use dense",
                                  o.method));
        return fail(RAD_ERROR(RAD_EINVAL, "solve: unknown method '%s' (expected dense)", o.method));
    }
    rad_assembly_params ap;
    rad_assembly_params_default(&ap);
    if (o.rule && (st = rad_ff_rule_parse(o.rule, &ap.rule)) != RAD_OK)
        return fail(st);
    if (o.tol && (st = parse_double("--tol", o.tol, 0.0, &ap.ff.tol)) != RAD_OK)
        return fail(st);
    rad_dense_params dp;
    rad_dense_params_default(&dp);
    if (o.solver && (st = rad_dense_method_parse(o.solver, &dp.method)) != RAD_OK)
        return fail(st);
    if (o.solver_tol && (st = parse_double("--solver-tol", o.solver_tol, 0.0, &dp.tol)) != RAD_OK)
        return fail(st);
    int refine = 0, threads = 0, strata = 3;
    if (o.max_iter && (st = cli_parse_positive_int("solve: --max-iter", o.max_iter, 100000000, &dp.max_iter)) != RAD_OK)
        return fail(st);
    if (o.refine && strcmp(o.refine, "0") != 0 &&
        (st = cli_parse_positive_int("solve: --refine", o.refine, 12, &refine)) != RAD_OK)
        return fail(st);
    if (o.threads && (st = cli_parse_positive_int("solve: --threads", o.threads, 1024, &threads)) != RAD_OK)
        return fail(st);
    if (o.strata && (st = cli_parse_positive_int("solve: --vis-strata", o.strata, 16, &strata)) != RAD_OK)
        return fail(st);
    ap.threads = threads;
    int show_progress = !o.quiet && isatty(2);
    if (show_progress)
        ap.progress = progress_line;

    /* ---- scene, mesh, plan ---- */
    double t_start = rad_sys_seconds();
    rad_scene *scene = NULL;
    rad_mesh *base = NULL, *mesh = NULL;
    rad_vis *vis = NULL;
    double *G = NULL, *work = NULL;
    FILE *out = stdout;
    if ((st = rad_scene_load(o.scene, &sp, &scene)) != RAD_OK)
        return fail(st);
    int faces = rad_scene_triangle_count(scene);
    if ((st = rad_mesh_create(rad_scene_vertices(scene), rad_scene_vertex_count(scene),
                              rad_scene_triangles(scene), faces, NULL, &base)) != RAD_OK)
        goto done;
    rad_effects_plan plan;
    if ((st = rad_scene_effects_plan(scene, base, &ep, &plan)) != RAD_OK)
        goto done;
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
    const rad_material *mats = rad_scene_materials(scene);
    work = malloc((size_t)n * 10 * sizeof *work);
    if (!work) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d elements", n);
        goto done;
    }
    double *rho = work, *E = work + 3 * (size_t)n, *B = work + 6 * (size_t)n, *areas = work + 9 * (size_t)n;
    for (int i = 0; i < n; i++) {
        const rad_material *m = &mats[tri_mat[parent[i]]];
        for (int c = 0; c < 3; c++) {
            rho[i + c * n] = m->rho[c];
            E[i + c * n] = m->emission[c];
        }
    }

    /* ---- visibility, only where the plan says something can occlude ---- */
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    vp.strata_per_edge = strata;
    if (plan.occlusion.on &&
        (st = rad_vis_create(rad_mesh_vertices(mesh), (size_t)rad_mesh_vertex_count(mesh),
                             rad_mesh_triangles(mesh), (size_t)n, &vp, &vis)) != RAD_OK)
        goto done;
    double t_vis = rad_sys_seconds();

    /* ---- assembly and solve ---- */
    G = malloc((size_t)n * (size_t)n * sizeof *G);
    if (!G) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for the %d x %d coupling matrix", n, n);
        goto done;
    }
    rad_assembly_stats as;
    st = rad_radiosity_assemble(rad_mesh_vertices(mesh), rad_mesh_triangles(mesh), n, vis, &ap, G,
                                areas, &as);
    if (show_progress)
        fputc('\n', stderr);
    if (st != RAD_OK)
        goto done;
    double t_assembled = rad_sys_seconds();
    rad_dense_report report;
    if ((st = rad_dense_radiosity_solve(n, G, areas, rho, E, B, &dp, &report)) != RAD_OK)
        goto done;
    double t_solved = rad_sys_seconds();

    /* ---- per input triangle: area average over its elements ---- */
    double *face_area = calloc((size_t)faces * 4, sizeof *face_area);
    if (!face_area) {
        st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for %d faces", faces);
        goto done;
    }
    double *face_B = face_area + faces;
    for (int i = 0; i < n; i++) {
        int f = parent[i];
        face_area[f] += areas[i];
        for (int c = 0; c < 3; c++)
            face_B[f + c * faces] += areas[i] * B[i + c * n];
    }

    if (o.out && !(out = fopen(o.out, "w"))) {
        free(face_area);
        st = RAD_ERROR(RAD_EIO, "solve: cannot write '%s'", o.out);
        goto done;
    }
    char rule_text[64];
    rad_ff_rule_format(ap.rule, rule_text, sizeof rule_text);
    fprintf(out, "# radkit %s solve\n# scene = %s\n# method = dense\n", RAD_VERSION, o.scene);
    fprintf(out, "# rule = %s\n# tol = %g\n# solver = %s\n", rule_text, ap.ff.tol,
            rad_dense_method_name(dp.method));
    fprintf(out, "# faces = %d\n# elements = %d\n# refine = %d\n", faces, n, refine);
    const rad_effect_decision *dec[5] = {&plan.occlusion, &plan.colour, &plan.facing_away,
                                         &plan.singular, &plan.clustering};
    static const char *const dec_name[5] = {"occlusion", "colour", "facing_away", "singular", "clustering"};
    for (int k = 0; k < 5; k++)
        fprintf(out, "# effect_%s = %s\n# effect_%s_reason = %s\n", dec_name[k],
                dec[k]->on ? "on" : "off", dec_name[k], dec[k]->reason);
    fprintf(out, "# pairs = %lld\n# pairs_not_facing = %lld\n# pairs_occlusion_tested = %lld\n",
            as.pairs, as.pairs_not_facing, as.pairs_occlusion_tested);
    fprintf(out, "# pairs_out_of_range = %lld\n# rays = %llu\n# kernel_evals = %lld\n",
            as.pairs_out_of_range, as.rays, as.kernel_evals);
    fprintf(out, "# solver_factorizations = %d\n# solver_iterations = %d\n# solver_residual = %.3e\n",
            report.factorizations, report.iterations, report.residual);
    fprintf(out, "# rcond = %.3e\n", report.rcond);
    fprintf(out, "# time_setup_s = %.4f\n# time_visibility_s = %.4f\n# time_assemble_s = %.4f\n"
                 "# time_solve_s = %.4f\n# time_total_s = %.4f\n# memory_peak_bytes = %.0f\n",
            t_setup - t_start, t_vis - t_setup - 0.0, t_assembled - t_vis, t_solved - t_assembled,
            rad_sys_seconds() - t_start, rad_sys_peak_rss_bytes());
    fprintf(out, "face\tarea\tB_r\tB_g\tB_b\n");
    for (int f = 0; f < faces; f++) {
        double a = face_area[f];
        fprintf(out, "%d\t%.10g", f, a);
        for (int c = 0; c < 3; c++)
            fprintf(out, "\t%.12g", a > 0.0 ? face_B[f + c * faces] / a : 0.0);
        fputc('\n', out);
    }
    free(face_area);
    if (out != stdout && fclose(out) != 0)
        st = RAD_ERROR(RAD_EIO, "solve: error writing '%s'", o.out);
    out = stdout;

done:
    if (out != stdout)
        fclose(out);
    free(G);
    free(work);
    rad_vis_destroy(vis);
    rad_mesh_destroy(mesh);
    rad_mesh_destroy(base);
    rad_scene_destroy(scene);
    return st == RAD_OK ? 0 : fail(st);
}
