/* rad_hier: estimating a link between elements a and b from point values.
 *
 * 1. Facing test (rad_ff_facing): a pair facing away or coplanar makes no link.
 * 2. Blockers: none without visibility, or when the pair of input triangles
 *    is clear (the pair table, pairs.c: a sub-element pair's shaft lies
 *    inside its input pair's); otherwise the triangles the shaft of the two
 *    elements does not dismiss (rad_vis_blockers).
 * 3. Point values at the nodes x_k of the symmetric rule on a and y_k on b:
 *    F(x_k, b) and F(y_k, a), the closed-form point-to-triangle form factor
 *    over the part visible from the point (rad_vis_point_visible_limited:
 *    exact clipping within a work budget), or, for a far pair nothing can
 *    block, from the kernel at the degree-2 nodes of the other element (the
 *    kernel is smooth there).
 * 4. G_a = A_a sum w_k F(x_k, b), G_b = A_b sum w_k F(y_k, a); G is their
 *    mean weighted towards the smaller element (one G for both directions:
 *    reciprocity exact), and dG = |G_a - G_b| / 2 its error.  Each side's
 *    values get a weighted least-squares linear fit over its element (the
 *    gradient the gather pushes down, solve.c, and, over the same element as
 *    a source, the kernel's variation) with its largest residual.  With an explicit rule the unoccluded G
 *    comes from rad_ff and the point values give the visible fraction.
 * 5. Fallback: where the clipping needs too many blockers, pieces or work
 *    (a pair seen between many objects), each point's open value is scaled
 *    by the kernel-weighted share of open rays to 9 points of the other
 *    element, drawn afresh for each point (side_values_rays): a fixed
 *    cost, whatever the scene holds; the rays' sampling error joins dG.
 * Estimates only read the hierarchy, so a batch runs in parallel (OpenMP),
 * each job into its own slot: the result does not depend on the thread count.
 * Shared among processes (rad_hier_exchange), each estimates a share of the
 * batch's slots and all of them are exchanged (exchange.c). */
#include "hier_internal.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rad_sys.h"

enum { LINK_MAX_BLOCKERS = RAD_HIER_CLIP_BLOCKERS_MAX, LINK_RAY_STRATA = 3 };

int hier_pair_can_block(const rad_hier *h, int r, int s)
{
    if (!h->use_vis)
        return 0;
    if (h->pairs)
        return rad_hier_pairs_get(h->pairs, r, s, -1) & RAD_HIER_PAIR_CAN_BLOCK;
    return rad_vis_pair_can_block(h->vis, (size_t)r, (size_t)s);
}

int hier_pair_may_touch(const rad_hier *h, int r, int s)
{
    return !h->pairs || (rad_hier_pairs_get(h->pairs, r, s, -1) & RAD_HIER_PAIR_MAY_TOUCH);
}

/* The most blockers a link clips: clip_blockers, or all it may (clip). */
static int link_cap(const rad_hier *h, int clip)
{
    return clip ? RAD_HIER_CLIP_BLOCKERS_MAX : h->p.clip_blockers;
}

/* Work counters of estimates made on one thread. */
typedef struct work_count {
    long long evals;
    unsigned long long rays;
} work_count;

/* The point-to-element form factor from x (normal n) to t (normal nt) by
 * the kernel at t's degree-2 nodes: far pairs only. */
static double kernel_sampled(rad_vec3 x, rad_vec3 n, const hier_elem *t, rad_vec3 nt)
{
    static const double w[3][3] = {{4.0 / 6, 1.0 / 6, 1.0 / 6}, {1.0 / 6, 4.0 / 6, 1.0 / 6},
                                   {1.0 / 6, 1.0 / 6, 4.0 / 6}};
    double f = 0.0;
    for (int j = 0; j < 3; j++) {
        rad_vec3 y = rad_vec3_add(rad_vec3_add(rad_vec3_scale(t->p[0], w[j][0]),
                                               rad_vec3_scale(t->p[1], w[j][1])),
                                  rad_vec3_scale(t->p[2], w[j][2]));
        f += rad_ff_kernel(x, n, y, nt, NULL);
    }
    return t->area * f / 3.0;
}

