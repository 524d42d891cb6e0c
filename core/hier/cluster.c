/* rad_hier: the cluster layer (Smits, Arvo, Greenberg 1994 and Sillion
 * 1995 for the idea, refs.bib smits1994, sillion1995).
 *
 * Without it rad_hier links every pair of input triangles first: n^2 work
 * before any refinement.  With it (params.cluster), the input triangles are
 * the leaves of a binary bounding-volume hierarchy (rad_cluster: split
 * between objects where a plane can be, one triangle per leaf), and linking
 * starts from the sibling pairs
 * of that tree: every pair of triangles lies below exactly one pair of
 * siblings (its lowest common ancestor's children), so the sibling links
 * cover all interactions with n - 1 links.
 *
 * A link with a cluster at one end (the other a cluster or an element)
 * carries light both ways between the ends (the centres c of their
 * bounding boxes, the radii R of the boxes' spheres, distance r,
 * w = (c_Y - c_X) / r): a point of X facing w receives
 *     kv I_Y(-w),   kv = V / (pi d^2),
 * I_Y the intensity of Y towards X (sum_j A_j B_j max(n_j.(-w), 0) over its
 * triangles), V the share of open segments between four pairs of sample
 * points (rays, from triangles turned towards the other end) and d the
 * distance between where the ends' projected areas lie (a small cluster's
 * triangles' centroid weighted by their projected areas, else the centre).
 * How a cluster emits and receives is the model:
 *  - ORIENTED (default): a cluster keeps the moments C, S, M of its
 *    triangles' normals weighted by A B (hier_dir), which bracket its
 *    intensity towards any direction (exact for a flat cluster, within 27%
 *    for a cube); a receiving cluster gathers the moments of the directions
 *    its links arrive from, weighted by what each brings, and each triangle
 *    below takes the middle of their bracket of sum_k c_k max(n.w_k, 0) for
 *    its own normal n (exact for links from one direction); a small cluster
 *    (CLUSTER_SMALL triangles or fewer) emits and receives exactly, each
 *    triangle with its own normal.  An element end emits and receives with
 *    its own normal.
 *  - ISO: a cluster emits a quarter of sum A B towards every direction and
 *    gives every triangle below a quarter of what arrives head-on (the mean
 *    of max(cos, 0) over directions: Cauchy), whatever their orientation.
 * Whatever the model, the point form factor F(x, Y) of any point x of X
 * lies in [0, F_X] with
 *     F_X = min(C_X U_Y / (pi gap^2), (R_Y / (r - R_X))^2, 1),
 * gap the distance between the ends' bounding boxes (at least the spheres'
 * gap r - R_X - R_Y), C_X the largest cosine X's normals make with a
 * direction towards Y's sphere, U_Y the largest sum of area x cosine of Y's
 * triangles towards X's sphere (from its cone, or its area and |N|: upper),
 * the second term the solid angle
 * of Y's sphere.  Where the spheres meet but the boxes do not, only
 *     F_X = min(A_Y / (pi gap^2), 1)
 * holds (a direction between them may be any), and the link's error is the
 * whole bracket, max(F_X, what a point of X receives).  The error of a
 * point's F is bounded where the spheres are apart: ISO by
 * max(G / A_X, F_X - G / A_X) (anything in [0, F_X]); ORIENTED by F_X times
 * the kernel's variation between the ends (kernel_spread: distance between
 * the gap and the boxes' farthest corners, direction within beta, sin beta
 * = (R_X + R_Y) / r), plus the bracket's
 * relative width of the source's projected area, plus 1 where the rays
 * disagree (where all four agree they are taken at their word: the one part
 * of the estimate that is sampled, not bounded).  The directions' bracket
 * at each receiving triangle adds its half width.  These are the link's
 * terms of solve.c's bound (q: times the source's B or, sealed, its
 * distance from the receiver's irradiance, as hier_weight; d: the source's
 * variation, times F_X for ISO and F_X times the kernel's variation for
 * ORIENTED, whose intensity follows the triangles' own B).
 *
 * The oracle refines a link whose term, times the receiver's reflectance,
 * exceeds link_share x eps R x the smallest threshold scale below it: the
 * source of the receiver whose term is the larger share of its threshold,
 * or the larger where the kernel's variation dominates, is split (an
 * element only against a larger group of triangles, split_link); two
 * elements become an element link (link.c).  Where the spheres meet, the
 * larger end is split; where the boxes meet there is no bound at all: such
 * a link is refined at once, at creation.  A link is not made where the
 * other end's box lies behind an element's plane, or behind the plane of
 * every triangle of a small cluster (the faces of a convex object: their
 * boxes meet, and would otherwise be split down to triangle pairs that
 * face away).
 *
 * In the solve the clusters pull their moments from the roots, and what the
 * cluster links bring is added to what the receiving elements gather, a
 * cluster's pushed down its tree to the roots: the hierarchy's rows include
 * the cluster links (the same operator carrying 1), so caps and the sealed
 * normalization cover them, and the error transport carries T through them
 * too. */
#include "hier_internal.h"

#include <limits.h>
#include <math.h>
#include <omp.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "rad_cluster.h"
#include "rad_sys.h"

/* CLUSTER_RAYS: visibility samples per cluster link, each on the first of
 * CLUSTER_TRIES triangles of a cluster that faces the other end;
 * CLUSTER_SMALL: a cluster of at most this many triangles emits exactly
 * (its triangles' own sum), so that a link's cost stays bounded. */
enum { CLUSTER_RAYS = 4, CLUSTER_TRIES = 4, CLUSTER_SMALL = 16 };

rad_status rad_hier_cluster_model_parse(const char *text, rad_hier_cluster_model *model)
{
    if (text && strcmp(text, "oriented") == 0)
        *model = RAD_HIER_CLUSTER_ORIENTED;
    else if (text && strcmp(text, "iso") == 0)
        *model = RAD_HIER_CLUSTER_ISO;
    else
        return RAD_ERROR(RAD_EINVAL, "hier: unknown cluster model '%s' (use oriented or iso)",
                         text ? text : "(null)");
    return RAD_OK;
}

const char *rad_hier_cluster_model_name(rad_hier_cluster_model model)
{
    return model == RAD_HIER_CLUSTER_ISO ? "iso" : "oriented";
}

/* ---- the ends of a link: a cluster (index >= 0) or an element (-1 - e) --- */

/* A leaf of the cluster tree is its root element. */
static int end_of(const rad_hier *h, int cluster)
{
    return h->cl[cluster].root >= 0 ? -1 - h->cl[cluster].root : cluster;
}

/* What a link reads of an end. */
typedef struct end_view {
    rad_vec3 c, N, axis;
    rad_vec3 mid, half;    /* its bounding box: centre and half extents */
    double radius, area, alpha;
    int elem;              /* the element, or -1 for a cluster */
    const hier_clus *cl;   /* the cluster, or NULL */
} end_view;

/* The radius of element e's bounding sphere about its centroid. */
static double elem_radius(const hier_elem *e)
{
    double r = 0.0;
    for (int k = 0; k < 3; k++)
        r = rad_dmax(r, rad_vec3_norm(rad_vec3_sub(e->p[k], e->c)));
    return r;
}

static void view(const rad_hier *h, int id, end_view *v)
{
    if (id >= 0) {
        const hier_clus *x = &h->cl[id];
        *v = (end_view){x->c, x->N, x->axis, x->c, x->half, x->radius, x->area, x->alpha, -1, x};
        return;
    }
    const hier_elem *e = &h->el[-1 - id];
    double r = elem_radius(e);
    rad_vec3 lo = e->p[0], hi = e->p[0];
    for (int k = 0; k < 3; k++) {
        lo = rad_vec3_make(rad_dmin(lo.x, e->p[k].x), rad_dmin(lo.y, e->p[k].y), rad_dmin(lo.z, e->p[k].z));
        hi = rad_vec3_make(rad_dmax(hi.x, e->p[k].x), rad_dmax(hi.y, e->p[k].y), rad_dmax(hi.z, e->p[k].z));
    }
    rad_vec3 n = h->normal[e->face];
    *v = (end_view){e->c,
                    rad_vec3_scale(n, e->area),
                    n,
                    rad_vec3_scale(rad_vec3_add(lo, hi), 0.5),
                    rad_vec3_scale(rad_vec3_sub(hi, lo), 0.5),
                    r,
                    e->area,
                    0.0,
                    -1 - id,
                    NULL};
}

static void dir_add(hier_dir *g, double c, rad_vec3 w)
{
    g->C += c;
    g->S = rad_vec3_add(g->S, rad_vec3_scale(w, c));
    g->M[0] += c * w.x * w.x;
    g->M[1] += c * w.y * w.y;
    g->M[2] += c * w.z * w.z;
    g->M[3] += c * w.x * w.y;
    g->M[4] += c * w.x * w.z;
    g->M[5] += c * w.y * w.z;
}

static void dir_sum(hier_dir *g, const hier_dir *p)
{
    g->C += p->C;
    g->S = rad_vec3_add(g->S, p->S);
    for (int i = 0; i < 6; i++)
        g->M[i] += p->M[i];
}

/* The quadratic monomials of unit n that n^T M n weighs with M's entries
 * (xx yy zz 2xy 2xz 2yz): computed once where several moments are read
 * at the same n (a source's channels, a leaf's). */
static void dir_square(rad_vec3 n, double q[6])
{
    q[0] = n.x * n.x;
    q[1] = n.y * n.y;
    q[2] = n.z * n.z;
    q[3] = 2.0 * n.x * n.y;
    q[4] = 2.0 * n.x * n.z;
    q[5] = 2.0 * n.y * n.z;
}

/* What a point of normal n (q: dir_square(n)) receives, sum c_k max(n.w_k, 0)
 * = (sum c_k |n.w_k| + n.S) / 2, with n^T M n <= sum c_k |n.w_k| <=
 * min(C, sqrt(C n^T M n)) (|n.w| <= 1, Cauchy-Schwarz): the middle of that
 * bracket, exact for one direction, and its half width (*err). */
static double dir_eval_at(const hier_dir *g, rad_vec3 n, const double q[6], double *err)
{
    double nS = rad_vec3_dot(n, g->S);
    double nMn = g->M[0] * q[0] + g->M[1] * q[1] + g->M[2] * q[2] + g->M[3] * q[3] +
                 g->M[4] * q[4] + g->M[5] * q[5];
    nMn = rad_dmax(0.0, nMn);
    double lo = rad_dmax(0.0, rad_dmax(nS, 0.5 * (nMn + nS)));
    double hi = rad_dmax(lo, 0.5 * (rad_dmin(g->C, sqrt(g->C * nMn)) + nS));
    *err = 0.5 * (hi - lo);
    return 0.5 * (lo + hi);
}

