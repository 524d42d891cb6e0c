/* rad_hier: the element tree, parameters, creation and the read-out.
 *
 * Elements live in one growing array and refer to each other by index; an
 * element's four children are contiguous (first_child .. first_child + 3),
 * made by the midpoint split (corner children a m_ab m_ca, m_ab b m_bc,
 * m_ca m_bc c and the middle m_ab m_bc m_ca, all with the parent's
 * orientation), and inherit the parent's face and B.  Creation makes one root
 * per input triangle (B = E) and links every ordered pair of input triangles
 * that face each other (link.c), or, with clustering, the sibling clusters
 * (cluster.c). */
#include "hier_internal.h"

#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rad_quad.h"
#include "rad_sys.h"

rad_status rad_hier_oracle_parse(const char *text, rad_hier_oracle *oracle)
{
    if (text && strcmp(text, "bf") == 0)
        *oracle = RAD_HIER_ORACLE_BF;
    else if (text && strcmp(text, "error") == 0)
        *oracle = RAD_HIER_ORACLE_ERROR;
    else
        return RAD_ERROR(RAD_EINVAL, "hier: unknown oracle '%s' (use bf or error)",
                         text ? text : "(null)");
    return RAD_OK;
}

const char *rad_hier_oracle_name(rad_hier_oracle oracle)
{
    return oracle == RAD_HIER_ORACLE_ERROR ? "error" : "bf";
}

void rad_hier_params_default(rad_hier_params *params)
{
    memset(params, 0, sizeof *params);
    params->oracle = RAD_HIER_ORACLE_ERROR;
    params->eps = 0.1;
    params->min_area = 0.0;
    params->max_depth = 10;
    params->degree = 4;
    params->use_rule = 0;
    params->rule.scheme = RAD_FF_ANALYTIC;
    params->rule.order = 6;
    rad_ff_params_default(&params->ff);
    params->link_share = 0.5;
    params->far_ratio = 3.0;
    params->clip_blockers = 24;
    params->singular = 1;
    params->round_tol = 0.5;
    params->final_share = 0.01;
    params->max_tighten = 3;
    params->source_slope = 1;
    params->tol = 1e-10;
    params->bound_tol = 1e-3;
    params->anderson = 4;
    params->max_iterations = 100000;
    params->max_rounds = 64;
    params->round_min = 1e-2;
    params->max_elements = 4000000;
    params->max_links = 50000000;
}

