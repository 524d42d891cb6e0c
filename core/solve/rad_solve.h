/* rad_solve: the solve pipeline, one call for every method.
 *
 *   scene (loaded, rad_scene_load) -> mesh -> effects plan -> per-element
 *   reflectance and emission -> visibility (only where the plan says
 *   something can occlude) -> dense assembly and solve | hierarchical
 *   refinement and solve | Monte Carlo paths -> per input triangle the
 *   area-average radiosity, the display mesh, the work done and the times.
 *
 * The plan decides what runs (rad_scene.h, "the effects plan"): occlusion
 * off builds no visibility and traces no ray; colour off solves one system
 * with each face's channel-mean reflectance (exact when the scene is grey),
 * colour on one system per channel; facing-away pairs are zero without
 * integration unless forced off; singular pairs get the singular-aware rules
 * unless forced off; reflectance near 1 tightens the defaults' tolerances by
 * plan.tighten; a scene no tolerance can serve is refused (RAD_ENUMERIC with
 * the plan's reason).  Monte Carlo needs no form factors: it honours
 * occlusion (shadow rays) and colour, and refuses overrides of facing_away
 * and singular, which mean nothing to it.
 *
 * The program (cli/) parses options into rad_solve_params, calls
 * rad_solve_run and prints the solution; tests, experiments and benchmarks
 * may call it directly. */
#ifndef RAD_SOLVE_H
#define RAD_SOLVE_H

#include <stddef.h>

#include "rad_dense_solve.h"
#include "rad_error.h"
#include "rad_hier.h"
#include "rad_mc.h"
#include "rad_radiosity.h"
#include "rad_scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum rad_solve_method {
    RAD_SOLVE_DENSE = 0, /* Galerkin, every pair of elements: rad_radiosity + rad_dense */
    RAD_SOLVE_HIER,      /* hierarchical: rad_hier */
    RAD_SOLVE_MC,        /* Monte Carlo path tracing: rad_mc (the independent reference) */
    RAD_SOLVE_CLUSTER    /* hierarchical over a cluster hierarchy: rad_hier, params.cluster */
} rad_solve_method;

/* "dense", "hier", "mc" or "cluster"; RAD_EINVAL naming the text otherwise. */
rad_status rad_solve_method_parse(const char *text, rad_solve_method *out);
const char *rad_solve_method_name(rad_solve_method m);

typedef struct rad_solve_params {
    rad_solve_method method;
    rad_effects_params effects;
    int threads;                   /* OpenMP threads for every method; 0: OpenMP's default */
    /* dense */
    rad_radiosity_params assembly; /* rule, ff tolerances, visible-integral parameters */
    rad_dense_params dense;        /* solver, its tolerance and sweep cap */
    int refine;                    /* split every triangle 1 -> 4 this many times (0..12) */
    int basis;                     /* polynomial order per element (rad_basis.h): 0 (default,
                                      constants), 1 or 2; dense only for now */
    /* An emission field instead of the materials' constants (dense, and hier
     * with basis 1 or 2; NULL by default): the emitted exitance of channel c at point x of input
     * face f, projected on each element's basis (a symmetric rule of degree
     * 2 basis + 6).  For manufactured solutions and studies of smooth light. */
    double (*emission)(int face, rad_vec3 x, int channel, void *ctx);
    void *emission_ctx;
    size_t dense_max_elements;     /* refuse refining beyond this (default 46340: a
                                      46340^2 matrix is 16 GiB) */
    /* hier: hier.min_area < 0 (the default) follows eps: total area times
     * min(1e-4, max(1e-10, 0.01 eps^2)), so that it does not cap the accuracy
     * asked for (an element's P0 error is about its size times the gradient) */
    rad_hier_params hier;
    /* mc */
    rad_mc_params mc;
    /* 1: the display mesh (display_*) is built: dense's elements, hier's
     * conforming leaf mesh, mc's input triangles; with edges = 1 each display
     * triangle also gets the corners of its element.  Default 0. */
    int display, edges;
    /* 1: assembly.ff.tol and dense.tol are the caller's and are kept;
     * 0 (default): they are the defaults, tightened near reflectance 1 */
    int keep_tol, keep_solver_tol;
} rad_solve_params;

void rad_solve_params_default(rad_solve_params *params);

typedef struct rad_solve_phase {
    const char *name; /* "setup", "visibility", "assemble", "link", "refine", "solve", "paths";
                         "comm": hier shared among processes, the exchanges (a part of
                         link, refine and solve) */
    double seconds;
} rad_solve_phase;

enum { RAD_SOLVE_MAX_PHASES = 6 };

typedef struct rad_solution {
    rad_solve_method method;
    rad_effects_plan plan;
    rad_solve_params used;  /* the parameters after the plan's tightening and defaults */
    int faces;              /* input triangles */
    double *face_area;      /* per input triangle */
    double *face_B;         /* faces x 3, column-major: the area-average radiosity */
    double *face_se;        /* mc: its standard error (same shape); NULL otherwise */
    /* dense: per element its corners (9 doubles each, n x 9), input face and
     * the coefficients of its radiosity in the orthonormal basis of order
     * used.basis (m = rad_basis_size functions; coefficient k of element i in
     * channel c at element_coef[(i m + k) + c n m]) */
    double *element_corners;
    int *element_face;
    double *element_coef;
    /* the work */
    size_t elements;        /* dense: elements; hier: leaves; mc: faces */
    long long links;        /* dense: pairs coupled (facing); hier: live links; mc: 0 */
    unsigned long long rays;
    long long kernel_evals;
    int systems;            /* linear systems solved (dense: factorizations or channels
                               iterated; hier: channels transported); mc: 0 */
    const char *solver_name;
    long long solver_iterations;
    double solver_residual;
    rad_solve_phase phases[RAD_SOLVE_MAX_PHASES];
    int nphases;
    double total_seconds;   /* rad_solve_run's wall time */
    /* the method's own figures (the others zero) */
    rad_radiosity_stats assembly;
    rad_dense_report dense;
    rad_hier_stats hier;
    rad_mc_stats mc;
    double se_rel_l1, se_rel_max; /* mc: the standard error over the mean reflected
                                     radiosity, area-weighted and worst face */
    /* the display mesh (params.display): triangles with material, emission and
     * radiosity (n x 3 column-major); element_corners with params.edges */
    size_t display_nv, display_nt;
    double *display_xyz;
    int *display_tri, *display_material;
    double *display_E, *display_B, *display_corners;
} rad_solution;

/* Solve `scene` by params->method (NULL: the defaults, dense).  *out is a new
 * solution (rad_solution_destroy) on RAD_OK, NULL otherwise.  RAD_EINVAL for
 * bad parameters, RAD_ETOOBIG when the scene is too big for the method,
 * RAD_ENUMERIC when the plan refuses the scene or the answer is not finite
 * and non-negative, RAD_ENOMEM. */
rad_status rad_solve_run(const rad_scene *scene, const rad_solve_params *params,
                         rad_solution **out);

void rad_solution_destroy(rad_solution *s);

#ifdef __cplusplus
}
#endif
#endif
