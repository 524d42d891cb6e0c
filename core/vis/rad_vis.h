/* rad_vis: visibility between points and triangles, over Embree 3.
 *
 * A rad_vis holds one Embree scene built from the caller's flat arrays
 * (double vertex positions xyz[3*v], int triangle indices tri[3*t]).  Embree
 * intersects in single precision, so rad_vis keeps a float copy of the vertices
 * in a buffer it shares with Embree: every ray test sees the triangles moved by
 * up to half a float ulp of the largest coordinate (about 6e-8 relative).  The
 * ray epsilon (below) is therefore scaled to the scene's extent AND to its
 * largest absolute coordinate, so a scene far from the origin still gets an
 * epsilon larger than that rounding.
 *
 * Queries:
 *  - rad_vis_occluded: batched point-to-point occlusion of open segments;
 *  - rad_vis_pair_fraction: the visible fraction of a triangle pair from
 *    stratified samples, ignoring hits on the two triangles themselves;
 *  - rad_vis_pair_can_block: a conservative shaft test, so that pairs nothing
 *    can block trace no rays;
 *  - rad_vis_intersect: closest hits of rays (primary rays for rad_render).
 * Every query may be called concurrently from several OpenMP threads on one
 * rad_vis (Embree allows concurrent queries on a committed scene); each call
 * adds its work to the caller's rad_vis_stats, so give each thread its own.
 * Embree's device and scene are made by the first query that casts a ray
 * (rad_vis_prepare_rays), so creating a rad_vis costs only the shaft
 * hierarchy.
 *
 * Threads: Embree (built on TBB in Debian) would otherwise start one worker per
 * core for its BVH build and keep them spinning beside OpenMP's.  rad_vis creates
 * its device with "threads=N,set_affinity=0" (N = build_threads, default 1): the
 * build runs on N threads and all ray queries run on the calling (OpenMP) threads,
 * so the two thread pools never compete (checked: with build_threads = 1 the
 * process has no extra thread during the build of 2 x 10^5 triangles, which
 * takes tens of milliseconds, negligible next to the ray work). */
#ifndef RAD_VIS_H
#define RAD_VIS_H

#include <stddef.h>
#include <stdint.h>

#include "rad_error.h"
#include "rad_geom.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rad_vis rad_vis;

typedef struct rad_vis_params {
    /* Ray epsilon relative to the scene scale L = max(bounding-box diagonal,
     * largest |coordinate|): rays start eps = eps_rel * L after their origin and
     * stop eps before their end.  Default 1e-5 (about 170 float ulps of L). */
    double eps_rel;
    /* Stratified samples of a triangle pair: each triangle is cut into
     * strata_per_edge^2 congruent sub-triangles and one point is taken in each;
     * every point of one triangle is joined to every point of the other, so a
     * pair costs strata_per_edge^4 rays.  Default 3 (81 rays). */
    int strata_per_edge;
    /* 1: a point drawn uniformly in each stratum from a hash of (triangle,
     * stratum, seed): jittered stratified sampling, unbiased, deterministic for
     * any thread count, and symmetric (a triangle's samples do not depend on
     * its partner).  0: the stratum's centroid (a midpoint rule, which aliases
     * with straight shadow edges; papers/dense-radiosity.md compares the two).
     * Default 1. */
    int jitter;
    unsigned seed;
    /* Threads Embree may use to build the BVH (see the header comment).  Default 1. */
    int build_threads;
    /* Rays per Embree call in rad_vis_occluded: 1 (rtcOccluded1 in a loop), 4, 8
     * or 16 (rtcOccludedN packets); also used by rad_vis_pair_fraction.  Default
     * 16, the fastest here (bench/vis.sh: 16 matches plain rtcOccluded1 on
     * pre-built rays, 1 reaches about 0.8 of it). */
    int packet;
    /* Shaft-test tolerance relative to L (see rad_vis_pair_can_block).  Default 1e-9. */
    double shaft_tol_rel;
    /* 1: the exact clipping subtracts every face's shadow by itself; 0 (default):
     * a small closed convex solid (a box) casts one shadow, its hull (solid.c).
     * The same visible parts up to rounding. */
    int no_solids;
} rad_vis_params;

