/* rad_hierp: the element tree, creation, the push matrices and the read-out.
 *
 * Elements live in one growing array and refer to each other by index; an
 * element's four children are contiguous, made by rad_hier's midpoint split
 * (a m_ab m_ca, m_ab b m_bc, m_ca m_bc c, and the middle m_ab m_bc m_ca, all
 * with the parent's orientation and corner 0 first), and start with the
 * parent's radiosity restricted to them.  A child's local coordinates are an
 * affine image of its parent's, the same on every triangle, so the
 * restriction of the parent's basis to child c is one matrix P[c] for the
 * whole scene: P[c]_lk = int_child phi_k phi^c_l = 1/2 mean_child(q_k q^c_l)
 * (computed once, by a rule exact for the products). */
#include "hierp_internal.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rad_ff.h"
#include "rad_quad.h"
#include "rad_sys.h"

/* the children's corners in the parent's local (s, t) */
static const double child_st[4][3][2] = {{{0.0, 0.0}, {0.5, 0.0}, {0.0, 0.5}},
                                         {{0.5, 0.0}, {1.0, 0.0}, {0.5, 0.5}},
                                         {{0.0, 0.5}, {0.5, 0.5}, {0.0, 1.0}},
                                         {{0.5, 0.0}, {0.5, 0.5}, {0.0, 0.5}}};

static void push_matrices(rad_hierp *h)
{
    double s[RAD_QUAD_TRI_MAX_POINTS], t[RAD_QUAD_TRI_MAX_POINTS], w[RAD_QUAD_TRI_MAX_POINTS];
    int n = 0;
    rad_quad_tri_symmetric(2 * RAD_BASIS_MAX_ORDER, s, t, w, &n);
    double wsum = 0.0;
    for (int i = 0; i < n; i++)
        wsum += w[i];
    memset(h->P, 0, sizeof h->P);
    for (int c = 0; c < 4; c++) {
        const double(*k)[2] = child_st[c];
        for (int i = 0; i < n; i++) {
            double ps = k[0][0] + s[i] * (k[1][0] - k[0][0]) + t[i] * (k[2][0] - k[0][0]);
            double pt = k[0][1] + s[i] * (k[1][1] - k[0][1]) + t[i] * (k[2][1] - k[0][1]);
            double qp[HP_M], qc[HP_M];
            rad_basis_eval(RAD_BASIS_MAX_ORDER, ps, pt, qp);
            rad_basis_eval(RAD_BASIS_MAX_ORDER, s[i], t[i], qc);
            for (int l = 0; l < HP_M; l++)
                for (int m = 0; m < HP_M; m++)
                    h->P[c][l][m] += 0.5 * w[i] / wsum * qp[m] * qc[l];
        }
    }
    /* the largest |q_k| over the triangle, on a fine lattice (the functions
       are quadratics: their extremes on it are within a few percent) */
    memset(h->qmax, 0, sizeof h->qmax);
    enum { LATTICE = 24 };
    for (int i = 0; i <= LATTICE; i++)
        for (int j = 0; i + j <= LATTICE; j++) {
            double q[HP_M];
            rad_basis_eval(RAD_BASIS_MAX_ORDER, (double)i / LATTICE, (double)j / LATTICE, q);
            for (int k = 0; k < HP_M; k++)
                h->qmax[k] = rad_dmax(h->qmax[k], fabs(q[k]));
        }
}

double hp_poly_bound(const rad_hierp *h, const double *v, double area)
{
    double b = 0.0;
    for (int k = 0; k < h->m; k++)
        b += fabs(v[k]) * h->qmax[k];
    return area > 0.0 ? b / sqrt(area) : 0.0;
}

void hp_bound_B(rad_hierp *h)
{
    for (size_t e = 0; e < h->nel; e++)
        for (int c = 0; c < 3; c++)
            h->el[e].Bmax[c] = hp_poly_bound(h, h->el[e].B[c], h->el[e].area);
}

/* Refuse more of what the machine cannot hold (hier/memory.c's check, for
 * this solver's arrays: each link with its K and the two ends the solve
 * lists for it, each element with the solve's rows of its coefficients
 * (Bs and the watch's copy); where the array must grow, rad_sys_grow
 * copies what it holds into the new block before it frees the old one, so
 * the items already made count again). */