static double dir_eval(const hier_dir *g, rad_vec3 n, double *err)
{
    double q[6];
    dir_square(n, q);
    return dir_eval_at(g, n, q, err);
}

/* The projected area of end x towards unit direction w, by the model, and
 * how far (relative) the truth may lie from it (*rel; the bracket's half
 * width over its middle, 0 for an element), and where it lies (*at): a small
 * cluster's centroid of its triangles weighted by their projected areas (the
 * faces a box turns towards w lie nearer the other end than its centre),
 * else the centre. */
static double projected(const rad_hier *h, const end_view *x, rad_vec3 w, double *rel,
                        rad_vec3 *at)
{
    *rel = 0.0;
    *at = x->c;
    if (x->elem >= 0)
        return x->area * rad_dmax(0.0, rad_vec3_dot(x->axis, w));
    if (h->p.cluster_model == RAD_HIER_CLUSTER_ISO) {
        *rel = 1.0;
        return 0.25 * x->area;
    }
    if (x->cl->count <= CLUSTER_SMALL) {
        double p = 0.0;
        rad_vec3 m = rad_vec3_make(0.0, 0.0, 0.0);
        for (int i = x->cl->first; i < x->cl->first + x->cl->count; i++) {
            const hier_ctri *t = &h->ctri[i];
            double d = rad_vec3_dot(t->n, w);
            if (!(d > 0.0))
                continue;
            double a = t->area * d;
            p += a;
            m = rad_vec3_add(m, rad_vec3_scale(t->c, a));
        }
        if (p > 0.0)
            *at = rad_vec3_scale(m, 1.0 / p);
        return p;
    }
    double err, p = dir_eval(&x->cl->geo, w, &err);
    *rel = p > 0.0 ? err / p : 1.0;
    return p;
}

/* The largest cosine any normal of x makes with a direction within beta of
 * w, and the largest sum of area x cosine over x's triangles when each
 * triangle sees its own direction within beta of w
 * (rad_cluster_projected_upper). */
static void upper(const end_view *x, rad_vec3 w, double beta, double *cosmax, double *proj)
{
    const double N[3] = {x->N.x, x->N.y, x->N.z}, axis[3] = {x->axis.x, x->axis.y, x->axis.z};
    const double wv[3] = {w.x, w.y, w.z};
    *proj = rad_cluster_projected_upper(x->area, N, axis, x->alpha, wv, beta, cosmax);
}

/* The distance between the ends' bounding boxes (0 where they meet). */
static double box_gap(const end_view *x, const end_view *y)
{
    double d[3] = {fabs(y->mid.x - x->mid.x) - x->half.x - y->half.x,
                   fabs(y->mid.y - x->mid.y) - x->half.y - y->half.y,
                   fabs(y->mid.z - x->mid.z) - x->half.z - y->half.z};
    double s = 0.0;
    for (int a = 0; a < 3; a++)
        s += d[a] > 0.0 ? d[a] * d[a] : 0.0;
    return sqrt(s);
}

/* A small cluster's triangles that face w (unit, from the cluster towards
 * the other end), in cluster order; none listed for an element or a larger
 * cluster. */
typedef struct facing_set {
    int t[CLUSTER_SMALL]; /* their places in cluster order */
    int m;
} facing_set;

static void facing_of(const rad_hier *h, const end_view *x, rad_vec3 w, facing_set *f)
{
    f->m = 0;
    if (x->elem >= 0 || x->cl->count > CLUSTER_SMALL)
        return;
    for (int i = x->cl->first; i < x->cl->first + x->cl->count; i++)
        if (rad_vec3_dot(h->ctri[i].n, w) > 0.0)
            f->t[f->m++] = i;
}

/* Sample point k of end x, seen from the direction w (unit, from x towards
 * the other end; f: facing_of(x, w)), and the input triangle it lies on.
 * Samples lie on triangles that face w: a ray from a triangle turned away
 * would first cross the triangle's own object, and count as blocked what
 * the model does not carry anyway (its projected area counts only faces
 * turned towards w).  A small cluster's samples are spread over the
 * triangles facing w (a box seen along an axis turns 2 of its 12 towards
 * it; fewer than CLUSTER_RAYS such triangles take points spread over them);
 * a larger cluster's is the centroid of the first that faces w among
 * CLUSTER_TRIES spread over it, where none does the first.  An element's
 * samples are points spread over it. */
static rad_vec3 sample_point(const rad_hier *h, const end_view *x, const facing_set *f, int k,
                             rad_vec3 w, int *tri)
{
    static const double bary[CLUSTER_RAYS][3] = {{1.0 / 3, 1.0 / 3, 1.0 / 3},
                                                 {2.0 / 3, 1.0 / 6, 1.0 / 6},
                                                 {1.0 / 6, 2.0 / 3, 1.0 / 6},
                                                 {1.0 / 6, 1.0 / 6, 2.0 / 3}};
    const rad_vec3 *p;
    const double *b = bary[k];
    if (x->elem >= 0) {
        p = h->el[x->elem].p;
        *tri = h->el[x->elem].face;
    } else {
        int i; /* the triangle's place in cluster order */
        if (x->cl->count <= CLUSTER_SMALL) {
            i = f->m > 0 ? f->t[(k * f->m) / CLUSTER_RAYS] : x->cl->first;
            b = f->m >= CLUSTER_RAYS ? bary[0] : bary[k];
        } else {
            const int spread = CLUSTER_RAYS * CLUSTER_TRIES;
            i = -1;
            for (int j = 0; j < CLUSTER_TRIES && i < 0; j++) {
                int at = x->cl->first + ((k + CLUSTER_RAYS * j) * x->cl->count) / spread;
                if (rad_vec3_dot(h->ctri[at].n, w) > 0.0)
                    i = at;
            }
            if (i < 0)
                i = x->cl->first + (k * x->cl->count) / spread;
            b = bary[0];
        }
        p = h->ctri[i].p;
        *tri = h->corder[i]; /* an input triangle's root element has its index */
    }
    return rad_vec3_add(rad_vec3_add(rad_vec3_scale(p[0], b[0]), rad_vec3_scale(p[1], b[1])),
                        rad_vec3_scale(p[2], b[2]));
}

/* Whether every corner of y's box lies on or behind the plane through p
 * of normal n, within tol (the corners are rebuilt from the box's centre
 * and half extents, which may round them past a plane they lie on). */
static int behind_plane(rad_vec3 n, rad_vec3 p, const end_view *y, double tol)
{
    for (int k = 0; k < 8; k++) {
        rad_vec3 c = rad_vec3_make(y->mid.x + (k & 1 ? y->half.x : -y->half.x),
                                   y->mid.y + (k & 2 ? y->half.y : -y->half.y),
                                   y->mid.z + (k & 4 ? y->half.z : -y->half.z));
        if (rad_vec3_dot(n, rad_vec3_sub(c, p)) > tol)
            return 0;
    }
    return 1;
}

/* Whether y's box lies behind the plane of element x, or of every triangle
 * of x, a small cluster: then no triangle of x sees anything of y, nor
 * anything of y a triangle of x.  The parts of a convex object (a box's
 * faces) are such pairs; their boxes meet, so without this test they would
 * be split at once down to their triangles, each pair of which faces away. */
static int box_behind(const rad_hier *h, const end_view *x, const end_view *y)
{
    double tol = 1e-9 * (x->radius + y->radius);
    if (x->elem >= 0)
        return behind_plane(x->axis, h->el[x->elem].p[0], y, tol);
    if (x->cl->count > CLUSTER_SMALL)
        return 0;
    for (int i = x->cl->first; i < x->cl->first + x->cl->count; i++)
        if (!behind_plane(h->ctri[i].n, h->ctri[i].p[0], y, tol))
            return 0;
    return 1;
}

/* How far, relative to F_X, the point kernel of the estimate (at distance
 * sqrt(r2) between where the projected areas lie) may lie from the kernel
 * between any two points of the ends: their distance d lies between gap and
 * the boxes' farthest corners' dmax, and each cosine moves by at most
 * sin beta, so the truth lies within [(r2 / dmax^2)(1 - sin beta),
 * (r2 / gap^2)(1 + sin beta)] times the estimate, itself at most F_X. */
static double kernel_spread(const end_view *x, const end_view *y, double r2, double gap,
                            double sin_beta)
{
    double far2 = 0.0;
    const double d[3] = {fabs(y->mid.x - x->mid.x) + x->half.x + y->half.x,
                         fabs(y->mid.y - x->mid.y) + x->half.y + y->half.y,
                         fabs(y->mid.z - x->mid.z) + x->half.z + y->half.z};
    for (int a = 0; a < 3; a++)
        far2 += d[a] * d[a];
    double up = r2 / (gap * gap) * (1.0 + sin_beta) - 1.0;
    double down = 1.0 - r2 / far2 * (1.0 - sin_beta);
    return rad_dmax(up, down);
}

/* The share of CLUSTER_RAYS segments between sample points of x and y
 * (w: unit, from x towards y) that nothing blocks (*mixed: some do, some
 * do not). */
static double sampled_visibility(const rad_hier *h, const end_view *x, const end_view *y,
                                 rad_vec3 w, int *mixed, unsigned long long *rays)
{
    *mixed = 0;
    if (!h->use_vis)
        return 1.0;
    rad_vec3 mw = rad_vec3_scale(w, -1.0);
    /* a larger cluster's samples try triangles spread over its run at
       places known now: asked for at once, not one wait after another */
    const end_view *ends[2] = {x, y};
    for (int s = 0; s < 2; s++)
        if (ends[s]->elem < 0 && ends[s]->cl->count > CLUSTER_SMALL)
            for (int m = 0; m < CLUSTER_RAYS * CLUSTER_TRIES; m++)
                __builtin_prefetch(&h->ctri[ends[s]->cl->first +
                                            (m * ends[s]->cl->count) /
                                                (CLUSTER_RAYS * CLUSTER_TRIES)]);
    facing_set fx, fy;
    facing_of(h, x, w, &fx);
    facing_of(h, y, mw, &fy);
    int open = 0;
    for (int k = 0; k < CLUSTER_RAYS; k++) {
        int ta, tb;
        rad_vec3 p = sample_point(h, x, &fx, k, w, &ta);
        rad_vec3 q = sample_point(h, y, &fy, (k + 1) % CLUSTER_RAYS, mw, &tb);
        double pa[3] = {p.x, p.y, p.z}, qa[3] = {q.x, q.y, q.z};
        open += !rad_vis_segment_blocked(h->vis, pa, qa, ta, tb);
    }
    *rays += CLUSTER_RAYS;
    *mixed = open > 0 && open < CLUSTER_RAYS;
    return (double)open / CLUSTER_RAYS;
}

/* What a link's estimate knows before its rays: the ends' geometry and
 * the bounds that do not depend on visibility. */
typedef struct link_geometry {
    int apart;
    double Fa, Fb, ux, uy, px, py, r2, kern, rel_x, rel_y;
} link_geometry;

