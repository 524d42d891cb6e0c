/* rad_hier: hierarchical radiosity (Hanrahan, Salzman, Aupperle 1991,
 * refs.bib key hanrahan1991) for piecewise-constant (P0) elements.
 *
 * Each input triangle is the root of a quadtree of elements (1 -> 4 midpoint
 * split).  Links join a receiver element to a source element at whatever level
 * their interaction deserves; a link carries the receiver's form factor
 * F_rs = G_rs / A_r (rad_ff, unoccluded, cosines clamped) and a visible
 * fraction V_rs.  The system solved is the hierarchical form of
 *     B_i = E_i + rho_i sum_j F_ij B_j
 * (DESIGN.md conventions: per-channel arrays n x 3 column-major, B in W/m^2).
 *
 * Refinement oracles.  Both compare a radiosity with eps * S, where S is the
 * area-weighted mean over the leaves of the reflected radiosity max_c (B - E)
 * of the current solution (E_max, the largest emission, before anything is
 * reflected).  So eps is a relative error per link: eps = 0.1 refines every
 * link whose error estimate exceeds 10% of the scene's mean reflected
 * radiosity.  (Relative to E_max, as first built, the Cornell box's lamp -- 200
 * times brighter than its walls -- set the scale, and links between walls were
 * never refined: coarse solutions came out 5-15% dark.)
 *  - BF (HSA 1991): the radiosity the link brings to its receiver,
 *        max_c rho_r[c] * F_rs * V_rs * max_c B_s[c]  >  eps * S;
 *    the larger element of the pair is split.
 *  - ERROR (after Bekaert & Willems 1996): the error of the link's constant
 *    transport, i.e. how far the point-to-element form factor F(x, s) strays
 *    from its Galerkin projection F_rs over the receiver (x at the centroids of
 *    r's four children), and the same from the source's side (F(y, r) over s,
 *    scaled by A_s / A_r to the receiver's units), times the transported
 *    radiosity:  max_c rho_r[c] * max(dF_r, dF_s) * max_c B_s[c]  >  eps * S;
 *    the side with the larger variation is split.
 * With either oracle a link that is not fully visible is judged on its
 * unoccluded transport rho F B_s (partial visibility raises the error: only
 * refinement can resolve a shadow), and a link whose estimate is 0 though its
 * elements are not provably apart is refined while it can be.  An element may
 * be split when its children (area / 4) are at least min_area and its depth is
 * below max_depth; when the chosen one may not, the other is split.
 *
 * Usage: rad_hier_create (initial linking), then either rad_hier_solve (the
 * whole loop) or the steps: rad_hier_step / rad_hier_test (gather and
 * push-pull until converged) and rad_hier_refine (one oracle pass), repeated until
 * rad_hier_refine refines nothing.  New links are estimated in parallel
 * (OpenMP, each into its own slot): results do not depend on the thread count. */
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
    RAD_HIER_ORACLE_ERROR = 1 /* kernel variation times transported radiosity */
} rad_hier_oracle;

/* "bf" or "error"; RAD_EINVAL naming the text otherwise. */
rad_status rad_hier_oracle_parse(const char *text, rad_hier_oracle *oracle);
const char *rad_hier_oracle_name(rad_hier_oracle oracle);

typedef struct rad_hier_params {
    rad_hier_oracle oracle; /* default RAD_HIER_ORACLE_ERROR (fewer links for the same
                               error than BF on the Cornell box) */
    double eps;           /* oracle threshold relative to S (see above); > 0.  Default 0.1 */
    double min_area;      /* no element is split into children smaller than this; >= 0.
                             Default 0 (then max_depth alone bounds refinement) */
    int max_depth;        /* quadtree levels below an input triangle; default 8 */
    rad_ff_rule rule;     /* form-factor estimate per link; default analytic:6 */
    /* ff.tol (auto's tolerance, when rule is auto) defaults to 1e-3 here */
    double far_ratio;     /* pairs whose centroids lie more than far_ratio times the
                             longest edge of either element apart use far_rule, and
                             the ERROR oracle samples the kernel at 3 points of the
                             other element instead of the closed form; 0: every pair
                             uses rule.  Default 1.5 */
    rad_ff_rule far_rule; /* default gauss:2 (0.15% off on average at 1.5-2 edges,
                             0.06% at 2-3: test ff_gauss2_far_pairs) */
    rad_ff_params ff;     /* its parameters (rad_ff_defaults) */
    int oracle_F;         /* 1: with the ERROR oracle, a link whose elements may
                             still be split takes F from the oracle's 8 point
                             values (4 per side) instead of rule or far_rule; only
                             links that stay unsplit take the rule.  0: every link
                             takes rule / far_rule.  Default 1 */
    int vis_points;       /* visibility samples per element, 1 (centroid) or 4 (the
                             centroids of its four children): vis_points^2 rays per
                             link that something may block.  Default 4 */
    double tol;           /* gather/push-pull stops when the largest change of a leaf
                             radiosity in one step is <= tol * the largest leaf
                             radiosity; default 1e-10 */
    int max_iterations;   /* steps per solve before RAD_ENUMERIC; default 10000 */
    int max_rounds;       /* refinement rounds in rad_hier_solve; default 64 */
    size_t max_elements;  /* RAD_ETOOBIG beyond this many elements (all levels); 4e6 */
    size_t max_links;     /* RAD_ETOOBIG beyond this many links; 5e7 */
    /* Called by rad_hier_solve after each solve (round 0: the initial links),
     * with the leaves and links at that point; may be NULL (default). */
    void (*progress)(int round, size_t leaves, size_t links, void *ctx);
    void *progress_ctx;
} rad_hier_params;

