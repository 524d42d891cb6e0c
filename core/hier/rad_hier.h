/* rad_hier: hierarchical radiosity (Hanrahan, Salzman, Aupperle 1991,
 * refs.bib key hanrahan1991) for piecewise-constant (P0) elements, with an a
 * posteriori bound of its error that eps controls.
 *
 * Each input triangle is the root of a quadtree of elements (1 -> 4 midpoint
 * split).  A link joins two elements a and b at whatever level their
 * interaction deserves and carries light both ways: G_ab = int_a int_b K V,
 * F_ab = G / A_a, F_ba = G / A_b, visibility included.  The system solved is
 * the hierarchical form of B_i = E_i + rho_i sum_j F_ij B_j (DESIGN.md
 * conventions: per-channel arrays n x 3 column-major, B in W/m^2).
 *
 * A link's G comes from point values (link.c): the point-to-element form
 * factor F(x, b) at the nodes x of a symmetric rule on a, and F(y, a) at the
 * nodes y of the same rule on b, each in closed form over the part of the
 * other element visible from the point (rad_vis_point_visible: exact
 * visibility, so that in a closed scene a point's form factors sum to 1).
 * G is the mean of the two sides' estimates, so reciprocity holds exactly;
 * touching elements take their unoccluded G from singular-aware rules.  From
 * the same values each link gets its error dG (the sides' disagreement, the
 * fits' residuals, or ss:5 - ss:4), each side's linear fit (the slope the
 * gather pushes down, solve.c) and each side's variation as a source.
 *
 * The solve (solve.c) gathers at every element a linear function of
 * irradiance, corrected for the slope of each source's B, and pushes it down
 * to the leaves (a leaf's B is the function's mean).  Rows are capped so the
 * step contracts; in a sealed scene every leaf's row is scaled to exactly 1.
 *
 * The error bound (solve.c).  With R the area-weighted mean reflected
 * radiosity (B - E, channels averaged), per leaf and channel: the error of
 * the links' G and the sources' unresolved variation carried through every
 * bounce, T = (I - rho K_h)^-1 (q + sqrt(d)) (up to 1 / (1 - rho) times the
 * local error), plus the linear fits' residuals, damped by
 * 1 / (1 - rho_max / 2).
 * Reported per input triangle (the area-weighted mean of its leaves': the
 * error of a row of the answer, bound_face_max) and per leaf.  eps is the
 * target for every input triangle's bound: bound_face_max <= eps R.
 *
 * Refinement oracles (refine.c).
 *  - ERROR (default): a link is refined when its share of an input
 *    triangle's bound exceeds link_share x eps R; when nothing is above,
 *    the thresholds of the triangles still above eps R are tightened and
 *    refinement goes on; from the second tightening on, only where the
 *    last one moved the triangle's mean B by more than eps R (the move
 *    estimates the error of the answer before it).  It ends when no
 *    triangle is left to tighten, at max_tighten, or when nothing more can
 *    be split (min_area or max_depth: links_bound says so).
 *  - BF (HSA 1991): a link is refined when the radiosity it brings,
 *    rho F B_s, exceeds eps R (the larger element is split).  eps is then a
 *    per-link threshold; the bound is still computed and reported.
 * A link whose point values are all 0 although its elements face each other
 * is refined while it can be.  An element may be split when its children
 * (area / 4) are at least min_area and its depth is below max_depth.
 *
 * Usage: rad_hier_create (initial linking), then either rad_hier_solve (the
 * whole loop) or the steps: rad_hier_step / rad_hier_test (gather and
 * push-pull until converged) and rad_hier_refine (one oracle pass), repeated
 * until rad_hier_refine refines nothing.  New links are estimated in parallel
 * (OpenMP, each into its own slot): results do not depend on the thread
 * count. */
#ifndef RAD_HIER_H
#define RAD_HIER_H

#include <stddef.h>

#include "rad_error.h"
#include "rad_ff.h"
#include "rad_vis.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rad_hier rad_hier;

typedef enum rad_hier_oracle {
    RAD_HIER_ORACLE_BF = 0,   /* transported radiosity (HSA 1991) */
    RAD_HIER_ORACLE_ERROR = 1 /* the error bound (see above) */
} rad_hier_oracle;

/* "bf" or "error"; RAD_EINVAL naming the text otherwise. */
rad_status rad_hier_oracle_parse(const char *text, rad_hier_oracle *oracle);
const char *rad_hier_oracle_name(rad_hier_oracle oracle);

#define RAD_HIER_MAX_NODES 25 /* points of the largest point-value rule */