/* The fields of link out that follow from its visibility V, the share of
 * CLUSTER_RAYS rays that passed (mixed: some passed, some did not). */
static void finish(const rad_hier *h, const end_view *x, const end_view *y,
                   const link_geometry *g, double V, int mixed, hier_clink *out)
{
    double G = g->px * g->py / (RAD_PI * g->r2) * V;
    G = rad_dmin(G, rad_dmin(x->area * g->Fa, y->area * g->Fb));
    out->G = G;
    out->kv = V / (RAD_PI * g->r2);
    if (!g->apart) {
        /* no bound of the kernel's variation: a point of x gets kv times
           at most U_Y, the truth lies in [0, F_X], and the oracle splits
           the larger end until the spheres part or eps is met */
        out->kv = g->px * g->py > 0.0 ? G / (g->px * g->py) : 0.0;
        out->ea = out->va = rad_dmax(g->Fa, out->kv * g->uy);
        out->eb = out->vb = rad_dmax(g->Fb, out->kv * g->ux);
        out->by_size = 1;
        return;
    }
    if (h->p.cluster_model == RAD_HIER_CLUSTER_ISO) {
        /* every point of a cluster gets the mean: anything in [0, F] is possible */
        out->ea = rad_dmax(G / x->area, g->Fa - G / x->area);
        out->eb = rad_dmax(G / y->area, g->Fb - G / y->area);
        out->va = g->Fa;
        out->vb = g->Fb;
        out->by_size = 0;
        return;
    }
    /* oriented: a point gets k max(n.w, 0) (solve: by direction), off by the
       kernel's variation over the spheres (distance and direction), the
       source's projected area, and visibility where the rays disagree (where
       they agree it is taken as they say: four rays are an estimate, not a
       bound) */
    out->ea = g->Fa * rad_dmin(1.0, g->kern + g->rel_y + (mixed ? 1.0 : 0.0));
    out->eb = g->Fb * rad_dmin(1.0, g->kern + g->rel_x + (mixed ? 1.0 : 0.0));
    /* the sources' intensity follows their triangles' own B: what is left
       of B's variation is the kernel's over the source */
    out->va = g->Fa * rad_dmin(1.0, g->kern);
    out->vb = g->Fb * rad_dmin(1.0, g->kern);
    out->by_size = g->kern > rad_dmax(g->rel_x, g->rel_y) + (mixed ? 1.0 : 0.0);
}

static int split_whatever_seen(const rad_hier *h, const end_view *x, const end_view *y,
                               const link_geometry *g, double target, hier_clink *out);

/* Estimate the link of ends a and b; 0 when nothing of one can reach the
 * other (every normal of one turned away from the other's sphere, or the
 * other's box behind an element's plane).  target > 0: the oracle's
 * target of the pass the link is made in (split_whatever_seen). */
static int estimate(const rad_hier *h, int ia, int ib, double target, hier_clink *out,
                    unsigned long long *rays)
{
    end_view x, y;
    view(h, ia, &x);
    view(h, ib, &y);
    memset(out, 0, sizeof *out);
    out->a = ia;
    out->b = ib;
    rad_vec3 d = rad_vec3_sub(y.c, x.c);
    double r = rad_vec3_norm(d), R = x.radius + y.radius;
    /* no two points of the ends lie nearer than their boxes' distance, at
       least the spheres' gap r - R (each box lies in its sphere) */
    link_geometry g = {.apart = r > R, .ux = x.area, .uy = y.area};
    double gap = rad_dmax(box_gap(&x, &y), r - R);
    if (box_behind(h, &x, &y) || box_behind(h, &y, &x))
        return 0;
    if (!(gap > 0.0) || !(r > 0.0)) {
        out->overlap = 1; /* the boxes meet: no bound */
        return 1;
    }
    rad_vec3 w = rad_vec3_scale(d, 1.0 / r), mw = rad_vec3_scale(w, -1.0);
    double beta = 0.0;
    if (g.apart) {
        double cx, cy;
        beta = asin(rad_dmin(1.0, R / r));
        upper(&x, w, beta, &cx, &g.ux);
        upper(&y, mw, beta, &cy, &g.uy);
        if (!(cx > 0.0) || !(cy > 0.0))
            return 0;
        double sa = y.radius / (r - x.radius), sb = x.radius / (r - y.radius);
        g.Fa = rad_dmin(1.0, rad_dmin(cx * g.uy / (RAD_PI * gap * gap), sa * sa));
        g.Fb = rad_dmin(1.0, rad_dmin(cy * g.ux / (RAD_PI * gap * gap), sb * sb));
    } else {
        /* the spheres meet, the boxes do not: a direction between the ends
           may be any, so every cosine is at most 1 */
        g.Fa = rad_dmin(1.0, g.uy / (RAD_PI * gap * gap));
        g.Fb = rad_dmin(1.0, g.ux / (RAD_PI * gap * gap));
    }
    rad_vec3 at_x, at_y;
    g.px = projected(h, &x, w, &g.rel_x, &at_x);
    g.py = projected(h, &y, mw, &g.rel_y, &at_y);
    /* the point kernel between where the projected areas lie (within the
       spheres, so never nearer than their gap) */
    rad_vec3 s = rad_vec3_sub(at_y, at_x);
    g.r2 = rad_dmax(rad_vec3_dot(s, s), gap * gap);
    g.kern = g.apart ? kernel_spread(&x, &y, g.r2, gap, sin(beta)) : 0.0;
    out->Fa = g.Fa;
    out->Fb = g.Fb;
    out->w = w;
    if (h->use_vis && target > 0.0 && split_whatever_seen(h, &x, &y, &g, target, out))
        return 1;
    int mixed;
    double V = sampled_visibility(h, &x, &y, w, &mixed, rays);
    finish(h, &x, &y, &g, V, mixed, out);
    return 1;
}

/* Estimate jobs[0..n) in parallel into the next n slots of the links (in
 * job order: the result does not depend on the thread count); target: as
 * estimate's.  A pair that carries nothing is marked as a refined link
 * (a = INT_MIN), which the examination passes over and refine_pass's
 * compaction drops with the generation's refined links: the new links are
 * not moved twice. */
static rad_status estimate_batch(rad_hier *h, const hier_job *jobs, size_t n, double target)
{
    if (n == 0)
        return RAD_OK;
    double t0 = rad_sys_seconds();
    if (h->ncln + n > h->p.max_links)
        return RAD_ERROR(RAD_ETOOBIG, "hier: more than %zu cluster links (max_links, "
                                      "--max-links): raise --eps, raise --max-links if the "
                                      "machine has the memory, or use fewer triangles", h->p.max_links);
    rad_status mem = hier_memory_check(h, 0, n, 0);
    if (mem != RAD_OK)
        return mem;
    if (!rad_sys_grow_mapped((void **)&h->cln, &h->capcln, h->ncln, h->ncln + n, sizeof *h->cln,
                             256))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu cluster links", h->ncln + n);
    hier_clink *out = h->cln + h->ncln;
    unsigned long long rays = 0;
    const rad_hier *hc = h;
    int threads = hier_threads(h);
    /* shared among processes: a share each, then every slot everywhere (exchange.c) */
    size_t first, step;
    hier_share(h, &first, &step);
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : rays) if (n / step > 64) num_threads(threads)
    for (long long k = (long long)first; k < (long long)n; k += (long long)step) {
        /* the ends lie at random: those of the job HIER_PREFETCH_AHEAD on
           are asked for (what view() and values() read) */
        long long f = k + HIER_PREFETCH_AHEAD * (long long)step;
        if (f < (long long)n) {
            const int ends[2] = {jobs[f].a, jobs[f].b};
            for (int s = 0; s < 2; s++) {
                const char *x = ends[s] >= 0 ? (const char *)&hc->cl[ends[s]]
                                             : (const char *)&hc->el[-1 - ends[s]];
                __builtin_prefetch(x);
                __builtin_prefetch(x + 64);
                __builtin_prefetch(x + 128);
                __builtin_prefetch(x + 192);
            }
        }
        if (!estimate(hc, jobs[k].a, jobs[k].b, target, &out[k], &rays))
            out[k].a = INT_MIN;
    }
    if (hier_shared(h)) {
        long long evals = 0;
        rad_status st;
        if ((st = hier_share_gather(h, out, sizeof *out, n)) != RAD_OK ||
            (st = hier_share_work(h, &evals, &rays)) != RAD_OK)
            return st;
    }
    h->ncln += n;
    h->cln_version++;
    h->st.rays += rays;
    h->st.time_estimate_cluster_s += rad_sys_seconds() - t0;
    return RAD_OK;
}

typedef struct job_list {
    hier_job *j;
    size_t n, cap;
} job_list;

static rad_status push_job(job_list *l, int a, int b)
{
    if (!rad_sys_grow((void **)&l->j, &l->cap, l->n, l->n + 1, sizeof *l->j, 256))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu link jobs", l->n + 1);
    l->j[l->n++] = (hier_job){a, b, 0};
    return RAD_OK;
}

/* Queue the pair of ends a, b: two elements as an element link (sj, for
 * hier_estimate_batch), anything with a cluster as a cluster link (cj). */
static rad_status queue_pair(job_list *cj, job_list *sj, int a, int b)
{
    return a < 0 && b < 0 ? push_job(sj, -1 - a, -1 - b) : push_job(cj, a, b);
}

/* The radius of end id's bounding sphere (view's). */
static double end_radius(const rad_hier *h, int id)
{
    return id >= 0 ? h->cl[id].radius : elem_radius(&h->el[-1 - id]);
}

/* Replace link k by the links of one end's parts to the other end: a
 * cluster's two children, or an element's four (its quadtree split).  The
 * end split is the source of the receiver whose term is the larger share of
 * its threshold (split_b: b) -- a point's form factor towards a source
 * shrinks with the source, not with the receiver -- or, where the spheres
 * meet or the kernel's variation dominates (split_b < 0), the larger.  An
 * element is split only where it is the larger end, may be split, and the
 * other is a cluster of more than CLUSTER_SMALL triangles: a wall beside
 * many small objects is linked to their clusters piece by piece, not to
 * each of their triangles through a shaft crossing all the others.
 * Otherwise the other end, a cluster, is split, and elements are left to
 * the element links' oracle, which refines them from exact point values
 * (splitting them against single small clusters too makes many links whose
 * sphere bounds the tightened oracle then refines). */