/* The point values of side e towards t (F[k], and the unoccluded Fo[k]);
 * 0 when the visible part was too complex somewhere. */
static int side_values(const rad_hier *h, const hier_elem *e, const hier_elem *t, int far,
                       const int *blk, int nb, double *F, double *Fo, work_count *wc)
{
    rad_vec3 ne = h->normal[e->face], nt = h->normal[t->face];
    for (int k = 0; k < h->nodes; k++) {
        rad_vec3 x = rad_geom_triangle_point(e->p[0], e->p[1], e->p[2], h->rs[k], h->rt[k]);
        if (far) {
            F[k] = Fo[k] = kernel_sampled(x, ne, t, nt);
            wc->evals += 3;
        } else if (nb == 0) {
            F[k] = Fo[k] = rad_ff_point_polygon(x, ne, t->p, 3);
            wc->evals++;
        } else {
            long ev = 0;
            int ok = rad_vis_point_visible_limited(h->vis, x, ne, t->p, blk, nb,
                                                   RAD_VIS_LINK_POINT_WORK, &F[k], &Fo[k], &ev);
            wc->evals += ev;
            if (!ok)
                return 0;
        }
    }
    return 1;
}

/* The point values of side e towards t where clipping would cost too much
 * (too many blockers, pieces or clipping work: a pair seen between many
 * objects): at each node x, the open closed form times the kernel-weighted
 * share of open rays from x to one point in each of t's LINK_RAY_STRATA^2
 * equal cells, jittered within its cell by a hash of the pair's corners and
 * the node (the same pair gives the same points on any thread or process).
 * Points at one place in every cell would line up with a regular scene (a
 * grid of boxes shadows them alike from link to link, a bias that does not
 * average out) and, at the cells' corners or edges, would end on t's
 * boundary, where the faces that meet t there can catch the ray; points
 * shared by every node would let a shadow narrower than a cell slip past
 * all of them at once.  A fixed cost, whatever the scene holds: 9 rays a
 * node.  Where their sampling error matters the oracle estimates the link
 * again clipping (refine.c), so more rays buy accuracy only where the
 * link's share does not need it; fewer (4) let the bias of the share (a
 * ratio of two sampled sums) show where nothing is clipped
 * (clip_blockers 0).
 *
 * Returns the sampling error of e's G (the rule's weighted sum of each
 * node's standard error, A_e sum w_k F_k^o s_k): a link whose rays all
 * passed may still hide a shadow narrower than a cell, and without this
 * term the oracle would keep exactly those links and refine the ones whose
 * rays saw the shadow, a bias upwards.  s_k is the standard error of the
 * blocked share p from the rays' effective count m (kernel weights:
 * (sum w)^2 / sum w^2), with p (1 - p) taken no less than 1 / m, the
 * uncertainty left when all m rays agree. */