rad_status rad_hier_params_check(const rad_hier_params *p)
{
    if (p->oracle != RAD_HIER_ORACLE_BF && p->oracle != RAD_HIER_ORACLE_ERROR)
        return RAD_ERROR(RAD_EINVAL, "hier: unknown oracle %d", (int)p->oracle);
    if (!(p->eps > 0.0) || !isfinite(p->eps))
        return RAD_ERROR(RAD_EINVAL, "hier: eps must be a finite number > 0 (got %g)", p->eps);
    if (!(p->min_area >= 0.0) || !isfinite(p->min_area))
        return RAD_ERROR(RAD_EINVAL, "hier: min_area must be a finite number >= 0 (got %g)",
                         p->min_area);
    if (p->max_depth < 0 || p->max_depth > 30)
        return RAD_ERROR(RAD_EINVAL, "hier: max_depth must lie in 0..30 (got %d)", p->max_depth);
    if (p->degree < 1 || p->degree > RAD_QUAD_TRI_MAX_DEGREE)
        return RAD_ERROR(RAD_EINVAL, "hier: the point-value degree must lie in 1..%d (got %d)",
                         RAD_QUAD_TRI_MAX_DEGREE, p->degree);
    if (!(p->link_share > 0.0) || !isfinite(p->link_share))
        return RAD_ERROR(RAD_EINVAL, "hier: link_share must be a finite number > 0 (got %g)",
                         p->link_share);
    if (!(p->far_ratio >= 0.0) || !isfinite(p->far_ratio))
        return RAD_ERROR(RAD_EINVAL, "hier: far_ratio must be a finite number >= 0 (got %g)",
                         p->far_ratio);
    if (p->clip_blockers < 0 || p->clip_blockers > RAD_HIER_CLIP_BLOCKERS_MAX)
        return RAD_ERROR(RAD_EINVAL, "hier: clip_blockers must lie in 0..%d (got %d)",
                         RAD_HIER_CLIP_BLOCKERS_MAX, p->clip_blockers);
    if (p->anderson < 0 || p->anderson > HIER_ACCEL_MAX)
        return RAD_ERROR(RAD_EINVAL, "hier: anderson must lie in 0..%d (got %d)", HIER_ACCEL_MAX,
                         p->anderson);
    if (!(p->tol > 0.0) || !isfinite(p->tol) || !(p->bound_tol > 0.0) || !isfinite(p->bound_tol))
        return RAD_ERROR(RAD_EINVAL, "hier: tol and bound_tol must be finite numbers > 0");
    if (p->max_iterations < 1 || p->max_rounds < 0)
        return RAD_ERROR(RAD_EINVAL, "hier: max_iterations must be >= 1 and max_rounds >= 0");
    if (!(p->round_tol > 0.0) || !(p->round_tol < 1.0) || p->max_tighten < 0 ||
        p->max_tighten > 30)
        return RAD_ERROR(RAD_EINVAL, "hier: round_tol must lie in (0, 1) and max_tighten in "
                                     "0..30");
    if (!(p->round_min >= 0.0) || !(p->round_min < 1.0))
        return RAD_ERROR(RAD_EINVAL, "hier: round_min must lie in [0, 1) (got %g)", p->round_min);
    if (!(p->final_share >= 0.0) || !(p->final_share < 1.0))
        return RAD_ERROR(RAD_EINVAL, "hier: final_share must lie in [0, 1) (got %g)",
                         p->final_share);
    if ((p->cluster != 0 && p->cluster != 1) ||
        (p->cluster_model != RAD_HIER_CLUSTER_ORIENTED && p->cluster_model != RAD_HIER_CLUSTER_ISO))
        return RAD_ERROR(RAD_EINVAL, "hier: cluster must be 0 or 1 and cluster_model oriented or "
                                     "iso (got %d, %d)", p->cluster, (int)p->cluster_model);
    if (p->max_elements < 1 || p->max_links < 1)
        return RAD_ERROR(RAD_EINVAL, "hier: max_elements and max_links must be >= 1");
    const rad_hier_exchange *x = &p->exchange;
    if (x->size > 1 && (!x->allgather || x->rank < 0 || x->rank >= x->size ||
                        (x->split_gather != 0 && x->split_gather != 1)))
        return RAD_ERROR(RAD_EINVAL, "hier: an exchange among %d processes needs an allgather, "
                                     "a rank in 0..%d and split_gather 0 or 1 (got rank %d)",
                         x->size, x->size - 1, x->rank);
    return RAD_OK;
}

rad_status hier_grow_elems(rad_hier *h, size_t extra)
{
    if (h->nel + extra > h->p.max_elements)
        return RAD_ERROR(RAD_ETOOBIG, "hier: more than %zu elements (max_elements): raise --eps "
                                      "or --min-area, or use fewer triangles", h->p.max_elements);
    rad_status st;
    if (h->nel + extra > h->capel &&
        (st = hier_memory_check(h, 0, 0, h->nel + extra - h->capel)) != RAD_OK)
        return st;
    if (!rad_sys_grow_mapped((void **)&h->el, &h->capel, h->nel, h->nel + extra, sizeof *h->el,
                             64))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu elements", h->nel + extra);
    return RAD_OK;
}

rad_status hier_reserve_links(rad_hier *h, size_t extra)
{
    if (h->nln + extra > h->p.max_links)
        return RAD_ERROR(RAD_ETOOBIG, "hier: more than %zu links (max_links, --max-links): "
                                      "raise --eps or --min-area, raise --max-links if the "
                                      "machine has the memory, or use fewer triangles", h->p.max_links);
    rad_status st = hier_memory_check(h, extra, 0, 0);
    if (st != RAD_OK)
        return st;
    if (!rad_sys_grow_mapped((void **)&h->ln, &h->capln, h->nln, h->nln + extra, sizeof *h->ln,
                             256))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu links", h->nln + extra);
    return RAD_OK;
}

int hier_can_split(const rad_hier *h, int e)
{
    const hier_elem *x = &h->el[e];
    /* an element split for another link already has its children */
    return x->first_child >= 0 ||
           (x->depth < h->p.max_depth && x->area / 4.0 >= h->p.min_area);
}