static rad_status hp_memory_check(const rad_hierp *h, double bytes, const char *what, size_t more)
{
    double would, have;
    if (rad_sys_memory_allows(bytes, &would, &have))
        return RAD_OK;
    const double gib = 1024.0 * 1024.0 * 1024.0;
    return RAD_ERROR(RAD_ETOOBIG,
                     "hier: %zu more %s would take the process to %.3g GiB, more than %.0f%% of "
                     "this machine's %.3g GiB (RADKIT_MEMORY_LIMIT sets it), with %zu links and "
                     "%zu elements made so far; raise --eps, use a lower --basis or fewer "
                     "triangles", more, what, would / gib, 100.0 * RAD_SYS_MEMORY_SHARE, have / gib, h->nln,
                     h->nel);
}

rad_status hp_grow_elems(rad_hierp *h, size_t extra)
{
    if (h->nel + extra > h->p.max_elements)
        return RAD_ERROR(RAD_ETOOBIG, "hier: more than %zu elements (max_elements): raise --eps "
                                      "or --min-area, or use fewer triangles", h->p.max_elements);
    rad_status st;
    if (h->nel + extra > h->capel &&
        (st = hp_memory_check(h,
                              (double)h->nel * sizeof *h->el +
                                  (double)(h->nel + extra - h->capel) *
                                      (sizeof *h->el + (6 * HP_M + 3) * sizeof *h->Bs +
                                       sizeof *h->inc_start),
                              "elements", h->nel + extra - h->capel)) != RAD_OK)
        return st;
    if (!rad_sys_grow((void **)&h->el, &h->capel, h->nel, h->nel + extra, sizeof *h->el, 64))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu elements", h->nel + extra);
    return RAD_OK;
}

rad_status hp_reserve_links(rad_hierp *h, size_t extra)
{
    if (h->nln + extra > h->p.max_links)
        return RAD_ERROR(RAD_ETOOBIG, "hier: more than %zu links (max_links, --max-links): "
                                      "raise --eps or --min-area, raise --max-links if the "
                                      "machine has the memory, or use fewer triangles", h->p.max_links);
    size_t cap = h->capln, mm = (size_t)(h->m * h->m);
    double per_link = (double)(sizeof *h->ln + mm * sizeof *h->K +
                               2 * (sizeof *h->inc + sizeof *h->inc_src));
    size_t counted = h->nln + extra > h->capln ? h->nln + extra : extra; /* a copy when grown */
    rad_status st = hp_memory_check(h, (double)counted * per_link, "links", extra);
    if (st != RAD_OK)
        return st;
    if (!rad_sys_grow((void **)&h->ln, &h->capln, h->nln, h->nln + extra, sizeof *h->ln, 256))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu links", h->nln + extra);
    if (!rad_sys_grow((void **)&h->K, &cap, h->nln, h->capln, mm * sizeof *h->K, 256))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu links", h->nln + extra);
    return RAD_OK;
}

int hp_can_split(const rad_hierp *h, int e)
{
    const hp_elem *x = &h->el[e];
    return x->depth < h->p.max_depth && 0.25 * x->area >= h->p.min_area;
}

rad_status hp_split(rad_hierp *h, int e)
{
    if (h->el[e].first_child >= 0)
        return RAD_OK;
    rad_status st = hp_grow_elems(h, 4);
    if (st != RAD_OK)
        return st;
    hp_elem *x = &h->el[e];
    rad_vec3 mid[3];
    for (int v = 0; v < 3; v++)
        mid[v] = rad_vec3_scale(rad_vec3_add(x->p[v], x->p[(v + 1) % 3]), 0.5);
    /* m_ab = mid[0], m_bc = mid[1], m_ca = mid[2] */
    const rad_vec3 corners[4][3] = {{x->p[0], mid[0], mid[2]},
                                    {mid[0], x->p[1], mid[1]},
                                    {mid[2], mid[1], x->p[2]},
                                    {mid[0], mid[1], mid[2]}};
    int first = (int)h->nel;
    for (int c = 0; c < 4; c++) {
        hp_elem *y = &h->el[h->nel++];
        memset(y, 0, sizeof *y);
        memcpy(y->p, corners[c], sizeof y->p);
        y->c = rad_geom_triangle_centroid(y->p[0], y->p[1], y->p[2]);
        y->area = 0.25 * x->area;
        y->size = rad_geom_triangle_longest_edge(y->p);
        y->parent = e;
        y->first_child = -1;
        y->face = x->face;
        y->depth = x->depth + 1;
        y->child = c;
        for (int ch = 0; ch < 3; ch++)
            for (int l = 0; l < h->m; l++) {
                double v = 0.0;
                for (int k = 0; k < h->m; k++)
                    v += h->P[c][l][k] * x->B[ch][k];
                y->B[ch][l] = v;
            }
        for (int ch = 0; ch < 3; ch++) {
            y->Bmax[ch] = hp_poly_bound(h, y->B[ch], y->area);
            if (!h->field)
                y->Em[ch][0] = h->E[(size_t)y->face + (size_t)ch * h->nroots] * sqrt(y->area);
        }
        if (h->field && (st = hp_project_emission(h, first + c)) != RAD_OK)
            return st;
    }
    x->first_child = first;
    if (h->el[first].depth > h->st.max_depth)
        h->st.max_depth = h->el[first].depth;
    return RAD_OK;
}

