/* radkit solve: a scene in, radiosities out.  The command parses its options
 * into pipeline parameters (solve_params.c), loads the scene, runs the
 * library's pipeline (rad_solve_run: mesh, effects plan, visibility, dense,
 * hierarchical or Monte Carlo solve) and prints the solution (solve_table.c,
 * solve_display.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "rad_io.h"
#include "rad_scene.h"
#include "rad_solve.h"
#include "rad_sys.h"
#include "solve.h"

static const char help_head[] =
    "usage: radkit solve SCENE [--method dense|hier|cluster|mc] [--rule RULE] [--tol T]\n"
    "                    [--solver S] [--oracle bf|error] [--eps E] [--min-area A]\n"
    "                    [--max-tighten K] [--clip-blockers N]\n"
    "                    [--cluster-model oriented|iso] [--edges]\n"
    "                    [--samples N] [--seed S]\n"
    "                    [--refine K] [--basis p0|p1|p2] [--threads N] [--out faces.tsv]\n"
    "                    [--ply out.ply]\n"
    "                    [--png out.png] [--image-size WxH] [--exposure X]\n"
    "                    [--stats stats.json] [--quiet]\n"
    "                    [--solver-tol T] [--max-iter N] [--anderson M]\n"
    "                    [--vis-strata K]\n"
    "                    [scene options]\n"
    "\n"
    "Solve B = E + rho F B on the triangles of SCENE by Galerkin radiosity with\n"
    "piecewise-constant elements, dense or hierarchical, or estimate it by Monte\n"
    "Carlo path tracing, and print one row per input triangle.\n"
    "\n"
    "  --method M       dense (default), mc, hier or cluster.  mc: Monte Carlo, the\n"
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
    "                   element), and error_target_met: whether it is within --eps.\n"
    "                   cluster: hier over a bounding-volume hierarchy of the\n"
    "                   input triangles: linking starts from sibling clusters\n"
    "                   instead of every pair of triangles, and a link between\n"
    "                   clusters stays while its bound (the point form factor\n"
    "                   from the clusters' spheres and normal cones) keeps its\n"
    "                   share of the error within --eps; --eps, --min-area and\n"
    "                   the error estimate as for hier (BF oracle and --rule do\n"
    "                   not apply)\n"
    "  --cluster-model M\n"
    "                   cluster: the projected area a cluster link assumes of a\n"
    "                   cluster, oriented (default: the middle of what its normal\n"
    "                   sum and normal cone allow) or iso (a quarter of its area)\n"
    "  --oracle O       hier: error (default: refine the links whose share of an\n"
    "                   input triangle's error bound is largest, until every\n"
    "                   triangle's bound meets --eps or --min-area stops it) or bf\n"
    "                   (refine a link when the radiosity it brings, rho F B,\n"
    "                   exceeds eps times the mean reflected radiosity; HSA 1991)\n"
    "  --eps E          hier: the error target: each input triangle's radiosity\n"
    "                   error (a row of the table) within E times the\n"
    "                   area-weighted mean reflected radiosity (B - E, channels\n"
    "                   averaged); > 0, default 0.1.  The bound is conservative\n"
    "                   (the Cornell box at 0.01: estimate 22%, error 0.46% worst\n"
    "                   face; 3.8% and 0.035% area-weighted)\n"
    "  --min-area A     hier: never split an element into children smaller than A\n"
    "                   (scene units squared, >= 0; default: total area times\n"
    "                   min(1e-4, 0.01 eps^2); it binds below eps 0.1, and at\n"
    "                   any eps in scenes of many small objects, whose input\n"
    "                   triangles are already near it; where it binds the\n"
    "                   table says links_bound > 0, and the error estimate\n"
    "                   can stay above --eps)\n"
    "  --max-tighten K  hier, cluster, --oracle error: when no link is left above\n"
    "                   its threshold but an input triangle's bound still exceeds\n"
    "                   --eps (its sources' variation taken from their slopes,\n"
    "                   as the oracle weighs them), the oracle quarters that\n"
    "                   triangle's thresholds and refines again, at most K times\n"
    "                   (a whole number 0-30; default 3, a 64-fold tightening);\n"
    "                   after the first time only where the last quartering\n"
    "                   moved the triangle's mean B by more than eps times the\n"
    "                   mean reflected radiosity (the move estimates the error\n"
    "                   of the answer before it; the bound, far above the\n"
    "                   error, does not say where the error lies).\n"
    "                   K sets what accuracy costs: see papers/clustering.md for\n"
    "                   links, time and error against K.  The error estimate\n"
    "                   (which adds the variation the links' linear fits leave\n"
    "                   out) bounds the error whatever K; a smaller K leaves it\n"
    "                   further above --eps.  The table's\n"
    "                   tightenings and tightened_share say how often, and over\n"
    "                   how much of the area (summed), the oracle tightened\n"
    "                   (one triangle at most K times, different triangles\n"
    "                   in different tightenings)\n"
    "  --clip-blockers N  hier, cluster: an element link whose shaft holds at\n"
    "                   most N triangles clips each point's view of the other\n"
    "                   element exactly; past N (or the clipping's work budget)\n"
    "                   9 rays a point sample it, and their sampling error\n"
    "                   joins the link's error (a whole number 0-256, default\n"
    "                   24; 0: rays only).  Rays cost the same whatever the\n"
    "                   crowd; clipping is exact but grows with it\n"
    "  --max-links N    hier, cluster: refuse (exit 2) a hierarchy of more than N\n"
    "                   links, element links and cluster links each (default\n"
    "                   50000000); whatever N, a hierarchy that would outgrow\n"
    "                   90% of the machine's memory (RADKIT_MEMORY_LIMIT bytes\n"
    "                   if set) is refused before it is made\n"
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
    "  --solver-tol T   iterative solvers stop at residual T ||E|| (default 1e-10;\n"
    "                   hier, cluster: by default the last solve stops where B\n"
    "                   is within eps/100 R of its fixed point, R the mean\n"
    "                   reflected radiosity; given, T is the step change\n"
    "                   relative to the largest B)\n"
    "  --max-iter N     iterative solvers' sweep cap (default 10000)\n"
    "  --anderson M     hier (p0) and cluster: each gather/push-pull step starts\n"
    "                   from the mix of the last steps that best cancels their\n"
    "                   changes (Anderson, over M of them, 0..8; default 4); 0:\n"
    "                   plain Jacobi steps.  The stopping test and the answer\n"
    "                   are each step's own, so only the number of steps changes\n"
    "  --refine K       split every triangle 1 -> 4, K times, before solving (default 0)\n"
    "  --basis B        dense, hier: the polynomial on each element, p0 (constant,\n"
    "                   the default), p1 (linear) or p2 (quadratic), discontinuous\n"
    "                   and orthonormal; the table keeps the per-face averages\n"
    "  --threads N      OpenMP threads for the assembly (hier: for the link\n"
    "                   estimates; mc: for the paths; default: all cores); as\n"
    "                   many as the CPUs, each is bound to one (not for dense)\n"
    "                   unless OMP_PROC_BIND or OMP_PLACES says otherwise\n"
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

/* Progress on a terminal, one line rewritten in place per method. */
static void dense_progress(double done, void *ctx)
{
    (void)ctx;
    fprintf(stderr, "\rradkit: assembling %5.1f%%", 100.0 * done);
    fflush(stderr);
}