rad_status hier_split(rad_hier *h, int e)
{
    if (h->el[e].first_child >= 0)
        return RAD_OK;
    rad_status st = hier_grow_elems(h, 4);
    if (st != RAD_OK)
        return st;
    hier_elem par = h->el[e];
    rad_vec3 a = par.p[0], b = par.p[1], c = par.p[2];
    rad_vec3 ab = rad_vec3_scale(rad_vec3_add(a, b), 0.5);
    rad_vec3 bc = rad_vec3_scale(rad_vec3_add(b, c), 0.5);
    rad_vec3 ca = rad_vec3_scale(rad_vec3_add(c, a), 0.5);
    rad_vec3 corners[4][3] = {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}};
    int first = (int)h->nel;
    for (int k = 0; k < 4; k++) {
        hier_elem *x = &h->el[first + k];
        *x = par;
        memcpy(x->p, corners[k], sizeof x->p);
        x->area = rad_geom_triangle_area(x->p[0], x->p[1], x->p[2]);
        x->size = rad_geom_triangle_longest_edge(x->p);
        x->c = rad_geom_triangle_centroid(x->p[0], x->p[1], x->p[2]);
        x->parent = e;
        x->first_child = -1;
        x->depth = par.depth + 1;
        x->cap = 1.0;
        for (int c3 = 0; c3 < 3; c3++) {
            x->Bg[c3] = x->Cg[c3] = x->q[c3] = x->d[c3] = x->Tg[c3] = 0.0;
            x->Gg[c3] = x->gB[c3] = rad_vec3_make(0.0, 0.0, 0.0);
        }
    }
    h->el[e].first_child = first;
    h->nel += 4;
    return RAD_OK;
}

#define HIER_BLOCK_TABLE_MAX 8192 /* input triangles: a table of at most 32 MB */

/* Root element t (input triangle t), and the largest emission and
 * reflectance so far (*emax, *rmax); RAD_EINPUT for a triangle that cannot
 * be one, with the message only when report is set (the caller's thread
 * holds it). */
