/* rad_hierp: a link's couplings and its errors.
 *
 * On elements a and b, the nodes x_i and y_j of one symmetric rule (degree
 * 2 order + 2 or more, weights w summing to 1; q_k the basis at the nodes):
 *
 * 1. Point form factors over the visible part, in closed form (rad_vis_point
 *    _visible, or rad_ff_point_polygon where nothing can block): F_i =
 *    F(x_i, b) and G_j = F(y_j, a).  In a closed scene a point's visible form
 *    factors sum to 1, so the constants' couplings conserve energy.  For a
 *    far pair that nothing can block, the product rule of the kernel below
 *    gives them instead (the kernel is smooth there).
 * 2. The kernel at every node pair, k_ij V_ij; V_ij = 1 where x_i sees all of
 *    b or y_j all of a, 0 where either sees none of it, else whether the
 *    segment crosses one of the pair's blockers (the only triangles that
 *    can: rad_vis_segment_blocked_by, exact, no Embree); an Embree ray per
 *    node pair where the blockers are too many to list or clip.
 * 3. The couplings (phi = q / sqrt(A)):
 *      K_00 = G / sqrt(A_a A_b), G the two sides' estimates A_a sum w F and
 *      A_b sum w G weighted towards the smaller element (rad_hier's rule),
 *      K_k0 = sqrt(A_a / A_b) sum_i w_i q_k(x_i) F_i, K_0l likewise from b,
 *      K_kl = sqrt(A_a A_b) sum_ij w_i w_j q_k(x_i) q_l(y_j) k_ij V_ij.
 *    The rows and columns that meet a constant come from the closed forms,
 *    the rest from the product rule.  Elements that touch take their
 *    unoccluded G from the singular rules (ss:5 where they share a vertex or
 *    an edge, the exact contour integral where one touches the other),
 *    times the visible fraction of the point values, as rad_hier's links.
 * 4. The errors (hp_link): dG, half the two sides' disagreement and no less
 *    than a quarter of the smaller of A_a f_a and A_b f_b (where elements
 *    touch: ss:5 against ss:4 or the contour integral's own error, and no
 *    less than the node values' miss of the singular rule); f_a, the
 *    largest departure of F_i from its projection on a's functions, and
 *    f_a1 its mean; k_a, the mean over i of A_b times the mean over j of
 *    the kernel's departure from its projection on b's functions (k_ma
 *    the largest over i); and the same seen from b.
 * Estimates only read the hierarchy, so a batch runs in parallel (OpenMP),
 * each job into its own slot: the result does not depend on the thread count. */
#include "hierp_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "rad_ff.h"
#include "rad_sys.h"

enum { LINK_MAX_BLOCKERS = 256 };

typedef struct work_count {
    long long evals;
    unsigned long long rays;
} work_count;

static int pair_can_block(const rad_hierp *h, int r, int s)
{
    if (!h->use_vis)
        return 0;
    if (h->pairs)
        return rad_hier_pairs_get(h->pairs, r, s, -1) & RAD_HIER_PAIR_CAN_BLOCK;
    return rad_vis_pair_can_block(h->vis, (size_t)r, (size_t)s);
}

/* 0 when no element of input triangle r can touch one of s. */
static int pair_may_touch(const rad_hierp *h, int r, int s)
{
    return !h->pairs || (rad_hier_pairs_get(h->pairs, r, s, -1) & RAD_HIER_PAIR_MAY_TOUCH);
}

static rad_vec3 node(const rad_hierp *h, const hp_elem *e, int i)
{
    return rad_geom_triangle_point(e->p[0], e->p[1], e->p[2], h->rs[i], h->rt[i]);
}

/* How far values v[i] at the nodes depart from their projection on the
 * basis (the fit whose coefficients are the rule's moments): the largest
 * departure, and (*mean) its mean over the nodes; m a constant at each call
 * (departure) so that the loops over the basis unroll. */
static inline double departure_m(const rad_hierp *h, const double *v, double *mean, const int m)
{
    double c[HP_M] = {0};
    for (int i = 0; i < h->nodes; i++) {
        double wv = h->rw[i] * v[i];
        for (int k = 0; k < m; k++)
            c[k] += wv * h->rq[i][k];
    }
    double d = 0.0, sum = 0.0;
    for (int i = 0; i < h->nodes; i++) {
        double f = 0.0;
        for (int k = 0; k < m; k++)
            f += c[k] * h->rq[i][k];
        double r = fabs(v[i] - f);
        d = rad_dmax(d, r);
        sum += h->rw[i] * r;
    }
    *mean = sum;
    return d;
}