static double side_values_rays(const rad_hier *h, const hier_elem *e, const hier_elem *t,
                               double *F, double *Fo, work_count *wc)
{
    enum { CELLS = LINK_RAY_STRATA * LINK_RAY_STRATA, RAYS = RAD_HIER_MAX_NODES * CELLS };
    rad_vec3 ne = h->normal[e->face], nt = h->normal[t->face];
    uint64_t key = rad_vis_pair_key(e->p, t->p);
    /* every node's rays in one query: Embree's packets then run full */
    double from[3 * RAYS], to[3 * RAYS], wj[RAYS];
    unsigned char blocked[RAYS];
    size_t first[RAD_HIER_MAX_NODES + 1], nseg = 0;
    for (int k = 0; k < h->nodes; k++) {
        rad_vec3 x = rad_geom_triangle_point(e->p[0], e->p[1], e->p[2], h->rs[k], h->rt[k]);
        uint64_t node = key + 2 * CELLS * (uint64_t)k;
        first[k] = nseg;
        for (int j = 0; j < CELLS; j++) {
            double s, u;
            rad_geom_triangle_stratum(LINK_RAY_STRATA, j, rad_sys_hash_unit(node + 2 * (uint64_t)j),
                                      rad_sys_hash_unit(node + 2 * (uint64_t)j + 1), &s, &u);
            rad_vec3 y = rad_geom_triangle_point(t->p[0], t->p[1], t->p[2], s, u);
            double w = rad_ff_kernel(x, ne, y, nt, NULL);
            if (!(w > 0.0))
                continue;
            from[3 * nseg] = x.x, from[3 * nseg + 1] = x.y, from[3 * nseg + 2] = x.z;
            to[3 * nseg] = y.x, to[3 * nseg + 1] = y.y, to[3 * nseg + 2] = y.z;
            wj[nseg++] = w;
        }
        Fo[k] = rad_ff_point_polygon(x, ne, t->p, 3);
    }
    first[h->nodes] = nseg;
    /* a query that cannot run reads as blocked, as rad_vis_segment_blocked does */
    if (nseg > 0 && rad_vis_occluded_between(h->vis, (size_t)e->face, (size_t)t->face, nseg, from,
                                             to, blocked, NULL) != RAD_OK)
        memset(blocked, 1, nseg);
    wc->rays += nseg;
    double err = 0.0;
    for (int k = 0; k < h->nodes; k++) {
        double all = 0.0, all2 = 0.0, open = 0.0;
        for (size_t j = first[k]; j < first[k + 1]; j++) {
            all += wj[j];
            all2 += wj[j] * wj[j];
            if (!blocked[j])
                open += wj[j];
        }
        F[k] = all > 0.0 ? Fo[k] * (open / all) : Fo[k];
        wc->evals += 1 + CELLS;
        if (all > 0.0) {
            double m = all * all / all2, pb = 1.0 - open / all;
            err += h->rw[k] * Fo[k] * sqrt(rad_dmax(pb * (1.0 - pb), 1.0 / m) / m);
        }
    }
    return e->area * err;
}

/* The weighted least-squares linear fit m + g (x - c) of the point values
 * F[k] over element e (the rule's nodes are symmetric about the centroid, so
 * the constant is their weighted mean m): *g, and the largest residual. */
static double linear_fit(const rad_hier *h, const hier_elem *e, const double *F, double m,
                         rad_vec3 *g)
{
    rad_vec3 u = rad_vec3_sub(e->p[1], e->p[0]);
    u = rad_vec3_scale(u, 1.0 / rad_vec3_norm(u));
    rad_vec3 v = rad_vec3_cross(h->normal[e->face], u);
    double saa = 0.0, sab = 0.0, sbb = 0.0, saf = 0.0, sbf = 0.0;
    double a[RAD_HIER_MAX_NODES], b[RAD_HIER_MAX_NODES];
    for (int k = 0; k < h->nodes; k++) {
        rad_vec3 x = rad_geom_triangle_point(e->p[0], e->p[1], e->p[2], h->rs[k], h->rt[k]);
        rad_vec3 d = rad_vec3_sub(x, e->c);
        a[k] = rad_vec3_dot(d, u);
        b[k] = rad_vec3_dot(d, v);
        double w = h->rw[k], f = F[k] - m;
        saa += w * a[k] * a[k];
        sab += w * a[k] * b[k];
        sbb += w * b[k] * b[k];
        saf += w * a[k] * f;
        sbf += w * b[k] * f;
    }
    double det = saa * sbb - sab * sab, al = 0.0, be = 0.0;
    if (det > 1e-12 * (saa * sbb) && h->nodes >= 3) {
        al = (saf * sbb - sbf * sab) / det;
        be = (sbf * saa - saf * sab) / det;
    }
    *g = rad_vec3_add(rad_vec3_scale(u, al), rad_vec3_scale(v, be));
    double res = 0.0;
    for (int k = 0; k < h->nodes; k++)
        res = rad_dmax(res, fabs(F[k] - m - al * a[k] - be * b[k]));
    return res;
}