/* How a cluster link estimates the projected area of a cluster towards the
 * other (cluster.c): ISO takes a quarter of its area (the mean over
 * directions of any surface's projected area, Cauchy), ORIENTED the middle
 * of the bracket its area-weighted normal and normal cone allow (exact for
 * a flat cluster, a quarter of the area for a closed convex one). */
typedef enum rad_hier_cluster_model {
    RAD_HIER_CLUSTER_ORIENTED = 0,
    RAD_HIER_CLUSTER_ISO = 1
} rad_hier_cluster_model;

/* "oriented" or "iso"; RAD_EINVAL naming the text otherwise. */
rad_status rad_hier_cluster_model_parse(const char *text, rad_hier_cluster_model *model);
const char *rad_hier_cluster_model_name(rad_hier_cluster_model model);

/* Sharing the work of one rad_hier among cooperating processes (radkit-mpi:
 * MPI ranks), without this library knowing how they talk.  Every process
 * builds the same rad_hier from the same input with the same exchange
 * (rank differing) and calls the same functions in the same order.  Then
 *  - each batch of link estimates (initial links, every refinement
 *    generation, cluster links) is dealt round-robin (process r estimates
 *    jobs r, r + size, ...: neighbouring jobs cost alike, so the shares
 *    do too), and `allgather` gives every
 *    process the whole batch in job order, so that everything after it (the
 *    links kept, the oracle, the solve) is computed alike everywhere and
 *    every hierarchy is the serial one bit for bit;
 *  - with split_gather = 1, every gather / push-pull step (and every step of
 *    the error transport) is cut by input triangles: each process gathers
 *    the links into the elements of its own triangles (in link order, so
 *    every sum is the serial sum) and pushes and pulls their trees, and
 *    `allgather` shares the elements' new values;
 *  - the work counters (kernel_evals, rays) are summed over the processes,
 *    so the statistics are the serial run's.
 * allgather is an in-place all-gather: buf holds count[r] items of
 * item_bytes bytes at item offset[r] for every process r, this process's
 * own block filled; on return every block holds its owner's.  It returns
 * RAD_OK on every process or a failure on every process (one of them
 * failed elsewhere and left: see mpi/), and the caller then returns that
 * failure without another exchange.  size <= 1 or allgather NULL (the
 * default): one process, nothing exchanged. */
typedef struct rad_hier_exchange {
    int rank, size;
    rad_status (*allgather)(void *ctx, void *buf, size_t item_bytes, const size_t *count,
                            const size_t *offset);
    void *ctx;
    int split_gather;     /* 1: share the gather too (see above); default 0 */
} rad_hier_exchange;

enum { RAD_HIER_CLIP_BLOCKERS_MAX = 256, RAD_HIER_ANDERSON_MAX = 8 };

