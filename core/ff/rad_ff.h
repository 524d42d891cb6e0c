/* rad_ff: the form factor between two triangles and every scheme radkit offers
 * for its double integral.
 *
 *   G = A_i F_ij = A_j F_ji = int_Ti int_Tj k(x, y) dA_y dA_x,
 *   k(x, y) = max(0, cos_i) max(0, cos_j) / (pi r^2)
 *
 * with cos_i = n_i . (y - x) / r and cos_j = n_j . (x - y) / r.  Each cosine is
 * clamped, not the product.  Triangles are one-sided: the front is the side the
 * counter-clockwise winding's normal (b - a) x (c - a) points to.  No
 * visibility: this is the unoccluded form factor.
 *
 * Thread safety and cost: every function is re-entrant, keeps no global state
 * and allocates nothing; scratch lives on the stack: up to about 40 kB for
 * the highest orders of gauss/analytic/ss, and about 140 kB inside exact (and
 * auto), whose adaptive integrator (rad_quad_adapt) keeps its interval table
 * on the stack.  Threads need stacks of at least 256 kB (OpenMP's default is
 * 2-8 MB).  One call computes one pair; the dense assembly may
 * call it from many threads at once.
 *
 * Schemes (rad_ff_rule; text form in parentheses, as the CLI takes it):
 *   vertex     (vertex)      the seed notes' rule: (A_i A_j / 9) sum of the
 *                            kernel over the 3 x 3 vertex pairs
 *   centroid   (centroid)    one point on each triangle
 *   gauss      (gauss:P)     a symmetric rule of degree P on both triangles
 *   analytic   (analytic:P)  inner integral in closed form (point to polygon),
 *                            outer rule of degree P
 *   ss         (ss:N)        Sauter-Schwab for edge/vertex-adjacent pairs, N
 *                            Gauss points per direction; a product rule otherwise
 *   exact      (exact)       double contour integral, inner closed form, outer
 *                            adaptive: the reference, near machine precision
 *   auto       (auto)        picks one of the above per pair for a tolerance */
#ifndef RAD_FF_H
#define RAD_FF_H

#include <stddef.h>

#include "rad_error.h"
#include "rad_geom.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum rad_ff_scheme {
    RAD_FF_VERTEX,   /* the notes' 3 x 3 vertex average */
    RAD_FF_CENTROID, /* one point per triangle */
    RAD_FF_GAUSS,    /* symmetric rule of degree `order` on both triangles */
    RAD_FF_ANALYTIC, /* closed-form inner integral, outer rule of degree `order` */
    RAD_FF_SS,       /* Sauter-Schwab, `order` Gauss points per direction */
    RAD_FF_EXACT,    /* contour-integral reference */
    RAD_FF_AUTO      /* per-pair choice for the tolerance in rad_ff_params */
} rad_ff_scheme;

#define RAD_FF_MAX_DEGREE 40 /* highest degree for gauss:P and analytic:P */
#define RAD_FF_SS_MAX 32     /* most Gauss points per direction for ss:N */

typedef struct rad_ff_rule {
    rad_ff_scheme scheme;
    int order; /* P for gauss and analytic, N for ss; 0 otherwise */
} rad_ff_rule;

/* Parse "vertex", "centroid", "gauss:P", "analytic:P", "ss:N", "exact", "auto".
 * RAD_EINVAL with a message naming the problem for an unknown rule, a missing
 * or malformed order, or an order outside what the scheme supports. */
rad_status rad_ff_rule_parse(const char *text, rad_ff_rule *rule);
/* The text form of a rule ("gauss:4"), truncated to `size`. */
void rad_ff_rule_format(rad_ff_rule rule, char *buf, size_t size);

/* How two triangles touch, detected from coordinates (rad_ff_adjacency_detect). */
typedef enum rad_ff_adjacency {
    RAD_FF_DISJOINT = 0,  /* no shared vertex */
    RAD_FF_SHARE_VERTEX,  /* exactly one shared vertex */
    RAD_FF_SHARE_EDGE,    /* two shared vertices (a common edge) */
    RAD_FF_SHARE_ALL      /* the same three vertices */
} rad_ff_adjacency;