static rad_status root_make(rad_hier *h, const double *xyz, size_t nverts, const int *tri,
                            const double *rho, const double *E, size_t t, int report,
                            double *emax, double *rmax)
{
    size_t ntris = h->nroots;
    hier_elem *e = &h->el[t];
    memset(e, 0, sizeof *e);
    for (int v = 0; v < 3; v++) {
        int k = tri[3 * t + (size_t)v];
        if (k < 0 || (size_t)k >= nverts)
            return report ? RAD_ERROR(RAD_EINPUT, "hier: triangle %zu: vertex index %d out of "
                                                  "range", t, k)
                          : RAD_EINPUT;
        e->p[v] = rad_vec3_make(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
        if (!rad_vec3_is_finite(e->p[v]))
            return report ? RAD_ERROR(RAD_EINPUT, "hier: triangle %zu: non-finite vertex", t)
                          : RAD_EINPUT;
    }
    if (rad_geom_triangle_is_degenerate(e->p[0], e->p[1], e->p[2], h->p.ff.degenerate_rel_tol))
        return report ? RAD_ERROR(RAD_EINPUT, "hier: triangle %zu is degenerate", t) : RAD_EINPUT;
    e->area = rad_geom_triangle_area(e->p[0], e->p[1], e->p[2]);
    e->size = rad_geom_triangle_longest_edge(e->p);
    e->c = rad_geom_triangle_centroid(e->p[0], e->p[1], e->p[2]);
    h->normal[t] = rad_geom_triangle_normal(e->p[0], e->p[1], e->p[2]);
    e->parent = e->first_child = -1;
    e->cap = 1.0;
    e->face = (int)t;
    for (int c = 0; c < 3; c++) {
        double r = rho[t + c * ntris], em = E[t + c * ntris];
        if (!(r >= 0.0 && r < 1.0) || !(em >= 0.0) || !isfinite(em))
            return report ? RAD_ERROR(RAD_EINPUT, "hier: triangle %zu: reflectance must lie in "
                                                  "[0,1) and emission be finite and >= 0 "
                                                  "(channel %d)", t, c)
                          : RAD_EINPUT;
        e->B[c] = em;
        *emax = fmax(*emax, em);
        *rmax = fmax(*rmax, r);
    }
    return RAD_OK;
}

static size_t size_min(size_t a, size_t b) { return a < b ? a : b; }

rad_status rad_hier_create(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                           const double *rho, const double *E, const rad_vis *vis,
                           const rad_hier_params *params, rad_hier **out)
{
    rad_hier_params p;
    if (params)
        p = *params;
    else
        rad_hier_params_default(&p);
    if (!out)
        return RAD_ERROR(RAD_EINVAL, "hier: no output handle");
    *out = NULL;
    rad_status st = rad_hier_params_check(&p);
    if (st != RAD_OK)
        return st;
    if (!xyz || !tri || !rho || !E || ntris < 1 || ntris > (size_t)1 << 30)
        return RAD_ERROR(RAD_EINVAL, "hier: bad arguments (%zu triangles)", ntris);
    if (vis && rad_vis_triangle_count(vis) != ntris)
        return RAD_ERROR(RAD_EINVAL, "hier: the visibility holds %zu triangles, the scene %zu",
                         rad_vis_triangle_count(vis), ntris);
    rad_hier *h = calloc(1, sizeof *h);
    if (!h)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
    h->p = p;
    h->vis = vis;
    h->use_vis = vis && !rad_vis_is_unoccluded(vis);
    h->nroots = ntris;
    h->rho = malloc(3 * ntris * sizeof *h->rho);
    h->E = malloc(3 * ntris * sizeof *h->E);
    h->normal = malloc(ntris * sizeof *h->normal);
    h->face_scale = malloc(ntris * sizeof *h->face_scale);
    if (!h->rho || !h->E || !h->normal || !h->face_scale) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
        goto fail;
    }
    memcpy(h->rho, rho, 3 * ntris * sizeof *rho);
    for (size_t t = 0; t < ntris; t++)
        h->face_scale[t] = 1.0;
    memcpy(h->E, E, 3 * ntris * sizeof *E);
    /* the point-value rule, weights summing to 1 */
    if ((st = rad_quad_tri_symmetric(p.degree, h->rs, h->rt, h->rw, &h->nodes)) != RAD_OK)
        goto fail;
    {
        double wsum = 0.0;
        for (int k = 0; k < h->nodes; k++)
            wsum += h->rw[k];
        for (int k = 0; k < h->nodes; k++)
            h->rw[k] /= wsum;
    }
    if ((st = hier_grow_elems(h, ntris)) != RAD_OK)
        goto fail;
    {
        /* in parallel: the elements' pages are first touched here, and on a
           scene of a million triangles faulting them in on one thread takes
           seconds; a refused triangle is reported as the first in order */
        size_t bad = ntris;
        double emax = 0.0, rmax = 0.0;
#pragma omp parallel for schedule(static) reduction(min : bad) reduction(max : emax, rmax) num_threads(hier_threads(h)) if (ntris > 65536)
        for (long long t = 0; t < (long long)ntris; t++)
            if (root_make(h, xyz, nverts, tri, rho, E, (size_t)t, 0, &emax, &rmax) != RAD_OK)
                bad = size_min(bad, (size_t)t);
        if (bad < ntris) {
            st = root_make(h, xyz, nverts, tri, rho, E, bad, 1, &emax, &rmax);
            goto fail;
        }
        h->E_max = emax;
        h->rho_max = rmax;
    }
    h->nel = ntris;
    /* Without clustering every pair of input triangles is estimated: refuse
       before the work when they could not all be held as links. */
    if (!p.cluster && (double)ntris * (double)(ntris - 1) / 2.0 > (double)p.max_links) {
        st = RAD_ERROR(RAD_ETOOBIG, "hier: %zu input triangles make %.3g pairs to link, beyond "
                                    "max_links (%zu, --max-links); use clustering (--method "
                                    "cluster) or fewer triangles",
                       ntris, (double)ntris * (double)(ntris - 1) / 2.0, p.max_links);
        goto fail;
    }
    rad_ff_params touching = rad_ff_params_link_exact(&p.ff);
    if (!(h->memo = rad_hier_memo_create(&touching))) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
        goto fail;
    }
    double t0 = rad_sys_seconds();
    if (p.cluster) {
        if ((st = hier_cluster_create(h)) != RAD_OK)
            goto fail;
        if ((st = hier_row_caps(h)) != RAD_OK)
            goto fail;
        h->st.time_link_s = rad_sys_seconds() - t0;
        *out = h;
        return RAD_OK;
    }
    if (h->use_vis && ntris <= HIER_BLOCK_TABLE_MAX) {
        if (!(h->pairs = rad_hier_pairs_create(vis))) {
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the blocker table of %zu "
                                       "triangles", ntris);
            goto fail;
        }
    }
    {
        hier_job *jobs = malloc(ntris * (ntris - 1 > 0 ? ntris - 1 : 1) / 2 * sizeof *jobs + 1);
        if (!jobs) {
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the initial links of %zu "
                                       "triangles", ntris);
            goto fail;
        }
        size_t nj = 0;
        for (size_t r = 0; r < ntris; r++)
            for (size_t s = r + 1; s < ntris; s++)
                jobs[nj++] = (hier_job){(int)r, (int)s, 0};
        st = hier_estimate_batch(h, jobs, nj, 0);
        free(jobs);
        if (st != RAD_OK)
            goto fail;
    }
    if ((st = hier_row_caps(h)) != RAD_OK)
        goto fail;
    h->st.time_link_s = rad_sys_seconds() - t0;
    *out = h;
    return RAD_OK;
