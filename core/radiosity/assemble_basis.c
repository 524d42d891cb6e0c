/* Dense assembly in a polynomial basis (rad_basis, order 1 or 2): the
 * couplings K_(ik)(jl) = int_i int_j phi_ik(x) k(x, y) V(x, y) phi_jl(y) of the
 * orthonormal functions of elements i and j.
 *
 * 1. The constant functions' coupling is the P0 assembly's G_ij (exact
 *    visibility, singular rules where elements touch) over sqrt(A_i A_j):
 *    the answer's per-face averages rest on the same couplings as P0's, and
 *    a furnace keeps its rows.
 * 2. Every other entry of a coupled pair (G_ij > 0) comes from a product of
 *    symmetric rules of degree 2 order + 2 on the two elements, where they
 *    are well apart (centroids farther than the sum of their longest edges);
 *    closer parts are split 1 -> 4, the larger first, recursively, each to
 *    depth 2 + order (the centroid values below err by the square of a part's size
 *    times the basis' curvature); parts still close there take their P0
 *    coupling (rad_ff auto at CLOSE_TOL: the singular rules where they touch)
 *    with the basis functions at their centroids.
 *    Where the shaft of two parts holds a possible blocker (rad_vis_blockers
 *    on the parts), V is a ray between the two nodes
 *    (rad_vis_segment_blocked); elsewhere 1, with no ray.
 * 3. K is symmetric by construction (each unordered pair once, both blocks
 *    written), and the self-couplings of flat elements vanish. */
#include "rad_radiosity.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_basis.h"
#include "rad_geom.h"
#include "rad_quad.h"
#include "rad_sys.h"

#ifdef _OPENMP
#include <omp.h>
#endif

enum { BASIS_EXTRA_DEGREE = 2 };
#define CLOSE_TOL 1e-4

/* One pair's integration: the two elements, their rule, the accumulator. */
typedef struct pair_ctx {
    rad_vec3 pa[3], pb[3], na, nb;
    int order, m;
    int np;
    const double *rs, *rt, *rw;
    const rad_vis *vis; /* NULL: nothing can block */
    int face_a, face_b;
    const rad_radiosity_params *p;
    double M[RAD_BASIS_MAX_SIZE][RAD_BASIS_MAX_SIZE];
    long long evals;
    unsigned long long rays;
    rad_status st;
} pair_ctx;

/* A part of an element: its corners in the element's local (s, t). */
typedef struct part {
    double c[3][2];
} part;

static rad_vec3 at(const rad_vec3 p[3], double s, double t)
{
    return rad_geom_triangle_point(p[0], p[1], p[2], s, t);
}

static void part_point(const part *q, double s, double t, double *ls, double *lt)
{
    *ls = q->c[0][0] + s * (q->c[1][0] - q->c[0][0]) + t * (q->c[2][0] - q->c[0][0]);
    *lt = q->c[0][1] + s * (q->c[1][1] - q->c[0][1]) + t * (q->c[2][1] - q->c[0][1]);
}

static void part_corners(const rad_vec3 p[3], const part *q, rad_vec3 out[3])
{
    for (int v = 0; v < 3; v++)
        out[v] = at(p, q->c[v][0], q->c[v][1]);
}

static void split(const part *q, part ch[4])
{
    double m[3][2];
    for (int e = 0; e < 3; e++)
        for (int d = 0; d < 2; d++)
            m[e][d] = 0.5 * (q->c[e][d] + q->c[(e + 1) % 3][d]);
    /* corners 0, 1, 2; midpoints 01, 12, 20 */
    const double *k[4][3] = {{q->c[0], m[0], m[2]}, {m[0], q->c[1], m[1]},
                             {m[2], m[1], q->c[2]}, {m[0], m[1], m[2]}};
    for (int c = 0; c < 4; c++)
        for (int v = 0; v < 3; v++)
            memcpy(ch[c].c[v], k[c][v], sizeof ch[c].c[v]);
}

static int visible(pair_ctx *x, rad_vec3 a, rad_vec3 b)
{
    if (!x->vis)
        return 1;
    double pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z};
    x->rays++;
    return !rad_vis_segment_blocked(x->vis, pa, pb, x->face_a, x->face_b);
}

/* Parts qa of element a and qb of element b (areas Aa, Ab): product rule,
 * added to M; *g00 gets the rule's unoccluded P0 coupling. */