enum {
    RAD_FF_FLAG_NOT_FACING = 1u,    /* one triangle lies behind or in the other's plane
                                       (facing away or coplanar): exactly 0, no integration */
    RAD_FF_FLAG_GUARDED = 2u,       /* the rule evaluated the kernel at r = 0 (a shared
                                       vertex); those terms were taken as 0 and counted */
    RAD_FF_FLAG_OUT_OF_RANGE = 4u,  /* F12 or F21 lies outside [0, 1]: the estimate is
                                       wrong; it is reported as computed, never clamped */
    RAD_FF_FLAG_NOT_CONVERGED = 8u, /* an adaptive integration (exact) or auto missed its
                                       tolerance; the value is the best one found */
    RAD_FF_FLAG_COINCIDENT = 16u    /* (with NOT_FACING) the triangles lie in one plane
                                       within rounding, face opposite ways and overlap: F
                                       is 0 for the two sides of one surface (what the
                                       assembly takes), but tends to the overlap's share as
                                       facing triangles close, so the pair is ambiguous */
};

typedef struct rad_ff_params {
    double adjacency_rel_tol; /* two vertices are the same when closer than this times
                                 the smaller triangle's longest edge (1e-10) */
    double plane_rel_tol;     /* a vertex nearer the other triangle's plane than this
                                 times the rounding scale, the larger of the pair's
                                 longest edge, its extent and its coordinates'
                                 magnitude, counts as on it (64 DBL_EPSILON: rounding,
                                 not geometry; a real gap, however thin, is integrated) */
    double degenerate_rel_tol;/* rad_geom_triangle_is_degenerate threshold (1e-12) */
    double exact_rel_tol;     /* relative tolerance of each adaptive outer integral of
                                 `exact` (1e-14) */
    double exact_retry_rel;   /* exact falls back to a checked analytic:40 when its
                                 contour estimate exceeds this (1e-12) */
    double exact_flag_rel;    /* exact flags not_converged when its estimate (a
                                 pessimistic bound) exceeds this (1e-10) */
    double exact_far_ratio;   /* exact uses a converged product Gauss rule instead of
                                 the contour integral when the centroid distance
                                 exceeds this times the longest edge (5) */
    double auto_near_ratio;   /* auto uses analytic:P instead of gauss:P for disjoint
                                 pairs closer than this times the longest edge (0.5) */
    double auto_min_ratio;    /* ... and exact for pairs closer than this (0.05) */
    double auto_safety;       /* auto accepts a rule when it differs from the previous
                                 one of its ladder by at most this times T (0.1) */
    long auto_exact_cost;     /* exact's cost on an adjacent pair in kernel-evaluation
                                 equivalents; auto tries ss:N only when cheaper (35000) */
    double tol;               /* relative accuracy auto aims for (1e-6) */
    int skip_facing_away;     /* 1 (default): a pair facing away (or coplanar) is 0 without
                                 integration, flagged NOT_FACING; 0: the rule integrates it
                                 anyway (the effects plan's facing_away forced off) */
    int singular_rules;       /* 1 (default): auto gives touching pairs the singular-aware
                                 rules (ss:N, exact); 0: the regular Gauss ladder, as if
                                 they were apart (the plan's singular decision forced off;
                                 flagged NOT_CONVERGED where the ladder does not settle) */
} rad_ff_params;

void rad_ff_params_default(rad_ff_params *params);
/* params with `exact` integrating its contour to 1e-6 (its retry and flag
 * thresholds raised to 1e-3, so that a touching pair's contour, whose bound
 * is pessimistic, is not redone by the product rules): for callers that
 * need a pair's G to about 1e-6 and take its error estimate with it, such as
 * hierarchical links, not to the reference's 1e-14. */