static rad_status split_link(rad_hier *h, size_t k, int split_b, job_list *cj, job_list *sj)
{
    hier_clink l = h->cln[k];
    h->cln[k].a = INT_MIN;
    double ra = end_radius(h, l.a), rb = end_radius(h, l.b);
    int split_a = split_b < 0 ? ra >= rb : !split_b;
    int end = split_a ? l.a : l.b, other = split_a ? l.b : l.a;
    if (end < 0 && !(other >= 0 && h->cl[other].count > CLUSTER_SMALL &&
                     (split_a ? ra > rb : rb > ra) && hier_can_split(h, -1 - end))) {
        split_a = !split_a; /* the other end, then, which is a cluster */
        end = split_a ? l.a : l.b;
    }
    if (end < 0) {
        rad_status st = hier_split(h, -1 - end);
        int first = h->el[-1 - end].first_child;
        for (int c = 0; c < 4 && st == RAD_OK; c++)
            st = split_a ? queue_pair(cj, sj, -1 - (first + c), l.b)
                         : queue_pair(cj, sj, l.a, -1 - (first + c));
        return st;
    }
    const hier_clus *s = &h->cl[end];
    for (int c = 0; c < 2; c++) {
        int child = end_of(h, s->child[c]);
        rad_status st = split_a ? queue_pair(cj, sj, child, l.b) : queue_pair(cj, sj, l.a, child);
        if (st != RAD_OK)
            return st;
    }
    return RAD_OK;
}

/* ---- what the clusters pull from their leaves ---------------------------- */

/* An element's irradiance (B - E) / rho, its mean over it as hier_weight
 * takes it (0 where rho = 0: then its weight is the source's B). */
static double element_H(const rad_hier *h, const hier_elem *e, int c)
{
    size_t n = h->nroots, f = (size_t)e->face;
    double rho = h->rho[f + (size_t)c * n];
    return rho > 0.0 ? (e->B[c] - h->E[f + (size_t)c * n]) / rho : 0.0;
}

/* The moments of one triangle (area a, normal n) weighted by v. */
static void dir_one(hier_dir *g, double a, rad_vec3 n)
{
    memset(g, 0, sizeof *g);
    dir_add(g, a, n);
}

/* Whether the gather reads a cluster of count triangles as a source from
 * its moments (every cluster in the isotropic model; in the oriented one
 * those above CLUSTER_SMALL: a small one's triangles are read one by one). */
static int reads_moments(const rad_hier *h, int count)
{
    return h->p.cluster_model == RAD_HIER_CLUSTER_ISO || count > CLUSTER_SMALL;
}

/* The channels a gather carries: the rows one, B and T h->cchannels. */
static int channels(const rad_hier *h, int carry)
{
    return carry == CLUSTER_ONE ? 1 : h->cchannels;
}

/* What element e carries, channel c: B, T or 1. */
static double carried(const hier_elem *e, int carry, int c)
{
    return carry == CLUSTER_T ? e->T[c] : carry == CLUSTER_ONE ? 1.0 : e->B[c];
}

/* Channel c of the source moments of cluster i: its row of cmom, or, where
 * it has none, summed over its rows of cemit (its triangle's, a leaf's). */
static void child_moments(const rad_hier *h, int i, size_t nch, int c, hier_dir *g)
{
    const hier_clus *x = &h->cl[i];
    if (x->mom >= 0) {
        *g = h->cmom[nch * (size_t)x->mom + (size_t)c];
        return;
    }
    memset(g, 0, sizeof *g);
    int first = x->root >= 0 ? x->first : x->grp, rows = x->root >= 0 ? 1 : x->ngrp;
    for (const double *m = h->cemit + 6 * (size_t)first; rows-- > 0; m += 6)
        dir_add(g, m[3 + c], rad_vec3_make(m[0], m[1], m[2]));
}

/* Cluster i's source moments of what is carried (B, T or 1), if it keeps a
 * row of them; with values (and B carried) also its mean B, var, H range
 * and threshold scale, which the oracle and the bound read, from its
 * children (or its triangle). */
static void pull_node(rad_hier *h, size_t i, int carry, int with_values)
{
    hier_clus *x = &h->cl[i];
    size_t nch = (size_t)channels(h, carry);
    hier_dir *src = x->mom >= 0 ? h->cmom + nch * (size_t)x->mom : NULL;
    with_values = with_values && carry == CLUSTER_B;
    if (!src && !with_values)
        return;
    if (x->root >= 0) {
        const hier_elem *e = &h->el[x->root];
        for (size_t c = 0; src && c < nch; c++)
            dir_one(&src[c], e->area * carried(e, carry, (int)c), h->normal[x->root]);
        if (!with_values)
            return;
        x->scale = h->face_scale[x->root];
        for (int c = 0; c < 3; c++) {
            x->B[c] = e->B[c];
            x->var[c] = e->var[c];
            x->Hlo[c] = x->Hhi[c] = element_H(h, e, c);
        }
        return;
    }
    for (size_t c = 0; src && c < nch; c++) {
        child_moments(h, x->child[0], nch, (int)c, &src[c]);
        hier_dir more;
        child_moments(h, x->child[1], nch, (int)c, &more);
        dir_sum(&src[c], &more);
    }
    if (!with_values)
        return;
    const hier_clus *u = &h->cl[x->child[0]], *v = &h->cl[x->child[1]];
    double a = u->area + v->area;
    x->scale = rad_dmin(u->scale, v->scale);
    for (int c = 0; c < 3; c++) {
        double m = a > 0.0 ? (u->area * u->B[c] + v->area * v->B[c]) / a : 0.0;
        x->B[c] = m;
        x->var[c] = rad_dmax(fabs(u->B[c] - m) + u->var[c], fabs(v->B[c] - m) + v->var[c]);
        x->Hlo[c] = rad_dmin(u->Hlo[c], v->Hlo[c]);
        x->Hhi[c] = rad_dmax(u->Hhi[c], v->Hhi[c]);
    }
}

/* Every cluster's, children before parents: the subtrees on every thread,
 * then the nodes above them, from the sources' rows of carry
 * (hier_fill_sources).  The gather needs only the moments; the oracle and
 * the bound need the values too. */
static void pull(rad_hier *h, int carry, int with_values)
{
    int threads = hier_threads(h);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (size_t k = 0; k < h->ncsub; k++) {
        if (with_values)
            for (size_t i = (size_t)h->csub_end[k]; i-- > (size_t)h->csub[k];)
                pull_node(h, i, carry, 1);
        else /* only the clusters with moments do anything */
            for (size_t j = h->csub_mom[2 * k + 1]; j-- > h->csub_mom[2 * k];)
                pull_node(h, (size_t)h->cmnode[j], carry, 0);
    }
    for (size_t k = h->nctop; k-- > 0;)
        pull_node(h, (size_t)h->ctop[k], carry, with_values);
}

/* What an end offers as a source, channel c: B, var; as a receiver: its
 * largest reflectance, its threshold scale and its irradiance range. */
typedef struct end_values {
    double B[3], var[3], rho[3], Hlo[3], Hhi[3], scale;
} end_values;

static void values(const rad_hier *h, int id, end_values *v)
{
    /* the irradiance range is read only by a sealed scene's weight */
    int sealed = h->p.sealed;
    if (id >= 0) {
        const hier_clus *x = &h->cl[id];
        for (int c = 0; c < 3; c++) {
            v->B[c] = x->B[c];
            v->var[c] = x->var[c];
            v->rho[c] = x->rho[c];
            v->Hlo[c] = sealed ? x->Hlo[c] : 0.0;
            v->Hhi[c] = sealed ? x->Hhi[c] : 0.0;
        }
        v->scale = x->scale;
        return;
    }
    const hier_elem *e = &h->el[-1 - id];
    for (int c = 0; c < 3; c++) {
        v->B[c] = e->B[c];
        v->var[c] = e->var[c];
        v->rho[c] = h->rho[(size_t)e->face + (size_t)c * h->nroots];
        v->Hlo[c] = v->Hhi[c] = sealed ? element_H(h, e, c) : 0.0;
    }
    v->scale = h->face_scale[e->face];
}

/* What an error of F between receiver r and source s is multiplied by
 * (solve.c's hier_weight for ends): s's B, or, sealed, how far s's B can
 * lie from r's irradiance. */
static double weight(const rad_hier *h, const end_values *r, const end_values *s, int c)
{
    if (!h->p.sealed || !(r->rho[c] > 0.0))
        return s->B[c];
    return rad_dmax(fabs(s->B[c] - r->Hlo[c]), fabs(s->B[c] - r->Hhi[c]));
}

/* A link's term of the bound at receiver r from source s (F's error e, and
 * F' what the source's variation is multiplied by), the largest over the
 * channels. */
static double term(const rad_hier *h, const end_values *r, const end_values *s, double e,
                   double F)
{
    double t = 0.0;
    for (int c = 0; c < 3; c++)
        t = rad_dmax(t, r->rho[c] * (e * weight(h, r, s, c) + F * s->var[c]));
    return t;
}

/* ---- refinement ---------------------------------------------------------- */

/* The oracle's decision on link l (target > 0, the ends' values x and y):
 * 0 keep it, else split_link's split_b + 2. */
static signed char decide_by(const rad_hier *h, const hier_clink *l, double target,
                             const end_values *x, const end_values *y)
{
    double share = h->p.link_share * target;
    double ta = term(h, x, y, l->ea, l->va) / (share * x->scale);
    double tb = term(h, y, x, l->eb, l->vb) / (share * y->scale);
    if (!(ta > 1.0 || tb > 1.0))
        return 0;
    return (signed char)((l->by_size ? -1 : ta >= tb) + 2);
}

/* The oracle's decision on link l: 0 keep it, else split_link's split_b + 2. */
static signed char decide(const rad_hier *h, const hier_clink *l, double target)
{
    if (l->a == INT_MIN)
        return 0;
    if (l->overlap)
        return -1 + 2;
    if (!(target > 0.0))
        return 0;
    end_values x, y;
    values(h, l->a, &x);
    values(h, l->b, &y);
    return decide_by(h, l, target, &x, &y);
}

/* Whether the oracle (decide, at target > 0) splits the link the same way
 * whatever its rays would see: then out holds one such outcome and no ray
 * is cast.  The link is examined in the pass's next generation, with the
 * same values, and replaced; its G is never used. */
static int split_whatever_seen(const rad_hier *h, const end_view *x, const end_view *y,
                               const link_geometry *g, double target, hier_clink *out)
{
    end_values vx, vy;
    values(h, out->a, &vx);
    values(h, out->b, &vy);
    signed char first = 0;
    for (int open = 0; open <= CLUSTER_RAYS; open++) { /* the last: every ray open */
        finish(h, x, y, g, (double)open / CLUSTER_RAYS, open > 0 && open < CLUSTER_RAYS, out);
        signed char d = decide_by(h, out, target, &vx, &vy);
        if (d == 0 || (open > 0 && d != first))
            return 0;
        first = d;
    }
    return 1;
}

/* One pass: target > 0 refines by the bound (refine.c's rule), target = 0
 * only links whose spheres meet.  Links made are examined in the same pass,
 * generation by generation. */
