/* Internal to rad_hier: the element tree, the links, and the functions the
 * module's files share (tree.c: elements; link.c: estimating links;
 * solve.c: gather / push-pull and the error transport; refine.c: the
 * oracles and the refinement loop). */
#ifndef HIER_INTERNAL_H
#define HIER_INTERNAL_H

#include <stddef.h>

#include "rad_geom.h"
#include "rad_hier.h"

/* The fields a solve step reads at every leaf come together after the
 * geometry (B, Hn and gB, which the gain's pass and the sources' rows read,
 * in the third and fourth cache lines), so that a pass over the elements
 * reads few lines of each. */
typedef struct hier_elem {
    rad_vec3 p[3];
    rad_vec3 c;              /* centroid */
    double area;
    double size;             /* longest edge */
    int parent, first_child; /* -1 for none; children are first_child .. + 3 */
    int face;                /* input triangle */
    int depth;
    double B[3];             /* radiosity (area average) */
    double Hn[3];            /* leaf, sealed: the step's normalized irradiance (what its
                                element and cluster links brought, each times its
                                scale from solve.c's row_scales), before the gain */
    rad_vec3 gB[3];          /* the gradient of B over the element: on a leaf, rho times
                                the gathered gradient (the variation P0 leaves
                                unresolved); on an inner element, the linear fit of its
                                children plus their mean gradient */
    double Bg[3];            /* irradiance gathered by its own element links, at the
                                centroid ... */
    rad_vec3 Gg[3];          /* ... and its gradient: a linear function over the element */
    double Cg[3];            /* what its cluster links brought of what is carried (B, T,
                                or the row in Cg[0]; constant over the element): kept
                                apart from Bg and Tg because it is the estimated part,
                                onto which a leaf's row excess goes (solve.c's
                                row_scales) */
    double cap;              /* leaf: the row ceiling (rad_hier_row_ceiling) over its row
                                sum where that exceeds it (sealed: always), else 1 */
    double row0;             /* leaf: its row sum (the push of B = 1) at the centroid ... */
    rad_vec3 rowg;           /* ... and its gradient */
    double rowc;             /* leaf: the part of row0 the cluster links bring */
    double var[3];           /* how far B strays from its mean over the element, set
                                by hier_inner_spread for the oracle and the bound,
                                which alone read it (a step leaves it as it was): on
                                a leaf, what gB implies at its corners (for the
                                bound, plus rho r w over the links at it and its
                                ancestors, r their linear fits' largest residuals);
                                on an inner element, the farthest leaf below, that
                                leaf's var included */
    double q[3], d[3], dr[3];/* local error bounds gathered by its own links:
                                q: F's own error (conservation); d (squared): the
                                sources' variation; dr: the linear fits'
                                residuals, which
                                count only below the element (its own average is
                                exact); on a leaf, after solve.c's push, the sums
                                over the leaf and its ancestors, and then q holds
                                q + sqrt(d), the local error T carries */
    double T[3], Tg[3];      /* the transported local error (solve.c) ... */
    rad_vec3 TGg[3];         /* ... gathered with its gradient, as B is */
} hier_elem;

/* The sources' rows of the gathers (hier_fill_sources), HIER_SRC doubles an
 * element: its unit normal [0, 3), its area [3], what it carries [4, 7) (B,
 * T or 1) and, carrying B, its slope gB [7, 16): a cluster link's element
 * end reads the first cache line, the element gather both. */
enum { HIER_SRC = 16 };

/* A link joins two elements both ways: a <- b and b <- a at the same levels
 * (a symmetric link structure keeps the hierarchical operator self-adjoint in
 * the area inner product, so that energy is conserved to second order). */