static double departure(const rad_hierp *h, const double *v, double *mean)
{
    switch (h->m) {
    case 1: return departure_m(h, v, mean, 1);
    case 3: return departure_m(h, v, mean, 3);
    default: return departure_m(h, v, mean, HP_M);
    }
}

/* Point form factors from the nodes of e to t: F[i] and the unoccluded
 * Fo[i]; 0 when a visible part was too complex to clip. */
static int side_values(const rad_hierp *h, const hp_elem *e, const hp_elem *t, const int *blk,
                       int nb, double *F, double *Fo, work_count *wc)
{
    rad_vec3 ne = h->normal[e->face];
    for (int i = 0; i < h->nodes; i++) {
        rad_vec3 x = node(h, e, i);
        if (nb == 0) {
            F[i] = Fo[i] = rad_ff_point_polygon(x, ne, t->p, 3);
            wc->evals++;
        } else {
            long ev = 0;
            int ok = rad_vis_point_visible_limited(h->vis, x, ne, t->p, blk, nb,
                                                   RAD_VIS_LINK_POINT_WORK, &F[i], &Fo[i], &ev);
            wc->evals += ev;
            if (!ok)
                return 0;
        }
    }
    return 1;
}

static int ray_open(const rad_hierp *h, rad_vec3 x, rad_vec3 y, int fa, int fb, work_count *wc)
{
    double p[3] = {x.x, x.y, x.z}, q[3] = {y.x, y.y, y.z};
    wc->rays++;
    return !rad_vis_segment_blocked(h->vis, p, q, fa, fb);
}

/* What a job of a split brings from its parent pair (estimate_split): the
 * parent pair's blockers (nb >= 0), from which the job's are filtered, and
 * b's point values towards a (Fb, Fbo; NULL when not given). */
typedef struct link_pre {
    const int *blk;
    int nb;
    const double *Fb, *Fbo;
} link_pre;