/* What a job of a split brings from its parent pair (estimate_split): the
 * parent pair's blockers (nb >= 0), from which the job's are filtered, and
 * b's point values towards a (Fb, Fbo; NULL when not given). */
typedef struct link_pre {
    const int *blk;
    int nb;
    const double *Fb, *Fbo;
} link_pre;

/* Estimate the link between elements a and b (both directions); *facing = 0
 * when there is nothing to link.  pre: see link_pre, or NULL.  Reads h only
 * (re-entrant); its work goes to *wc. */
static rad_status estimate(const rad_hier *h, int ia, int ib, int clip, const link_pre *pre,
                           int *facing, hier_link *out, work_count *wc)
{
    const hier_elem *ea = &h->el[ia], *eb = &h->el[ib];
    if (!rad_ff_facing(ea->p, eb->p, &h->p.ff)) {
        *facing = 0;
        return RAD_OK;
    }
    *facing = 1;
    int blk[LINK_MAX_BLOCKERS], nb = 0, too_many = 0, blocked;
    int cap = link_cap(h, clip);
    /* the initial link of two input triangles walks their shaft for its
       blockers and tells the pair table what it found */
    int first = !pre && h->pairs && ia == ea->face && ib == eb->face &&
                !rad_hier_pairs_known(h->pairs, ia, ib);
    if (first) {
        /* from the lower index, as rad_vis_pair_can_block walks it: the
           table's one answer for both orders is the direct test's */
        const hier_elem *lo = ia < ib ? ea : eb, *hi = ia < ib ? eb : ea;
        nb = rad_vis_blockers(h->vis, lo->p, lo->face, hi->p, hi->face, blk, cap);
        blocked = rad_hier_pairs_get(h->pairs, ia, ib, nb != 0) & RAD_HIER_PAIR_CAN_BLOCK;
    } else if (!pre && !h->pairs && h->use_vis && ia == ea->face && ib == eb->face) {
        /* no table (the cluster layer): a pair of input triangles walks its
           shaft once for both answers */
        nb = rad_vis_pair_blockers(h->vis, (size_t)ia, (size_t)ib, blk, cap, &blocked);
    } else {
        blocked = hier_pair_can_block(h, ea->face, eb->face);
        if (blocked && pre && pre->nb >= 0)
            nb = rad_vis_blockers_within(h->vis, ea->p, eb->p, pre->blk, pre->nb, blk);
        else if (blocked)
            nb = rad_vis_blockers(h->vis, ea->p, ea->face, eb->p, eb->face, blk, cap);
    }
    too_many = nb > cap;
    if (too_many)
        nb = 0;
    int far = 0;
    if (!blocked && h->p.far_ratio > 0.0)
        far = rad_vec3_norm(rad_vec3_sub(ea->c, eb->c)) >
              h->p.far_ratio * rad_dmax(ea->size, eb->size);
    double Fa[RAD_HIER_MAX_NODES], Fao[RAD_HIER_MAX_NODES];
    double Fb[RAD_HIER_MAX_NODES], Fbo[RAD_HIER_MAX_NODES];
    int given = blocked && pre && pre->Fb;
    double sampled = 0.0; /* the rays' sampling error of G, where they are used */
    if (given) {
        memcpy(Fb, pre->Fb, (size_t)h->nodes * sizeof *Fb);
        memcpy(Fbo, pre->Fbo, (size_t)h->nodes * sizeof *Fbo);
    }
    if (too_many || !side_values(h, ea, eb, far, blk, nb, Fa, Fao, wc) ||
        (!given && !side_values(h, eb, ea, far, blk, nb, Fb, Fbo, wc))) {
        rad_status st = rad_vis_prepare_rays(h->vis);
        if (st != RAD_OK)
            return st;
        sampled = rad_dmax(side_values_rays(h, ea, eb, Fa, Fao, wc),
                           side_values_rays(h, eb, ea, Fb, Fbo, wc));
    }
    double ma = 0.0, mb = 0.0, mao = 0.0, mbo = 0.0;
    for (int k = 0; k < h->nodes; k++) {
        ma += h->rw[k] * Fa[k];
        mb += h->rw[k] * Fb[k];
        mao += h->rw[k] * Fao[k];
        mbo += h->rw[k] * Fbo[k];
    }
    double Ga = ea->area * ma, Gb = eb->area * mb, Go = 0.5 * (ea->area * mao + eb->area * mbo);
    rad_vec3 ga, gb;
    double ra = linear_fit(h, ea, Fa, ma, &ga), rb = linear_fit(h, eb, Fb, mb, &gb);
    double va = 0.0, vb = 0.0;
    for (int k = 0; k < h->nodes; k++) {
        va = rad_dmax(va, fabs(Fa[k] - ma));
        vb = rad_dmax(vb, fabs(Fb[k] - mb));
    }
    va *= ea->area / eb->area; /* as sources: a's in b's units, b's in a's */
    vb *= eb->area / ea->area;
    /* dG: the two sides' disagreement, and no less than what the better side's
       residual says of its rule (linear functions it integrates exactly; a
       shadow or a peak that both sides miss alike shows in the residuals)
       or than the rays' sampling error */
    /* G: the two sides' estimates, the smaller element's weighted up (a
       rule's error grows like a power of its element's size over the scale
       on which the other element's form factor varies: a small element near
       a large one sees all of it alike, while the large one's few nodes
       miss the small one's narrow peak) */
    double ra2 = ea->area / eb->area, wb = ra2 * ra2 * ra2 * ra2;
    double G = isfinite(wb) ? (Ga + wb * Gb) / (1.0 + wb) : Ga;
    double dG = rad_dmax(0.5 * fabs(Ga - Gb), 0.25 * rad_dmin(ra * ea->area, rb * eb->area));
    dG = rad_dmax(dG, sampled);
    unsigned char vis = 0;
    if (blocked) {
        int all_open = 1, all_hidden = 1;
        for (int k = 0; k < h->nodes; k++) {
            all_open &= Fa[k] == Fao[k] && Fb[k] == Fbo[k];
            all_hidden &= Fa[k] == 0.0 && Fb[k] == 0.0;
        }
        vis = all_open ? 1 : all_hidden ? 3 : 2;
    }
    /* Elements that touch have a kernel singular where they meet, and no
     * point rule's error shrinks as they do.  Their unoccluded G comes from
     * Sauter-Schwab where they share a vertex or an edge (ss:5, about 1e-4;
     * ss:4 beside it gives the error), from the contour-integral reference
     * where one touches the other without a shared vertex (a box standing on
     * a floor), or from an explicit rule; the point values then give the
     * visible fraction only. */
    int map[3], adjacent = 0, contact = 0;
    if (!h->p.use_rule && !far && h->p.singular) {
        adjacent = rad_ff_adjacency_detect(ea->p, eb->p, 1e-9, map) != RAD_FF_DISJOINT;
        contact = !adjacent && hier_pair_may_touch(h, ea->face, eb->face) &&
                  rad_ff_triangles_touch(ea->p, ea->c, ea->size, eb->p, eb->c, eb->size);
    }
    if (h->p.use_rule || adjacent || contact) {
        rad_ff_rule rule = h->p.rule;
        if (adjacent) {
            rule.scheme = RAD_FF_SS;
            rule.order = 5;
        } else if (contact) {
            rule.scheme = RAD_FF_EXACT;
            rule.order = 0;
        }
        /* an explicit rule keeps the caller's tolerances; the singular
           rules are needed to the link's accuracy only, and the memo gives
           a pair the value of an earlier one equal up to translation and
           scale (subdivision repeats them) */
        rad_ff_result res, low;
        rad_status st = h->p.use_rule ? rad_ff_compute(ea->p, eb->p, rule, &h->p.ff, &res)
                                      : rad_hier_memo_compute(h->memo, ea->p, eb->p, rule, &res);
        if (st == RAD_OK && adjacent) {
            rule.order = 4;
            st = rad_hier_memo_compute(h->memo, ea->p, eb->p, rule, &low);
            wc->evals += low.evals;
        }
        if (st != RAD_OK)
            return st;
        wc->evals += res.evals;
        double V = vis == 0 ? 1.0 : Go > 0.0 ? G / Go : 0.0;
        G = res.G * V;
        dG = adjacent ? fabs(res.G - low.G) * V
                      : isfinite(res.rel_error) ? res.rel_error * G : 0.0;
    }
    if (!isfinite(G) || !(G >= 0.0) || !isfinite(dG) || !isfinite(ra) || !isfinite(rb))
        return RAD_ERROR(RAD_ENUMERIC, "hier: form factor of elements %d, %d is not finite", ia,
                         ib);
    /* each side's linear function G / A + g (x - c) must not go negative on it */
    const hier_elem *side[2] = {ea, eb};
    rad_vec3 *grad[2] = {&ga, &gb};
    for (int t = 0; t < 2; t++) {
        double F = G / side[t]->area, low = 0.0;
        for (int v = 0; v < 3; v++)
            low = rad_dmin(low, rad_vec3_dot(*grad[t], rad_vec3_sub(side[t]->p[v], side[t]->c)));
        if (F + low < 0.0)
            *grad[t] = rad_vec3_scale(*grad[t], low < 0.0 ? F / -low : 0.0);
    }
    out->a = ia;
    out->b = ib;
    out->G = G;
    out->ga = ga;
    out->gb = gb;
    out->dG = dG;
    out->ra = ra;
    out->rb = rb;
    out->va = va;
    out->vb = vb;
    out->vis = vis;
    out->clip = (unsigned char)clip;
    out->sampled = (unsigned char)too_many;
    /* A pair that faces but whose point values are all 0 straddles a plane;
     * what it carries is unknown, so it is refined while it can be. */
    out->unknown = !(G > 0.0) && vis != 3;
    return RAD_OK;
}