void rad_vis_params_default(rad_vis_params *params);

/* Work counters; the caller owns them and sums per-thread copies. */
typedef struct rad_vis_stats {
    unsigned long long rays;          /* rays traced */
    unsigned long long pairs_traced;  /* pair queries that traced rays */
    unsigned long long pairs_skipped; /* pair queries answered without rays */
} rad_vis_stats;

/* The scene sizes Embree's single precision resolves: the largest coordinate
 * at most RAD_VIS_MAX_SIZE, the extent at least RAD_VIS_MIN_SIZE (its
 * intersection tests multiply three coordinates, which must stay in float's
 * range). */
#define RAD_VIS_MIN_SIZE 1e-12
#define RAD_VIS_MAX_SIZE 1e12

/* Build the Embree scene.  xyz (3 * nverts doubles) and tri (3 * ntris ints,
 * 0-based) are copied; the caller may free them afterwards.  params may be NULL
 * for the defaults.  RAD_EINPUT for a non-finite coordinate or an index out of
 * range (naming the triangle), or a scene outside RAD_VIS_MIN_SIZE ..
 * RAD_VIS_MAX_SIZE; RAD_EINVAL for bad parameters, RAD_EDEP if Embree fails
 * (with Embree's message). */
rad_status rad_vis_create(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                          const rad_vis_params *params, rad_vis **out);
void rad_vis_destroy(rad_vis *vis);

/* The absolute ray epsilon in scene units, and the scene scale L it is made from. */
double rad_vis_epsilon(const rad_vis *vis);
double rad_vis_scale(const rad_vis *vis);
size_t rad_vis_triangle_count(const rad_vis *vis);
/* Triangle t's corners (t < rad_vis_triangle_count). */
void rad_vis_triangle_corners(const rad_vis *vis, size_t t, rad_vec3 out[3]);

/* Nonzero when no triangle can block any segment between two points of the
 * scene: every vertex lies on or in front of every triangle's plane (within the
 * shaft tolerance).  A convex closed enclosure seen from inside is the typical
 * case; then rad_vis_pair_fraction traces no rays at all. */
int rad_vis_is_unoccluded(const rad_vis *vis);

/* Batched occlusion of the segments from[3k..3k+2] -> to[3k..3k+2], k < n:
 * blocked[k] = 1 if some triangle crosses the segment shortened by the epsilon
 * at both ends, else 0.  Runs on the calling thread (call it from inside your
 * own OpenMP loop to parallelise). */
rad_status rad_vis_occluded(const rad_vis *vis, size_t n, const double *from, const double *to,
                            unsigned char *blocked, rad_vis_stats *stats);

/* As rad_vis_occluded for segments from points of triangle i to points of
 * triangle j (e.g. the quadrature points of a form-factor rule): hits on i
 * and j themselves are ignored, so end points on (or rounded slightly behind)
 * their own triangles are safe.  Traces every segment: call
 * rad_vis_pair_can_block first to skip pairs nothing can block. */
rad_status rad_vis_occluded_between(const rad_vis *vis, size_t i, size_t j, size_t n,
                                    const double *from, const double *to, unsigned char *blocked,
                                    rad_vis_stats *stats);

/* The sample points rad_vis_pair_fraction uses on triangle t (strata_per_edge^2
 * points, xyz interleaved, written to pts which must hold 3 * that many doubles). */
rad_status rad_vis_triangle_samples(const rad_vis *vis, size_t t, double *pts);
/* Number of sample points per triangle (strata_per_edge^2). */
int rad_vis_sample_count(const rad_vis *vis);