typedef struct hier_link {
    int a, b;       /* the elements; a = -1 marks a refined (dead) link */
    double G;       /* int_a int_b K V: F_ab = G / A_a, F_ba = G / A_b */
    rad_vec3 ga, gb;/* the gradients of F(x, b) over a and of F(y, a) over b */
    double dG;      /* estimated error of G */
    double ra, rb;  /* the largest residual of each side's linear fit (its receiver's units) */
    double va, vb;  /* the largest deviation of each side's point values from their
                       mean, in the units of the other side (the kernel's variation
                       over that element as a source) */

    unsigned char unknown; /* G is 0 although the pair faces: refine while possible */
    unsigned char vis;     /* 0: nothing can block, 1: blockers, all open, 2: partly
                              hidden, 3: hidden at every point value */
    unsigned char clip;    /* 1: estimated clipping up to RAD_HIER_CLIP_BLOCKERS_MAX
                              blockers (refine.c: a sampled link the oracle would
                              refine), as its children are; 0: up to clip_blockers */
    unsigned char sampled; /* 1: more blockers than the estimate's cap, rays sampled
                              the view (link.c) */
} hier_link;

/* Weights c_k on unit directions w_k, as moments: C = sum c_k,
 * S = sum c_k w_k, M = sum c_k w_k w_k^T (xx yy zz xy xz yz), which bracket
 * sum c_k max(n.w_k, 0) for any n (cluster.c).  What a cluster gathers
 * (links arriving from w_k, c_k the irradiance each brings to a point facing
 * it: a triangle of normal n receives that sum), and what it emits (its
 * triangles' normals, c = area x radiosity: its intensity towards n). */
typedef struct hier_dir {
    double C;
    rad_vec3 S;
    double M[6];
} hier_dir;

/* A node of the cluster hierarchy (cluster.c; the tree of
 * rad_cluster with one input triangle per leaf).  Parents come before their
 * children in the array. */
typedef struct hier_clus {
    rad_vec3 c;            /* centre of its bounding box */
    rad_vec3 half;         /* the box's half extents */
    double radius;         /* half the box's diagonal: its triangles lie in that sphere */
    double area;
    rad_vec3 N;            /* sum of area x unit normal over its triangles */
    rad_vec3 axis;         /* its normal cone: every unit normal within alpha of axis */
    double alpha;          /* > pi when no cone narrower than the sphere holds them */
    int child[2];          /* -1 for a leaf */
    int root;              /* a leaf's input triangle (its root element), else -1 */
    int first, count;      /* its triangles: rad_cluster_order()[first .. first + count) */
    int mom;               /* its row of cmom and cgot, or -1 where a gather reads
                              its triangles instead and they receive one by one
                              (a small cluster, oriented) */
    int above;             /* a small cluster's (oriented) nearest ancestor that
                              is not small, whose g its triangles receive (-1:
                              none); its own g is never written */
    int grp, ngrp;         /* a small cluster's (not a leaf) rows of cemit: what
                              it emits, its triangles' own rows or, where some
                              share a normal, rows of the groups */
    double rho[3];         /* the largest reflectance below */
    double scale;          /* the smallest threshold scale (face_scale) below */
    double B[3], var[3];   /* area-mean radiosity of its triangles, and how far a leaf
                              element's B strays from it */
    double Hlo[3], Hhi[3]; /* the range of its leaves' irradiance (B - E) / rho */
    hier_dir geo;          /* the same of its areas: projected areas */
    double q[3], qb[3];    /* the errors e of F of its links (and ancestors'), summed,
                              and summed times their sources' B ... */
    double bmin[3], bmax[3];/* ... and the range of those B (cluster.c's bound) */
    double d[3];           /* (what the sources' variation contributes)^2, summed */
} hier_clus;

/* An input triangle as a cluster link's estimate reads it (its root
 * element's unit normal, corners, centroid and area: two cache lines, where
 * the root elements are long and in input order). */
typedef struct hier_ctri {
    rad_vec3 n, p[3], c;
    double area;
} hier_ctri;

/* A link with a cluster of two or more triangles at one end at least; the
 * other end is a cluster or an element (two elements are joined by a
 * hier_link).  An end is a cluster index c >= 0 or an element e as -1 - e.
 * It carries light both ways as G / A to every point of the receiver. */