/* The four jobs of a split, (child i of one element, the same other end b):
 * the parent pair's blockers are found once and each child pair's filtered
 * from them, and each of b's nodes clips the parent once for all four
 * children (rad_vis_split_values), where estimating the jobs one by one
 * would clip each child. */
static void estimate_split(const rad_hier *h, const hier_job *job, rad_status *st, int *facing,
                           hier_link *out, work_count *wc)
{
    const hier_elem *eo = &h->el[job[0].b], *ep = &h->el[h->el[job[0].a].parent];
    int blk[LINK_MAX_BLOCKERS], nb = -1, have = 0;
    double F[4][RAD_HIER_MAX_NODES], Fo[4][RAD_HIER_MAX_NODES];
    if (hier_pair_can_block(h, ep->face, eo->face)) {
        rad_vec3 y[RAD_HIER_MAX_NODES], parts[12];
        for (int k = 0; k < h->nodes; k++)
            y[k] = rad_geom_triangle_point(eo->p[0], eo->p[1], eo->p[2], h->rs[k], h->rt[k]);
        for (int i = 0; i < 4; i++)
            memcpy(parts + 3 * i, h->el[job[i].a].p, 3 * sizeof *parts);
        long ev = 0;
        have = rad_vis_split_values(h->vis, eo->p, eo->face, y, h->nodes, h->normal[eo->face], ep->p,
                                    ep->face, parts, blk, link_cap(h, job[0].clip),
                                    &nb, RAD_VIS_LINK_POINT_WORK, F[0], Fo[0], RAD_HIER_MAX_NODES,
                                    &ev);
        wc->evals += ev;
    }
    for (int i = 0; i < 4; i++) {
        link_pre pre = {blk, nb, have ? F[i] : NULL, have ? Fo[i] : NULL};
        st[i] = estimate(h, job[i].a, job[i].b, job[i].clip, nb >= 0 ? &pre : NULL, &facing[i],
                         &out[i], wc);
    }
}