static rad_status estimate(const rad_hierp *h, int ia, int ib, const link_pre *pre, int *facing,
                           hp_link *out, double *K, work_count *wc)
{
    const hp_elem *ea = &h->el[ia], *eb = &h->el[ib];
    if (!rad_ff_facing(ea->p, eb->p, &h->p.ff)) {
        *facing = 0;
        return RAD_OK;
    }
    *facing = 1;
    int n = h->nodes, m = h->m;
    int blk[LINK_MAX_BLOCKERS], nb = 0, too_many = 0;
    /* the initial link of two input triangles walks their shaft for its
       blockers and tells the pair table what it found */
    int first = !pre && h->pairs && ia == ea->face && ib == eb->face &&
                !rad_hier_pairs_known(h->pairs, ia, ib);
    int blocked = first || pair_can_block(h, ea->face, eb->face);
    if (blocked && pre && pre->nb >= 0) {
        nb = rad_vis_blockers_within(h->vis, ea->p, eb->p, pre->blk, pre->nb, blk);
        blocked = nb > 0;
    } else if (blocked) {
        nb = rad_vis_blockers(h->vis, ea->p, ea->face, eb->p, eb->face, blk, LINK_MAX_BLOCKERS);
        if (first)
            rad_hier_pairs_get(h->pairs, ia, ib, nb != 0);
        too_many = nb > LINK_MAX_BLOCKERS;
        if (too_many)
            nb = 0;
        blocked = too_many || nb > 0;
    }
    int far = !blocked && h->p.far_ratio > 0.0 &&
              rad_vec3_norm(rad_vec3_sub(ea->c, eb->c)) >
                  h->p.far_ratio * rad_dmax(ea->size, eb->size);
    rad_vec3 na = h->normal[ea->face], nbn = h->normal[eb->face];
    rad_vec3 x[HP_MAX_NODES], y[HP_MAX_NODES];
    for (int i = 0; i < n; i++) {
        x[i] = node(h, ea, i);
        y[i] = node(h, eb, i);
    }
    /* the kernel at every node pair */
    double kv[HP_MAX_NODES][HP_MAX_NODES];
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            kv[i][j] = rad_ff_kernel(x[i], na, y[j], nbn, NULL);
    wc->evals += (long long)n * n;
    double Fa[HP_MAX_NODES], Fao[HP_MAX_NODES], Fb[HP_MAX_NODES], Fbo[HP_MAX_NODES];
    if (far) {
        for (int i = 0; i < n; i++) {
            double sa = 0.0, sb = 0.0;
            for (int j = 0; j < n; j++) {
                sa += h->rw[j] * kv[i][j];
                sb += h->rw[j] * kv[j][i];
            }
            Fa[i] = Fao[i] = eb->area * sa;
            Fb[i] = Fbo[i] = ea->area * sb;
        }
    } else if (too_many || !side_values(h, ea, eb, blk, nb, Fa, Fao, wc)) {
        too_many = 1;
    } else if (blocked && pre && pre->Fb) {
        memcpy(Fb, pre->Fb, (size_t)n * sizeof *Fb);
        memcpy(Fbo, pre->Fbo, (size_t)n * sizeof *Fbo);
    } else if (!side_values(h, eb, ea, blk, nb, Fb, Fbo, wc)) {
        too_many = 1;
    }
    /* visibility of the node pairs */
    if (too_many) {
        rad_status st = rad_vis_prepare_rays(h->vis);
        if (st != RAD_OK)
            return st;
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                if (kv[i][j] > 0.0 && !ray_open(h, x[i], y[j], ea->face, eb->face, wc))
                    kv[i][j] = 0.0;
        for (int i = 0; i < n; i++) {
            double sa = 0.0, sb = 0.0, oa = 0.0, ob = 0.0;
            for (int j = 0; j < n; j++) {
                sa += h->rw[j] * kv[i][j];
                sb += h->rw[j] * kv[j][i];
            }
            oa = rad_ff_point_polygon(x[i], na, eb->p, 3);
            ob = rad_ff_point_polygon(y[i], nbn, ea->p, 3);
            Fa[i] = eb->area * sa;
            Fb[i] = ea->area * sb;
            Fao[i] = oa;
            Fbo[i] = ob;
        }
        wc->evals += 2 * n;
    } else if (blocked) {
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                if (kv[i][j] == 0.0 || Fa[i] == Fao[i] || Fb[j] == Fbo[j])
                    continue;
                /* the segment lies in the pair's shaft: only its blockers can cross it */
                if (Fa[i] == 0.0 || Fb[j] == 0.0 ||
                    rad_vis_segment_blocked_by(h->vis, x[i], y[j], blk, nb))
                    kv[i][j] = 0.0;
            }
    }
    double ma = 0.0, mb = 0.0, mao = 0.0, mbo = 0.0;
    for (int i = 0; i < n; i++) {
        ma += h->rw[i] * Fa[i];
        mb += h->rw[i] * Fb[i];
        mao += h->rw[i] * Fao[i];
        mbo += h->rw[i] * Fbo[i];
    }
    double Ga = ea->area * ma, Gb = eb->area * mb, Go = 0.5 * (ea->area * mao + eb->area * mbo);
    double ra2 = ea->area / eb->area, wb = ra2 * ra2 * ra2 * ra2;
    double G = isfinite(wb) ? (Ga + wb * Gb) / (1.0 + wb) : Ga;
    /* dG: the two sides' disagreement, and no less than a quarter of the
       better side's departure from its projection (times its area): a
       shadow or a peak that both sides' rules miss alike, as between two
       congruent elements facing each other across a gap, shows there (as
       rad_hier's floor on the residual of its linear fit) */
    double fa1, fb1, fa = departure(h, Fa, &fa1), fb = departure(h, Fb, &fb1);
    double dG = rad_dmax(0.5 * fabs(Ga - Gb), 0.25 * rad_dmin(fa * ea->area, fb * eb->area));
    unsigned char vis = 0;
    if (blocked) {
        int all_open = 1, all_hidden = 1;
        for (int i = 0; i < n; i++) {
            all_open &= Fa[i] == Fao[i] && Fb[i] == Fbo[i];
            all_hidden &= Fa[i] == 0.0 && Fb[i] == 0.0;
        }
        vis = all_open ? 1 : all_hidden ? 3 : 2;
    }
    /* touching elements: the singular rules for the unoccluded G */
    int map[3], adjacent = 0, contact = 0;
    if (!far && h->p.singular) {
        adjacent = rad_ff_adjacency_detect(ea->p, eb->p, 1e-9, map) != RAD_FF_DISJOINT;
        contact = !adjacent && pair_may_touch(h, ea->face, eb->face) &&
                  rad_ff_triangles_touch(ea->p, ea->c, ea->size, eb->p, eb->c, eb->size);
    }
    if (adjacent || contact) {
        rad_ff_rule rule = {adjacent ? RAD_FF_SS : RAD_FF_EXACT, adjacent ? 5 : 0};
        rad_ff_result res, low;
        rad_status st = rad_hier_memo_compute(h->memo, ea->p, eb->p, rule, &res);
        if (st == RAD_OK && adjacent) {
            rule.order = 4;
            st = rad_hier_memo_compute(h->memo, ea->p, eb->p, rule, &low);
            wc->evals += low.evals;
        }
        if (st != RAD_OK)
            return st;
        wc->evals += res.evals;
        double V = vis == 0 ? 1.0 : Go > 0.0 ? G / Go : 0.0, G_nodes = G;
        G = res.G * V;
        dG = adjacent ? fabs(res.G - low.G) * V
                      : isfinite(res.rel_error) ? res.rel_error * G : 0.0;
        /* the node values still give the link's other couplings and its
           departures: how far their G misses the singular rule's is how
           badly they resolve the pair, and is charged as its error */
        dG = rad_dmax(dG, fabs(G - G_nodes));
    }
    /* the couplings */
    double sa = sqrt(ea->area), sb = sqrt(eb->area);
    memset(K, 0, (size_t)(m * m) * sizeof *K);
    K[0] = G / (sa * sb);
    for (int k = 1; k < m; k++) {
        double ck = 0.0, cl = 0.0;
        for (int i = 0; i < n; i++) {
            ck += h->rw[i] * h->rq[i][k] * Fa[i];
            cl += h->rw[i] * h->rq[i][k] * Fb[i];
        }
        /* each side's moments scaled to the G taken (one side's values, or
           the singular rule's): a's column is a's quadrature of F(x, b)
           q_k and b's row b's of F(y, a) q_l, so the mean a nonnegative
           source brings stays a positive sum over the nodes */
        K[k * m] = Ga > 0.0 ? sa / sb * ck * (G / Ga) : 0.0;
        K[k] = Gb > 0.0 ? sb / sa * cl * (G / Gb) : 0.0;
    }
    /* a close pair's product rule is not to be trusted (the kernel peaks
       between its nodes): its functions couple through the rows and columns
       above only, and what that leaves out is its departure terms' */
    int close = rad_vec3_norm(rad_vec3_sub(ea->c, eb->c)) <= ea->size + eb->size;
    if (m > 1 && !close) {
        double wk[HP_MAX_NODES][HP_M]; /* sum_j w_j kv_ij q_l(y_j) */
        for (int i = 0; i < n; i++)
            for (int l = 1; l < m; l++) {
                double s = 0.0;
                for (int j = 0; j < n; j++)
                    s += h->rw[j] * kv[i][j] * h->rq[j][l];
                wk[i][l] = s;
            }
        for (int k = 1; k < m; k++)
            for (int l = 1; l < m; l++) {
                double s = 0.0;
                for (int i = 0; i < n; i++)
                    s += h->rw[i] * h->rq[i][k] * wk[i][l];
                /* |phi_k| <= qmax_k / sqrt(A) and k V >= 0: the true coupling
                   lies within qmax_k qmax_l K_00, where a product rule on a
                   near pair may not */
                double cap = h->qmax[k] * h->qmax[l] * K[0];
                K[k * m + l] = rad_dmax(-cap, rad_dmin(cap, sa * sb * s));
            }
    }
    for (int k = 1; k < m; k++) {
        double cap = h->qmax[k] * K[0];
        K[k * m] = rad_dmax(-cap, rad_dmin(cap, K[k * m]));
        K[k] = rad_dmax(-cap, rad_dmin(cap, K[k]));
    }
    /* the errors */
    double ka = 0.0, kb = 0.0, kma = 0.0, kmb = 0.0;
    for (int i = 0; i < n; i++) {
        double row[HP_MAX_NODES], col[HP_MAX_NODES], ra, rb;
        for (int j = 0; j < n; j++) {
            row[j] = kv[i][j];
            col[j] = kv[j][i];
        }
        departure(h, row, &ra);
        departure(h, col, &rb);
        ra *= eb->area;
        rb *= ea->area;
        ka += h->rw[i] * ra;
        kb += h->rw[i] * rb;
        kma = rad_dmax(kma, ra);
        kmb = rad_dmax(kmb, rb);
    }
    if (!isfinite(G) || !(G >= 0.0) || !isfinite(dG) || !isfinite(fa) || !isfinite(fb) ||
        !isfinite(ka) || !isfinite(kb))
        return RAD_ERROR(RAD_ENUMERIC, "hier: couplings of elements %d, %d are not finite", ia,
                         ib);
    for (int k = 0; k < m * m; k++)
        if (!isfinite(K[k]))
            return RAD_ERROR(RAD_ENUMERIC, "hier: couplings of elements %d, %d are not finite",
                             ia, ib);
    out->a = ia;
    out->b = ib;
    out->G = G;
    out->dG = dG;
    out->fa = fa;
    out->fb = fb;
    out->fa1 = fa1;
    out->fb1 = fb1;
    out->ka = ka;
    out->kb = kb;
    out->kma = kma;
    out->kmb = kmb;
    out->vis = vis;
    out->unknown = !(G > 0.0) && vis != 3;
    out->constant = 0;
    return RAD_OK;
}

