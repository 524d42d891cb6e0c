/* rad_radiosity: dense Galerkin radiosity assembly, the step of the data flow
 * between form factors and the solver (DESIGN.md).
 *
 * For P0 elements on triangles the Galerkin system is
 *     B_i = E_i + rho_i sum_j F_ij B_j,
 * and radkit assembles the symmetric coupling G_ij = int_i int_j K V (the
 * visible part of the kernel integral) once per unordered pair {i, j}:
 * reciprocity A_i F_ij = A_j F_ji then holds exactly in the assembled system,
 * and every pair costs one form factor instead of two.  G is dense,
 * column-major, with zero diagonal (a flat triangle does not see itself).
 * A pair nothing can block takes rad_ff's unoccluded G; a pair with possible
 * blockers takes rad_vis_pair_visible (visibility exact at every outer point,
 * so that the rows of a closed scene sum to 1 up to the outer rule's error;
 * rays where the clipping would be too complex).
 *
 * Departure from DESIGN.md: the assembly lives here, not in rad_dense, so that
 * the linear-algebra module does not depend on form factors and visibility. */
#ifndef RAD_RADIOSITY_H
#define RAD_RADIOSITY_H

#include <stddef.h>

#include "rad_error.h"
#include "rad_ff.h"
#include "rad_vis.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rad_radiosity_params {
    rad_ff_rule rule;   /* form-factor scheme per pair (default auto) */
    rad_ff_params ff;   /* its parameters (auto's tolerance among them) */
    int threads;        /* OpenMP threads; 0 = the OpenMP default */
    /* The triangle of the visibility structure each element lies on (borrowed,
     * n entries): the elements of a refined mesh over a rad_vis built on the
     * input triangles.  NULL: the rad_vis holds the elements themselves. */
    const int *face_of;
    rad_vis_visible_params visible; /* the visible integral's parameters */
    /* Called from one thread now and then with the fraction of pairs done
     * (0..1); NULL for none.  Must not call back into the library. */
    void (*progress)(double done, void *ctx);
    void *progress_ctx;
} rad_radiosity_params;

void rad_radiosity_params_default(rad_radiosity_params *params);

/* Work done by one assembly. */
typedef struct rad_radiosity_stats {
    long long pairs;             /* unordered pairs considered, n (n-1)/2 */
    long long pairs_not_facing;  /* zero without integration (facing away, coplanar) */
    long long pairs_occlusion_tested; /* pairs with possible blockers (visible integral) */
    long long pairs_sampled;          /* of those, pairs that fell back to rays */
    double visibility_error;          /* sum of the visible integrals' error estimates,
                                         over the sum of their G (relative) */
    long long pairs_out_of_range;     /* form-factor estimates flagged outside [0,1] */
    double rows_closed;               /* sealed: the largest |1 - sum_j F_ij| moved to a
                                         diagonal (rad_radiosity_close_rows); else 0 */
    long long kernel_evals;
    unsigned long long rays;
    double seconds;
} rad_radiosity_stats;

/* Assemble G (n x n, column-major, caller-owned) and the areas (n) of the
 * triangles tri[3k..3k+2] over the vertices xyz.  `vis` may be NULL: no
 * occlusion (the effects plan found that nothing can block).  Otherwise each
 * pair with a nonzero unoccluded form factor and possible blockers takes
 * rad_vis_pair_visible (see params->face_of).
 * RAD_EINPUT for a degenerate triangle (naming it), RAD_ENUMERIC if a form
 * factor is not finite. */
rad_status rad_radiosity_assemble(const double *xyz, const int *tri, int n, const rad_vis *vis,
                                  const rad_radiosity_params *params, double *G, double *areas,
                                  rad_radiosity_stats *stats);

/* Close the rows of a sealed scene's G (n x n, column-major; every point
 * sees only front faces, so the exact rows sum to the areas): each row's
 * deficit or excess, A_i - sum_j G_ij, joins its diagonal G_ii.  G stays
 * symmetric, so a uniform radiosity gathers exactly itself (the furnace
 * holds whatever the form factors' error, which 1 / (1 - rho) would
 * amplify) and the power the faces send arrives whole.  G_ii may then be
 * negative, down to -A_i (the dense solvers accept that).  Returns the
 * largest |A_i - sum_j G_ij| / A_i. */
double rad_radiosity_close_rows(double *G, const double *areas, int n);

/* One pair's coupling G_ij (= G_ji) exactly as rad_radiosity_assemble
 * computes it (the smaller index first, so either order gives the same
 * bits), for callers that distribute the pairs (radkit-mpi); its work is
 * added to *stats (may be NULL), all but visibility_error and seconds. */
rad_status rad_radiosity_pair(const double *xyz, const int *tri, int i, int j, const rad_vis *vis,
                              const rad_radiosity_params *params, double *G,
                              rad_radiosity_stats *stats);

/* The couplings of the orthonormal polynomial basis of `order` (rad_basis.h;
 * 1 or 2, m = rad_basis_size(order) functions per element) from the P0
 * couplings G and areas of rad_radiosity_assemble over the same triangles:
 * K (N x N, N = n m, column-major; unknown k of element i at i m + k) with
 * K_(ik)(jl) = int_i int_j phi_ik k V phi_jl.  The constants' entries are
 * G_ij / sqrt(A_i A_j); the others a product rule of degree 2 order + 2 where
 * the parts of a pair are well apart, recursive splitting (2 + order levels)
 * where they are not, and the parts' P0 coupling with centroid values at
 * the deepest level; V by a ray per node pair where the pair's shaft may
 * hold blockers (vis, params->face_of as for the assembly).  Kernel
 * evaluations and rays are added to *stats. */
rad_status rad_radiosity_assemble_basis(const double *xyz, const int *tri, int n,
                                        const rad_vis *vis, const rad_radiosity_params *params,
                                        int order, const double *G, const double *areas,
                                        double *K, rad_radiosity_stats *stats);

#ifdef __cplusplus
}
#endif
#endif