rad_status hier_estimate_batch(rad_hier *h, const hier_job *jobs, size_t n, int splits)
{
    if (n == 0)
        return RAD_OK;
    double t0 = rad_sys_seconds();
    rad_status st = hier_reserve_links(h, n);
    unsigned char *ok = st == RAD_OK ? malloc(n) : NULL;
    if (!ok)
        return st != RAD_OK ? st
                            : RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu link estimates", n);
    long long evals = 0, failed = -1;
    unsigned long long rays = 0;
    const rad_hier *hc = h;
    hier_link *out = h->ln + h->nln;
    int threads = hier_threads(h);
    /* shared among processes: this one estimates its share, then every
       process gets every slot and flag (exchange.c) */
    size_t first, step;
    hier_share(h, &first, &step);
    /* a refinement's batch comes in splits of four jobs: estimated a split at
       a time (estimate_split), the unit of the threads' and processes' shares */
    size_t unit = splits ? 4 : 1, units = n / unit;
    int chunk = (int)(4 / unit);
#pragma omp parallel for schedule(dynamic, chunk) reduction(+ : evals, rays) if (n / step > 4) num_threads(threads)
    for (long long u = (long long)first; u < (long long)units; u += (long long)step) {
        work_count wc = {0, 0};
        int facing[4] = {0, 0, 0, 0};
        rad_status est[4];
        size_t k = (size_t)u * unit;
        if (unit == 4)
            estimate_split(hc, jobs + k, est, facing, out + k, &wc);
        else
            est[0] = estimate(hc, jobs[k].a, jobs[k].b, jobs[k].clip, NULL, &facing[0], &out[k],
                              &wc);
        evals += wc.evals;
        rays += wc.rays;
        for (size_t i = 0; i < unit; i++)
            ok[k + i] = est[i] == RAD_OK ? (unsigned char)(facing[i] ? 1 : 0) : 2;
    }
    if (hier_shared(h) && ((st = hier_share_gather(h, out, unit * sizeof *out, units)) != RAD_OK ||
                           (st = hier_share_gather(h, ok, unit, units)) != RAD_OK ||
                           (st = hier_share_work(h, &evals, &rays)) != RAD_OK)) {
        free(ok);
        return st;
    }
    h->st.kernel_evals += evals;
    h->st.rays += rays;
    h->st.time_estimate_element_s += rad_sys_seconds() - t0;
    size_t w = h->nln;
    for (size_t k = 0; k < n; k++) {
        if (ok[k] == 2) {
            failed = (long long)k;
            break;
        }
        if (ok[k] == 1)
            h->ln[w++] = out[k]; /* w <= nln + k: never overwrites an unread slot */
    }
    free(ok);
    if (failed >= 0) {
        /* estimated again on this thread, so that its (thread-local) message is the
           caller's (and every process's: the estimate is the same everywhere) */
        work_count wc = {0, 0};
        int facing = 0;
        hier_link l;
        st = estimate(h, jobs[failed].a, jobs[failed].b, jobs[failed].clip, NULL, &facing, &l,
                      &wc);
        if (st == RAD_OK)
            st = RAD_ERROR(RAD_ENUMERIC, "hier: link %d, %d failed on a worker thread",
                           jobs[failed].a, jobs[failed].b);
        return st;
    }
    h->nln = w;
    return RAD_OK;
}
