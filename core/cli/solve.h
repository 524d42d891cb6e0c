/* Internal to `radkit solve`: what its methods (cmd_solve.c: dense,
 * solve_hier.c: hierarchical, solve_mc.c: Monte Carlo) share — the parsed
 * options, the check of the output paths, the outputs made from a solution on
 * a display mesh (PLY, PNG) and the table's effect lines.  Every output goes
 * through rad_io_output (whole file or none). */
#ifndef RAD_CLI_SOLVE_H
#define RAD_CLI_SOLVE_H

#include <stdio.h>

#include "cli.h"
#include "rad_io.h"
#include "rad_scene.h"
#include "rad_vis.h"

typedef struct solve_options {
    const char *scene, *method, *rule, *tol, *solver, *solver_tol, *max_iter, *refine;
    const char *threads, *out, *strata, *ply, *png, *size, *exposure, *stats;
    const char *eps, *min_area, *oracle, *samples, *seed;
    int quiet, help, edges;
    cli_scene_options scene_opts;
} solve_options;

/* A number > lo; RAD_EINVAL naming the option otherwise. */
rad_status solve_parse_double(const char *option, const char *text, double lo, double *out);

/* The output paths (--out, --ply, --png, --stats), checked before any work:
 * each one writable (rad_io_output_check), no two naming the same file
 * (rad_io_output_same; the table without --out is standard output, "-"),
 * none naming the scene.  RAD_EINVAL naming the options and paths. */
rad_status solve_check_outputs(const solve_options *o);

/* Every face's B finite and >= 0 (n x 3 column-major); RAD_ENUMERIC naming
 * the method, face and channel otherwise.  Called before a table is written. */
rad_status solve_check_answer(const char *method, size_t n, const double *B);

/* --image-size and --exposure (0 when not given: automatic). */
rad_status solve_parse_image(const solve_options *o, int *width, int *height, double *exposure);

/* A solution on the triangles it is shown with.  Dense: the elements
 * themselves; hier: the conforming mesh of the leaves.  Per display triangle
 * (n x 3 column-major for E and B): material, emission, radiosity, and the
 * corners of the element it belongs to (9 doubles, for --edges). */
typedef struct solve_display {
    size_t nv, nt;
    const double *xyz;
    const int *tri;
    const int *material;
    const double *E, *B;
    const double *element_corners;
} solve_display;

/* --ply and --png (with --edges, element edges drawn on the image).
 * *render_s gets the image's time (0 without --png). */
rad_status solve_write_display(const solve_options *o, const rad_scene *scene,
                               const solve_display *d, double *render_s);

/* The effects plan as '#' lines of the table. */
void solve_print_effects(FILE *out, const rad_effects_plan *plan);
/* The same as the stats JSON's effects (RAD_EFFECT_COUNT entries). */
void solve_effects_json(const rad_effects_plan *plan, rad_io_effect effects[RAD_EFFECT_COUNT]);

int solve_hier(const solve_options *o, const rad_scene_params *sp, const rad_effects_params *ep);
int solve_mc(const solve_options *o, const rad_scene_params *sp, const rad_effects_params *ep);

#endif