fail:
    rad_hier_destroy(h);
    return st;
}

void rad_hier_destroy(rad_hier *h)
{
    if (!h)
        return;
    free(h->rho);
    free(h->E);
    rad_hier_pairs_destroy(h->pairs);
    rad_hier_memo_destroy(h->memo);
    free(h->normal);
    free(h->face_scale);
    free(h->tight_B);
    hier_cluster_destroy(h);
    hier_share_destroy(h);
    rad_sys_free_mapped(h->el, h->capel, sizeof *h->el);
    rad_sys_free_mapped(h->ln, h->capln, sizeof *h->ln);
    free(h->inc_start);
    rad_sys_free_mapped(h->inc, h->inc_cap, sizeof *h->inc);
    free(h->src);
    hier_accel_destroy(h);
    free(h);
}

void rad_hier_get_stats(const rad_hier *h, rad_hier_stats *stats)
{
    if (!h || !stats)
        return;
    *stats = h->st;
    stats->nodes = h->nel;
    stats->links = h->nln + h->ncln;
    stats->links_cluster = h->ncln;
    stats->clusters = h->ncl;
    stats->elements = rad_hier_leaf_count(h);
    stats->links_clear = stats->links_visible = stats->links_partial = 0;
    stats->links_blocked = stats->links_unknown = stats->links_leaf = 0;
    stats->links_sampled = 0;
    for (size_t k = 0; k < h->nln; k++) {
        const hier_link *l = &h->ln[k];
        if (l->unknown)
            stats->links_unknown++;
        else if (l->vis == 0)
            stats->links_clear++;
        else if (l->vis == 1)
            stats->links_visible++;
        else if (l->vis == 2)
            stats->links_partial++;
        else
            stats->links_blocked++;
        stats->links_leaf += h->el[l->a].first_child < 0 && h->el[l->b].first_child < 0;
        stats->links_sampled += l->sampled;
    }
    stats->max_depth = 0;
    for (size_t e = 0; e < h->nel; e++)
        if (h->el[e].first_child < 0 && h->el[e].depth > stats->max_depth)
            stats->max_depth = h->el[e].depth;
}

size_t rad_hier_leaf_count(const rad_hier *h)
{
    size_t n = 0;
    if (!h)
        return 0;
    for (size_t e = 0; e < h->nel; e++)
        n += h->el[e].first_child < 0;
    return n;
}

void rad_hier_leaves(const rad_hier *h, int *face, double *area, double *corners, double *B)
{
    if (!h)
        return;
    size_t n = rad_hier_leaf_count(h), k = 0;
    for (size_t e = 0; e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        if (face)
            face[k] = x->face;
        if (area)
            area[k] = x->area;
        if (corners)
            for (int v = 0; v < 3; v++) {
                corners[9 * k + 3 * v] = x->p[v].x;
                corners[9 * k + 3 * v + 1] = x->p[v].y;
                corners[9 * k + 3 * v + 2] = x->p[v].z;
            }
        if (B)
            for (int c = 0; c < 3; c++)
                B[k + c * n] = x->B[c];
        k++;
    }
}

void rad_hier_leaf_bounds(const rad_hier *h, double *bound)
{
    if (!h || !bound)
        return;
    size_t n = rad_hier_leaf_count(h), k = 0;
    for (size_t e = 0; e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        for (int c = 0; c < 3; c++)
            bound[k + c * n] = hier_leaf_bound(h, x, c);
        k++;
    }
}