static rad_status refine_pass(rad_hier *h, double target, long long *count)
{
    job_list cj = {NULL, 0, 0}, sj = {NULL, 0, 0};
    signed char *dec = NULL;
    size_t capdec = 0;
    rad_status st = RAD_OK;
    int threads = hier_threads(h);
    if (target > 0.0) {
        if ((st = hier_fill_sources(h, CLUSTER_B)) != RAD_OK)
            return st;
        pull(h, CLUSTER_B, 1);
    }
    size_t begin = 0, end = h->ncln;
    while (begin < end && st == RAD_OK) {
        cj.n = sj.n = 0;
        /* the decisions read only the ends' values, which splitting leaves
           as they are: made in parallel, then carried out in link order */
        if (!rad_sys_grow((void **)&dec, &capdec, 0, end - begin, 1, 4096)) {
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu link decisions", end - begin);
            break;
        }
        const rad_hier *hc = h;
#pragma omp parallel for schedule(static) num_threads(threads) if (end - begin > 4096)
        for (long long k = (long long)begin; k < (long long)end; k++) {
            /* the ends' values lie at random: those of the link
               HIER_PREFETCH_AHEAD on are asked for (values() reads) */
            if (target > 0.0 && k + HIER_PREFETCH_AHEAD < (long long)end) {
                const hier_clink *f = &hc->cln[k + HIER_PREFETCH_AHEAD];
                const int ends[2] = {f->a, f->b};
                for (int s = 0; s < 2 && f->a != INT_MIN; s++) {
                    if (ends[s] >= 0) {
                        const hier_clus *x = &hc->cl[ends[s]];
                        __builtin_prefetch(&x->rho);
                        __builtin_prefetch(&x->var);
                    } else {
                        const hier_elem *x = &hc->el[-1 - ends[s]];
                        __builtin_prefetch(&x->face);
                        __builtin_prefetch(&x->B);
                        __builtin_prefetch(&x->var);
                    }
                }
            }
            dec[k - (long long)begin] = decide(hc, &hc->cln[k], target);
        }
        for (size_t k = begin; k < end && st == RAD_OK; k++) {
            /* split_link reads the ends' nodes, and the nodes of the split
               end's children, all far apart: the ends of the link twice
               HIER_PREFETCH_AHEAD places on are asked for, and the children
               of the ends HIER_PREFETCH_AHEAD on (their nodes by then read) */
            size_t far = k + 2 * HIER_PREFETCH_AHEAD, near = k + HIER_PREFETCH_AHEAD;
            if (far < end && dec[far - begin]) {
                const int ends[2] = {h->cln[far].a, h->cln[far].b};
                for (int s = 0; s < 2; s++) {
                    const char *x = ends[s] >= 0 ? (const char *)&h->cl[ends[s]]
                                                 : (const char *)&h->el[-1 - ends[s]];
                    __builtin_prefetch(x);
                    __builtin_prefetch(x + (ends[s] >= 0 ? offsetof(hier_clus, child) : 64));
                }
            }
            if (near < end && dec[near - begin]) {
                const int ends[2] = {h->cln[near].a, h->cln[near].b};
                for (int s = 0; s < 2; s++)
                    if (ends[s] >= 0 && h->cl[ends[s]].root < 0)
                        for (int c = 0; c < 2; c++)
                            __builtin_prefetch(&h->cl[h->cl[ends[s]].child[c]].root);
            }
            if (!dec[k - begin])
                continue;
            st = split_link(h, k, dec[k - begin] - 2, &cj, &sj);
            ++*count;
        }
        if (st == RAD_OK)
            st = estimate_batch(h, cj.j, cj.n, target);
        if (st == RAD_OK)
            st = hier_estimate_batch(h, sj.j, sj.n, 0);
        /* the generation's split links, and its new pairs that carry
           nothing, go before the next is examined, so the array holds the
           live links and one generation's new ones, not every link made
           (order is kept: results do not depend on it) */
        size_t kept = begin, w = begin;
        for (size_t k = begin; k < h->ncln; k++)
            if (h->cln[k].a != INT_MIN) {
                kept += k < end;
                h->cln[w++] = h->cln[k];
            }
        h->ncln = w;
        begin = kept;
        end = h->ncln;
        if (st == RAD_OK)
            hier_working(h, "linking", h->nln + h->ncln);
    }
    free(cj.j);
    free(sj.j);
    free(dec);
    h->cln_version++;
    return st;
}

rad_status hier_cluster_refine(rad_hier *h, double target, long long *count)
{
    return h->ncl ? refine_pass(h, target, count) : RAD_OK;
}

/* ---- creation ------------------------------------------------------------ */

/* The tree cut for the passes that run on every thread (h->csub, h->ctop):
 * the subtrees CUT_DEPTH levels below the root, enough for the threads to
 * share them out, and the nodes above.  Nodes are made depth-first, so a
 * subtree is the run from its root to its rightmost leaf.  0 when out of
 * memory. */
enum { CUT_DEPTH = 6 };
static int tree_cut(rad_hier *h)
{
    size_t cap = (size_t)2 << CUT_DEPTH;
    h->csub = malloc(cap * sizeof *h->csub);
    h->csub_end = malloc(cap * sizeof *h->csub_end);
    h->ctop = malloc(cap * sizeof *h->ctop);
    if (!h->csub || !h->csub_end || !h->ctop)
        return 0;
    int stack[2 * CUT_DEPTH + 4], depth[2 * CUT_DEPTH + 4], top = 0;
    if (h->ncl > 0) {
        stack[top] = 0;
        depth[top++] = 0;
    }
    while (top > 0) { /* left before right: both lists come out in index order */
        int i = stack[--top], d = depth[top];
        const hier_clus *x = &h->cl[i];
        if (d == CUT_DEPTH && x->root < 0) {
            int last = i;
            while (h->cl[last].root < 0)
                last = h->cl[last].child[1];
            h->csub[h->ncsub] = i;
            h->csub_end[h->ncsub++] = last + 1;
            continue;
        }
        h->ctop[h->nctop++] = i;
        if (x->root < 0) {
            for (int k = 1; k >= 0; k--) {
                stack[top] = x->child[k];
                depth[top++] = d + 1;
            }
        }
    }
    return 1;
}

/* h->cmnode and h->csub_mom (nmom clusters have a row of cmom); 0 when out
 * of memory. */
static int moment_runs(rad_hier *h, size_t nmom)
{
    h->nmom = nmom;
    h->cmnode = malloc((nmom ? nmom : 1) * sizeof *h->cmnode);
    h->csub_mom = malloc((2 * h->ncsub + 1) * sizeof *h->csub_mom);
    if (!h->cmnode || !h->csub_mom)
        return 0;
    size_t m = 0, k = 0;
    for (size_t i = 0; i < h->ncl; i++) {
        /* subtrees come in index order: their runs open and close in it */
        while (k < 2 * h->ncsub && i == (size_t)(k % 2 ? h->csub_end[k / 2] : h->csub[k / 2]))
            h->csub_mom[k++] = m;
        if (h->cl[i].mom >= 0)
            h->cmnode[m++] = (int)i;
    }
    while (k < 2 * h->ncsub)
        h->csub_mom[k++] = m;
    return 1;
}

static int receives_exactly(const rad_hier *h, int end);

static struct hier_cleaf leaf_of(const rad_hier *h, int i)
{
    const hier_clus *x = &h->cl[i];
    int row = !receives_exactly(h, i) ? x->mom : x->above >= 0 ? h->cl[x->above].mom : -1;
    return (struct hier_cleaf){x->first, row};
}

/* The groups of small cluster i's triangles with equal unit normals, in
 * the order their first triangles come, into set (may be NULL); their
 * count. */
static int groups_of(const rad_hier *h, size_t i, struct hier_cgrp *set)
{
    const hier_clus *x = &h->cl[i];
    int first[CLUSTER_SMALL], ng = 0;
    for (int k = 0; k < x->count; k++) {
        rad_vec3 n = h->ctri[x->first + k].n;
        int g = 0;
        for (; g < ng; g++) {
            rad_vec3 m = h->ctri[x->first + first[g]].n;
            if (n.x == m.x && n.y == m.y && n.z == m.z)
                break;
        }
        if (g == ng) {
            first[ng++] = k;
            if (set)
                set[g] = (struct hier_cgrp){x->first, 0u};
        }
        if (set)
            set[g].mask |= 1u << k;
    }
    return ng;
}

/* Every small cluster's rows of cemit (its triangles' own where their
 * normals all differ, else its groups'; the isotropic model, whose gathers
 * read moments only, keeps no groups), cemit made for them and the
 * groups' normals written once; 0 when out of memory. */
static int make_groups(rad_hier *h)
{
    int threads = hier_threads(h);
    size_t n = h->nroots;
    int grouped = h->p.cluster_model != RAD_HIER_CLUSTER_ISO;
#pragma omp parallel for schedule(static) num_threads(threads) if (h->ncl > 65536)
    for (long long i = 0; i < (long long)h->ncl; i++) {
        hier_clus *x = &h->cl[i];
        x->ngrp = x->root >= 0 || x->count > CLUSTER_SMALL ? 0
                  : grouped                                ? groups_of(h, (size_t)i, NULL)
                                                           : x->count;
    }
    size_t total = 0;
    for (size_t i = 0; i < h->ncl; i++) {
        hier_clus *x = &h->cl[i];
        if (x->ngrp == x->count || x->ngrp == 0) {
            x->grp = x->first;
            x->ngrp = x->ngrp ? x->count : 0;
        } else {
            x->grp = (int)(n + total);
            total += (size_t)x->ngrp;
        }
    }
    h->ngrp = total;
    h->cemit = rad_sys_alloc_huge(6 * (n + total) * sizeof *h->cemit);
    h->cgrp_set = rad_sys_alloc_huge((total ? total : 1) * sizeof *h->cgrp_set);
    if (!h->cemit || !h->cgrp_set)
        return 0;
#pragma omp parallel for schedule(static) num_threads(threads) if (h->ncl > 65536)
    for (long long i = 0; i < (long long)h->ncl; i++) {
        const hier_clus *x = &h->cl[i];
        if ((size_t)x->grp < n)
            continue;
        struct hier_cgrp *set = h->cgrp_set + ((size_t)x->grp - n);
        groups_of(h, (size_t)i, set);
        for (int g = 0; g < x->ngrp; g++) {
            rad_vec3 v = h->ctri[set[g].first + __builtin_ctz(set[g].mask)].n;
            double *row = h->cemit + 6 * ((size_t)x->grp + (size_t)g);
            row[0] = v.x;
            row[1] = v.y;
            row[2] = v.z;
        }
    }
    return 1;
}