static void solver_progress(int channel, int iteration, double residual, void *ctx)
{
    (void)ctx;
    fprintf(stderr, "\rradkit: solving channel %d: sweep %d, residual %.2e   ", channel, iteration,
            residual);
    fflush(stderr);
}

static void mc_progress(double done, void *ctx)
{
    (void)ctx;
    fprintf(stderr, "\rradkit: mc paths %5.1f%%", 100.0 * done);
    fflush(stderr);
}

/* hier: a warning when the error estimate misses --eps, and why. */
static void warn_target(const rad_solution *s)
{
    const rad_hier_stats *hs = &s->hier;
    if ((s->method != RAD_SOLVE_HIER && s->method != RAD_SOLVE_CLUSTER) || hs->target_met)
        return;
    fprintf(stderr, "radkit: warning: the error estimate %.3g (worst input triangle, relative to "
                    "the mean reflected radiosity) exceeds --eps %g", hs->bound_face_max,
            s->used.hier.eps);
    int k = s->used.hier.max_tighten;
    char tightened[192];
    if (k > 0)
        snprintf(tightened, sizeof tightened, "the oracle tightened a triangle's thresholds at "
                 "most %.0f-fold (--max-tighten %d), again only where its B still moved by "
                 "more than eps R", pow(4.0, k), k);
    else
        snprintf(tightened, sizeof tightened, "the oracle did not tighten its thresholds "
                 "(--max-tighten 0)");
    if (hs->links_bound > 0)
        fprintf(stderr, ": %lld links could not be refined further (--min-area or the depth "
                        "limit binds), and %s\n", hs->links_bound, tightened);
    else
        fprintf(stderr, "; %s, and the estimate is conservative: see error_estimate_l1\n",
                tightened);
}

