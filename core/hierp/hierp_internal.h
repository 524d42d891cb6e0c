/* Internal to rad_hierp: elements, links and what the module's files share
 * (tree.c: elements, creation, read-out; link.c: a link's couplings and
 * errors; solve.c: gather / push-pull and the error estimate; refine.c: the
 * oracle and the rounds). */
#ifndef HIERP_INTERNAL_H
#define HIERP_INTERNAL_H

#include <math.h>
#include <stddef.h>

#include "rad_basis.h"
#include "rad_geom.h"
#include "rad_hierp.h"

#define HP_M RAD_BASIS_MAX_SIZE
#define HP_MAX_NODES 25

typedef struct hp_elem {
    rad_vec3 p[3];
    rad_vec3 c;              /* centroid */
    double area;
    double size;             /* longest edge */
    int parent, first_child; /* -1 for none; children first_child .. + 3 */
    int face, depth;
    int child;               /* which of its parent's children (0..3) */
    double B[3][HP_M];       /* radiosity coefficients per channel */
    double Em[3][HP_M];      /* the emission's: E sqrt(A) on the constant, or the
                                emission field's projection (rad_hierp_set_emission) */
    double Bmax[3];          /* hp_poly_bound of B: set by hp_bound_B (refinement and
                                error rounds, where B holds still) and by hp_split */
    double H[3][HP_M];       /* irradiance its own links gather (coefficients) */
    double dep[3], dep1[3];           /* the departure of the irradiance its links bring from
                                its polynomial, times rho (pointwise, W/m^2); on a
                                leaf, summed with its ancestors'; dep1 the same
                                in the mean over the element */
    double detail[3];        /* the oracle's measure of the detail below: on a leaf
                                0, on an inner element the largest of its children's
                                departure from its B plus their detail */
    double dev[3];           /* how far the radiosity below departs from B (a bound
                                over the element: on a leaf its dep, on an inner
                                element its children's departure from its B plus
                                theirs) */
    double row[HP_M];        /* leaf: the irradiance of B = 1 everywhere (its row) */
    double send[HP_M];       /* leaf, sealed: the power a unit of each coefficient
                                brings the leaves as their normalized irradiance
                                counts it (solve.c, hp_rows) */
    double charge[3];        /* leaf, sealed, m > 1: what the positivity limiter's cut
                                of its slopes would send, as a change of the constant
                                (solve.c, leaf_update): taken off the constant it sends */
    double q[3];             /* the errors its own links bring (W/m^2); on a leaf after
                                the estimate, summed with its ancestors' */
    double T[3], Tg[3];      /* the transported error (mean value) and its gather */
} hp_elem;

/* A link joins a and b both ways; its m x m couplings live in rad_hierp.K at
 * the link's index. */
typedef struct hp_link {
    int a, b;         /* a = -1: refined (dead) */
    double G;         /* the constants' coupling int_a int_b K V */
    double dG;        /* its integration error */
    double fa, fb;    /* the point form factor's departure from its projection over a
                         (over b): per unit B of the other side */
    double fa1, fb1;  /* the same departures' mean over the element */
    double ka, kb;    /* the kernel's departure from its projection over the source,
                         seen from a (from b), in the mean over both elements, times
                         the source's area: per unit of the source's mean departure
                         from its polynomial (the estimate) */
    double kma, kmb;  /* the same, the largest over the receiver's nodes (the oracle) */
    unsigned char vis;     /* 0 clear, 1 blockers but open, 2 partly hidden, 3 hidden */
    unsigned char unknown; /* faces but every value 0: refine while possible */
    unsigned char constant; /* its couplings beyond the constants' dropped, their bound added
                               to dG (solve.c: a mode the step did not contract) */
} hp_link;