void hier_cluster_fill_groups(rad_hier *h)
{
    size_t n = h->nroots;
#pragma omp parallel for schedule(static) num_threads(hier_threads(h)) if (h->ngrp > 65536)
    for (long long g = 0; g < (long long)h->ngrp; g++) {
        const struct hier_cgrp *set = &h->cgrp_set[g];
        double s0 = 0.0, s1 = 0.0, s2 = 0.0;
        for (unsigned m = set->mask; m; m &= m - 1) {
            const double *v = h->cemit + 6 * ((size_t)set->first + (size_t)__builtin_ctz(m)) + 3;
            s0 += v[0];
            s1 += v[1];
            s2 += v[2];
        }
        double *row = h->cemit + 6 * (n + (size_t)g);
        row[3] = s0;
        row[4] = s1;
        row[5] = s2;
    }
}

/* Cluster i's area moments and largest reflectance, from its children's
 * (or its triangle's). */
static void below(rad_hier *h, size_t i)
{
    size_t n = h->nroots;
    hier_clus *x = &h->cl[i];
    if (x->root >= 0) {
        dir_one(&x->geo, x->area, h->normal[x->root]);
    } else {
        x->geo = h->cl[x->child[0]].geo;
        dir_sum(&x->geo, &h->cl[x->child[1]].geo);
    }
    for (int c = 0; c < 3; c++)
        x->rho[c] = x->root >= 0 ? h->rho[(size_t)x->root + (size_t)c * n]
                                 : rad_dmax(h->cl[x->child[0]].rho[c], h->cl[x->child[1]].rho[c]);
}

rad_status hier_cluster_create(rad_hier *h)
{
    size_t n = h->nroots;
    if (h->use_vis) { /* cluster links sample visibility with rays */
        rad_status rays_ready = rad_vis_prepare_rays(h->vis);
        if (rays_ready != RAD_OK)
            return rays_ready;
    }
    double *xyz = rad_sys_alloc_huge(9 * n * sizeof *xyz);
    int *tri = rad_sys_alloc_huge(3 * n * sizeof *tri);
    rad_cluster_tree *tree = NULL;
    rad_status st = RAD_OK;
    if (!xyz || !tri) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the cluster hierarchy");
        goto done;
    }
#pragma omp parallel for schedule(static) num_threads(hier_threads(h)) if (n > 65536)
    for (size_t t = 0; t < n; t++)
        for (int v = 0; v < 3; v++) {
            rad_vec3 p = h->el[t].p[v];
            xyz[9 * t + 3 * (size_t)v] = p.x;
            xyz[9 * t + 3 * (size_t)v + 1] = p.y;
            xyz[9 * t + 3 * (size_t)v + 2] = p.z;
            tri[3 * t + (size_t)v] = (int)(3 * t + (size_t)v);
        }
    if ((st = rad_cluster_build(xyz, 3 * n, tri, n, 1, hier_threads(h), &tree)) != RAD_OK)
        goto done;
    h->ncl = rad_cluster_node_count(tree);
    /* on huge pages: the nodes alone are about 1 kB a triangle, and a
       4 KB page's first touch is a fault (zeroed below on every thread).
       crecv stays calloc's: the solve writes it first, and the memory
       check counts its pages from then (memory.c) */
    int threads = hier_threads(h);
    h->cl = rad_sys_alloc_huge(h->ncl * sizeof *h->cl);
    h->corder = rad_sys_alloc_huge(n * sizeof *h->corder);
    h->crecv = calloc(3 * n, sizeof *h->crecv);
    const rad_cluster_node *nd = rad_cluster_nodes(tree);
    if (h->cl) {
#pragma omp parallel for schedule(static) num_threads(threads) if (h->ncl > 65536)
        for (long long i = 0; i < (long long)h->ncl; i++)
            memset(&h->cl[i], 0, sizeof *h->cl);
    }
    size_t nmom = 0;
    for (size_t i = 0; h->cl && i < h->ncl; i++)
        h->cl[i].mom = reads_moments(h, nd[i].count) ? (int)nmom++ : -1;
    h->cmom = rad_sys_alloc_huge(3 * (nmom ? nmom : 1) * sizeof *h->cmom);
    h->cgot = rad_sys_alloc_huge(3 * (nmom ? nmom : 1) * sizeof *h->cgot);
    if (!h->cl || !h->corder || !h->crecv || !h->cmom || !h->cgot) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu clusters", h->ncl);
        goto done;
    }
    memcpy(h->corder, rad_cluster_order(tree), n * sizeof *h->corder);
    h->ctri = rad_sys_alloc_huge(n * sizeof *h->ctri);
    if (!h->ctri) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu clusters", h->ncl);
        goto done;
    }
#pragma omp parallel for schedule(static) num_threads(threads) if (n > 65536)
    for (size_t i = 0; i < n; i++) {
        const hier_elem *e = &h->el[h->corder[i]];
        hier_ctri *t = &h->ctri[i];
        t->n = h->normal[e->face];
        for (int v = 0; v < 3; v++)
            t->p[v] = e->p[v];
        t->c = e->c;
        t->area = e->area;
    }
#pragma omp parallel for schedule(static) num_threads(threads) if (h->ncl > 65536)
    for (long long i = 0; i < (long long)h->ncl; i++) {
        hier_clus *x = &h->cl[i];
        const rad_cluster_node *m = &nd[i];
        rad_vec3 lo = rad_vec3_make(m->lo[0], m->lo[1], m->lo[2]);
        rad_vec3 hi = rad_vec3_make(m->hi[0], m->hi[1], m->hi[2]);
        x->c = rad_vec3_scale(rad_vec3_add(lo, hi), 0.5);
        x->half = rad_vec3_scale(rad_vec3_sub(hi, lo), 0.5);
        x->radius = rad_vec3_norm(x->half);
        x->area = m->area;
        x->N = rad_vec3_scale(rad_vec3_make(m->normal[0], m->normal[1], m->normal[2]), m->area);
        double len = rad_vec3_norm(x->N);
        x->alpha = 4.0; /* > pi: no cone */
        if (m->cone_cos > -1.0 && len > 0.0) {
            x->axis = rad_vec3_scale(x->N, 1.0 / len);
            x->alpha = acos(rad_dmax(-1.0, rad_dmin(1.0, m->cone_cos)));
        }
        x->child[0] = m->child[0];
        x->child[1] = m->child[1];
        x->first = m->first;
        x->count = m->count;
        x->root = m->child[0] < 0 ? h->corder[m->first] : -1;
    }
    /* each cluster's nearest ancestor that is not small */
#pragma omp parallel for schedule(static) num_threads(threads) if (h->ncl > 65536)
    for (long long i = 0; i < (long long)h->ncl; i++) {
        int up = nd[i].parent;
        while (up >= 0 && h->cl[up].count <= CLUSTER_SMALL)
            up = nd[up].parent;
        h->cl[i].above = up;
    }
    h->cleaf = rad_sys_alloc_huge(n * sizeof *h->cleaf);
    if (!h->cleaf || !tree_cut(h)) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu clusters", h->ncl);
        goto done;
    }
#pragma omp parallel for schedule(static) num_threads(threads) if (h->ncl > 65536)
    for (long long i = 0; i < (long long)h->ncl; i++)
        if (h->cl[i].root >= 0)
            h->cleaf[h->cl[i].root] = leaf_of(h, (int)i);
    /* the largest reflectance below each cluster and its area moments,
       children before parents: the subtrees on every thread, then the
       nodes above them */
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (size_t k = 0; k < h->ncsub; k++)
        for (size_t i = (size_t)h->csub_end[k]; i-- > (size_t)h->csub[k];)
            below(h, i);
    for (size_t k = h->nctop; k-- > 0;)
        below(h, (size_t)h->ctop[k]);
    if (!moment_runs(h, nmom) || !make_groups(h))
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu clusters", h->ncl);
    h->cchannels = 1;
    for (size_t t = 0; t < n; t++)
        for (int c = 1; c < 3; c++)
            if (h->rho[t + (size_t)c * n] != h->rho[t] || h->E[t + (size_t)c * n] != h->E[t])
                h->cchannels = 3;
    {
        job_list cj = {NULL, 0, 0}, sj = {NULL, 0, 0};
        for (size_t i = 0; i < h->ncl && st == RAD_OK; i++)
            if (h->cl[i].root < 0)
                st = queue_pair(&cj, &sj, end_of(h, h->cl[i].child[0]),
                                end_of(h, h->cl[i].child[1]));
        if (st == RAD_OK)
            st = estimate_batch(h, cj.j, cj.n, 0.0);
        if (st == RAD_OK)
            st = hier_estimate_batch(h, sj.j, sj.n, 0);
        free(cj.j);
        free(sj.j);
    }
    if (st == RAD_OK) {
        long long count = 0;
        st = refine_pass(h, 0.0, &count);
    }
done:
    rad_cluster_destroy(tree);
    free(xyz);
    free(tri);
    return st;
}

void hier_cluster_destroy(rad_hier *h)
{
    free(h->cl);
    free(h->csub);
    free(h->csub_end);
    free(h->ctop);
    free(h->corder);
    free(h->ctri);
    free(h->cleaf);
    free(h->cmnode);
    free(h->csub_mom);
    rad_sys_free_mapped(h->cln, h->capcln, sizeof *h->cln);
    free(h->cemit);
    free(h->cgrp_set);
    free(h->crecv);
    free(h->cmom);
    free(h->cgot);
    free(h->cinc_start);
    rad_sys_free_mapped(h->cinc, h->cinc_cap, sizeof *h->cinc);
}

/* ---- the solve's gather and the local error bounds ----------------------- */

/* Where cluster-link end x reads its source's row, and the row's bytes. */
static const char *source_row(const rad_hier *h, const hier_cinc *x, int nch, size_t *bytes)
{
    if (x->kind == HIER_CINC_ELEMENT) {
        *bytes = 7 * sizeof(double);
        return (const char *)(h->src + HIER_SRC * (size_t)x->src);
    }
    if (x->kind == HIER_CINC_MOMENTS) {
        *bytes = (size_t)nch * sizeof(hier_dir);
        return (const char *)(h->cmom + (size_t)nch * (size_t)x->src);
    }
    *bytes = 6 * sizeof(double) * (size_t)x->kind;
    return (const char *)(h->cemit + 6 * (size_t)x->src);
}

/* The intensity of cluster-link end i's other end (what is carried, each
 * channel carried into p[c]) towards the receiver, u = -dir:
 * sum_j A_j v_j max(n_j.u, 0) (a cluster's by the model), from the sources'
 * rows (hier_fill_sources).  The channels share each triangle's projected
 * area, so it is computed once.  It first asks for the row of the end
 * HIER_PREFETCH_AHEAD on: its first and last lines (the second and third
 * of a long row too), the ones between following as the reads stream. */