/* Conservative test: 0 when no triangle other than i and j can cross any
 * segment joining an interior point of triangle i to an interior point of j
 * along which the form-factor kernel is positive, 1 when one might.  Such a
 * segment lies in the convex hull of the two triangles (the shaft) and, its
 * ends each strictly in front of the other's plane, in front of both planes;
 * a triangle k can cross it only if k reaches into the hull, so k is
 * dismissed when all its vertices lie outside (or on) one face plane of the
 * hull or on or behind the plane of i or j, tested through a
 * bounding-volume hierarchy of triangle boxes.  (Segments of zero kernel
 * carry nothing: every user weighs visibility by the kernel.)
 * Conservative: a dismissed triangle provably cannot cross such a
 * segment (up to the tolerance tol = shaft_tol_rel * L, i.e. geometry reaching
 * into the hull by less than tol is ignored); a triangle that is not dismissed
 * may still miss every segment (the test never looks at k's interior against
 * the hull's, only its vertices against one plane at a time).  A flat hull
 * (coplanar pair) always answers 1. */
int rad_vis_pair_can_block(const rad_vis *vis, size_t i, size_t j);

/* The sampling key of the pair of triangles a, b: their corners' bits
 * hashed, so the same pair gives the same jittered samples on any thread or
 * process (the visible integral's sampled fallback, hier's ray fallback). */
uint64_t rad_vis_pair_key(const rad_vec3 a[3], const rad_vec3 b[3]);

/* Visible fraction of the pair (i, j): the share of the strata_per_edge^4
 * sample segments (every sample of i to every sample of j) that no triangle
 * other than i and j blocks, whatever the kernel along it.  1 without
 * tracing when rad_vis_is_unoccluded or nothing can cross any segment (the
 * shaft test without the planes of i and j).  Hits on i and j themselves
 * are ignored (by primitive id in the geometry's occlusion filter, and by the epsilon). */
rad_status rad_vis_pair_fraction(const rad_vis *vis, size_t i, size_t j, double *fraction,
                                 rad_vis_stats *stats);

/* Closest hits of n rays org[3k..] + t dir[3k..], t in (tnear, inf): tri[k] is
 * the triangle hit (-1 for none), t_hit[k] the distance in units of |dir|, and
 * (u[k], v[k]) the barycentric weights of the triangle's second and third
 * vertices at the hit (the first has 1 - u - v).  Any output pointer but tri may
 * be NULL. */
rad_status rad_vis_intersect(const rad_vis *vis, size_t n, const double *org, const double *dir,
                             double tnear, int *tri, double *t_hit, double *u, double *v,
                             rad_vis_stats *stats);

/* ---- exact visibility: what part of a triangle a point sees ------------------
 * visible.c opens with the method: the shadows of the possible blockers are
 * projected from the point onto the target's plane and subtracted from it
 * (convex polygon clipping), and the visible pieces are integrated in closed
 * form.  In a closed scene the visible pieces of all triangles tile a point's
 * hemisphere, so rows of form factors built on it sum to 1 up to the outer
 * quadrature's error: energy is conserved where rays would only sample it. */

/* The triangles that may block a segment of positive kernel between
 * triangle a (lying on input triangle face_a of the vis scene, or -1) and
 * triangle b (on face_b): the shaft test's survivors (with the planes of
 * face_a and face_b, as rad_vis_pair_can_block), face_a and face_b
 * excluded.  Up to max indices into out; returns their count, max + 1 when
 * there are more than max. */
int rad_vis_blockers(const rad_vis *vis, const rad_vec3 a[3], int face_a, const rad_vec3 b[3],
                     int face_b, int *out, int max);

/* Both answers for the pair of input triangles i and j from one walk of
 * their shaft: rad_vis_blockers into out (up to max, max + 1 when more),
 * and *can_block, rad_vis_pair_can_block's answer (1 for a flat pair, with
 * no blockers listed). */
int rad_vis_pair_blockers(const rad_vis *vis, size_t i, size_t j, int *out, int max,
                          int *can_block);