/* The field at a point of one input triangle, in one channel, as
 * rad_basis_project takes it. */
typedef struct field_at {
    const rad_hierp *h;
    int face, channel;
} field_at;

static double field_value(rad_vec3 x, void *ctx)
{
    const field_at *f = ctx;
    return f->h->field(f->face, x, f->channel, f->h->field_ctx);
}

rad_status hp_project_emission(rad_hierp *h, int e)
{
    hp_elem *x = &h->el[e];
    for (int c = 0; c < 3; c++) {
        field_at at = {h, x->face, c};
        double coef[RAD_BASIS_MAX_SIZE];
        rad_status st = rad_basis_project(h->order, x->p, field_value, &at, 2 * h->order + 6, coef);
        if (st != RAD_OK)
            return st;
        double mean = coef[0] / sqrt(x->area);
        if (!(mean >= 0.0) || !isfinite(mean))
            return RAD_ERROR(RAD_EINPUT, "hier: the emission field's mean on an element of "
                                         "triangle %d is %g (channel %d): it must be finite "
                                         "and >= 0", x->face, mean, c);
        memset(x->Em[c], 0, sizeof x->Em[c]);
        memcpy(x->Em[c], coef, (size_t)h->m * sizeof *coef);
    }
    return RAD_OK;
}

rad_status rad_hierp_set_emission(rad_hierp *h,
                                  double (*field)(int face, rad_vec3 x, int channel, void *ctx),
                                  void *ctx)
{
    if (!h || !field)
        return RAD_ERROR(RAD_EINVAL, "hier: no handle or no emission field");
    h->field = field;
    h->field_ctx = ctx;
    h->E_max = 0.0;
    for (size_t e = 0; e < h->nel; e++) {
        rad_status st = hp_project_emission(h, (int)e);
        if (st != RAD_OK)
            return st;
        hp_elem *x = &h->el[e];
        for (int c = 0; c < 3; c++) {
            h->E_max = fmax(h->E_max, hp_emitted(x, c));
            if (x->first_child < 0)
                memcpy(x->B[c], x->Em[c], sizeof x->B[c]);
        }
    }
    return RAD_OK;
}

static rad_status check_params(const rad_hier_params *p, int order)
{
    if (order < 0 || order > RAD_BASIS_MAX_ORDER)
        return RAD_ERROR(RAD_EINVAL, "hier: basis order %d is not 0, 1 or 2", order);
    if (p->oracle != RAD_HIER_ORACLE_ERROR)
        return RAD_ERROR(RAD_EINVAL, "hier: the bf oracle applies to constant elements only "
                                     "(--basis p0)");
    if (p->use_rule)
        return RAD_ERROR(RAD_EINVAL, "hier: an explicit form-factor rule applies to constant "
                                     "elements only (--basis p0)");
    return rad_hier_params_check(p);
}

