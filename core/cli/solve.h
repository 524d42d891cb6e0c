/* Internal to `radkit solve`: what its methods (cmd_solve.c: dense,
 * solve_hier.c: hierarchical, solve_mc.c: Monte Carlo) share — the parsed options and the outputs made
 * from a solution on a display mesh (PLY, PNG) and the table's effect lines. */
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