/* F_vis(x, b): the form factor from the point x (unit normal nx, its cosine
 * clamped) to the part of triangle b that the given blockers leave visible
 * (0 when x is behind b's plane); *F_open (may be NULL) the unoccluded one.
 * Returns 0 when the visible part has too many pieces to represent (then F
 * is not set; the caller falls back to rays), 1 otherwise.  evals (may be
 * NULL) counts closed-form evaluations. */
int rad_vis_point_visible(const rad_vis *vis, rad_vec3 x, rad_vec3 nx, const rad_vec3 b[3],
                          const int *blockers, int nb, double *F, double *F_open, long *evals);

/* The same within a budget: 0 also when the clipping would take more than
 * max_work piece-against-shadow tests (> 0; 0: no limit).  Its cost grows
 * like blockers x visible pieces, so a point that sees b between many
 * objects could take 10^4 tests and more, where rays estimate the value at
 * a fixed cost; scenes of a few objects stay far below
 * RAD_VIS_LINK_POINT_WORK, the budget of the hierarchical solvers' links. */
#define RAD_VIS_LINK_POINT_WORK 1024
int rad_vis_point_visible_limited(const rad_vis *vis, rad_vec3 x, rad_vec3 nx,
                                  const rad_vec3 b[3], const int *blockers, int nb, long max_work,
                                  double *F, double *F_open, long *evals);

/* rad_vis_point_visible_limited towards each of nparts triangles that tile
 * b in b's plane (a hierarchy's children of b; part i's corners are
 * parts[3 i .. 3 i + 2]), from one clipping of b: the visible part of b is
 * cut to each part.  F[i], F_open[i] per part; 0 as there (and when a cut
 * piece would have too many corners).  A part no shadow reaches gets its
 * F_open exactly. */
int rad_vis_point_visible_parts(const rad_vis *vis, rad_vec3 x, rad_vec3 nx, const rad_vec3 b[3],
                                const rad_vec3 *parts, int nparts, const int *blockers, int nb,
                                long max_work, double *F, double *F_open, long *evals);

/* The blockers in[0..n) of a pair that the shaft of triangles a and b does
 * not dismiss, in order, into out (which may be in); their count.  A pair
 * inside another's shaft (a child of one of its triangles with the other)
 * gets its rad_vis_blockers from its parent's this way. */
int rad_vis_blockers_within(const rad_vis *vis, const rad_vec3 a[3], const rad_vec3 b[3],
                            const int *in, int n, int *out);

/* A hierarchy's split: triangle b (on input face_b) is cut into four parts
 * (corners parts[3 i .. 3 i + 2]) that each will be linked with triangle o
 * (on face_o), whose points y[0..n)
 * (unit normal no) need their form factors towards each part.  The pair's
 * blockers go to blk (up to max; *nb = -1 when there are more, else their
 * count, which each part's pair may filter with rad_vis_blockers_within),
 * and when there are some, each point clips b once for the four parts
 * (rad_vis_point_visible_parts within max_work): F[i * stride + k] and
 * F_open[i * stride + k] for part i and point k.  Returns 1 with the values
 * set; 0 when the pair has no blockers, more than max, or a point exceeds
 * the budget (then each part's pair is to be clipped on its own). */
int rad_vis_split_values(const rad_vis *vis, const rad_vec3 o[3], int face_o, const rad_vec3 *y,
                         int n, rad_vec3 no, const rad_vec3 b[3], int face_b,
                         const rad_vec3 *parts, int *blk, int max, int *nb, long max_work,
                         double *F, double *F_open, int stride, long *evals);

typedef struct rad_vis_visible_params {
    int degree;       /* symmetric rule of this degree on each outer cell; default 2 */
    double tol;       /* accept a cell when its 4 children change the value by at most
                         its share of tol x the pair's unoccluded G; default 1e-2 */
    int max_depth;    /* outer cell levels at most (1: the rule and its children once);
                         0 (default): ceil(log4(1 / tol)) + 1 within 3..8 */
    int max_blockers; /* more possible blockers than this: rays instead (status
                         SAMPLED); default 1024, at most 65536 */
    int sample_strata;/* the rays' fallback: k^2 jittered points per triangle, k^4 rays;
                         default 8 */
} rad_vis_visible_params;