rad_status rad_hierp_create(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                            const double *rho, const double *E, const rad_vis *vis,
                            const rad_hier_params *params, int order, rad_hierp **out)
{
    rad_hier_params p;
    if (params)
        p = *params;
    else
        rad_hier_params_default(&p);
    if (!out)
        return RAD_ERROR(RAD_EINVAL, "hier: no output handle");
    *out = NULL;
    rad_status st = check_params(&p, order);
    if (st != RAD_OK)
        return st;
    if (!xyz || !tri || !rho || !E || ntris < 1 || ntris > (size_t)1 << 30)
        return RAD_ERROR(RAD_EINVAL, "hier: bad arguments (%zu triangles)", ntris);
    if (vis && rad_vis_triangle_count(vis) != ntris)
        return RAD_ERROR(RAD_EINVAL, "hier: the visibility holds %zu triangles, the scene %zu",
                         rad_vis_triangle_count(vis), ntris);
    rad_hierp *h = calloc(1, sizeof *h);
    if (!h)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
    h->p = p;
    h->order = order;
    h->m = rad_basis_size(order);
    h->vis = vis;
    h->use_vis = vis && !rad_vis_is_unoccluded(vis);
    h->nroots = ntris;
    h->rho = malloc(3 * ntris * sizeof *h->rho);
    h->E = malloc(3 * ntris * sizeof *h->E);
    h->normal = malloc(ntris * sizeof *h->normal);
    h->face_scale = malloc(ntris * sizeof *h->face_scale);
    h->face_reach = malloc(ntris * sizeof *h->face_reach);
    if (!h->rho || !h->E || !h->normal || !h->face_scale || !h->face_reach) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
        goto fail;
    }
    memcpy(h->rho, rho, 3 * ntris * sizeof *rho);
    memcpy(h->E, E, 3 * ntris * sizeof *E);
    for (size_t t = 0; t < ntris; t++)
        h->face_scale[t] = h->face_reach[t] = 1.0;
    push_matrices(h);
    /* the coupling rule: exact for two order-p functions against a kernel of
       degree 2 over each element, weights summing to 1 */
    int degree = p.degree > 2 * order + 2 ? p.degree : 2 * order + 2;
    if ((st = rad_quad_tri_symmetric(degree, h->rs, h->rt, h->rw, &h->nodes)) != RAD_OK)
        goto fail;
    {
        double wsum = 0.0;
        for (int k = 0; k < h->nodes; k++)
            wsum += h->rw[k];
        for (int k = 0; k < h->nodes; k++) {
            h->rw[k] /= wsum;
            rad_basis_eval(order, h->rs[k], h->rt[k], h->rq[k]);
        }

    }
    if ((st = hp_grow_elems(h, ntris)) != RAD_OK)
        goto fail;
    for (size_t t = 0; t < ntris; t++) {
        hp_elem *e = &h->el[t];
        memset(e, 0, sizeof *e);
        for (int v = 0; v < 3; v++) {
            int k = tri[3 * t + (size_t)v];
            if (k < 0 || (size_t)k >= nverts) {
                st = RAD_ERROR(RAD_EINPUT, "hier: triangle %zu: vertex index %d out of range", t,
                               k);
                goto fail;
            }
            e->p[v] = rad_vec3_make(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
            if (!rad_vec3_is_finite(e->p[v])) {
                st = RAD_ERROR(RAD_EINPUT, "hier: triangle %zu: non-finite vertex", t);
                goto fail;
            }
        }
        if (rad_geom_triangle_is_degenerate(e->p[0], e->p[1], e->p[2], p.ff.degenerate_rel_tol)) {
            st = RAD_ERROR(RAD_EINPUT, "hier: triangle %zu is degenerate", t);
            goto fail;
        }
        e->area = rad_geom_triangle_area(e->p[0], e->p[1], e->p[2]);
        e->size = rad_geom_triangle_longest_edge(e->p);
        e->c = rad_geom_triangle_centroid(e->p[0], e->p[1], e->p[2]);
        h->normal[t] = rad_geom_triangle_normal(e->p[0], e->p[1], e->p[2]);
        e->parent = e->first_child = -1;
        e->face = (int)t;
        for (int c = 0; c < 3; c++) {
            double r = rho[t + c * ntris], em = E[t + c * ntris];
            if (!(r >= 0.0 && r < 1.0) || !(em >= 0.0) || !isfinite(em)) {
                st = RAD_ERROR(RAD_EINPUT, "hier: triangle %zu: reflectance must lie in [0,1) "
                                           "and emission be finite and >= 0 (channel %d)", t, c);
                goto fail;
            }
            e->B[c][0] = e->Em[c][0] = em * sqrt(e->area);
            h->E_max = fmax(h->E_max, em);
            h->rho_max = fmax(h->rho_max, r);
        }
    }
    h->nel = ntris;
    h->row_ceiling = rad_hier_row_ceiling(p.sealed, h->rho_max);
    rad_ff_params touching = rad_ff_params_link_exact(&p.ff);
    if (!(h->memo = rad_hier_memo_create(&touching))) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
        goto fail;
    }
    double t0 = rad_sys_seconds(); /* the link phase: the blocker table and the initial links */
    if (h->use_vis && ntris <= 8192) {
        /* which pairs of input triangles something can block (pairs.c) */
        if (!(h->pairs = rad_hier_pairs_create(vis))) {
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
            goto fail;
        }
    }
    /* every pair of input triangles (those that face make links) */
    size_t npairs = ntris * (ntris - 1) / 2;
    hp_job *jobs = malloc((npairs ? npairs : 1) * sizeof *jobs);
    if (!jobs) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu initial links", npairs);
        goto fail;
    }
    size_t nj = 0;
    for (size_t a = 0; a < ntris; a++)
        for (size_t b = a + 1; b < ntris; b++)
            jobs[nj++] = (hp_job){(int)a, (int)b};
    st = hp_estimate_batch(h, jobs, nj, 0);
    free(jobs);
    if (st != RAD_OK)
        goto fail;
    h->st.time_link_s = rad_sys_seconds() - t0;
    *out = h;
    return RAD_OK;