typedef struct rad_hier_params {
    rad_hier_oracle oracle; /* default RAD_HIER_ORACLE_ERROR */
    int cluster;          /* 1: link through a cluster hierarchy over the input triangles
                             (cluster.c) instead of linking every pair of them; default 0 */
    rad_hier_cluster_model cluster_model; /* default RAD_HIER_CLUSTER_ORIENTED */
    double eps;           /* the error target relative to R (see above); > 0.  Default 0.1 */
    double min_area;      /* no element is split into children smaller than this; >= 0.
                             Default 0 (then max_depth alone bounds refinement) */
    int max_depth;        /* quadtree levels below an input triangle; default 10 */
    int sealed;           /* 1: every point sees only front faces (rad_effects_plan.sealed),
                             so every leaf's row of form factors is scaled to sum to 1
                             exactly; 0 (default): rows summing above 1 are scaled to 1 */
    double link_share;    /* ERROR: a link is refined when its contribution to the bound
                             exceeds link_share x eps R (x its triangle's scale); > 0,
                             default 0.5 */
    int degree;           /* the point-value rule: symmetric, of this degree, on both
                             elements of a link (2..10, 4 points or more fit the gradient
                             with a residual); default 4 (6 points each) */
    /* An explicit rule: use_rule = 1 takes the unoccluded F from rad_ff with
     * `rule` (and ff) and the point values only for the visible fraction,
     * the error terms and the oracle.  Default 0. */
    int use_rule;
    rad_ff_rule rule;
    rad_ff_params ff;
    int source_slope;     /* 1 (default): the gather corrects each source's mean B for
                             its slope against the form factor's (solve.c); 0: plain
                             P0 transport, which on leaf-level links is the dense
                             Galerkin system */
    double far_ratio;     /* pairs that nothing can block and whose centroids lie more
                             than far_ratio times the longer element's longest edge
                             apart take their point values from the kernel at the
                             degree-2 nodes of the other element instead of the
                             closed form; 0: never.  Default 3 */
    double tol;           /* gather/push-pull stops when the largest change of a leaf
                             radiosity in one step is <= tol x the largest leaf
                             radiosity; default 1e-10 */
    double bound_tol;     /* the same for the error transport T; default 1e-3 */
    int anderson;         /* the steps of a solve are mixed (Anderson, accel.c) over the
                             last `anderson` residual differences (at most 8); 0: plain
                             Jacobi steps.  Default 4 */
    int max_iterations;   /* steps per solve before RAD_ENUMERIC; default 100000 */
    int max_rounds;       /* refinement rounds in rad_hier_solve; default 64 */
    double round_min;     /* a round that refines fewer than round_min x the links ends
                             the rounds (it is solved and the oracle's tightening, if any,
                             goes on from there): the last rounds of a large hierarchy
                             refine the few links B's last change pushed over their
                             thresholds, each at the cost of a full pass and solve, and
                             what they leave the bound reports.  0: only a round that
                             refines nothing.  Default 1e-2 */
    double round_tol;     /* the solves between rounds only feed the oracle, whose
                             decisions compare errors with eps R (R the mean reflected
                             radiosity): they stop where B is within about
                             round_tol eps R of its fixed point.  Default 0.5 */
    double final_share;   /* the last solve stops where B is within about final_share
                             eps R of its fixed point (a share of the target the
                             error estimate carries as its iteration part), or at
                             tol where that is looser; 0: at tol.  Default 0.01 */
    int max_tighten;      /* ERROR: an input triangle whose bound still exceeds eps when
                             no link wants refining (and, after the first time, whose
                             mean B the last tightening moved by more than eps R) has
                             its thresholds quartered, at most this many times
                             (default 3: 64-fold) */
    int clip_blockers;    /* an element link whose shaft holds at most this many blockers
                             clips each point's view of the other element exactly; beyond
                             it (or past the clipping's work budget) the view is sampled
                             by rays, whose sampling error joins the link's, until the
                             oracle would refine the link: then it and the links split
                             from it clip up to RAD_HIER_CLIP_BLOCKERS_MAX (refine.c).
                             0: always rays.  0..RAD_HIER_CLIP_BLOCKERS_MAX; default 24
                             (rays cost the same for any crowd, clipping about
                             blockers x pieces) */
    int singular;         /* 1 (default): elements that touch get their unoccluded F from
                             a singular-aware rule (ss:5 where they share a vertex or an
                             edge, exact where one touches the other); 0: from point
                             values like every other pair (the effects plan's singular
                             decision forced off) */
    int threads;          /* OpenMP threads for the link estimates; 0 (default): OpenMP's
                             default.  Results do not depend on it */
    size_t max_elements;  /* RAD_ETOOBIG beyond this many elements (all levels); 4e6 */
    size_t max_links;     /* RAD_ETOOBIG beyond this many links (pairs, each carrying
                             light both ways); 5e7 */
    /* Called by rad_hier_solve after each solve (round 0: the initial links),
     * with the leaves and links (element and cluster links) at that point;
     * may be NULL (default). */
    void (*progress)(int round, size_t leaves, size_t links, void *ctx);
    /* Called while a round's hierarchy is made or solved, so that a long run
     * shows it is moving (may be NULL, the default): what is "linking" with
     * the links made so far, after each generation of new links, "solving"
     * with the gather/push-pull steps taken, or "bounding" with the error
     * transport's steps; round as progress will report it (0: the initial
     * links).  Gets progress_ctx. */
    void (*working)(int round, const char *what, size_t count, void *ctx);
    void *progress_ctx;
    rad_hier_exchange exchange; /* cooperating processes (above); default: none */
} rad_hier_params;

void rad_hier_params_default(rad_hier_params *params);
/* RAD_OK, or RAD_EINVAL naming the first parameter out of range. */
rad_status rad_hier_params_check(const rad_hier_params *params);