rad_ff_params rad_ff_params_link_exact(const rad_ff_params *params);

typedef struct rad_ff_result {
    double F12, F21;     /* F_ij = G / A_i and F_ji = G / A_j */
    double G;            /* A_i F_ij, the symmetric coupling */
    double A1, A2;       /* areas */
    double rel_error;    /* estimated relative error of G (hence of F12 and F21);
                            NAN when the scheme has no estimate */
    long evals;          /* kernel evaluations; for analytic and exact, closed-form
                            point-to-polygon / point-to-edge evaluations */
    long guarded;        /* kernel evaluations at r = 0 taken as 0 */
    unsigned flags;      /* RAD_FF_FLAG_* */
    rad_ff_rule used;    /* the rule that produced the value (auto's choice) */
    rad_ff_adjacency adjacency;
} rad_ff_result;

/* The form factor between triangles ti (i = 1) and tj (j = 2) by `rule`.
 * RAD_EINPUT for a degenerate (zero-area, collinear: a matter of shape, not
 * size) or non-finite triangle, or one whose area is below DBL_MIN (about
 * 1e-154 across); RAD_EINVAL for an unsupported rule order.  Scale-invariant:
 * a pair scaled by s gives the same F (G and the areas scale by s^2).  Out of range values are flagged,
 * not errors; a non-converged `exact` returns RAD_OK with the flag set. */
rad_status rad_ff_compute(const rad_vec3 ti[3], const rad_vec3 tj[3], rad_ff_rule rule,
                          const rad_ff_params *params, rad_ff_result *out);

/* 1 when the pair can exchange light: rad_ff_compute's facing test, without
 * the validation or any integration; 0 when it would set
 * RAD_FF_FLAG_NOT_FACING (faces away or coplanar).  For valid triangles only. */
int rad_ff_facing(const rad_vec3 ti[3], const rad_vec3 tj[3], const rad_ff_params *params);

/* The kernel k(x, y) above: x with unit normal nx, y with unit normal ny.
 * Returns 0 (and increments *guarded when not NULL) when x == y. */
double rad_ff_kernel(rad_vec3 x, rad_vec3 nx, rad_vec3 y, rad_vec3 ny, long *guarded);

/* Form factor from a differential area at x with unit normal n to the planar
 * polygon poly[0..nv) (nv <= 8, counter-clockwise seen from its front), with
 * both cosines clamped: the polygon is clipped to the half-space in front of x,
 * and the result is 0 when x is not in front of the polygon.  Closed form:
 * F = -(1/2pi) sum_k gamma_k n . (R_k x R_k+1) / |R_k x R_k+1| (Howell B-3,
 * Lambert's contour formula), R_k = poly[k] - x, gamma_k the angle between
 * R_k and R_k+1. */
double rad_ff_point_polygon(rad_vec3 x, rad_vec3 n, const rad_vec3 *poly, int nv);

/* Shared vertices of two triangles: vertex a of ti and b of tj are the same
 * when closer than rel_tol times the smaller triangle's longest edge.  On
 * return, map_i[a] is the index in tj matching ti's vertex a, or -1. */
rad_ff_adjacency rad_ff_adjacency_detect(const rad_vec3 ti[3], const rad_vec3 tj[3],
                                         double rel_tol, int map_i[3]);

/* Smallest distance between the two (closed) triangles. */
double rad_ff_triangle_distance(const rad_vec3 ti[3], const rad_vec3 tj[3]);

/* 1 when triangles ti and tj (centroids ci, cj, longest edges si, sj) touch:
 * within 1e-9 of the longer edge of each other.  A corner lies within the
 * longest edge of its centroid, so triangles whose centroids are farther
 * apart than both longest edges, or whose bounding boxes are apart, are
 * dismissed before the distance. */
int rad_ff_triangles_touch(const rad_vec3 ti[3], rad_vec3 ci, double si, const rad_vec3 tj[3],
                           rad_vec3 cj, double sj);

#ifdef __cplusplus
}
#endif
#endif