typedef struct hier_clink {
    int a, b;              /* ends; a = INT_MIN marks a refined link, or a new pair
                              that carries nothing (refine_pass drops both) */
    double G;              /* estimated int_a int_b K V */
    double Fa, Fb;         /* bounds of the point form factor from any point of a
                              towards b, and of b towards a */
    double ea, eb;         /* bounds of the error of G / A_a as that point form factor
                              (and of G / A_b) */
    double va, vb;         /* what the source's variation var is multiplied by in the
                              error at a (at b) */
    rad_vec3 w;            /* unit direction from a's centre to b's */
    double kv;             /* V / (pi r^2): a point facing the source head-on receives
                              kv times the source's intensity (sum A B max(cos, 0)) */
    unsigned char overlap; /* the bounding boxes meet: no bound, refine */
    unsigned char by_size; /* the kernel's variation over the spheres dominates the
                              error: split the larger end, not the source */
} hier_clink;

/* A gather reads its ends' source rows at random (the rows lie in source
 * order, the ends in receiver order) and would wait on each one: the loops
 * ask for the row of the end this many places on while they work on one. */
enum { HIER_PREFETCH_AHEAD = 8 };

/* One end of a link as the receiver sees it: the source element, the form
 * factor, its gradient over the receiver and the source-slope vector (the
 * moment's over the receiver's area: constant while the links are), and
 * whether the receiver is the link's b end (the order of gather_link's
 * terms there). */
typedef struct hier_end {
    int src, is_b;
    double F;
    rad_vec3 g, m;
} hier_end;

/* A cluster link's end as its receiver gathers it: where to read the other
 * end as a source, the link's kv and the unit direction from the receiver's
 * centre towards the other's (cluster.c).  A receiver's ends lie together,
 * so a gather step reads them in order and each source's compact row once
 * per end, never the clusters themselves. */
typedef struct hier_cinc {
    rad_vec3 dir;
    double kv;
    int src;  /* the other end's source row: an element's (src), a small
                 cluster's first (cemit) or a cluster's moments (cmom) */
    int kind; /* HIER_CINC_ELEMENT, HIER_CINC_MOMENTS, or the small cluster's
                 count of rows (1 .. 16) */
} hier_cinc;
enum { HIER_CINC_ELEMENT = -1, HIER_CINC_MOMENTS = 0 };

/* The gather's arrays, built at solve time: element-link ends, cluster-link
 * ends, their receivers' starts, the sources' rows, the small clusters'
 * triangles' irradiance (memory.c counts them), and the solve's history
 * (accel.c counts it). */
enum { HIER_GATHER_INC, HIER_GATHER_CINC, HIER_GATHER_INC_START, HIER_GATHER_CINC_START,
       HIER_GATHER_SRC, HIER_GATHER_CRECV, HIER_GATHER_ACCEL,
       HIER_GATHER_ARRAYS };

/* The history of accel.c's Anderson mixing of the solve's steps. */
enum { HIER_ACCEL_MAX = RAD_HIER_ANDERSON_MAX, HIER_ACCEL_WARMUP_B = 8, HIER_ACCEL_WARMUP_T = 2 };
typedef struct hier_accel {
    int on;                /* 1: mixing (from a step past HIER_ACCEL_WARMUP_B or _T) */
    int began;             /* mixing began in this solve (it does not begin twice) */
    int steps;             /* the steps of this solve so far */
    double tol;            /* the solve's test on a step's change ... */
    double last;           /* ... and its last step's change in the same units
                              (negative: none yet) */
    int carry;             /* CARRY_B or CARRY_T */
    int width;             /* doubles of a leaf's state (B and gB, or T) */
    int depth, cols, next; /* columns held at most, held, and the ring's next slot */
    int have_prev;         /* a step's output and residual are held (gp, fp) */
    double best;           /* the smallest squared residual seen ... */
    int stall;             /* ... and the steps since it fell */
    double gram[HIER_ACCEL_MAX][HIER_ACCEL_MAX]; /* the residual differences' dot products */
    int *leaf;             /* the leaves, in element order */
    size_t n, leaf_cap;
    double *buf;           /* accel.c's arrays */
    size_t buf_cap;
} hier_accel;