/* The four jobs of a split, (child i of one element, the same other end b):
 * the parent pair's blockers are found once and each child pair's filtered
 * from them, and each of b's nodes clips the parent once for all four
 * children (rad_vis_split_values). */
static void estimate_split(const rad_hierp *h, const hp_job *job, rad_status *st, int *facing,
                           hp_link *out, double *K, size_t mm, work_count *wc)
{
    const hp_elem *eo = &h->el[job[0].b], *ep = &h->el[h->el[job[0].a].parent];
    int blk[LINK_MAX_BLOCKERS], nb = -1, have = 0;
    double F[4][HP_MAX_NODES], Fo[4][HP_MAX_NODES];
    if (pair_can_block(h, ep->face, eo->face)) {
        rad_vec3 y[HP_MAX_NODES], parts[12];
        for (int k = 0; k < h->nodes; k++)
            y[k] = node(h, eo, k);
        for (int i = 0; i < 4; i++)
            memcpy(parts + 3 * i, h->el[job[i].a].p, 3 * sizeof *parts);
        long ev = 0;
        have = rad_vis_split_values(h->vis, eo->p, eo->face, y, h->nodes, h->normal[eo->face], ep->p,
                                    ep->face, parts, blk, LINK_MAX_BLOCKERS,
                                    &nb, RAD_VIS_LINK_POINT_WORK, F[0], Fo[0], HP_MAX_NODES, &ev);
        wc->evals += ev;
    }
    for (int i = 0; i < 4; i++) {
        link_pre pre = {blk, nb, have ? F[i] : NULL, have ? Fo[i] : NULL};
        st[i] = estimate(h, job[i].a, job[i].b, nb >= 0 ? &pre : NULL, &facing[i], &out[i],
                         K + (size_t)i * mm, wc);
    }
}