int solve_option_table(solve_options *o, cli_option *table)
{
    memset(o, 0, sizeof *o);
    cli_scene_options_init(&o->scene_opts);
    const cli_option own[SOLVE_OWN_OPTIONS] = {
        {"", &o->scene, NULL, "scene"},
        {"--method", &o->method, NULL, NULL},
        {"--rule", &o->rule, NULL, NULL},
        {"--tol", &o->tol, NULL, NULL},
        {"--solver", &o->solver, NULL, NULL},
        {"--solver-tol", &o->solver_tol, NULL, NULL},
        {"--max-iter", &o->max_iter, NULL, NULL},
        {"--refine", &o->refine, NULL, NULL},
        {"--basis", &o->basis, NULL, NULL},
        {"--threads", &o->threads, NULL, NULL},
        {"--vis-strata", &o->strata, NULL, NULL},
        {"--out", &o->out, NULL, NULL},
        {"--ply", &o->ply, NULL, NULL},
        {"--png", &o->png, NULL, NULL},
        {"--image-size", &o->size, NULL, NULL},
        {"--exposure", &o->exposure, NULL, NULL},
        {"--stats", &o->stats, NULL, NULL},
        {"--quiet", NULL, &o->quiet, NULL},
        {"--help", NULL, &o->help, NULL},
        {"-h", NULL, &o->help, NULL},
        {"--eps", &o->eps, NULL, NULL},
        {"--min-area", &o->min_area, NULL, NULL},
        {"--max-tighten", &o->max_tighten, NULL, NULL},
        {"--clip-blockers", &o->clip_blockers, NULL, NULL},
        {"--anderson", &o->anderson, NULL, NULL},
        {"--max-links", &o->max_links, NULL, NULL},
        {"--oracle", &o->oracle, NULL, NULL},
        {"--cluster-model", &o->cluster_model, NULL, NULL},
        {"--edges", NULL, &o->edges, NULL},
        {"--samples", &o->samples, NULL, NULL},
        {"--seed", &o->seed, NULL, NULL},
    };
    memcpy(table, own, sizeof own);
    int nopt = SOLVE_OWN_OPTIONS;
    nopt += cli_scene_options_add(&o->scene_opts, table + nopt);
    table[nopt] = (cli_option){NULL, NULL, NULL, NULL};
    return nopt;
}

int cli_solve(int argc, char **argv)
{
    solve_options o;
    cli_option table[SOLVE_OPTION_SLOTS];
    solve_option_table(&o, table);

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

    /* ---- options -> parameters, checked before the scene is read ---- */
    rad_scene_params sp;
    rad_effects_params ep;
    rad_scene_params_default(&sp);
    rad_scene_effects_params_default(&ep);
    rad_solve_params p;
    int width, height;
    double exposure;
    if ((st = cli_scene_options_apply("solve", &o.scene_opts, &sp, &ep)) != RAD_OK ||
        (st = solve_parse_params(&o, &ep, &p)) != RAD_OK ||
        (st = solve_parse_image(&o, &width, &height, &exposure)) != RAD_OK)
        return cli_fail(st);
    int show_progress = !o.quiet && isatty(2);
    if (show_progress) {
        p.assembly.progress = dense_progress;
        p.dense.progress = solver_progress;
        p.hier.progress = cli_hier_progress;
        p.hier.working = cli_hier_working;
        p.mc.progress = mc_progress;
    }

    /* ---- scene, solve, outputs ---- */
    rad_scene *scene = NULL;
    rad_solution *sol = NULL;
    rad_io_output table_out = {0};
    if ((st = rad_scene_load(o.scene, &sp, &scene)) != RAD_OK)
        return cli_fail(st);
    /* The scene's warnings (no emitter, duplicate faces, ...) go to stderr and
     * into the table's header: a scene without light solves to zeros. */
    if (!o.quiet)
        for (int w = 0; w < rad_scene_warning_count(scene); w++)
            fprintf(stderr, "radkit: warning: %s\n", rad_scene_warning(scene, w));
    /* hier, cluster and mc run many short parallel loops: bound threads keep
       them from waiting on a thread the scheduler moved (rad_sys.h: only a
       pool that fills the CPUs); dense does not bind, because OpenBLAS would
       start its workers on the main thread's one CPU */
    if (p.method != RAD_SOLVE_DENSE)
        rad_sys_bind_threads(p.threads);
    st = rad_solve_run(scene, &p, &sol);
    if (show_progress)
        fputc('\n', stderr);
    if (st != RAD_OK)
        goto done;
    if (!o.quiet)
        warn_target(sol);
    if ((st = rad_io_output_open(o.out ? o.out : "-", 0, &table_out)) != RAD_OK)
        goto done;
    solve_print_table(table_out.f, &o, scene, sol);
    if ((st = rad_io_output_commit(&table_out)) != RAD_OK)
        goto done;
    double render_s = 0.0;
    if ((o.ply || o.png) && (st = solve_write_display(&o, scene, sol, &render_s)) != RAD_OK)
        goto done;
    if (o.stats)
        st = solve_write_stats(o.stats, sol, render_s);
done:
    rad_io_output_discard(&table_out);
    rad_solution_destroy(sol);
    rad_scene_destroy(scene);
    return st == RAD_OK ? 0 : cli_fail(st);
}