fail:
    rad_hierp_destroy(h);
    return st;
}

void rad_hierp_destroy(rad_hierp *h)
{
    if (!h)
        return;
    free(h->rho);
    free(h->E);
    free(h->normal);
    free(h->face_scale);
    free(h->face_reach);
    rad_hier_pairs_destroy(h->pairs);
    rad_hier_memo_destroy(h->memo);
    free(h->el);
    free(h->ln);
    free(h->K);
    free(h->inc_start);
    free(h->inc);
    free(h->inc_src);
    free(h->Bs);
    free(h->good);
    free(h);
}

size_t rad_hierp_leaf_count(const rad_hierp *h)
{
    size_t n = 0;
    for (size_t e = 0; h && e < h->nel; e++)
        n += h->el[e].first_child < 0;
    return n;
}

void rad_hierp_leaves(const rad_hierp *h, int *face, double *area, double *corners, double *B,
                      double *coef)
{
    size_t n = rad_hierp_leaf_count(h), i = 0, m = (size_t)h->m;
    for (size_t e = 0; e < h->nel; e++) {
        const hp_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        if (face)
            face[i] = x->face;
        if (area)
            area[i] = x->area;
        if (corners)
            for (int v = 0; v < 3; v++) {
                corners[9 * i + 3 * (size_t)v] = x->p[v].x;
                corners[9 * i + 3 * (size_t)v + 1] = x->p[v].y;
                corners[9 * i + 3 * (size_t)v + 2] = x->p[v].z;
            }
        for (int c = 0; c < 3; c++) {
            if (B)
                B[i + (size_t)c * n] = x->B[c][0] / sqrt(x->area);
            if (coef)
                for (size_t k = 0; k < m; k++)
                    coef[(i * m + k) + (size_t)c * n * m] = x->B[c][k];
        }
        i++;
    }
}

void rad_hierp_get_stats(const rad_hierp *h, rad_hier_stats *stats)
{
    if (!h || !stats)
        return;
    *stats = h->st;
    stats->elements = rad_hierp_leaf_count(h);
    stats->nodes = h->nel;
    stats->links = h->nln;
    stats->links_clear = stats->links_visible = stats->links_partial = 0;
    stats->links_blocked = stats->links_unknown = stats->links_leaf = 0;
    stats->links_constant = stats->links_sampled = 0;
    for (size_t k = 0; k < h->nln; k++) {
        const hp_link *l = &h->ln[k];
        size_t *count[4] = {&stats->links_clear, &stats->links_visible, &stats->links_partial,
                            &stats->links_blocked};
        (*count[l->vis & 3])++;
        stats->links_unknown += l->unknown;
        stats->links_constant += l->constant;
        stats->links_leaf += h->el[l->a].first_child < 0 && h->el[l->b].first_child < 0;
    }
}