struct rad_hier {
    rad_hier_params p;
    const rad_vis *vis;
    int use_vis;
    rad_hier_pairs *pairs;    /* per pair of input triangles, or NULL (ask each time) */
    rad_hier_memo *memo;      /* touching pairs' singular integrals */
    rad_vec3 *normal;         /* unit normal per input triangle */
    size_t nroots;
    double *rho, *E;          /* per input triangle, ntris x 3 */
    double E_max, rho_max;
    double *face_scale;       /* per input triangle, the ERROR oracle's threshold scale */
    double *tight_B;          /* per input triangle x 3, its mean B when the oracle last
                                 tightened (refine.c), or NULL before the first time */
    hier_elem *el;
    size_t nel, capel;
    hier_link *ln;
    size_t nln, capln;
    rad_hier_stats st;
    int stepped;
    double last_change;       /* relative */
    double last_bmax;         /* the largest leaf B of the last step */
    double T_tail;            /* what the error transport's last step leaves of its
                                 fixed point (absolute; solve.c) */
    double iter_err;          /* what the last step's change leaves of the fixed point
                                 (absolute; solve.c) */
    /* the cluster layer (cluster.c); ncl = 0 without clustering */
    hier_clus *cl;
    size_t ncl;
    /* the tree cut for the passes that run on every thread: the roots of
       disjoint subtrees (csub[k] and their ends csub_end[k], nodes made
       depth-first) and the nodes above them (ctop), in index order */
    int *csub, *csub_end, *ctop;
    size_t ncsub, nctop;
    /* the clusters with a row of cmom, in index order (cmnode, nmom of
       them: every cluster that gathers moments), and each subtree's run of
       them, cmnode[csub_mom[2k] .. csub_mom[2k + 1]): the gather's pull,
       receive and push work only there */
    int *cmnode;
    size_t nmom;
    size_t *csub_mom;
    int *corder;              /* input triangles in cluster order */
    /* the same triangles' geometry, in cluster order (hier_ctri): what a
       cluster link's estimate reads of a cluster's triangles, in one run */
    struct hier_ctri *ctri;
    /* the leaf clusters by input triangle, each as what the gather's pass
       over the elements reads of it (hier_cleaf): one short row, where the
       nodes are long */
    struct hier_cleaf *cleaf;
    hier_clink *cln;
    size_t ncln, capcln;
    /* the channels the cluster gather carries: 1 where every face's
       reflectance and emission are the same in the three channels (they then
       stay equal bit for bit, and channel 0 serves all three), else 3 */
    int cchannels;
    /* what each input triangle emits, in cluster order (6 doubles each: its
       unit normal, then area x the three channels carried), filled at each
       gather so that a small cluster's intensity reads one contiguous run;
       then, for each small cluster (not a leaf) some of whose triangles
       share a normal, a row per group of equal normals, in the order their
       first triangles come (the normal, then the sums of the group's
       rows): a gather reads a box's six faces, not its twelve triangles.
       cgrp_set: each of those ngrp groups' triangles, a bit each over its
       cluster's run in cluster order (bit k: the run's k-th) */
    double *cemit;
    struct hier_cgrp {
        int first;
        unsigned mask;
    } *cgrp_set;
    size_t ngrp;
    /* what each input triangle received through the links of the small
       clusters above it (3 channels each, in cluster order): a small
       cluster hands each of its triangles its own share, max(n.w, 0) per
       link, instead of gathering moments whose bracket is only a bound */
    double *crecv;
    /* each cluster's source moments of what is carried (B, T or 1; the
       carried channels' hier_dir each, written by its pull): the moments of
       a_j = A_j x what is carried over its triangles' normals n_j, whose
       bracket gives the intensity sum_j a_j max(n_j.w, 0) towards w; kept
       out of hier_clus so that the gather reads them from one short row,
       and only for the clusters whose gather reads them (hier_clus.mom) */
    hier_dir *cmom;
    /* what each cluster with a row of cmom gathered by its own links (B, T
       or 1, as carried; its channels' hier_dir each), with what its
       ancestors pushed down: a small cluster's triangles receive their own
       share instead (crecv), so only the others have a row */
    hier_dir *cgot;
    /* each receiving end's cluster-link ends, in link order: clusters
       0 .. ncl - 1, then the elements (cluster.c's parallel gather); built
       for cinc_version == cln_version and cinc_nel == nel */
    size_t *cinc_start;
    struct hier_cinc *cinc;
    size_t cinc_start_cap, cinc_cap, cinc_nel;
    unsigned long long cln_version, cinc_version;
    int round;                /* the round being made or solved (params.working) */
    /* the links or elements changed (refine.c): bumped so that exchange.c
       rebuilds its plan of the shared gather */
    unsigned long long version;
    struct hier_share *share;  /* exchange.c's plan of the shared gather, or NULL */
    /* each element's links as what they bring it (solve.c's parallel
       gather): inc[inc_start[e] .. inc_start[e + 1]), in link order; built
       for inc_version == version and inc_nel == nel (0 until built) */
    size_t *inc_start;
    struct hier_end *inc;
    size_t inc_start_cap, inc_cap, inc_nel;
    unsigned long long inc_version;
    /* what the gathers read of each element as a source, copied out of
       the elements once per step (HIER_SRC doubles an element), so that a
       link end reads its source from one short row */
    double *src;
    size_t src_cap;
    /* the bytes each of the gather's arrays has touched (HIER_GATHER_*):
       what is resident of them, which a forecast of their next build
       subtracts (memory.c) */
    double gather_touched[HIER_GATHER_ARRAYS];
    hier_accel acc;           /* accel.c's history, over the solve that is running */
    /* the point-value rules (link.c) */
    double rs[RAD_HIER_MAX_NODES], rt[RAD_HIER_MAX_NODES], rw[RAD_HIER_MAX_NODES];
    int nodes;
};