typedef struct rad_hier_stats {
    size_t elements;      /* leaves */
    size_t nodes;         /* elements at every level */
    size_t links;         /* live links: pairs, each carrying light both ways (DESIGN.md's
                             stats `links`, pairs coupled, as dense counts them; an
                             implementation with one-way links needs two for each) */
    /* live links by visibility: nothing can block the pair; blockers but every
     * point value sees all of the other element; partly hidden; hidden at
     * every point value; and links whose point values are all 0 although
     * their elements face each other */
    size_t links_clear, links_visible, links_partial, links_blocked, links_unknown;
    size_t links_sampled; /* live links whose view rays sampled: more blockers than
                             clip_blockers (and not clipped again, refine.c) */
    size_t links_leaf;    /* live links joining two leaves */
    size_t links_constant;/* hier p1/p2: live links reduced to the constants' coupling
                             because a mode through them did not contract (hierp/solve.c) */
    size_t links_cluster; /* live links with a cluster of two or more triangles at one end
                             (counted in links too) */
    size_t clusters;      /* nodes of the cluster hierarchy (0 without clustering) */
    int max_depth;        /* deepest leaf */
    long long kernel_evals; /* closed forms and kernel evaluations of all estimates */
    unsigned long long rays;
    long long iterations; /* gather/push-pull steps, all rounds */
    long long refinements;/* links refined (replaced by finer ones), all rounds */
    int rounds;           /* refinement rounds that refined something */
    double residual;      /* last step's largest change relative to the largest B */
    /* The error bound after the last solve, relative to R (see the header):
     * the largest over the leaves, the largest over the input triangles of
     * their area-weighted mean, and the area-weighted mean over the scene. */
    double bound_leaf_max, bound_face_max, bound_mean;
    double reflected;     /* R */
    double local_cluster; /* the share of the leaves' local errors of F (area-weighted,
                             the channels summed, before the transport) that links
                             with a cluster at one end bring: where the bound comes
                             from (0 without clusters) */
    long long links_bound;/* links the oracle would refine but whose elements can no
                             longer be split (min_area, max_depth) */
    int target_met;       /* 1: every leaf's bound is within eps R */
    double time_link_s;   /* initial linking (rad_hier_create) */
    double time_refine_s; /* oracle passes and the links they make */
    double time_solve_s;  /* gather / push-pull and the error transport */
    /* where those times go: estimating links with a cluster at one end and
     * links between elements (inside time_link_s and time_refine_s), and the
     * error transport (inside time_solve_s) with its steps */
    double time_estimate_cluster_s, time_estimate_element_s, time_bound_s;
    long long iterations_bound;
    double time_comm_s;   /* exchanges between processes (params.exchange), inside the
                             three times above; 0 for one process */
    int tightenings;      /* ERROR: the oracle's tightenings, each quartering the
                             thresholds of some input triangles (each triangle's at
                             most max_tighten times; different triangles' in different
                             tightenings, so there may be more than max_tighten) */
    double tightened_share; /* the sum over the tightenings of the share of the scene's
                             area each quarters (0 .. tightenings) */
    double gain;          /* sealed: the last step's gain farthest from 1 over the
                             channels, the power the leaves send over what reaches
                             them (solve.c); 0 where the scene is not sealed */
} rad_hier_stats;

/* Build the roots (one per input triangle; xyz: 3 * nverts doubles, tri:
 * 3 * ntris indices, rho and E: ntris x 3 column-major, copied) and link every
 * pair of input triangles that face each other (both directions).  B starts
 * at E.  vis may be NULL (no occlusion); it must hold exactly these triangles,
 * is borrowed and must outlive the rad_hier.  RAD_EINVAL for bad parameters
 * (eps <= 0, min_area < 0, ...), RAD_EINPUT for an index out of range, rho
 * outside [0,1), E < 0 or a degenerate triangle (naming it). */
rad_status rad_hier_create(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                           const double *rho, const double *E, const rad_vis *vis,
                           const rad_hier_params *params, rad_hier **out);
void rad_hier_destroy(rad_hier *h);

/* One Jacobi step: gather B_gathered = sum F B_source on every receiver,
 * then push (add ancestors' gathered radiosity on the way down, leaves take
 * B = E + rho * total) and pull (parents take the area-weighted mean of their
 * children).  RAD_ENUMERIC if a radiosity is not finite. */
rad_status rad_hier_step(rad_hier *h);
/* RAD_OK when the last step changed no leaf by more than tol * max B,
 * RAD_CONTINUE otherwise (also before the first step). */
rad_status rad_hier_test(const rad_hier *h);
/* One oracle pass with the current B (the ERROR oracle computes the error
 * bound first); links made by splitting are examined in the same pass.
 * *refined (may be NULL) gets the number of links refined.  RAD_ETOOBIG past
 * max_elements / max_links. */
