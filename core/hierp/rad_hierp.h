/* rad_hierp: hierarchical Galerkin radiosity with polynomial elements (the
 * orthonormal bases of rad_basis.h, order 1 or 2; order 0 works too and is
 * the plain P0 hierarchy of the same engine).  Hanrahan, Salzman and
 * Aupperle's hierarchy (refs.bib hanrahan1991) in the Galerkin form of
 * Gortler, Schroeder, Cohen and Hanrahan 1993 and Bekaert and Willems 1996:
 *
 *  - Every input triangle is the root of a quadtree (1 -> 4 midpoint split,
 *    as rad_hier's).  Every element carries its radiosity as m coefficients
 *    per channel in its own orthonormal basis (m = 1, 3, 6), so its first
 *    coefficient over sqrt(A) is its mean.
 *  - A link joins elements a and b both ways with the m x m couplings
 *    K_kl = int_a int_b phi_ak(x) k(x, y) V(x, y) phi_bl(y) (link.c): a
 *    gathers K b_b and b gathers K^T b_a.
 *  - Push and pull are L2 projections between a parent's basis and its
 *    children's.  Restricting a polynomial to a child is exact, so the push
 *    is a fixed m x m matrix per child position (the same on every triangle:
 *    the basis is defined in the local coordinates the split keeps), and the
 *    pull, the projection of the four children's functions onto the parent's
 *    space, is the sum of the transposes (solve.c).
 *  - The oracle (refine.c) measures each link in the basis: how far the
 *    point form factor over the receiver departs from its projection on the
 *    receiver's functions (what the receiver's polynomial cannot show), how
 *    far the kernel over the source departs from its projection (what the
 *    source's unresolved detail does to the transport), and the integration
 *    error of the constants' coupling.  These per-link errors, carried
 *    through the transport (up to 1 / (1 - rho)), are the error estimate.
 *
 * Parameters are rad_hier's (rad_hier_params) with the order beside them:
 * eps, min_area, max_depth, sealed, link_share, ff, singular, far_ratio,
 * tol, bound_tol, round_tol, max_iterations, max_rounds, threads,
 * max_elements, max_links and progress apply as documented there; degree is
 * raised to at least 2 order + 2 (the couplings of two order-p functions
 * against a smooth kernel); max_tighten bounds the tightening of the
 * oracle's thresholds as it does for P0 (refine.c); the BF oracle,
 * use_rule and source_slope are rad_hier's P0 devices and are refused or
 * ignored as rad_hierp_create says.  The statistics are rad_hier_stats. */
#ifndef RAD_HIERP_H
#define RAD_HIERP_H

#include <stddef.h>

#include "rad_error.h"
#include "rad_hier.h"
#include "rad_vis.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rad_hierp rad_hierp;

/* Roots, initial links and B = E, as rad_hier_create; order 0..2.
 * RAD_EINVAL for an order out of range, the BF oracle or use_rule (P0
 * devices of rad_hier), or bad parameters; RAD_EINPUT for bad triangles,
 * reflectance outside [0,1) or negative emission, naming the triangle. */
rad_status rad_hierp_create(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                            const double *rho, const double *E, const rad_vis *vis,
                            const rad_hier_params *params, int order, rad_hierp **out);
void rad_hierp_destroy(rad_hierp *h);

/* An emission field in place of the per-triangle constants E (for a
 * manufactured solution): field(face, x, channel, ctx) at a point x of
 * input triangle face; projected on each element's functions as it is
 * made (a rule of degree 2 order + 6).  Call before rad_hierp_solve.
 * RAD_EINPUT when an element's mean is negative or not finite. */
rad_status rad_hierp_set_emission(rad_hierp *h,
                                  double (*field)(int face, rad_vec3 x, int channel, void *ctx),
                                  void *ctx);

/* Solve, refine where the oracle says, repeat until nothing is refined (or
 * max_rounds), then the last solve to tol and the error estimate.
 * RAD_ENUMERIC when a solve does not converge in max_iterations steps or a
 * radiosity is not finite; RAD_ETOOBIG past max_elements / max_links. */
rad_status rad_hierp_solve(rad_hierp *h);

void rad_hierp_get_stats(const rad_hierp *h, rad_hier_stats *stats);

/* The leaves, in a fixed order: count, then per leaf (each pointer may be
 * NULL) its input triangle, area, corners (9 doubles, counter-clockwise like
 * its input triangle, the basis' local coordinates running from corner 0),
 * mean radiosity B (count x 3 column-major) and coefficients (coefficient k
 * of leaf i in channel c at coef[(i m + k) + c count m], m =
 * rad_basis_size(order)). */
size_t rad_hierp_leaf_count(const rad_hierp *h);
void rad_hierp_leaves(const rad_hierp *h, int *face, double *area, double *corners, double *B,
                      double *coef);

#ifdef __cplusplus
}
#endif
#endif
