/* rad_mc: Monte Carlo radiosity, the independent reference.
 *
 * For every input triangle i, the area average of the radiosity
 *
 *   B_i = E_i + rho_i (1/A_i) int_Ti H(x) dA_x,
 *   H(x) = int_hemisphere L(y(x, w) -> x) cos(theta) dw,  L = B / pi,
 *
 * estimated by path tracing, with a standard error per channel.  Nothing of
 * the Galerkin code is used: no form factors, no mesh, no linear system; only
 * the scene's triangles and Embree (rad_vis) for closest hits and shadow
 * rays.  The integral equation is the continuous one that every Galerkin
 * solution converges to as its mesh is refined, so this is the reference the
 * deterministic methods are measured against.
 *
 * Conventions (DESIGN.md): faces are one-sided; a point reflects and emits
 * into the hemisphere of its counter-clockwise normal only; a ray that meets
 * the back of a triangle ends there (the back is black and opaque); rho is
 * the albedo per RGB channel, E the emitted exitance.
 *
 * The estimator (per sample; rad_mc.c opens with the algorithm in steps):
 *  - x uniform on triangle i, stratified: each batch of a triangle's samples
 *    takes jittered points of the k^2 congruent cells of the triangle
 *    (rad_geom_triangle_stratum), and pairs them with stratified first
 *    directions and emitter points (padded stratification);
 *  - at every path vertex, next-event estimation (an emitter point drawn in
 *    proportion to area times emitted power, one shadow ray) and a
 *    cosine-weighted continuation direction (one closest-hit ray), the two
 *    combined by multiple importance sampling with the power heuristic
 *    \cite{veach1995mis};
 *  - Russian roulette once the path throughput falls below rr_weight:
 *    unbiased, no depth cap within max_depth.
 * The standard error comes from batch means: a triangle's samples are split
 * into `batches` equal batches, each a complete stratified estimate, and the
 * standard error is the standard deviation of the batch means over
 * sqrt(batches).  It is the standard error of B_i (emission included, which
 * is exact).
 *
 * Reproducibility: every sample draws its random numbers from a counter-based
 * generator keyed by (seed, triangle, sample), and every triangle's sums are
 * formed in a fixed order, so a seed gives the same table bit for bit for any
 * number of OpenMP threads.
 *
 * Threads: the samples run on the caller's OpenMP threads (omp parallel in
 * rad_mc_solve); rad_mc sets no thread count. */
#ifndef RAD_MC_H
#define RAD_MC_H

#include <stddef.h>

#include "rad_error.h"
#include "rad_vis.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rad_mc_params {
    /* Paths per input triangle, >= 2; rounded up to a multiple of the batch
     * count (the rounded figure is in rad_mc_stats).  Default 4096. */
    long long samples;
    unsigned long long seed; /* default 1 */
    /* Batches per triangle for the standard error, 2..1024 (fewer when
     * samples is smaller).  Default 32: the standard error is then itself
     * known to about 13% (1 / sqrt(2 (batches - 1))). */
    int batches;
    /* A path longer than this many bounces is an error (RAD_ENUMERIC): it
     * happens only when the reflectance is so close to 1 that paths do not
     * end (mean length 1 / (1 - rho)).  Default 100000. */
    int max_depth;
    /* 0: no shadow rays (the scene cannot occlude: a convex enclosure, as the
     * effects plan decides); 1: shadow rays for next-event estimation.
     * Default 1. */
    int occlusion;
    /* 0: cosine-weighted continuation only (no next-event estimation; for
     * tests of the estimator's independence of its sampling).  Default 1. */
    int next_event;
    /* Russian roulette starts when the largest channel of a path's throughput
     * falls below this weight (then survival probability throughput / weight,
     * survivors carry the weight).  In (0, 1]; default 0.5, the most efficient
     * of 1, 0.5, 0.25, 0.1 on the Cornell box (standard error squared times
     * time). */
    double rr_weight;
    /* Progress: called from one thread with the fraction of samples done,
     * at most about 100 times; NULL for none. */
    void (*progress)(double done, void *ctx);
    void *progress_ctx;
    /* OpenMP threads; 0 (default): OpenMP's default.  The table does not
     * depend on it (per-sample seeds). */
    int threads;
} rad_mc_params;

void rad_mc_params_default(rad_mc_params *params);

typedef struct rad_mc_stats {
    long long samples_per_face; /* after rounding to the batches */
    int batches;
    long long paths;            /* all triangles */
    long long rays;             /* closest-hit and shadow rays */
    long long bounces;          /* path vertices after the first: mean path length is
                                   bounces / paths + 1 segments */
    double seconds;
} rad_mc_stats;

/* Estimate B (ntris x 3, column-major) and its standard error se (same shape)
 * for the triangles xyz / tri with per-triangle reflectance rho and emission
 * E (ntris x 3, column-major).  vis must have been built over exactly these
 * triangles (rad_vis_create(xyz, nverts, tri, ntris)) and is borrowed.
 * RAD_EINVAL for bad parameters or a vis over other triangles, RAD_EINPUT for
 * reflectance outside [0, 1) or negative emission, RAD_ENUMERIC when a path
 * exceeds max_depth, RAD_ENOMEM. */
rad_status rad_mc_solve(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                        const double *rho, const double *E, const rad_vis *vis,
                        const rad_mc_params *params, double *B, double *se,
                        rad_mc_stats *stats);

#ifdef __cplusplus
}
#endif
#endif