rad_status rad_hier_refine(rad_hier *h, long long *refined);
/* The whole algorithm: steps to convergence, refine, repeat until a round
 * refines nothing or fewer than round_min of the links (or max_rounds), then
 * the final solve and error bound.
 * RAD_ENUMERIC when a solve does not converge in max_iterations steps. */
rad_status rad_hier_solve(rad_hier *h);

/* The largest row sum (the irradiance a uniform unit radiosity brings to a
 * point) a leaf keeps; the approximations can make a row larger, and the
 * solve scales such a leaf's irradiance back to it.  Sealed: exactly 1 (the
 * solve scales every row to 1).  Otherwise halfway between 1 and 1 / rho_max
 * (rho_max taken as at least 1/2): the step then contracts by at most
 * (1 + rho_max) / 2 < 1, and a row a little over 1 is left alone, since
 * scaling it would scale the leaf's accurate terms (a light's) with the
 * inaccurate ones that made it exceed 1.  Shared by rad_hier and rad_hierp. */
double rad_hier_row_ceiling(int sealed, double rho_max);

/* The step-change tolerance (relative to the largest radiosity bmax) at which
 * a solve stops that must leave B within share eps R of its fixed point (R
 * the mean reflected radiosity): a step change delta leaves B within delta
 * bmax q / (1 - q), q <= (1 + rho_max) / 2 the step's contraction.  The
 * solves between refinement rounds only feed the oracle, whose decisions
 * compare errors with eps R (share round_tol); the last one's distance is the
 * error estimate's iteration part (share final_share).  R and bmax from the
 * last solve (bmax <= 0: none yet, taken as R); never below p->tol.  Shared by
 * rad_hier and rad_hierp. */
double rad_hier_solve_tolerance(const rad_hier_params *p, double share, double rho_max, double R,
                                double bmax);

/* Per pair of the triangles of vis (the input triangles, pairs.c): whether
 * something can block it (rad_vis_pair_can_block) and whether the two may
 * touch (rad_ff_triangles_touch), each entry made when first asked for.
 * get: the entry's flags; can_block >= 0 gives the shaft test's answer when
 * the caller has walked the pair's shaft already (its blockers: nonzero when
 * any), -1 lets the table walk it.  known: whether the entry is made.
 * Thread-safe.  Shared by rad_hier and rad_hierp. */
enum { RAD_HIER_PAIR_CAN_BLOCK = 1, RAD_HIER_PAIR_MAY_TOUCH = 2 };
typedef struct rad_hier_pairs rad_hier_pairs;
rad_hier_pairs *rad_hier_pairs_create(const rad_vis *vis);
void rad_hier_pairs_destroy(rad_hier_pairs *t);
unsigned rad_hier_pairs_get(rad_hier_pairs *t, int r, int s, int can_block);
int rad_hier_pairs_known(const rad_hier_pairs *t, int r, int s);

/* Touching pairs' singular integrals, remembered (memo.c): rad_ff_compute
 * of the pair with params, run on the pair moved and scaled by a power of two
 * to a canonical frame and rounded there to 2^-40 of its size, so that pairs
 * equal up to translation and power-of-two scale (midpoint subdivision makes
 * many) share one computation and every call gets the same bits, remembered
 * or not.  out->evals are the value's, remembered or not.  Thread-safe.
 * Shared by rad_hier and rad_hierp. */
typedef struct rad_hier_memo rad_hier_memo;
rad_hier_memo *rad_hier_memo_create(const rad_ff_params *params);
void rad_hier_memo_destroy(rad_hier_memo *m);
rad_status rad_hier_memo_compute(rad_hier_memo *m, const rad_vec3 ti[3], const rad_vec3 tj[3],
                                 rad_ff_rule rule, rad_ff_result *out);
size_t rad_hier_memo_count(const rad_hier_memo *m); /* values remembered */

void rad_hier_get_stats(const rad_hier *h, rad_hier_stats *stats);

/* The leaves, in a fixed order: count, then per leaf (each pointer may be
 * NULL) its input triangle, its area, its corners (9 doubles: a, b, c, counter
 * -clockwise like its input triangle) and B (leaf_count x 3 column-major). */
size_t rad_hier_leaf_count(const rad_hier *h);
void rad_hier_leaves(const rad_hier *h, int *face, double *area, double *corners, double *B);
/* The error bound of every leaf (same order; leaf_count x 3), absolute
 * (W/m^2), as of the last rad_hier_solve or rad_hier_refine. */
void rad_hier_leaf_bounds(const rad_hier *h, double *bound);

#ifdef __cplusplus
}
#endif
#endif