static void product(pair_ctx *x, const part *qa, double Aa, const part *qb, double Ab,
                    double M[RAD_BASIS_MAX_SIZE][RAD_BASIS_MAX_SIZE], double *g00)
{
    *g00 = 0.0;
    /* rays only where the two parts' own shaft holds a possible blocker */
    const rad_vis *pair_vis = x->vis;
    if (pair_vis) {
        rad_vec3 ta[3], tb[3];
        int none[1];
        part_corners(x->pa, qa, ta);
        part_corners(x->pb, qb, tb);
        if (rad_vis_blockers(pair_vis, ta, x->face_a, tb, x->face_b, none, 0) == 0)
            x->vis = NULL;
    }
    for (int i = 0; i < x->np; i++) {
        double sa, ta, phia[RAD_BASIS_MAX_SIZE];
        part_point(qa, x->rs[i], x->rt[i], &sa, &ta);
        rad_basis_eval(x->order, sa, ta, phia);
        rad_vec3 xa = at(x->pa, sa, ta);
        for (int j = 0; j < x->np; j++) {
            double sb, tb, phib[RAD_BASIS_MAX_SIZE];
            part_point(qb, x->rs[j], x->rt[j], &sb, &tb);
            rad_vec3 yb = at(x->pb, sb, tb);
            double k = rad_ff_kernel(xa, x->na, yb, x->nb, NULL);
            x->evals++;
            double w = x->rw[i] * x->rw[j] * Aa * Ab * k;
            *g00 += w;
            if (k == 0.0 || !visible(x, xa, yb))
                continue;
            rad_basis_eval(x->order, sb, tb, phib);
            for (int r = 0; r < x->m; r++)
                for (int c = 0; c < x->m; c++)
                    M[r][c] += w * phia[r] * phib[c];
        }
    }
    x->vis = pair_vis;
}

/* Parts still close at the deepest level: their P0 coupling (rad_ff auto,
 * the singular rules where they touch) with the basis at their centroids,
 * visibility along the centroids' segment. */
static void close_parts(pair_ctx *x, const part *qa, const part *qb)
{
    rad_vec3 ta[3], tb[3];
    part_corners(x->pa, qa, ta);
    part_corners(x->pb, qb, tb);
    rad_ff_result r;
    rad_ff_rule rule = {RAD_FF_AUTO, 0};
    /* a part's coupling is a small share of the pair's, weighted by centroid
       values whose own error is larger: CLOSE_TOL is accurate enough */
    rad_ff_params ff = x->p->ff;
    ff.tol = rad_dmax(ff.tol, CLOSE_TOL);
    rad_status st = rad_ff_compute(ta, tb, rule, &ff, &r);
    if (st != RAD_OK) {
        x->st = st;
        return;
    }
    x->evals += r.evals;
    double sa, tta, sb, ttb, phia[RAD_BASIS_MAX_SIZE], phib[RAD_BASIS_MAX_SIZE];
    part_point(qa, 1.0 / 3.0, 1.0 / 3.0, &sa, &tta);
    part_point(qb, 1.0 / 3.0, 1.0 / 3.0, &sb, &ttb);
    if (!(r.G > 0.0) || !visible(x, at(x->pa, sa, tta), at(x->pb, sb, ttb)))
        return;
    rad_basis_eval(x->order, sa, tta, phia);
    rad_basis_eval(x->order, sb, ttb, phib);
    for (int i = 0; i < x->m; i++)
        for (int j = 0; j < x->m; j++)
            x->M[i][j] += r.G * phia[i] * phib[j];
}

/* Parts qa (area Aa, split da times) and qb: the product rule where they
 * are well apart, else the larger part split 1 -> 4 (the other when the
 * larger may not be split further), and close_parts when neither may. */
static void integrate(pair_ctx *x, const part *qa, double Aa, int da, const part *qb, double Ab,
                      int db)
{
    if (x->st != RAD_OK)
        return;
    rad_vec3 ta[3], tb[3];
    part_corners(x->pa, qa, ta);
    part_corners(x->pb, qb, tb);
    double ha = rad_geom_triangle_longest_edge(ta), hb = rad_geom_triangle_longest_edge(tb);
    rad_vec3 ca = rad_geom_triangle_centroid(ta[0], ta[1], ta[2]);
    rad_vec3 cb = rad_geom_triangle_centroid(tb[0], tb[1], tb[2]);
    if (rad_vec3_norm(rad_vec3_sub(ca, cb)) > ha + hb) {
        double g00;
        product(x, qa, Aa, qb, Ab, x->M, &g00);
        return;
    }
    int max_depth = 2 + x->order, can_a = da < max_depth, can_b = db < max_depth;
    if (!can_a && !can_b) {
        close_parts(x, qa, qb);
        return;
    }
    part ch[4];
    if (can_a && (ha >= hb || !can_b)) {
        split(qa, ch);
        for (int i = 0; i < 4; i++)
            integrate(x, &ch[i], 0.25 * Aa, da + 1, qb, Ab, db);
    } else {
        split(qb, ch);
        for (int j = 0; j < 4; j++)
            integrate(x, qa, Aa, da, &ch[j], 0.25 * Ab, db + 1);
    }
}