struct rad_hierp {
    rad_hier_params p;
    int order, m;
    const rad_vis *vis;
    int use_vis;
    rad_hier_pairs *pairs;    /* per pair of input triangles, or NULL (ask each time) */
    rad_hier_memo *memo;      /* touching pairs' singular integrals */
    rad_vec3 *normal;
    size_t nroots;
    double *rho, *E;
    double E_max, rho_max;
    double row_ceiling; /* rad_hier_row_ceiling(sealed, rho_max) */
    double *face_scale;  /* per input triangle, the oracle's threshold scale (refine.c) */
    double (*field)(int face, rad_vec3 x, int channel, void *ctx); /* or NULL */
    void *field_ctx;
    double *face_reach;  /* per input triangle, the share of a departure of its radiosity
                            from its polynomial that the oracle charges (refine.c) */
    hp_elem *el;
    size_t nel, capel;
    hp_link *ln;
    double *K; /* m * m per link */
    size_t nln, capln;
    rad_hier_stats st;
    double last_change, last_vmax; /* the last step's change (relative to vmax) and largest mean */
    double gain[3]; /* sealed: the power the leaves send over what their sends count
                       (solve.c, copy_sources), each leaf's irradiance's factor */
    /* the links at each element, in link order (solve.c: gathers run in
       parallel over the receivers): link k's end at element e is
       inc[inc_start[e] .. inc_start[e + 1]) as 2 k + (e is its b), and
       inc_src[i] the element at its other end */
    size_t *inc_start, *inc;
    int *inc_src;
    size_t inc_nel, inc_cap;
    /* the gather's copy of every element's B, m coefficients per channel
       side by side (3 m per element), so that a link's source is one short
       read instead of scattered rows of a large element; after a step, the
       B it started from (solve.c's drop_unstable reads how far it moved) */
    double *Bs;
    size_t Bs_cap;
    /* the solve's watch: each element's coefficients and charges at the
       round's lowest change (hp_solve_links), kept between solves like Bs */
    double *good;
    size_t good_cap;
    int inc_valid;
    /* the nodes of the coupling rule and the basis at them */
    double rs[HP_MAX_NODES], rt[HP_MAX_NODES], rw[HP_MAX_NODES];
    double rq[HP_MAX_NODES][HP_M];
    int nodes;
    /* push: child coefficients = P[child] parent coefficients (order 2's; the
       lower orders are its leading blocks) */
    double P[4][HP_M][HP_M];
    /* the largest |q_k| over a triangle */
    double qmax[HP_M];
};


/* tree.c */
rad_status hp_grow_elems(rad_hierp *h, size_t extra);
rad_status hp_reserve_links(rad_hierp *h, size_t extra);
int hp_can_split(const rad_hierp *h, int e);
rad_status hp_split(rad_hierp *h, int e);
/* A bound of |f| over a triangle of area A for coefficients v[0..m). */
double hp_poly_bound(const rad_hierp *h, const double *v, double area);
/* Every element's Bmax from its B. */
void hp_bound_B(rad_hierp *h);

/* link.c */
typedef struct hp_job {
    int a, b;
} hp_job;
/* Estimate jobs[0..n) in parallel and append the facing ones to the links
 * in job order; splits: the jobs come in fours, (child i of one element, the
 * same other element), as a refinement makes them. */
rad_status hp_estimate_batch(rad_hierp *h, const hp_job *jobs, size_t n, int splits);

/* solve.c */
/* The links at each element (call after the links change: refine.c,
 * creation invalidate them with inc_valid = 0). */
rad_status hp_incidence(rad_hierp *h);
void hp_rows(rad_hierp *h);
rad_status hp_solve_links(rad_hierp *h, double tol);
/* Each element's departure and detail (needs the links at each element). */
void hp_pull_dev(rad_hierp *h);
double hp_reflected(const rad_hierp *h);
rad_status hp_estimate_error(rad_hierp *h);
/* What a link brings its receivers per channel (W/m^2; any pointer may be
 * NULL): ea, eb the errors of the transport, which reach a receiver's mean
 * (the constants' integration error, the source's unresolved detail);
 * ma, mb the mean over the receiver of its departure from the receiver's
 * polynomial (the pointwise departure is hp_pull_dev's, one end at a time). */
void hp_link_errors(const rad_hierp *h, const hp_link *l, double ea[3], double eb[3],
                    double ma[3], double mb[3]);

/* The oracle's errors of a link on a and on b (the largest channel): the
 * receiver's mean departure times its triangle's face_reach and the
 * constants' integration error, at the largest source value, and the
 * source's detail below the link. */
void hp_link_oracle(const rad_hierp *h, const hp_link *l, double *oa, double *ob);

/* An element's mean emission in channel c. */
static inline double hp_emitted(const hp_elem *x, int c)
{
    return x->Em[c][0] / sqrt(x->area);
}
/* Project the emission field onto element e's functions (Em). */
rad_status hp_project_emission(rad_hierp *h, int e);

/* refine.c */
rad_status hp_refine(rad_hierp *h, long long *refined);
/* Quarter the scale of the input triangles whose estimated error exceeds
 * eps R; how many (0: none, or none may be tightened further). */
int hp_tighten_failing(rad_hierp *h);

#endif