static void intensity(const rad_hier *h, size_t i, int carry, double p[3])
{
    int nch = channels(h, carry);
    if (i + HIER_PREFETCH_AHEAD < 2 * h->ncln) {
        size_t bytes;
        const char *row = source_row(h, &h->cinc[i + HIER_PREFETCH_AHEAD], nch, &bytes);
        __builtin_prefetch(row);
        __builtin_prefetch(row + bytes - 1);
        if (bytes > 128) {
            __builtin_prefetch(row + 64);
            __builtin_prefetch(row + 128);
        }
    }
    const hier_cinc *x = &h->cinc[i];
    rad_vec3 u = rad_vec3_scale(x->dir, -1.0);
    if (x->kind == HIER_CINC_ELEMENT) {
        const double *m = h->src + HIER_SRC * (size_t)x->src;
        double a = m[3] * rad_dmax(0.0, rad_vec3_dot(rad_vec3_make(m[0], m[1], m[2]), u));
        for (int c = 0; c < nch; c++)
            p[c] = a * m[4 + c];
        return;
    }
    if (x->kind == HIER_CINC_MOMENTS) {
        const hier_dir *g = h->cmom + (size_t)nch * (size_t)x->src;
        if (h->p.cluster_model == RAD_HIER_CLUSTER_ISO) {
            for (int c = 0; c < nch; c++)
                p[c] = 0.25 * g[c].C;
            return;
        }
        double q[6], err;
        dir_square(u, q);
        for (int c = 0; c < nch; c++)
            p[c] = dir_eval_at(&g[c], u, q, &err);
        return;
    }
    /* the gather's innermost loop, over the groups of equal normals: the
       sums stay in registers, and max(d, 0) is taken without a branch,
       (d + |d|) / 2, exact for a finite d (a small cluster's faces face the
       direction or not in no pattern a branch predictor could follow) */
    const double *m = h->cemit + 6 * (size_t)x->src;
    double p0 = 0.0, p1 = 0.0, p2 = 0.0;
    for (int j = 0; j < x->kind; j++, m += 6) {
        double d = m[0] * u.x + m[1] * u.y + m[2] * u.z, a = 0.5 * (d + fabs(d));
        p0 += a * m[3];
        p1 += a * m[4];
        p2 += a * m[5];
    }
    p[0] = p0;
    p[1] = nch > 1 ? p1 : 0.0;
    p[2] = nch > 1 ? p2 : 0.0;
}

/* Where a gather reads end id as a source (hier_cinc's src and kind). */
static hier_cinc source_of(const rad_hier *h, int id)
{
    hier_cinc x = {rad_vec3_make(0.0, 0.0, 0.0), 0.0, 0, HIER_CINC_MOMENTS};
    if (id < 0) {
        x.src = -1 - id;
        x.kind = HIER_CINC_ELEMENT;
    } else if (h->p.cluster_model != RAD_HIER_CLUSTER_ISO && h->cl[id].count <= CLUSTER_SMALL) {
        x.src = h->cl[id].grp;
        x.kind = h->cl[id].ngrp;
    } else {
        x.src = h->cl[id].mom;
    }
    return x;
}

/* Each receiving end's cluster-link ends (h->cinc), in link order; 0 when
 * out of memory. */
static int cluster_incidence(rad_hier *h)
{
    size_t nr = h->ncl + h->nel;
    if (h->cinc_start && h->cinc_version == h->cln_version && h->cinc_nel == h->nel)
        return 1;
    if (!rad_sys_grow((void **)&h->cinc_start, &h->cinc_start_cap, 0, nr + 1,
                      sizeof *h->cinc_start, 1024) ||
        !rad_sys_grow_mapped((void **)&h->cinc, &h->cinc_cap, 0, 2 * h->ncln, sizeof *h->cinc,
                             1024))
        return 0;
    hier_gather_touch(h, HIER_GATHER_CINC_START, (nr + 1) * sizeof *h->cinc_start);
    hier_gather_touch(h, HIER_GATHER_CINC, 2 * h->ncln * sizeof *h->cinc);
    /* each cluster's source row, read once here instead of at every end */
    hier_cinc *src = malloc((h->ncl ? h->ncl : 1) * sizeof *src);
    if (!src)
        return 0;
    for (size_t i = 0; i < h->ncl; i++)
        src[i] = source_of(h, (int)i);
    size_t *start = h->cinc_start;
    memset(start, 0, (nr + 1) * sizeof *start);
    int threads = hier_threads(h);
    /* the counts, on every thread (a count does not depend on the order) */
#pragma omp parallel for schedule(static) num_threads(threads) if (h->ncln > 65536)
    for (long long k = 0; k < (long long)h->ncln; k++) {
        const int ends[2] = {h->cln[k].a, h->cln[k].b};
        for (int s = 0; s < 2; s++) {
            size_t r = ends[s] >= 0 ? (size_t)ends[s] : h->ncl + (size_t)(-1 - ends[s]);
#pragma omp atomic
            start[r + 1]++;
        }
    }
    for (size_t r = 0; r < nr; r++)
        start[r + 1] += start[r];
    /* each thread writes the receivers of its share of the ends (whole
       receivers, so each keeps link order); start[r] runs ahead, then is
       restored */
#pragma omp parallel num_threads(threads)
    {
        size_t lo, hi;
        hier_thread_rows(start, nr, omp_get_thread_num(), omp_get_num_threads(), &lo, &hi);
#pragma omp barrier
        for (size_t k = 0; k < h->ncln; k++) {
            const hier_clink *l = &h->cln[k];
            const int ends[2] = {l->a, l->b};
            for (int s = 0; s < 2; s++) {
                size_t r = ends[s] >= 0 ? (size_t)ends[s] : h->ncl + (size_t)(-1 - ends[s]);
                if (r < lo || r >= hi)
                    continue;
                int o = ends[1 - s];
                hier_cinc x = o >= 0 ? src[o] : source_of(h, o);
                x.dir = s == 0 ? l->w : rad_vec3_scale(l->w, -1.0);
                x.kv = l->kv;
                h->cinc[start[r]++] = x;
            }
        }
    }
    free(src);
    for (size_t r = nr; r > 0; r--)
        start[r] = start[r - 1];
    start[0] = 0;
    h->cinc_version = h->cln_version;
    h->cinc_nel = h->nel;
    return 1;
}

/* What cluster id gathers into (its channels' rows of cgot): a cluster
 * that reads moments (hier_clus.mom), which is every cluster that does not
 * receive triangle by triangle. */
static hier_dir *got(const rad_hier *h, int id)
{
    return h->cgot + 3 * (size_t)h->cl[id].mom;
}

/* Cluster `end` takes v (the channels carried) from direction dir. */
static void receive(rad_hier *h, int end, int carry, rad_vec3 dir, const double v[3])
{
    int nch = channels(h, carry);
    for (int c = 0; c < nch; c++) {
        if (h->p.cluster_model == RAD_HIER_CLUSTER_ISO)
            got(h, end)[c].C += 0.25 * v[c];
        else
            dir_add(&got(h, end)[c], v[c], dir);
    }
}

/* What cluster i gathered, added to its children's. */
/* Whether cluster end receives triangle by triangle (crecv): a small one,
 * in the oriented model. */
static int receives_exactly(const rad_hier *h, int end)
{
    return h->p.cluster_model != RAD_HIER_CLUSTER_ISO && h->cl[end].count <= CLUSTER_SMALL;
}

/* What cluster i gathered, added to its children's; not to a small one's
 * (oriented), whose triangles read it at the nearest ancestor that is not
 * small (pushed_to). */
static void push_node(rad_hier *h, size_t i, int nch)
{
    const hier_clus *x = &h->cl[i];
    if (x->root >= 0)
        return;
    for (int k = 0; k < 2; k++)
        if (!receives_exactly(h, x->child[k]))
            for (int c = 0; c < nch; c++)
                dir_sum(&got(h, x->child[k])[c], &got(h, (int)i)[c]);
}

/* What the links of the clusters above leaf x brought it (the directions'
 * moments, channel c), or NULL for nothing. */
static const hier_dir *pushed_to(const rad_hier *h, const struct hier_cleaf *x, int c)
{
    return x->got >= 0 ? h->cgot + 3 * (size_t)x->got + (size_t)c : NULL;
}

/* The links of the small clusters of subtree `top` (a small cluster whose
 * parent is not), each triangle below taking max(n.w, 0) of what each link
 * of each cluster above it brings; crecv of its triangles is rewritten. */
static void receive_subtree(rad_hier *h, int top, int carry)
{
    int nch = channels(h, carry);
    const hier_clus *t = &h->cl[top];
    /* the subtree's triangles' normals and sums in short arrays, one
       triangle a lane: each link's cosines and shares then run as one loop
       the compiler may vectorize, the sums at each triangle in link order */
    double nx[CLUSTER_SMALL], ny[CLUSTER_SMALL], nz[CLUSTER_SMALL];
    double s0[CLUSTER_SMALL], s1[CLUSTER_SMALL], s2[CLUSTER_SMALL];
    for (int m = 0; m < t->count; m++) {
        rad_vec3 n = h->ctri[t->first + m].n;
        nx[m] = n.x;
        ny[m] = n.y;
        nz[m] = n.z;
        s0[m] = s1[m] = s2[m] = 0.0;
    }
    /* nodes are made depth-first: the subtree is the run of 2 count - 1 */
    for (int j = top; j < top + 2 * t->count - 1; j++) {
        const hier_clus *x = &h->cl[j];
        int lo = x->first - t->first, hi = lo + x->count;
        for (size_t i = h->cinc_start[j]; i < h->cinc_start[j + 1]; i++) {
            const hier_cinc *in = &h->cinc[i];
            double v[3];
            intensity(h, i, carry, v);
            double w0 = v[0] * in->kv, w1 = v[1] * in->kv, w2 = v[2] * in->kv;
            double dx = in->dir.x, dy = in->dir.y, dz = in->dir.z;
#pragma omp simd
            for (int m = lo; m < hi; m++) {
                double d = nx[m] * dx + ny[m] * dy + nz[m] * dz, a = 0.5 * (d + fabs(d));
                s0[m] += w0 * a;
                s1[m] += w1 * a;
                s2[m] += w2 * a;
            }
        }
    }
    for (int m = 0; m < t->count; m++) {
        double *r = h->crecv + 3 * (size_t)(t->first + m);
        r[0] = s0[m];
        r[1] = nch > 1 ? s1[m] : 0.0;
        r[2] = nch > 1 ? s2[m] : 0.0;
    }
}

/* receive_subtree for every small subtree (in parallel: they are disjoint). */
static void small_receive(rad_hier *h, int carry)
{
    if (h->p.cluster_model == RAD_HIER_CLUSTER_ISO)
        return;
    hier_gather_touch(h, HIER_GATHER_CRECV, 3 * h->nroots * sizeof *h->crecv);
    if (h->cl[0].count <= CLUSTER_SMALL) {
        receive_subtree(h, 0, carry);
        return;
    }
    int threads = hier_threads(h);
    /* the clusters that are not small are those that gather moments */
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) if (h->nmom > 4096)
    for (long long j = 0; j < (long long)h->nmom; j++) {
        const hier_clus *x = &h->cl[h->cmnode[j]];
        for (int k = 0; k < 2; k++)
            if (h->cl[x->child[k]].count <= CLUSTER_SMALL)
                receive_subtree(h, x->child[k], carry);
    }
}