void rad_hier_params_default(rad_hier_params *params);

typedef struct rad_hier_stats {
    size_t elements;      /* leaves */
    size_t nodes;         /* elements at every level */
    size_t links;         /* live links */
    /* live links by visibility: no rays needed (nothing can block the pair),
     * traced and all open, partly blocked, all blocked; and links whose
     * estimate is 0 though their elements are not provably apart */
    size_t links_clear, links_visible, links_partial, links_blocked, links_unknown;
    size_t links_leaf;    /* live links joining two leaves */
    int max_depth;        /* deepest leaf */
    long long kernel_evals; /* rad_ff kernel evaluations over all links ever estimated,
                               plus the oracle's point-to-element evaluations */
    unsigned long long rays;
    long long iterations; /* gather/push-pull steps, all rounds */
    long long refinements;/* links refined (replaced by finer ones), all rounds */
    int rounds;           /* refinement rounds that refined something */
    double residual;      /* last step's largest change relative to the largest B */
    double time_link_s;   /* initial linking (rad_hier_create) */
    double time_refine_s; /* oracle passes and the links they make */
    double time_solve_s;  /* gather / push-pull */
} rad_hier_stats;

/* Build the roots (one per input triangle; xyz: 3 * nverts doubles, tri:
 * 3 * ntris indices, rho and E: ntris x 3 column-major, copied) and link every
 * pair of input triangles that face each other (both directions).  B starts
 * at E.  vis may be NULL (no occlusion); it is borrowed and must outlive the
 * rad_hier.  RAD_EINVAL for bad parameters (eps <= 0, min_area < 0, ...),
 * RAD_EINPUT for an index out of range, rho outside [0,1), E < 0 or a
 * degenerate triangle (naming it). */
rad_status rad_hier_create(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                           const double *rho, const double *E, const rad_vis *vis,
                           const rad_hier_params *params, rad_hier **out);
void rad_hier_destroy(rad_hier *h);

/* One Jacobi step: gather B_gathered = sum F V B_source on every receiver,
 * then push (add ancestors' gathered radiosity on the way down, leaves take
 * B = E + rho * total) and pull (parents take the area-weighted mean of their
 * children).  RAD_ENUMERIC if a radiosity is not finite. */
rad_status rad_hier_step(rad_hier *h);
/* RAD_OK when the last step changed no leaf by more than tol * max B,
 * RAD_CONTINUE otherwise (also before the first step). */
rad_status rad_hier_test(const rad_hier *h);
/* One oracle pass over every link with the current B; links made by splitting
 * are examined in the same pass.  *refined (may be NULL) gets the number of
 * links refined.  RAD_ETOOBIG past max_elements / max_links. */
rad_status rad_hier_refine(rad_hier *h, long long *refined);
/* The whole algorithm: steps to convergence, refine, repeat until a round
 * refines nothing (or max_rounds).  RAD_ENUMERIC when a solve does not
 * converge in max_iterations steps. */
rad_status rad_hier_solve(rad_hier *h);

void rad_hier_get_stats(const rad_hier *h, rad_hier_stats *stats);

/* The leaves, in a fixed order: count, then per leaf (each pointer may be
 * NULL) its input triangle, its area, its corners (9 doubles: a, b, c, counter
 * -clockwise like its input triangle) and B (leaf_count x 3 column-major). */
size_t rad_hier_leaf_count(const rad_hier *h);
void rad_hier_leaves(const rad_hier *h, int *face, double *area, double *corners, double *B);

#ifdef __cplusplus
}
#endif
#endif
