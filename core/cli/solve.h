/* Internal to `radkit solve`: the parsed options (cmd_solve.c), their
 * translation into pipeline parameters (solve_params.c), the check of the
 * output paths and the outputs made from a solution's display mesh (PLY, PNG;
 * solve_display.c), the table and the stats (solve_table.c).  The pipeline
 * itself is the library's (rad_solve.h).  Every output goes through
 * rad_io_output (whole file or none). */
#ifndef RAD_CLI_SOLVE_H
#define RAD_CLI_SOLVE_H

#include <stdio.h>

#include "cli.h"
#include "rad_io.h"
#include "rad_scene.h"
#include "rad_solve.h"

typedef struct solve_options {
    const char *scene, *method, *rule, *tol, *solver, *solver_tol, *max_iter, *refine;
    const char *threads, *out, *strata, *ply, *png, *size, *exposure, *stats;
    const char *eps, *min_area, *max_tighten, *max_links, *clip_blockers, *anderson, *oracle, *samples, *seed, *basis, *cluster_model;
    int quiet, help, edges;
    cli_scene_options scene_opts;
} solve_options;

/* radkit solve's options (cmd_solve.c): o cleared, its scene options
 * initialised, and table filled with the command's own options, the scene
 * options and the terminator; returns the entries before the terminator.
 * A table of SOLVE_OPTION_SLOTS holds them (radkit-mpi adds its own after). */
enum { SOLVE_OWN_OPTIONS = 31, SOLVE_OPTION_SLOTS = SOLVE_OWN_OPTIONS + CLI_SCENE_OPTION_COUNT + 1 };
int solve_option_table(solve_options *o, cli_option *table);

/* A number > lo; RAD_EINVAL naming the option otherwise. */
rad_status solve_parse_double(const char *option, const char *text, double lo, double *out);

/* The output paths (--out, --ply, --png, --stats), checked before any work:
 * each one writable (rad_io_output_check), no two naming the same file
 * (rad_io_output_same; the table without --out is standard output, "-"),
 * none naming the scene.  RAD_EINVAL naming the options and paths. */
rad_status solve_check_outputs(const solve_options *o);

/* --image-size and --exposure (0 when not given: automatic). */
rad_status solve_parse_image(const solve_options *o, int *width, int *height, double *exposure);

/* A solution's display mesh (rad_solution display_*), as the renderer takes it. */
typedef struct solve_display {
    size_t nv, nt;
    const double *xyz;
    const int *tri;
    const int *material;
    const double *E, *B;
    const double *element_corners;
} solve_display;

/* --ply and --png from the solution's display mesh (with --edges, element
 * edges drawn on the image).  *render_s gets the image's time (0 without
 * --png). */
rad_status solve_write_display(const solve_options *o, const rad_scene *scene,
                               const rad_solution *sol, double *render_s);

/* The effects plan as '#' lines of the table. */
void solve_print_effects(FILE *out, const rad_effects_plan *plan);
/* The same as the stats JSON's effects (RAD_EFFECT_COUNT entries). */
void solve_effects_json(const rad_effects_plan *plan, rad_io_effect effects[RAD_EFFECT_COUNT]);

/* The options as pipeline parameters (solve_params.c): each method's own
 * options parsed, the others' refused by name; --threads for every method. */
rad_status solve_parse_params(const solve_options *o, const rad_effects_params *ep,
                              rad_solve_params *p);

/* The table ('#' lines of parameters, plan, work and times, then one row per
 * input triangle) and the --stats JSON (solve_table.c). */
void solve_print_table(FILE *out, const solve_options *o, const rad_scene *scene,
                       const rad_solution *s);
rad_status solve_write_stats(const char *path, const rad_solution *s, double render_s);
/* The same for a run over MPI ranks: top-level ranks and the largest rank's
 * peak memory (radkit-mpi). */
rad_status solve_write_stats_ranks(const char *path, const rad_solution *s, double render_s,
                                   int ranks, double memory_per_rank);

#endif