static void load_triangle(const double *xyz, const int *tri, int k, rad_vec3 t[3])
{
    for (int v = 0; v < 3; v++) {
        const double *p = xyz + 3 * (size_t)tri[3 * (size_t)k + v];
        t[v] = rad_vec3_make(p[0], p[1], p[2]);
    }
}

rad_status rad_radiosity_assemble_basis(const double *xyz, const int *tri, int n,
                                        const rad_vis *vis, const rad_radiosity_params *params,
                                        int order, const double *G, const double *areas,
                                        double *K, rad_radiosity_stats *stats)
{
    rad_radiosity_params p;
    if (params)
        p = *params;
    else
        rad_radiosity_params_default(&p);
    int m = rad_basis_size(order);
    if (!xyz || !tri || n < 1 || !G || !areas || !K || m == 0)
        return RAD_ERROR(RAD_EINVAL, "assembly: bad arguments (n = %d, basis order %d)", n, order);
    double rs[RAD_QUAD_TRI_MAX_POINTS], rt[RAD_QUAD_TRI_MAX_POINTS], rw[RAD_QUAD_TRI_MAX_POINTS];
    int np = 0;
    rad_status st = rad_quad_tri_symmetric(2 * order + BASIS_EXTRA_DEGREE, rs, rt, rw, &np);
    if (st == RAD_OK && vis && !rad_vis_is_unoccluded(vis))
        st = rad_vis_prepare_rays(vis); /* the higher modes' visibility is sampled by rays */
    if (st != RAD_OK)
        return st;
    size_t nn = (size_t)n, N = nn * (size_t)m;
    memset(K, 0, N * N * sizeof *K);
    long long evals = 0;
    unsigned long long rays = 0;
    rad_status first_error = RAD_OK;
    int bad_i = -1, bad_j = -1;
    char bad_message[512] = "";
#ifdef _OPENMP
    int threads = p.threads > 0 ? p.threads : omp_get_max_threads();
#endif
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+ : evals, rays)
    for (int i = 0; i < n; i++) {
        for (int j = i + 1; j < n; j++) {
            double g = G[(size_t)i + (size_t)j * nn];
            if (!(g > 0.0))
                continue;
            pair_ctx x;
            memset(&x, 0, sizeof x);
            load_triangle(xyz, tri, i, x.pa);
            load_triangle(xyz, tri, j, x.pb);
            x.na = rad_geom_triangle_normal(x.pa[0], x.pa[1], x.pa[2]);
            x.nb = rad_geom_triangle_normal(x.pb[0], x.pb[1], x.pb[2]);
            x.order = order;
            x.m = m;
            x.np = np;
            x.rs = rs;
            x.rt = rt;
            x.rw = rw;
            x.face_a = p.face_of ? p.face_of[i] : i;
            x.face_b = p.face_of ? p.face_of[j] : j;
            x.vis = vis && rad_vis_pair_can_block(vis, (size_t)x.face_a, (size_t)x.face_b) ? vis
                                                                                           : NULL;
            x.p = &p;
            part whole = {{{0.0, 0.0}, {1.0, 0.0}, {0.0, 1.0}}};
            if (m > 1) /* order 0: the constants' entry alone */
                integrate(&x, &whole, areas[i], 0, &whole, areas[j], 0);
            evals += x.evals;
            rays += x.rays;
            if (x.st != RAD_OK) {
#pragma omp critical(rad_radiosity_basis_error)
                if (first_error == RAD_OK) {
                    first_error = x.st;
                    bad_i = i;
                    bad_j = j;
                    snprintf(bad_message, sizeof bad_message, "%s", rad_error_message());
                }
                continue;
            }
            /* phi = q / sqrt(A); the constants' coupling is the P0 assembly's */
            double scale = 1.0 / sqrt(areas[i] * areas[j]);
            x.M[0][0] = g;
            for (int k = 0; k < m; k++)
                for (int l = 0; l < m; l++) {
                    size_t I = (size_t)i * (size_t)m + (size_t)k;
                    size_t J = (size_t)j * (size_t)m + (size_t)l;
                    double v = x.M[k][l] * scale;
                    K[I + J * N] = v;
                    K[J + I * N] = v;
                }
        }
    }
    if (stats) {
        stats->kernel_evals += evals;
        stats->rays += rays;
    }
    if (first_error != RAD_OK)
        return RAD_ERROR(first_error, "assembly (basis): elements %d and %d: %s", bad_i, bad_j,
                         bad_message);
    return RAD_OK;
}