rad_status hp_estimate_batch(rad_hierp *h, const hp_job *jobs, size_t n, int splits)
{
    if (n == 0)
        return RAD_OK;
    double t0 = rad_sys_seconds();
    rad_status st = hp_reserve_links(h, n);
    unsigned char *ok = st == RAD_OK ? malloc(n) : NULL;
    if (!ok)
        return st != RAD_OK ? st
                            : RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu link estimates", n);
    long long evals = 0, failed = -1;
    unsigned long long rays = 0;
    const rad_hierp *hc = h;
    size_t mm = (size_t)(h->m * h->m);
    hp_link *out = h->ln + h->nln;
    double *Kout = h->K + h->nln * mm;
    int threads = h->p.threads > 0 ? h->p.threads : omp_get_max_threads();
    /* a refinement's batch comes in splits of four jobs: estimated a split at
       a time (estimate_split) */
    size_t unit = splits ? 4 : 1;
    long long units = (long long)(n / unit);
    int chunk = (int)(4 / unit);
#pragma omp parallel for schedule(dynamic, chunk) reduction(+ : evals, rays) if (n > 4) num_threads(threads)
    for (long long u = 0; u < units; u++) {
        work_count wc = {0, 0};
        int facing[4] = {0, 0, 0, 0};
        rad_status est[4];
        size_t k = (size_t)u * unit;
        if (unit == 4)
            estimate_split(hc, jobs + k, est, facing, out + k, Kout + k * mm, mm, &wc);
        else
            est[0] = estimate(hc, jobs[k].a, jobs[k].b, NULL, &facing[0], &out[k],
                              Kout + k * mm, &wc);
        evals += wc.evals;
        rays += wc.rays;
        for (size_t i = 0; i < unit; i++)
            ok[k + i] = est[i] == RAD_OK ? (unsigned char)(facing[i] ? 1 : 0) : 2;
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
        if (ok[k] == 1) {
            h->ln[w] = out[k]; /* w <= nln + k: never overwrites an unread slot */
            if (h->K + w * mm != Kout + k * mm)
                memmove(h->K + w * mm, Kout + k * mm, mm * sizeof *h->K);
            w++;
        }
    }
    free(ok);
    if (failed >= 0) {
        work_count wc = {0, 0};
        int facing = 0;
        hp_link l;
        double Kl[HP_M * HP_M];
        st = estimate(h, jobs[failed].a, jobs[failed].b, NULL, &facing, &l, Kl, &wc);
        if (st == RAD_OK)
            st = RAD_ERROR(RAD_ENUMERIC, "hier: link %d, %d failed on a worker thread",
                           jobs[failed].a, jobs[failed].b);
        return st;
    }
    h->nln = w;
    return RAD_OK;
}