/* ---- memory.c ---- */
/* RAD_ETOOBIG when adding links element links, clinks cluster links and
 * elems elements (and what the gather's arrays will hold for them) would
 * take the process past its share of the machine's memory. */
rad_status hier_memory_check(const rad_hier *h, size_t links, size_t clinks, size_t elems);
/* Array k of the gather now holds `bytes` (written from its start). */
void hier_gather_touch(rad_hier *h, int k, size_t bytes);

/* ---- tree.c ---- */
rad_status hier_grow_elems(rad_hier *h, size_t extra);
rad_status hier_reserve_links(rad_hier *h, size_t extra);
int hier_can_split(const rad_hier *h, int e);
rad_status hier_split(rad_hier *h, int e);

/* ---- link.c ---- */
typedef struct hier_job {
    int a, b;
    int clip; /* hier_link's clip for the new link */
} hier_job;
/* Estimate jobs[0..n) (pairs) in parallel and append the facing ones to the
 * links in job order (the result does not depend on the thread count).
 * splits: the jobs come in fours, (child i of one element, the same other
 * element), i = 0..3, as a refinement makes them. */
rad_status hier_estimate_batch(rad_hier *h, const hier_job *jobs, size_t n, int splits);
int hier_pair_can_block(const rad_hier *h, int face_r, int face_s);
/* 0 when no element of input triangle r can touch one of s (their distance
 * exceeds the contact test's 1e-9 of the larger's longest edge, which no
 * sub-element pair can then meet); 1 when they may. */
int hier_pair_may_touch(const rad_hier *h, int face_r, int face_s);

/* ---- accel.c: Anderson mixing of the gather / push-pull steps ---- */
/* What a step contracts by at most (solve.c): rho_max sealed, else
 * (1 + rho_max) / 2, the rows being held under rad_hier_row_ceiling. */