void rad_vis_visible_params_default(rad_vis_visible_params *params);

enum {
    RAD_VIS_VISIBLE_EXACT = 0,  /* visibility exact at every outer point */
    RAD_VIS_VISIBLE_SAMPLED = 1 /* too many blockers or pieces: rays (the fallback) */
};

typedef struct rad_vis_visible_result {
    double G;       /* int_a int_b K V */
    double G_open;  /* the caller's unoccluded G */
    double error;   /* sum of the accepted cells' coarse-fine differences */
    long evals;     /* closed-form point-to-polygon (or kernel) evaluations */
    long rays;      /* rays of the fallback */
    int blockers;   /* possible blockers found by the shaft test */
    int status;     /* RAD_VIS_VISIBLE_EXACT or RAD_VIS_VISIBLE_SAMPLED */
} rad_vis_visible_result;

/* G_vis(a, b) = int_a int_b K V by the adaptive outer rule of visible.c,
 * with the blockers of the pair (a on input triangle face_a, b on face_b; -1
 * for none).  G_open is the pair's unoccluded G (rad_ff): the scale of the
 * tolerance; 0 (or less) returns G = 0 at once.  Re-entrant; call from many
 * threads.  RAD_EINVAL for bad arguments. */
rad_status rad_vis_pair_visible(const rad_vis *vis, const rad_vec3 a[3], int face_a,
                                const rad_vec3 b[3], int face_b, double G_open,
                                const rad_vis_visible_params *params,
                                rad_vis_visible_result *out);

/* ---- single rays, for callers that trace paths (rad_mc) -------------------
 * No batching and no conversion arrays: one Embree call each, on the calling
 * thread.  `ignore` names a triangle whose hits are rejected by primitive id
 * (the one a path vertex lies on), -1 for none; with it a ray may start
 * exactly on its triangle with tnear = 0. */

/* A closest hit: the triangle, the distance in units of |dir|, and the
 * barycentric weights (u, v) of the triangle's second and third vertices. */
typedef struct rad_vis_hit {
    int tri; /* -1: no hit */
    double t, u, v;
} rad_vis_hit;

/* Embree's device and scene, made by the first query that casts a ray (so
 * that a run whose visibility is all clipped exactly, or that needs none,
 * never starts Embree).  Safe to call from any thread, any
 * number of times; RAD_OK once they exist, or the error that made them fail
 * (RAD_EDEP with Embree's code, RAD_ENOMEM), every time.  The queries that
 * return a status call it themselves; call it before rad_vis_ray_closest and
 * rad_vis_segment_blocked, which cannot report its failure (they then read
 * as no hit and blocked). */
rad_status rad_vis_prepare_rays(const rad_vis *vis);

/* The closest hit of org + t dir, t in (tnear, inf), ignoring `ignore`.
 * Returns 1 on a hit, 0 otherwise (hit->tri = -1).  Needs
 * rad_vis_prepare_rays. */
int rad_vis_ray_closest(const rad_vis *vis, const double org[3], const double dir[3],
                        double tnear, int ignore, rad_vis_hit *hit);

/* 1 when some triangle other than ignore0 and ignore1 (-1: none) crosses the
 * segment p -> q shortened by the ray epsilon at both ends, else 0.  Needs
 * rad_vis_prepare_rays. */
int rad_vis_segment_blocked(const rad_vis *vis, const double p[3], const double q[3],
                            int ignore0, int ignore1);

/* The same test against the listed triangles only, in double precision and
 * without Embree: for a segment inside a shaft whose blockers the caller
 * has (rad_vis_blockers, rad_vis_blockers_within), which are the only
 * triangles that can cross it.  A segment along a triangle's plane crosses
 * nothing. */
int rad_vis_segment_blocked_by(const rad_vis *vis, rad_vec3 p, rad_vec3 q, const int *blockers,
                               int n);

#ifdef __cplusplus
}
#endif
#endif