/* Gather the links that end at clusters (by direction) and push what the
 * clusters gathered down their tree (parents come before their children);
 * the links' element ends wait for gather_elements.  Each receiving
 * cluster adds up its own links' ends in link order, in parallel over the
 * clusters, so the result does not depend on the thread count. */
static rad_status gather_links(rad_hier *h, int carry)
{
    pull(h, carry, 0);
    if (!cluster_incidence(h))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the gather of %zu cluster links",
                         h->ncln);
    int threads = hier_threads(h);
    int nch = channels(h, carry);
    const size_t *start = h->cinc_start;
    const hier_cinc *inc = h->cinc;
    /* the clusters that gather moments (a small one, oriented, receives
       triangle by triangle: small_receive) */
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) if (h->ncln > 1024)
    for (long long j = 0; j < (long long)h->nmom; j++) {
        int end = h->cmnode[j];
        size_t r = (size_t)end;
        memset(got(h, end), 0, 3 * sizeof *h->cgot);
        for (size_t i = start[r]; i < start[r + 1]; i++) {
            double v[3];
            intensity(h, i, carry, v);
            for (int c = 0; c < nch; c++)
                v[c] *= inc[i].kv;
            receive(h, end, carry, inc[i].dir, v);
        }
    }
    small_receive(h, carry);
    /* parents before children: the nodes above the subtrees, then the
       subtrees on every thread */
    for (size_t k = 0; k < h->nctop; k++)
        push_node(h, (size_t)h->ctop[k], nch);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (size_t k = 0; k < h->ncsub; k++) /* a cluster without moments pushes nothing */
        for (size_t j = h->csub_mom[2 * k]; j < h->csub_mom[2 * k + 1]; j++)
            push_node(h, (size_t)h->cmnode[j], nch);
    return RAD_OK;
}

/* What a leaf cluster's triangle (normal n, q: dir_square(n)) receives of
 * what it gathered, and the bracket's half width (*err). */
static double received(const rad_hier *h, const hier_dir *g, rad_vec3 n, const double q[6],
                       double *err)
{
    *err = 0.0;
    if (!g)
        return 0.0;
    return h->p.cluster_model == RAD_HIER_CLUSTER_ISO ? g->C : dir_eval_at(g, n, q, err);
}

/* Each element's Cg (B, T or, in Cg[0], the row; with one channel
 * carried, each channel takes channel 0's): what its own cluster links
 * bring (in link order), then, at a root, what its leaf cluster received
 * (the moments pushed to it and its triangle's own share), summed apart
 * and written once, in one pass over the elements in their order. */
static void gather_elements(rad_hier *h, int carry)
{
    int nch = channels(h, carry);
    const size_t *start = h->cinc_start;
    const hier_cinc *inc = h->cinc;
#pragma omp parallel for schedule(dynamic, 1024) num_threads(hier_threads(h)) if (h->nel > 65536)
    for (long long e = 0; e < (long long)h->nel; e++) {
        hier_elem *x = &h->el[e];
        rad_vec3 n = h->normal[x->face];
        double sum[3] = {0.0, 0.0, 0.0};
        size_t r = h->ncl + (size_t)e;
        for (size_t i = start[r]; i < start[r + 1]; i++) {
            double v[3];
            intensity(h, i, carry, v);
            double d = rad_vec3_dot(n, inc[i].dir), cosine = 0.5 * (d + fabs(d));
            for (int c = 0; c < nch; c++)
                sum[c] += v[c] * inc[i].kv * cosine;
        }
        if ((size_t)e < h->nroots) {
            const struct hier_cleaf *l = &h->cleaf[e];
            double q[6];
            dir_square(n, q);
            for (int c = 0; c < nch; c++) {
                double err;
                sum[c] += received(h, pushed_to(h, l, c), n, q, &err) +
                          h->crecv[3 * (size_t)l->first + (size_t)c];
            }
        }
        if (carry == CLUSTER_ONE)
            x->Cg[0] = sum[0];
        else
            for (int c = 0; c < 3; c++)
                x->Cg[c] = sum[nch == 1 ? 0 : c];
    }
}

rad_status hier_cluster_gather(rad_hier *h, int carry)
{
    if (!h->ncl)
        return RAD_OK;
    rad_status st = gather_links(h, carry);
    if (st != RAD_OK)
        return st;
    gather_elements(h, carry);
    return RAD_OK;
}

/* Link l's terms at those of its ends whose receiver index (a cluster's,
 * or ncl + an element's, as in h->cinc_start) lies in [lo, hi): its error
 * e, the source's B (its range) and the variation's square at a cluster,
 * rho e times the weight and the variation's square at an element. */
static void local_link(rad_hier *h, const hier_clink *l, size_t lo, size_t hi)
{
    const int ends[2] = {l->a, l->b};
    int mine[2];
    for (int s = 0; s < 2; s++) {
        size_t r = ends[s] >= 0 ? (size_t)ends[s] : h->ncl + (size_t)(-1 - ends[s]);
        mine[s] = r >= lo && r < hi;
    }
    if (!mine[0] && !mine[1])
        return;
    size_t n = h->nroots;
    double e[2] = {l->ea, l->eb}, F[2] = {l->va, l->vb};
    end_values v[2];
    values(h, l->a, &v[0]);
    values(h, l->b, &v[1]);
    for (int s = 0; s < 2; s++) {
        if (!mine[s])
            continue;
        const end_values *r = &v[s], *src = &v[1 - s];
        for (int c = 0; c < 3; c++) {
            double d = F[s] * src->var[c];
            if (ends[s] >= 0) {
                hier_clus *x = &h->cl[ends[s]];
                x->q[c] += e[s];
                x->qb[c] += e[s] * src->B[c];
                x->bmin[c] = rad_dmin(x->bmin[c], src->B[c]);
                x->bmax[c] = rad_dmax(x->bmax[c], src->B[c]);
                x->d[c] += d * d;
            } else {
                hier_elem *x = &h->el[-1 - ends[s]];
                double rho = h->rho[(size_t)x->face + (size_t)c * n];
                x->q[c] += rho * e[s] * weight(h, r, src, c);
                x->d[c] += rho * rho * d * d;
            }
        }
    }
}

/* Cluster i's sums of its links' terms (and its ancestors'), added to its
 * children's, or, at a leaf, its element's share of the bound. */
static void local_down(rad_hier *h, size_t i)
{
    size_t n = h->nroots;
    hier_clus *x = &h->cl[i];
    if (x->root >= 0) {
        hier_elem *e = &h->el[x->root];
        for (int c = 0; c < 3; c++) {
            double rho = h->rho[(size_t)x->root + (size_t)c * n], w = x->qb[c];
            if (h->p.sealed && rho > 0.0 && x->q[c] > 0.0) {
                double H = element_H(h, e, c), span = x->bmax[c] - x->bmin[c];
                /* weights on bmin and bmax with the sums' mean */
                double whi = span > 0.0 ? (x->qb[c] - x->q[c] * x->bmin[c]) / span : 0.0;
                whi = rad_dmax(0.0, rad_dmin(x->q[c], whi));
                w = (x->q[c] - whi) * fabs(x->bmin[c] - H) + whi * fabs(x->bmax[c] - H);
            }
            e->q[c] += rho * w;
            e->d[c] += rho * rho * x->d[c];
        }
        return;
    }
    for (int k = 0; k < 2; k++)
        for (int c = 0; c < 3; c++) {
            hier_clus *y = &h->cl[x->child[k]];
            y->q[c] += x->q[c];
            y->qb[c] += x->qb[c];
            y->d[c] += x->d[c];
            y->bmin[c] = rad_dmin(y->bmin[c], x->bmin[c]);
            y->bmax[c] = rad_dmax(y->bmax[c], x->bmax[c]);
        }
}

rad_status hier_cluster_local(rad_hier *h)
{
    if (!h->ncl)
        return RAD_OK;
    size_t n = h->nroots;
    /* what the directions' bracket leaves open, at each root */
    rad_status st = hier_fill_sources(h, CLUSTER_B);
    if (st != RAD_OK)
        return st;
    pull(h, CLUSTER_B, 1);
    st = gather_links(h, CLUSTER_B);
    if (st != RAD_OK)
        return st;
    int nch = channels(h, CLUSTER_B), threads = hier_threads(h);
#pragma omp parallel for schedule(static) num_threads(threads) if (n > 65536)
    for (size_t i = 0; i < n; i++) {
        const struct hier_cleaf *x = &h->cleaf[i]; /* root element i's */
        hier_elem *e = &h->el[i];
        double q[6];
        dir_square(h->normal[i], q);
        for (int c = 0; c < 3; c++) {
            double err;
            received(h, pushed_to(h, x, c < nch ? c : 0), h->normal[i], q, &err);
            e->q[c] += h->rho[i + (size_t)c * n] * err;
        }
    }
    /* A cluster receiver keeps, per channel, the sum of its links' errors
     * e, of e times their sources' B, and the range of those B: at each
     * leaf the sealed weight |B_s - H| (hier_weight) is then bounded with
     * the leaf's own irradiance H, by the two-point distribution on the
     * range that gives the sums. */
#pragma omp parallel for schedule(static) num_threads(threads) if (h->ncl > 65536)
    for (size_t i = 0; i < h->ncl; i++)
        for (int c = 0; c < 3; c++) {
            hier_clus *x = &h->cl[i];
            x->q[c] = x->qb[c] = x->d[c] = 0.0;
            x->bmin[c] = INFINITY;
            x->bmax[c] = -INFINITY;
        }
    /* each thread sums the link ends whose receivers it holds (whole
       receivers, as cluster_incidence shares them out): each receiver's
       sums run in link order, the serial loop's */
#pragma omp parallel num_threads(threads) if (h->ncln > 1024)
    {
        size_t lo, hi;
        hier_thread_rows(h->cinc_start, h->ncl + h->nel, omp_get_thread_num(),
                         omp_get_num_threads(), &lo, &hi);
        for (size_t k = 0; k < h->ncln; k++)
            local_link(h, &h->cln[k], lo, hi);
    }
    /* parents before children: the nodes above the subtrees, then the
       subtrees on every thread */
    for (size_t k = 0; k < h->nctop; k++)
        local_down(h, (size_t)h->ctop[k]);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (size_t k = 0; k < h->ncsub; k++)
        for (size_t i = (size_t)h->csub[k]; i < (size_t)h->csub_end[k]; i++)
            local_down(h, i);
    return RAD_OK;
}