double hier_contraction(const rad_hier *h);
/* Start a solve of carry (CARRY_B or CARRY_T) over the current leaves, which
 * ends when a step's change is at most tol. */
void hier_accel_begin(rad_hier *h, int carry, double tol);
/* Before a step: note the state it starts from and the last step's change
 * in tol's units (negative before the first step); mixing starts after
 * HIER_ACCEL_WARMUP_B or _T plain steps, once plain steps could not end the
 * solve within as many more, where the machine has the memory. */
rad_status hier_accel_save(rad_hier *h, double change);
/* After a step that did not meet its test: the next state to start from. */
void hier_accel_mix(rad_hier *h);
void hier_accel_destroy(rad_hier *h);

/* ---- cluster.c ---- */
/* Build the cluster hierarchy over the roots and its initial links (every
 * pair of siblings), refined where bounding spheres meet; pairs of single
 * triangles become root links (hier_estimate_batch). */
rad_status hier_cluster_create(rad_hier *h);
void hier_cluster_destroy(rad_hier *h);
/* One oracle pass over the cluster links (refine.c's thresholds);
 * *count += links refined. */
rad_status hier_cluster_refine(rad_hier *h, double target, long long *count);
/* What the cluster links bring the elements (Cg, written whole), every end
 * carrying: CLUSTER_B its radiosity, CLUSTER_T its transported error,
 * CLUSTER_ONE 1 (the rows, into Cg[0]); clusters pull theirs from the
 * sources' rows (hier_fill_sources of the same carry, which the caller
 * writes first), and push what they gather down to them. */
enum { CLUSTER_B, CLUSTER_T, CLUSTER_ONE };
rad_status hier_cluster_gather(rad_hier *h, int carry);
/* A leaf cluster as the cluster gather's pass over the elements reads it
 * (rad_hier.cleaf holds them by input triangle, its root element): its
 * place in cluster order (crecv's and cemit's row) and the row of cgot
 * whose moments reach its triangle, -1 for none: its own where it gathers
 * moments (ISO), else (oriented: a leaf is small, its triangle receives
 * its own share) that of its nearest ancestor that is not small. */
struct hier_cleaf {
    int first, got;
};
/* Add the cluster links' local error bounds to the elements' q and d. */
rad_status hier_cluster_local(rad_hier *h);

/* ---- refine.c ---- */
/* Quarter the threshold scale of the input triangles whose bound exceeds
 * eps R (after the first time, only where their B moved by more than eps R
 * since the last); *count: how many (0: none fails, or none may be
 * tightened). */
rad_status hier_tighten_failing(rad_hier *h, int *count);

/* ---- exchange.c: the work shared among processes (rad_hier_exchange) ---- */
/* 1 when params.exchange shares the work among two or more processes. */
int hier_shared(const rad_hier *h);
/* This process's jobs of a batch: first, first + step, ... (process r of
 * size: r, r + size, ...; without sharing all of them: 0, 1, ...). */
void hier_share(const rad_hier *h, size_t *first, size_t *step);
/* buf holds n items of item_bytes, this process's (hier_share) filled:
 * afterwards all of them are.  Its time goes to time_comm_s. */
rad_status hier_share_gather(rad_hier *h, void *buf, size_t item_bytes, size_t n);
/* A batch's work counters summed over the processes (in process order). */
rad_status hier_share_work(rad_hier *h, long long *evals, unsigned long long *rays);
/* What a push-pull carries: the radiosity B (gathered Bg, Gg) or the
 * transported error bound T (gathered Tg, TGg), by the same operator. */
enum { CARRY_B, CARRY_T };
/* Write the sources' rows (rad_hier.src; with clusters also cemit) of
 * carry: CLUSTER_B, CLUSTER_T or CLUSTER_ONE (CARRY_B and CARRY_T are the
 * first two), in one pass over the elements. */
rad_status hier_fill_sources(rad_hier *h, int carry);
/* The rows of cemit's groups, from its triangles' rows (cluster.c). */
void hier_cluster_fill_groups(rad_hier *h);
/* The shared gather (params.exchange.split_gather): 1 when it is on.  Its
 * plan (which input triangles this process owns, the links that end in
 * them, the elements in process order) is rebuilt when h->version moved. */
int hier_split_on(const rad_hier *h);
rad_status hier_split_plan(rad_hier *h);
/* This process's links: indices into h->ln, in order, and for each which
 * ends it owns (bit 1: a, bit 2: b); and its input triangles [*lo, *hi). */
const int *hier_split_links(const rad_hier *h, const unsigned char **ends, size_t *n);
void hier_split_roots(const rad_hier *h, size_t *lo, size_t *hi);
/* After this process pushed and pulled its own trees: every element's
 * carried values (B: B, gB, Hn; T: T) from its owner, and the step's
 * largest change and value over every process. */
rad_status hier_split_exchange(rad_hier *h, int carry, double *change, double *vmax);
void hier_share_destroy(rad_hier *h);

/* The threads a parallel pass uses: params.threads, or OpenMP's count. */
int hier_threads(const rad_hier *h);
/* The chunk of roots a thread takes at a time in the passes over the
 * trees: one where the roots are few and their trees deep (a few input
 * triangles refined far), many where they are many and mostly leaves (a
 * scene of a million triangles, where handing them out one by one costs
 * more than the work). */
int hier_root_chunk(size_t roots, int threads);
/* Thread t of nt's share [*lo, *hi) of the rows of a compressed table
 * (start[0 .. n], start[n] entries in all): whole rows, about start[n] / nt
 * entries each, so that each thread writes its rows' entries in order. */
void hier_thread_rows(const size_t *start, size_t n, int t, int nt, size_t *lo, size_t *hi);

/* ---- solve.c ---- */
/* Every leaf's cap: its row sum (the form factors of the links over it, the
 * linear push included) scaled back to 1 where it exceeds 1.  Call after the
 * links change. */
rad_status hier_row_caps(rad_hier *h);
/* Inner element e's B (carry CARRY_B) or T: its children's area-weighted mean. */
void hier_children_mean(rad_hier *h, int e, int carry);
/* The inner elements under e take their children's area-weighted mean,
 * children first, as push-pull makes them. */
void hier_pull_means(rad_hier *h, int e, int carry);
/* Steps until the step change is at most tol relative to the largest B. */
rad_status hier_solve_links(rad_hier *h, double tol);
/* The local error bounds per leaf (q, d summed over the links at the leaf and
 * its ancestors) and the transported conservation error T (solve.c); with
 * residuals the leaves' var counts their links' residuals (the reported
 * bound), without it only their slopes (the oracle's tightening). */
rad_status hier_error_estimate(rad_hier *h, int residuals);
/* Every leaf's var (with residuals, its links' residuals added: the
 * bound's), and every inner element's gB (the fit of its children's B) and
 * var (how far the B of the leaves below stray from its mean), from the
 * leaves' current B: the oracle reads var, the bound both. */
rad_status hier_inner_spread(rad_hier *h, int residuals);
/* R: the area-weighted mean reflected radiosity of the leaves, the three
 * channels averaged (E_max before anything is reflected). */
double hier_reflected_scale(const rad_hier *h);
/* Tell params.working (if any) what round h->round is doing (rad_hier.h). */
void hier_working(const rad_hier *h, const char *what, size_t count);
/* The error bound of a leaf, channel c, and the part of it that does not
 * average out over an input triangle (the linear fits' residuals do): see
 * solve.c. */
double hier_leaf_bound(const rad_hier *h, const hier_elem *x, int c);
double hier_face_part(const rad_hier *h, const hier_elem *x, int c);
/* What an error of F between receiver r and source s is multiplied by:
 * s's B, or, in a sealed scene, where every row is normalized so that an
 * error of F only moves light between the sources of a receiver, how far
 * s's B lies from r's irradiance (the rows' weighted mean of their B). */
double hier_weight(const rad_hier *h, const hier_elem *r, const hier_elem *s, int c);


#endif
