/* rad_hier: the solve (gather / push-pull) and the error bound.
 *
 * 1. Step (Jacobi): gather at every element the irradiance its links bring,
 *    as a linear function over it (value F_ab B_b at its centroid, gradient
 *    g_a B_b; all levels, old B), the mean value corrected for the slope of
 *    the source's B (gB_b) against the slope of the form factor over b
 *    (g_b): int_b (g_b . (y - c_b)) (gB_b . (y - c_b)) dy / A_a.  Without it
 *    the transport of a source's mean misses where B and the kernel rise
 *    together, towards a shared edge or a contact, and every face near one
 *    comes out dark.  Each element sums its own links' ends (struct
 *    hier_end, rebuilt when the links change), so the gather runs in
 *    parallel over the elements with the serial loop's sums, bit for bit
 *    (the processes' split gather keeps the loop over links).  Push-pull
 *    from each root, in parallel over the roots: the linear
 *    functions are summed down the tree, a leaf takes
 *    B = E + rho cap (value at its centroid), which is the linear function's
 *    mean over the leaf, and an inner element the area-weighted mean of its
 *    children's B.  cap scales a leaf whose row sum (the same push with
 *    B = 1) exceeds (1 + 1 / rho_max) / 2 back to that: no point sees more
 *    than its hemisphere, and the step then contracts by less than
 *    (1 + rho_max) / 2 < 1 whatever the approximations.  In a sealed scene
 *    every row is scaled to 1, its exact value: the hierarchy's approximation
 *    then only redistributes light, it cannot create or lose any, which
 *    reflectance near 1 would amplify.  The test compares the largest change
 *    of a leaf B in the step with tol times the largest leaf B.  Jacobi
 *    converges because the hierarchical operator keeps the norm of rho F
 *    below max rho < 1 (push-pull conserves power; F rows sum to about 1).
 * 2. The error bound (rad_hier.h): in each direction a <- b a link adds
 *    rho_a (dG / A_a) B_b to a's q (the error of F); (rho_a v_b var_b)^2 to
 *    its d, v_b the kernel's largest deviation over b (in a's units) and
 *    var_b how far B strays from b's mean, which bounds the error of
 *    transporting b's mean B.  A leaf's var is its gathered gradient's plus
 *    rho r w over the links at it and its ancestors, r the largest residual
 *    of a link's linear fit and w its source's B (sealed: its distance from
 *    the farthest of the leaf's sources): the part of B no linear function
 *    holds (a ceiling element over the edge of a box top close under it is
 *    bright over the box and not beside it, and the box top sees mostly the
 *    bright part), up to rho times the range of its sources' B, since its
 *    irradiance is a mean of them; an inner element's var is the farthest
 *    leaf below.  The
 *    oracle, its tightening included, weighs a source by its slope's var
 *    only: the residuals' refine many links that gain little, and in a
 *    sealed scene lit by a small bright source refining further moves its
 *    leaves' rows, which the normalization turns into an error of the
 *    direct light.  And rho_a r_a B_b to its dr (the residual of the linear
 *    push over a).  Pushed down, a leaf's q and d sum the links at it and
 *    at its ancestors, its dr those at its ancestors only
 *    (its own average is exact); a leaf whose cap scaled its irradiance down
 *    adds to q what the cap took off (the link terms bound the error of the
 *    uncapped sum).  The sources' variations add as independent errors, so
 *    a leaf's local error is q + sqrt(d); T = q + sqrt(d) + rho K T carries
 *    it through every bounce, solved by the same gather / push-pull (to
 *    bound_tol, plus what its last step leaves of the fixed point, as
 *    for B), in a sealed scene too: there an error only moves light
 *    between receivers, but where two surfaces face each other across a
 *    narrow gap the light it moves into the gap crosses it again and again,
 *    as the transport does.  A leaf's bound per channel is
 *    T + dr / (1 - rho_max / 2), the residuals (which near a shared edge
 *    have one sign for all its links) in full.  Over an input triangle the
 *    residuals average out (each fit's residual has zero mean over its
 *    receiver), so its bound is the area-weighted mean of T.
 * 3. Solve: steps until the test passes; rad_hier_solve alternates solves and
 *    refinement rounds (refine.c) until a round refines nothing or fewer than
 *    round_min of the links, then solves to tol and computes the bound.
 * Shared among processes with split_gather (exchange.c), a step gathers only
 * the link ends in this process's input triangles, pushes and pulls only
 * their trees, and exchanges the elements' new values (sealed, before the
 * gain, which every process then applies to the whole tree alike). */
#include "hier_internal.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_sys.h"

#include <omp.h>

/* The gain (apply_gain) stays above HIER_GAIN_MIN: the bound only keeps a
   first step's sums, far from the answer, from darkening every leaf. */
#define HIER_GAIN_MIN 0.5

/* Sealed, a leaf's row under HIER_ROW_FLOOR times the ceiling is left as it
   is, not scaled up to the ceiling: a coarse hierarchy's links may bring a
   leaf nothing (every cluster link at it from clusters it turns away from),
   and what rounding leaves of their cancelling terms (1e-20) would be scaled
   to a whole row, the leaf's B then flipping from step to step as that
   rounding does, and the solve's change with it. */
#define HIER_ROW_FLOOR 1e-12

int hier_threads(const rad_hier *h)
{
    return h->p.threads > 0 ? h->p.threads : omp_get_max_threads();
}

int hier_root_chunk(size_t roots, int threads)
{
    size_t c = roots / ((size_t)(threads > 0 ? threads : 1) * 64);
    return c < 1 ? 1 : c > 4096 ? 4096 : (int)c;
}

void hier_thread_rows(const size_t *start, size_t n, int t, int nt, size_t *lo, size_t *hi)
{
    size_t a = 0, b = n;
    while (a < n && start[a] * (size_t)nt < start[n] * (size_t)t)
        a++;
    while (b > 0 && start[b - 1] * (size_t)nt >= start[n] * (size_t)(t + 1))
        b--;
    *lo = a;
    *hi = b;
}

/* Leaf x's scales of what its element links brought (*se) and what its
 * cluster links brought (*sc).  Where its row exceeds the ceiling (sealed:
 * 1; open: rad_hier_row_ceiling) the excess comes off the cluster part
 * first, down to nothing, and only then off the element part; elsewhere
 * both take cap, the ceiling over the row (sealed: a row short of 1 is
 * scaled up whole).  Either way a uniform radiosity gathers to the ceiling
 * times itself.  The element links' F are integrals with a small error;
 * the cluster links' are estimates that may be off by their whole value,
 * and a receiving cluster does not see its own triangles hide one another:
 * a face in a narrow gap whose element links bring 0.9 of its row keeps
 * them whole instead of losing a third to the excess of the cluster links
 * around it. */
static void row_scales(const rad_hier *h, const hier_elem *x, double *se, double *sc)
{
    double top = rad_hier_row_ceiling(h->p.sealed, h->rho_max), rc = x->rowc;
    *se = *sc = x->cap;
    if (!(rc > 0.0) || !(x->row0 > top))
        return;
    double re = x->row0 - rc;
    *se = re < top ? 1.0 : top / re; /* re >= top > 0 */
    *sc = re < top ? (top - re) / rc : 0.0;
}

/* A leaf takes E + rho (se x its element links' value at its centroid + sc
 * x its cluster links'), the linear function's mean over the leaf; its
 * slope follows (see hier_elem). */
static void leaf_B(rad_hier *h, hier_elem *x, const double tot0[3], const rad_vec3 totg[3],
                   const double totc[3], double *change, double *vmax)
{
    const double *rho = h->rho, *E = h->E;
    size_t n = h->nroots, f = (size_t)x->face;
    double se, sc;
    row_scales(h, x, &se, &sc);
    for (int c = 0; c < 3; c++) {
        double r = rho[f + c * n], got = se * tot0[c] + sc * totc[c];
        if (h->p.sealed) { /* B waits for the step's gain (apply_gain) */
            x->Hn[c] = got;
            rad_vec3 g = totg[c];
            double re = x->row0 - x->rowc;
            if (re > 0.0)
                g = rad_vec3_sub(g, rad_vec3_scale(x->rowg, tot0[c] / re));
            x->gB[c] = rad_vec3_scale(g, r * se);
            continue;
        }
        double b = E[f + c * n] + r * got;
        /* a non-finite b makes the change infinite, which the caller reports */
        *change = isfinite(b) ? rad_dmax(*change, fabs(b - x->B[c])) : INFINITY;
        *vmax = rad_dmax(*vmax, fabs(b));
        x->B[c] = b;
        x->gB[c] = rad_vec3_scale(totg[c], r * se);
    }
}

/* Sealed: the normalized rows make a uniform radiosity gather exactly
 * itself, but the links' columns are not exact, so a varying one delivers
 * a little more or less power than its sources send, which reflectance
 * near 1 multiplies by up to 1 / (1 - rho).  So each step multiplies every leaf's
 * normalized irradiance by the gain, the power the leaves send, sum A B
 * with the step's old B, over what reaches them, sum A Hn, per channel (1
 * for a uniform radiosity), held between HIER_GAIN_MIN and the row ceiling
 * (so that the step still contracts); then each leaf
 * takes B = E + rho gain Hn (its slope scaled alike), the
 * step's change is measured, and the inner elements take their children's
 * means again.  The sums run over fixed runs of elements (at most
 * GAIN_RUNS of at least GAIN_RUN_MIN each: the runs depend on the element
 * count only), each summed in index order and the runs' sums in order, so
 * that the answer does not depend on the threads or the processes. */
enum { GAIN_RUNS = 1024, GAIN_RUN_MIN = 256 };

/* Run r's (of len elements) sums of A B (p[0..3)) and A Hn (p[3..6)) over
 * its leaves. */
static void gain_run(const rad_hier *h, size_t r, size_t len, double p[6])
{
    for (int c = 0; c < 6; c++)
        p[c] = 0.0;
    size_t end = (r + 1) * len < h->nel ? (r + 1) * len : h->nel;
    for (size_t e = r * len; e < end; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        for (int c = 0; c < 3; c++) {
            p[c] += x->area * x->B[c];
            p[3 + c] += x->area * x->Hn[c];
        }
    }
}

static void apply_gain(rad_hier *h, double *change, double *vmax)
{
    size_t len = (h->nel + GAIN_RUNS - 1) / GAIN_RUNS;
    len = len > GAIN_RUN_MIN ? len : GAIN_RUN_MIN;
    size_t runs = (h->nel + len - 1) / len;
    double part[6 * GAIN_RUNS], sent[3] = {0, 0, 0}, got[3] = {0, 0, 0};
    int threads = hier_threads(h);
#pragma omp parallel for schedule(static) num_threads(threads) if (runs > 1)
    for (long long r = 0; r < (long long)runs; r++)
        gain_run(h, (size_t)r, len, part + 6 * r);
    for (size_t r = 0; r < runs; r++)
        for (int c = 0; c < 3; c++) {
            sent[c] += part[6 * r + c];
            got[c] += part[6 * r + 3 + c];
        }
    /* the step contracts by rho_max x gain: held under rad_hier_row_ceiling's
       (1 + 1 / rho_max) / 2, it contracts by (1 + rho_max) / 2 at most */
    double top = rad_hier_row_ceiling(0, h->rho_max), gain[3];
    h->st.gain = 1.0;
    for (int c = 0; c < 3; c++) {
        double g = got[c] > 0.0 && isfinite(sent[c]) ? sent[c] / got[c] : 1.0;
        gain[c] = rad_dmin(top, rad_dmax(HIER_GAIN_MIN, g));
        if (fabs(gain[c] - 1.0) > fabs(h->st.gain - 1.0))
            h->st.gain = gain[c];
    }
    const double *rho = h->rho, *E = h->E;
    size_t n = h->nroots;
    double ch = 0.0, vm = 0.0;
#pragma omp parallel for schedule(static) reduction(max : ch, vm) num_threads(threads) if (h->nel > 65536)
    for (long long e = 0; e < (long long)h->nel; e++) {
        hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        size_t f = (size_t)x->face;
        for (int c = 0; c < 3; c++) {
            double b = E[f + c * n] + rho[f + c * n] * gain[c] * x->Hn[c];
            double d = fabs(b - x->B[c]);
            ch = isfinite(b) ? (d > ch ? d : ch) : INFINITY;
            vm = fabs(b) > vm ? fabs(b) : vm;
            x->B[c] = b;
            x->gB[c] = rad_vec3_scale(x->gB[c], gain[c]);
        }
    }
    int chunk = hier_root_chunk(h->nroots, threads);
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads) if (h->nroots > 1)
    for (long long t = 0; t < (long long)h->nroots; t++)
        hier_pull_means(h, (int)t, CARRY_B);
    *change = ch;
    *vmax = vm;
}

/* A leaf's var from its gB (how far B strays from its mean at its corners). */
static void leaf_var(hier_elem *x)
{
    for (int c = 0; c < 3; c++) {
        double v = 0.0;
        for (int i = 0; i < 3; i++)
            v = rad_dmax(v, fabs(rad_vec3_dot(x->gB[c], rad_vec3_sub(x->p[i], x->c))));
        x->var[c] = v;
    }
}

/* T = q + rho (se x its element links' value at its centroid + sc x its
 * cluster links'), the scales B's step takes (row_scales). */
static void leaf_T(rad_hier *h, hier_elem *x, const double tot0[3], const double totc[3],
                   double *change, double *vmax)
{
    size_t n = h->nroots, f = (size_t)x->face;
    double se, sc;
    row_scales(h, x, &se, &sc);
    for (int c = 0; c < 3; c++) {
        double t = x->q[c] + h->rho[f + c * n] * (se * tot0[c] + sc * totc[c]);
        *change = rad_dmax(*change, fabs(t - x->T[c]));
        *vmax = rad_dmax(*vmax, fabs(t));
        x->T[c] = t;
    }
}

/* Push the ancestors' gathered linear function (down0 + downg . (x - c_e),
 * re-centred at e, and the constant their cluster links brought, downc)
 * to the leaves under e, update them, and pull the area-weighted mean back
 * up; accumulates the largest leaf change and the largest leaf value. */
static void push_pull(rad_hier *h, int e, int carry, const double down0[3],
                      const rad_vec3 downg[3], const double downc[3], double *change,
                      double *vmax)
{
    hier_elem *x = &h->el[e];
    const double *g0 = carry == CARRY_B ? x->Bg : x->Tg;
    const rad_vec3 *gg = carry == CARRY_B ? x->Gg : x->TGg;
    double tot0[3], totc[3];
    rad_vec3 totg[3];
    for (int c = 0; c < 3; c++) {
        tot0[c] = down0[c] + g0[c];
        totg[c] = rad_vec3_add(downg[c], gg[c]);
        totc[c] = downc[c] + x->Cg[c];
    }
    if (x->first_child < 0) {
        if (carry == CARRY_B)
            leaf_B(h, x, tot0, totg, totc, change, vmax);
        else
            leaf_T(h, x, tot0, totc, change, vmax);
        return;
    }
    for (int k = 0; k < 4; k++) {
        int ch = h->el[e].first_child + k;
        double d0[3];
        rad_vec3 delta = rad_vec3_sub(h->el[ch].c, h->el[e].c);
        for (int c = 0; c < 3; c++)
            d0[c] = tot0[c] + rad_vec3_dot(totg[c], delta);
        push_pull(h, ch, carry, d0, totg, totc, change, vmax);
    }
    if (carry != CARRY_B || !h->p.sealed) /* sealed, apply_gain takes the means */
        hier_children_mean(h, e, carry);
}

void hier_pull_means(rad_hier *h, int e, int carry)
{
    if (h->el[e].first_child < 0)
        return;
    for (int k = 0; k < 4; k++)
        hier_pull_means(h, h->el[e].first_child + k, carry);
    hier_children_mean(h, e, carry);
}

void hier_children_mean(rad_hier *h, int e, int carry)
{
    double sum[3] = {0, 0, 0}, area = 0.0;
    for (int k = 0; k < 4; k++) {
        const hier_elem *y = &h->el[h->el[e].first_child + k];
        const double *v = carry == CARRY_B ? y->B : y->T;
        area += y->area;
        for (int c = 0; c < 3; c++)
            sum[c] += y->area * v[c];
    }
    double *v = carry == CARRY_B ? h->el[e].B : h->el[e].T;
    for (int c = 0; c < 3; c++)
        v[c] = area > 0.0 ? sum[c] / area : 0.0;
}

/* Push the gathered form factors (value and gradient; the cluster links'
 * part, a constant, apart) down to the leaves. */
static void push_rows(rad_hier *h, int e, double down0, rad_vec3 downg, double downc)
{
    hier_elem *x = &h->el[e];
    double tot0 = down0 + x->Bg[0], totc = downc + x->Cg[0];
    rad_vec3 totg = rad_vec3_add(downg, x->Gg[0]);
    if (x->first_child < 0) {
        double top = rad_hier_row_ceiling(h->p.sealed, h->rho_max), row = tot0 + totc;
        x->cap = row > top || (h->p.sealed && row > HIER_ROW_FLOOR * top) ? top / row : 1.0;
        x->row0 = row;
        x->rowc = totc;
        x->rowg = totg;
        return;
    }
    for (int k = 0; k < 4; k++) {
        int ch = h->el[e].first_child + k;
        push_rows(h, ch, tot0 + rad_vec3_dot(totg, rad_vec3_sub(h->el[ch].c, h->el[e].c)), totg,
                  totc);
    }
}

double rad_hier_row_ceiling(int sealed, double rho_max)
{
    return sealed ? 1.0 : 0.5 * (1.0 + 1.0 / rad_dmax(rho_max, 0.5));
}

static rad_status incidence(rad_hier *h);

/* Zero what element x's own links gathered (carry B: Bg and Gg; T: Tg and
 * TGg); the cluster gather writes Cg whole. */
static void clear_gathered(hier_elem *x, int carry)
{
    rad_vec3 zero_v = rad_vec3_make(0.0, 0.0, 0.0);
    for (int c = 0; c < 3; c++) {
        *(carry == CARRY_B ? &x->Bg[c] : &x->Tg[c]) = 0.0;
        *(carry == CARRY_B ? &x->Gg[c] : &x->TGg[c]) = zero_v;
    }
}

/* clear_gathered on every element, before a gather that adds link by link
 * (shared among processes, split_gather; gather_elem clears each element
 * as it sums it). */
static void zero_gathered(rad_hier *h, int carry)
{
#pragma omp parallel for schedule(static) num_threads(hier_threads(h)) if (h->nel > 65536)
    for (long long e = 0; e < (long long)h->nel; e++)
        clear_gathered(&h->el[e], carry);
}

/* Each element's row sums, B's gather with every source 1: summed at each
 * element over its own link ends (in link order, as the serial loop over
 * the links would), then pushed down each tree, in parallel; shared among
 * processes every process sums every link, as it holds no incidence. */
rad_status hier_row_caps(rad_hier *h)
{
    rad_vec3 zero_v = rad_vec3_make(0.0, 0.0, 0.0);
    int threads = hier_threads(h);
    rad_status st;
    if (hier_split_on(h)) {
        zero_gathered(h, CARRY_B);
        for (size_t k = 0; k < h->nln; k++) {
            const hier_link *l = &h->ln[k];
            if (l->a < 0)
                continue;
            hier_elem *a = &h->el[l->a], *b = &h->el[l->b];
            a->Bg[0] += l->G / a->area;
            a->Gg[0] = rad_vec3_add(a->Gg[0], l->ga);
            b->Bg[0] += l->G / b->area;
            b->Gg[0] = rad_vec3_add(b->Gg[0], l->gb);
        }
    } else {
        if ((st = incidence(h)) != RAD_OK)
            return st;
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads) if (h->nel > 64)
        for (long long e = 0; e < (long long)h->nel; e++) {
            hier_elem *x = &h->el[e];
            x->Bg[0] = 0.0;
            x->Gg[0] = zero_v;
            for (size_t i = h->inc_start[e]; i < h->inc_start[e + 1]; i++) {
                x->Bg[0] += h->inc[i].F;
                x->Gg[0] = rad_vec3_add(x->Gg[0], h->inc[i].g);
            }
        }
    }
    if (h->ncl && ((st = hier_fill_sources(h, CLUSTER_ONE)) != RAD_OK ||
                   (st = hier_cluster_gather(h, CLUSTER_ONE)) != RAD_OK))
        return st;
    int chunk = hier_root_chunk(h->nroots, threads);
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads) if (h->nroots > 1)
    for (long long t = 0; t < (long long)h->nroots; t++)
        push_rows(h, (int)t, 0.0, zero_v, 0.0);
    return RAD_OK;
}

static void pull_gradient(rad_hier *h, int e);

/* int_x (g1 . (y - c)) (g2 . (y - c)) dy = g2 . moment(x, g1) over triangle
 * x (its second moment about the centroid is A / 12 sum_i d_i d_i^T,
 * d_i = p_i - c): the flux a linear variation g2 of the source's B carries to
 * the receiver through the linear variation g1 of the form factor towards
 * it.  The vector does not depend on the channel, so a link computes it once
 * per step. */
static rad_vec3 moment(const hier_elem *x, rad_vec3 g1)
{
    rad_vec3 s = rad_vec3_make(0.0, 0.0, 0.0);
    for (int i = 0; i < 3; i++) {
        rad_vec3 d = rad_vec3_sub(x->p[i], x->c);
        s = rad_vec3_add(s, rad_vec3_scale(d, rad_vec3_dot(g1, d)));
    }
    return rad_vec3_scale(s, x->area / 12.0);
}

/* What link l brings its ends (ends: bit 1 a, bit 2 b; 3 both), in the
 * order of the serial sum at each end. */
static void gather_link(const rad_hier *h, const hier_link *l, unsigned ends)
{
    hier_elem *a = &h->el[l->a], *b = &h->el[l->b];
    double Fab = l->G / a->area, Fba = l->G / b->area;
    rad_vec3 mb = rad_vec3_make(0.0, 0.0, 0.0), ma = mb;
    if (h->p.source_slope) {
        if (ends & 1)
            mb = rad_vec3_scale(moment(b, l->gb), 1.0 / a->area);
        if (ends & 2)
            ma = rad_vec3_scale(moment(a, l->ga), 1.0 / b->area);
    }
    for (int c = 0; c < 3; c++) {
        if (ends & 1) {
            a->Bg[c] += Fab * b->B[c];
            a->Gg[c] = rad_vec3_add(a->Gg[c], rad_vec3_scale(l->ga, b->B[c]));
            if (h->p.source_slope)
                a->Bg[c] += rad_vec3_dot(mb, b->gB[c]);
        }
        if (ends & 2) {
            if (h->p.source_slope)
                b->Bg[c] += rad_vec3_dot(ma, a->gB[c]);
            b->Bg[c] += Fba * a->B[c];
            b->Gg[c] = rad_vec3_add(b->Gg[c], rad_vec3_scale(l->gb, a->B[c]));
        }
    }
}

/* The same for the error transport T. */
static void gather_link_T(const rad_hier *h, const hier_link *l, unsigned ends)
{
    hier_elem *a = &h->el[l->a], *b = &h->el[l->b];
    for (int c = 0; c < 3; c++) {
        if (ends & 1) {
            a->Tg[c] += l->G / a->area * b->T[c];
            a->TGg[c] = rad_vec3_add(a->TGg[c], rad_vec3_scale(l->ga, b->T[c]));
        }
        if (ends & 2) {
            b->Tg[c] += l->G / b->area * a->T[c];
            b->TGg[c] = rad_vec3_add(b->TGg[c], rad_vec3_scale(l->gb, a->T[c]));
        }
    }
}

/* Each element's link ends, in link order. */
static rad_status incidence(rad_hier *h)
{
    if (h->inc_nel == h->nel && h->inc_version == h->version)
        return RAD_OK;
    size_t ne = h->nel, nl = h->nln;
    if (!rad_sys_grow((void **)&h->inc_start, &h->inc_start_cap, 0, ne + 1, sizeof *h->inc_start,
                      1024) ||
        !rad_sys_grow_mapped((void **)&h->inc, &h->inc_cap, 0, 2 * nl, sizeof *h->inc, 1024))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the ends of %zu links", nl);
    hier_gather_touch(h, HIER_GATHER_INC_START, (ne + 1) * sizeof *h->inc_start);
    hier_gather_touch(h, HIER_GATHER_INC, 2 * nl * sizeof *h->inc);
    size_t *start = h->inc_start;
    memset(start, 0, (ne + 1) * sizeof *start);
    int threads = hier_threads(h);
    /* the counts, on every thread (a count does not depend on the order) */
#pragma omp parallel for schedule(static) num_threads(threads) if (nl > 65536)
    for (long long k = 0; k < (long long)nl; k++)
        if (h->ln[k].a >= 0) {
#pragma omp atomic
            start[h->ln[k].a + 1]++;
#pragma omp atomic
            start[h->ln[k].b + 1]++;
        }
    for (size_t e = 0; e < ne; e++)
        start[e + 1] += start[e];
    rad_vec3 zero_v = rad_vec3_make(0.0, 0.0, 0.0);
    /* each thread writes the elements of its share of the ends (whole
       elements, so each keeps link order); start[e] runs ahead, then is
       restored */
#pragma omp parallel num_threads(threads) if (nl > 65536)
    {
        size_t lo, hi;
        hier_thread_rows(start, ne, omp_get_thread_num(), omp_get_num_threads(), &lo, &hi);
#pragma omp barrier
        for (size_t k = 0; k < nl; k++) {
            const hier_link *l = &h->ln[k];
            if (l->a < 0)
                continue;
            const hier_elem *a = &h->el[l->a], *b = &h->el[l->b];
            if ((size_t)l->a >= lo && (size_t)l->a < hi) {
                struct hier_end ea = {l->b, 0, l->G / a->area, l->ga, zero_v};
                if (h->p.source_slope)
                    ea.m = rad_vec3_scale(moment(b, l->gb), 1.0 / a->area);
                h->inc[start[l->a]++] = ea;
            }
            if ((size_t)l->b >= lo && (size_t)l->b < hi) {
                struct hier_end eb = {l->a, 1, l->G / b->area, l->gb, zero_v};
                if (h->p.source_slope)
                    eb.m = rad_vec3_scale(moment(a, l->ga), 1.0 / b->area);
                h->inc[start[l->b]++] = eb;
            }
        }
    }
    for (size_t e = ne; e > 0; e--)
        start[e] = start[e - 1];
    start[0] = 0;
    h->inc_nel = ne;
    h->inc_version = h->version;
    return RAD_OK;
}

/* What element e's own links bring it (carry B or T): gather_link's (and
 * gather_link_T's) terms at that end, in the same order, so that the sums
 * are those of the serial loop over the links, bit for bit. */
static void gather_elem(rad_hier *h, size_t e, int carry)
{
    hier_elem *x = &h->el[e];
    clear_gathered(x, carry);
    size_t ends = h->inc_start[h->inc_nel];
    for (size_t i = h->inc_start[e]; i < h->inc_start[e + 1]; i++) {
        const struct hier_end *u = &h->inc[i];
        const double *s = h->src + (size_t)u->src * HIER_SRC + 4; /* B or T, then gB */
        if (i + HIER_PREFETCH_AHEAD < ends) { /* the rows are read at random: ask ahead */
            const double *next = h->src + (size_t)h->inc[i + HIER_PREFETCH_AHEAD].src * HIER_SRC;
            __builtin_prefetch(next + 4);
            __builtin_prefetch(next + 15);
        }
        if (carry != CARRY_B) {
            for (int c = 0; c < 3; c++) {
                x->Tg[c] += u->F * s[c];
                x->TGg[c] = rad_vec3_add(x->TGg[c], rad_vec3_scale(u->g, s[c]));
            }
            continue;
        }
        for (int c = 0; c < 3; c++) {
            rad_vec3 gB = rad_vec3_make(s[3 + 3 * c], s[4 + 3 * c], s[5 + 3 * c]);
            if (h->p.source_slope && u->is_b)
                x->Bg[c] += rad_vec3_dot(u->m, gB);
            x->Bg[c] += u->F * s[c];
            x->Gg[c] = rad_vec3_add(x->Gg[c], rad_vec3_scale(u->g, s[c]));
            if (h->p.source_slope && !u->is_b)
                x->Bg[c] += rad_vec3_dot(u->m, gB);
        }
    }
}

rad_status hier_fill_sources(rad_hier *h, int carry)
{
    if (!rad_sys_grow((void **)&h->src, &h->src_cap, 0, h->nel * HIER_SRC, sizeof *h->src,
                      1024 * HIER_SRC))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu elements' values", h->nel);
    hier_gather_touch(h, HIER_GATHER_SRC, h->nel * HIER_SRC * sizeof *h->src);
#pragma omp parallel for schedule(static) num_threads(hier_threads(h)) if (h->nel > 65536)
    for (long long e = 0; e < (long long)h->nel; e++) {
        const hier_elem *x = &h->el[e];
        rad_vec3 n = h->normal[x->face];
        double *s = h->src + (size_t)e * HIER_SRC;
        s[0] = n.x;
        s[1] = n.y;
        s[2] = n.z;
        s[3] = x->area;
        for (int c = 0; c < 3; c++) {
            s[4 + c] = carry == CLUSTER_T ? x->T[c] : carry == CLUSTER_ONE ? 1.0 : x->B[c];
            if (carry == CLUSTER_B) {
                s[7 + 3 * c] = x->gB[c].x;
                s[8 + 3 * c] = x->gB[c].y;
                s[9 + 3 * c] = x->gB[c].z;
            }
        }
        if (h->ncl && (size_t)e < h->nroots) {
            /* a small cluster's triangles as it emits them, in cluster order */
            double *m = h->cemit + 6 * (size_t)h->cleaf[e].first;
            m[0] = n.x;
            m[1] = n.y;
            m[2] = n.z;
            for (int c = 0; c < 3; c++)
                m[3 + c] = x->area * s[4 + c];
        }
    }
    if (h->ncl)
        hier_cluster_fill_groups(h);
    return RAD_OK;
}

/* Gather every link (carry B or T) and push-pull every tree, both in
 * parallel (over the elements, each summing its own links; over the
 * trees); shared among processes (split_gather), only this process's ends
 * and trees, then the exchange (exchange.c). */
static rad_status gather_push_pull(rad_hier *h, int carry, double *change, double *vmax)
{
    rad_vec3 zero_v = rad_vec3_make(0.0, 0.0, 0.0), zerog[3] = {zero_v, zero_v, zero_v};
    double zero[3] = {0, 0, 0};
    void (*one)(const rad_hier *, const hier_link *, unsigned) =
        carry == CARRY_B ? gather_link : gather_link_T;
    size_t lo = 0, hi = h->nroots;
    int split = hier_split_on(h);
    int threads = hier_threads(h);
    rad_status st;
    if (split && (st = hier_split_plan(h)) != RAD_OK)
        return st;
    /* shared among processes the element links read the elements: only the
       cluster gather reads these rows */
    if ((!split || h->ncl) && (st = hier_fill_sources(h, carry)) != RAD_OK)
        return st;
    if (split) {
        const unsigned char *ends;
        size_t n;
        const int *mine = hier_split_links(h, &ends, &n);
        zero_gathered(h, carry);
        for (size_t i = 0; i < n; i++)
            one(h, &h->ln[mine[i]], ends[i]);
        hier_split_roots(h, &lo, &hi);
    } else {
        if ((st = incidence(h)) != RAD_OK)
            return st;
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads) if (h->nel > 64)
        for (long long e = 0; e < (long long)h->nel; e++)
            gather_elem(h, (size_t)e, carry);
    }
    if ((st = hier_cluster_gather(h, carry == CARRY_B ? CLUSTER_B : CLUSTER_T)) != RAD_OK)
        return st;
    double ch = *change, vm = *vmax;
    int chunk = hier_root_chunk(hi - lo, threads);
#pragma omp parallel for schedule(dynamic, chunk) reduction(max : ch, vm) num_threads(threads) if (h->nel > 64 && hi - lo > 1)
    for (long long t = (long long)lo; t < (long long)hi; t++)
        push_pull(h, (int)t, carry, zero, zerog, zero, &ch, &vm);
    *change = ch;
    *vmax = vm;
    if (split && (st = hier_split_exchange(h, carry, change, vmax)) != RAD_OK)
        return st;
    if (carry == CARRY_B && h->p.sealed)
        apply_gain(h, change, vmax);
    return RAD_OK;
}

rad_status rad_hier_step(rad_hier *h)
{
    if (!h)
        return RAD_ERROR(RAD_EINVAL, "hier: no handle");
    int threads = hier_threads(h), chunk = hier_root_chunk(h->nroots, threads);
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads) if (h->nroots > 1)
    for (long long t = 0; t < (long long)h->nroots; t++)
        pull_gradient(h, (int)t);
    double change = 0.0, bmax = 0.0;
    rad_status st = gather_push_pull(h, CARRY_B, &change, &bmax);
    if (st != RAD_OK)
        return st;
    if (!isfinite(change) || !isfinite(bmax))
        return RAD_ERROR(RAD_ENUMERIC, "hier: a radiosity is not finite after step %lld",
                         h->st.iterations + 1);
    h->last_change = bmax > 0.0 ? change / bmax : change;
    h->last_bmax = bmax;
    h->st.residual = h->last_change;
    h->st.iterations++;
    h->stepped = 1;
    return RAD_OK;
}

rad_status rad_hier_test(const rad_hier *h)
{
    if (!h || !h->stepped)
        return RAD_CONTINUE;
    return h->last_change <= h->p.tol ? RAD_OK : RAD_CONTINUE;
}

rad_status hier_solve_links(rad_hier *h, double tol)
{
    double t0 = rad_sys_seconds();
    rad_status fits = hier_memory_check(h, 0, 0, 0); /* the gather's arrays, built below */
    if (fits != RAD_OK)
        return fits;
    rad_status st;
    hier_accel_begin(h, CARRY_B, tol);
    for (int it = 0; it < h->p.max_iterations; it++) {
        if ((st = hier_accel_save(h, it > 0 ? h->last_change : -1.0)) != RAD_OK ||
            (st = rad_hier_step(h)) != RAD_OK)
            return st;
        hier_working(h, "solving", (size_t)it + 1);
        if (h->last_change <= tol) {
            h->st.time_solve_s += rad_sys_seconds() - t0;
            return RAD_OK;
        }
        hier_accel_mix(h);
    }
    return RAD_ERROR(RAD_ENUMERIC, "hier: gather/push-pull did not converge in %d steps "
                                   "(change %.3g > tol %.3g)", h->p.max_iterations,
                     h->last_change, tol);
}

void hier_working(const rad_hier *h, const char *what, size_t count)
{
    if (h->p.working)
        h->p.working(h->round, what, count, h->p.progress_ctx);
}

double hier_reflected_scale(const rad_hier *h)
{
    double sum = 0.0, area = 0.0;
    for (size_t e = 0; e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        for (int c = 0; c < 3; c++)
            sum += x->area * (x->B[c] - h->E[(size_t)x->face + c * h->nroots]);
        area += x->area;
    }
    double mean = area > 0.0 ? sum / (3.0 * area) : 0.0;
    return mean > 0.0 ? mean : h->E_max;
}

static double sq(double x) { return x * x; }

double hier_weight(const rad_hier *h, const hier_elem *r, const hier_elem *s, int c)
{
    if (!h->p.sealed)
        return s->B[c];
    size_t n = h->nroots, f = (size_t)r->face;
    double rho = h->rho[f + c * n];
    if (!(rho > 0.0))
        return s->B[c];
    return fabs(s->B[c] - (r->B[c] - h->E[f + c * n]) / rho);
}

/* T is the transported local error (q + sqrt(d)), within T_tail of the
 * transport's fixed point. */
double hier_leaf_bound(const rad_hier *h, const hier_elem *x, int c)
{
    double damp = 1.0 / (1.0 - 0.5 * h->rho_max);
    return x->T[c] + h->T_tail + x->dr[c] * damp + h->iter_err;
}

double hier_face_part(const rad_hier *h, const hier_elem *x, int c)
{
    return x->T[c] + h->T_tail + h->iter_err;
}

/* What an iteration of gather / push-pull (of B or of T) stopped at a step
 * change delta (absolute) leaves of its fixed point: a step contracts the
 * error by q <= rho_max (sealed, rows 1) or (1 + rho_max) / 2 (rows capped
 * there), so the fixed point lies within delta q / (1 - q). */
double hier_contraction(const rad_hier *h)
{
    return h->p.sealed ? h->rho_max : 0.5 * (1.0 + h->rho_max);
}

static double fixed_point_tail(const rad_hier *h, double delta)
{
    double q = hier_contraction(h);
    return q < 1.0 ? delta * q / (1.0 - q) : 0.0;
}

/* What the last solve leaves of B's fixed point: the tail of its last
 * step's change, and the rounding of a step, taken as 64 ulps of the
 * largest B, carried through the bounces (a solve whose steps are mixed
 * reaches the fixed point of the floating-point map, whose distance from
 * the exact one its changes do not show). */
static double iteration_error(const rad_hier *h)
{
    if (!h->stepped)
        return 0.0;
    double q = h->p.sealed ? h->rho_max : 0.5 * (1.0 + h->rho_max);
    double rounding = q < 1.0 ? 64.0 * DBL_EPSILON * h->last_bmax / (1.0 - q) : 0.0;
    return fixed_point_tail(h, h->last_change * h->last_bmax) + rounding;
}

/* Push the local errors down: a leaf's q and d become the sums over the
 * links at it and at its ancestors, its dr the sum over its ancestors only. */
static void push_local(rad_hier *h, int e, const double dq[3], const double dd[3],
                       const double ddr[3])
{
    hier_elem *x = &h->el[e];
    double q[3], d[3], dr[3];
    for (int c = 0; c < 3; c++) {
        q[c] = dq[c] + x->q[c];
        d[c] = dd[c] + x->d[c];
        dr[c] = ddr[c] + x->dr[c];
    }
    if (x->first_child < 0) {
        memcpy(x->q, q, sizeof q);
        memcpy(x->d, d, sizeof d);
        memcpy(x->dr, ddr, sizeof x->dr);
        return;
    }
    for (int k = 0; k < 4; k++)
        push_local(h, h->el[e].first_child + k, q, d, dr);
}

/* An inner element's var: the farthest deviation from its B of a leaf
 * below, that leaf's own var included (lo, hi: the subtree's extremes). */
static void spread(rad_hier *h, int e, double lo[3], double hi[3])
{
    hier_elem *x = &h->el[e];
    if (x->first_child < 0) {
        for (int c = 0; c < 3; c++) {
            lo[c] = x->B[c] - x->var[c];
            hi[c] = x->B[c] + x->var[c];
        }
        return;
    }
    for (int c = 0; c < 3; c++) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
    }
    for (int k = 0; k < 4; k++) {
        double l2[3], h2[3];
        spread(h, h->el[e].first_child + k, l2, h2);
        for (int c = 0; c < 3; c++) {
            lo[c] = rad_dmin(lo[c], l2[c]);
            hi[c] = rad_dmax(hi[c], h2[c]);
        }
    }
    x = &h->el[e];
    for (int c = 0; c < 3; c++)
        x->var[c] = rad_dmax(hi[c] - x->B[c], x->B[c] - lo[c]);
}

/* An inner element's gB: the least-squares linear fit of its children's B
 * at their centroids (the constant is its own B, their area-weighted mean). */
static void pull_gradient(rad_hier *h, int e)
{
    hier_elem *x = &h->el[e];
    if (x->first_child < 0)
        return;
    for (int k = 0; k < 4; k++)
        pull_gradient(h, h->el[e].first_child + k);
    x = &h->el[e];
    rad_vec3 u = rad_vec3_sub(x->p[1], x->p[0]);
    u = rad_vec3_scale(u, 1.0 / rad_vec3_norm(u));
    rad_vec3 v = rad_vec3_cross(h->normal[x->face], u);
    double saa = 0.0, sab = 0.0, sbb = 0.0, saf[3] = {0, 0, 0}, sbf[3] = {0, 0, 0};
    for (int k = 0; k < 4; k++) {
        const hier_elem *y = &h->el[x->first_child + k];
        rad_vec3 d = rad_vec3_sub(y->c, x->c);
        double a = rad_vec3_dot(d, u), b = rad_vec3_dot(d, v), w = y->area;
        saa += w * a * a;
        sab += w * a * b;
        sbb += w * b * b;
        for (int c = 0; c < 3; c++) {
            saf[c] += w * a * (y->B[c] - x->B[c]);
            sbf[c] += w * b * (y->B[c] - x->B[c]);
        }
    }
    double det = saa * sbb - sab * sab;
    for (int c = 0; c < 3; c++) {
        double al = 0.0, be = 0.0;
        if (det > 0.0) {
            al = (saf[c] * sbb - sbf[c] * sab) / det;
            be = (sbf[c] * saa - saf[c] * sab) / det;
        }
        x->gB[c] = rad_vec3_add(rad_vec3_scale(u, al), rad_vec3_scale(v, be));
    }
}

/* Each leaf below e: var from its gB, plus, with res, what the links'
 * linear fits leave out of its irradiance at it and its ancestors (up, and
 * res at each element: rho r w summed over its own links, w as
 * residual_weight), as far as the range of its sources' B allows: its
 * irradiance at any point is a mean of the B its sources take (sealed; or
 * lies between 0 and their largest, where the rows fall short of 1), so B
 * cannot stray further than rho times that range.  The residuals' sum
 * bounds each link's part separately, and with hundreds of links at a
 * large element it exceeds what any mean of the sources could reach.
 * lo, hi: the range at each element (link_residuals); glo, ghi: every
 * leaf's, since cluster links may bring any (NULL without them). */
typedef struct {
    const double *res, *lo, *hi, *glo, *ghi;
} var_sources;

static void leaf_var_below(rad_hier *h, int e, const double up[3], const var_sources *vs)
{
    double r[3];
    for (int c = 0; c < 3; c++)
        r[c] = up[c] + (vs ? vs->res[3 * (size_t)e + (size_t)c] : 0.0);
    hier_elem *x = &h->el[e];
    if (x->first_child < 0) {
        leaf_var(x);
        for (int c = 0; c < 3; c++) {
            double add = r[c];
            if (vs) {
                size_t i = 3 * (size_t)e + (size_t)c;
                double lo = vs->lo[i], hi = vs->hi[i];
                if (vs->glo) {
                    lo = rad_dmin(lo, vs->glo[c]);
                    hi = rad_dmax(hi, vs->ghi[c]);
                }
                if (!h->p.sealed)
                    lo = rad_dmin(lo, 0.0);
                double cap = h->rho[(size_t)x->face + (size_t)c * h->nroots] * (hi - lo);
                if (hi >= lo && isfinite(cap))
                    add = rad_dmin(add, rad_dmax(0.0, cap - x->var[c]));
            }
            x->var[c] += add;
        }
        return;
    }
    for (int k = 0; k < 4; k++)
        leaf_var_below(h, x->first_child + k, r, vs);
}

/* The range of B (lo, hi: 3 per element) of the sources of the element
 * links at e and its ancestors: a parent's range widened by e's own. */
static void range_below(rad_hier *h, int e, const double up_lo[3], const double up_hi[3],
                        double *lo, double *hi)
{
    for (int c = 0; c < 3; c++) {
        size_t i = 3 * (size_t)e + (size_t)c;
        lo[i] = rad_dmin(lo[i], up_lo[c]);
        hi[i] = rad_dmax(hi[i], up_hi[c]);
    }
    const hier_elem *x = &h->el[e];
    if (x->first_child < 0)
        return;
    for (int k = 0; k < 4; k++)
        range_below(h, x->first_child + k, lo + 3 * (size_t)e, hi + 3 * (size_t)e, lo, hi);
}

/* What a residual of the link bringing source s's light to an element whose
 * sources' B range over lo..hi (channel c) is multiplied by in the
 * element's variation.  Unsealed, s's B.  Sealed, the true form factors at
 * a point sum to 1, so the residuals of a point's links sum to a linear
 * function and only B's differences between its sources count; but a
 * residual stands against those of other links that may be ancestors'
 * links whose nodes missed what this link's saw (a ceiling element over
 * the edge of a box top close under it sees the bright top on one side
 * and, beside it, the darker room the top hides), so against the farthest
 * of the sources. */
static double residual_weight(const rad_hier *h, const hier_elem *s, double lo, double hi, int c)
{
    if (!h->p.sealed)
        return s->B[c];
    return rad_dmax(fabs(s->B[c] - lo), fabs(s->B[c] - hi));
}

/* rho r w per element and channel, summed over its own element links,
 * then the range of its sources' B at it and its ancestors: res, lo, hi,
 * 3 nel + 1 each, for leaf_var_below; NULL when out of memory. */
static double *link_residuals(rad_hier *h)
{
    size_t n = h->nroots, m = 3 * h->nel + 1;
    double *res = calloc(3 * m, sizeof *res);
    if (!res)
        return NULL;
    double *lo = res + m, *hi = lo + m;
    for (size_t i = 0; i < m; i++) {
        lo[i] = INFINITY;
        hi[i] = -INFINITY;
    }
    for (size_t k = 0; k < h->nln; k++) {
        const hier_link *l = &h->ln[k];
        if (l->a < 0)
            continue;
        for (int c = 0; c < 3; c++) {
            size_t ia = 3 * (size_t)l->a + (size_t)c, ib = 3 * (size_t)l->b + (size_t)c;
            double Ba = h->el[l->a].B[c], Bb = h->el[l->b].B[c];
            lo[ia] = rad_dmin(lo[ia], Bb);
            hi[ia] = rad_dmax(hi[ia], Bb);
            lo[ib] = rad_dmin(lo[ib], Ba);
            hi[ib] = rad_dmax(hi[ib], Ba);
        }
    }
    int threads = hier_threads(h), chunk = hier_root_chunk(n, threads);
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads) if (n > 1)
    for (long long t = 0; t < (long long)n; t++) {
        double up_lo[3] = {INFINITY, INFINITY, INFINITY};
        double up_hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        range_below(h, (int)t, up_lo, up_hi, lo, hi);
    }
    for (size_t k = 0; k < h->nln; k++) {
        const hier_link *l = &h->ln[k];
        if (l->a < 0)
            continue;
        const hier_elem *a = &h->el[l->a], *b = &h->el[l->b];
        for (int c = 0; c < 3; c++) {
            size_t ch = (size_t)c * n;
            size_t ia = 3 * (size_t)l->a + (size_t)c, ib = 3 * (size_t)l->b + (size_t)c;
            res[ia] += h->rho[(size_t)a->face + ch] * l->ra *
                       residual_weight(h, b, lo[ia], hi[ia], c);
            res[ib] += h->rho[(size_t)b->face + ch] * l->rb *
                       residual_weight(h, a, lo[ib], hi[ib], c);
        }
    }
    return res;
}

/* The leaves' extremes of B per channel. */
static void leaf_extremes(const rad_hier *h, double lo[3], double hi[3])
{
    for (int c = 0; c < 3; c++) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
    }
    for (size_t e = 0; e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        for (int c = 0; c < 3; c++) {
            lo[c] = rad_dmin(lo[c], x->B[c]);
            hi[c] = rad_dmax(hi[c], x->B[c]);
        }
    }
}

rad_status hier_inner_spread(rad_hier *h, int residuals)
{
    size_t n = h->nroots, m = 3 * h->nel + 1;
    double *res = residuals ? link_residuals(h) : NULL;
    if (residuals && !res)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the variation of %zu elements",
                         h->nel);
    double glo[3], ghi[3];
    var_sources vs = {res, NULL, NULL, NULL, NULL};
    if (res) {
        vs.lo = res + m;
        vs.hi = res + 2 * m;
    }
    if (res && h->ncln > 0) {
        leaf_extremes(h, glo, ghi);
        vs.glo = glo;
        vs.ghi = ghi;
    }
    int threads = hier_threads(h), chunk = hier_root_chunk(n, threads);
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads) if (n > 1)
    for (long long t = 0; t < (long long)n; t++) {
        double lo[3], hi[3], zero[3] = {0.0, 0.0, 0.0};
        leaf_var_below(h, (int)t, zero, res ? &vs : NULL);
        pull_gradient(h, (int)t);
        spread(h, (int)t, lo, hi);
    }
    free(res);
    return RAD_OK;
}

/* The local errors of F over every element, area-weighted, the channels
 * summed (before push_local: a parent's area is its children's, so this is
 * the sum the leaves will hold). */
static double local_sum(const rad_hier *h)
{
    double sum = 0.0;
    for (size_t e = 0; e < h->nel; e++)
        sum += h->el[e].area * (h->el[e].q[0] + h->el[e].q[1] + h->el[e].q[2]);
    return sum;
}

rad_status hier_error_estimate(rad_hier *h, int residuals)
{
    double t0 = rad_sys_seconds();
    size_t n = h->nroots;
    int threads = hier_threads(h), chunk = hier_root_chunk(n, threads);
    h->iter_err = iteration_error(h);
    rad_status st = hier_inner_spread(h, residuals);
    if (st != RAD_OK)
        return st;
#pragma omp parallel for schedule(static) num_threads(threads) if (h->nel > 65536)
    for (long long e = 0; e < (long long)h->nel; e++) {
        hier_elem *x = &h->el[e];
        for (int c = 0; c < 3; c++)
            x->q[c] = x->d[c] = x->dr[c] = 0.0;
    }
    for (size_t k = 0; k < h->nln; k++) {
        const hier_link *l = &h->ln[k];
        if (l->a < 0)
            continue;
        hier_elem *a = &h->el[l->a], *b = &h->el[l->b];
        for (int c = 0; c < 3; c++) {
            double ra = h->rho[(size_t)a->face + c * n], rb = h->rho[(size_t)b->face + c * n];
            /* a <- b */
            double wb = hier_weight(h, a, b, c), wa = hier_weight(h, b, a, c);
            a->q[c] += ra * l->dG / a->area * wb;
            a->d[c] += sq(ra * l->vb * b->var[c]);
            a->dr[c] += ra * l->ra * wb;
            /* b <- a */
            b->q[c] += rb * l->dG / b->area * wa;
            b->d[c] += sq(rb * l->va * a->var[c]);
            b->dr[c] += rb * l->rb * wa;
        }
    }
    double element_part = h->ncl ? local_sum(h) : 0.0;
    st = hier_cluster_local(h);
    if (st != RAD_OK)
        return st;
    double all = h->ncl ? local_sum(h) : 0.0;
    h->st.local_cluster = all > 0.0 ? (all - element_part) / all : 0.0;
    double zero[3] = {0, 0, 0};
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads) if (n > 1)
    for (long long t = 0; t < (long long)n; t++)
        push_local(h, (int)t, zero, zero, zero);
    /* the link terms bound the error of a leaf's irradiance before its cap:
       what a cap took off is charged to the leaf too */
    for (size_t e = 0; !h->p.sealed && e < h->nel; e++) {
        hier_elem *x = &h->el[e];
        if (x->first_child >= 0 || !(x->cap > 0.0 && x->cap < 1.0))
            continue;
        for (int c = 0; c < 3; c++)
            x->q[c] += fabs(x->B[c] - h->E[(size_t)x->face + c * n]) * (1.0 / x->cap - 1.0);
    }
    /* a leaf's local error is q + sqrt(d); T = q + rho K T, whose solution
       lies above q: start from q on the leaves, or from the last estimate's
       T where that is larger (a leaf made since has its parent's) */
#pragma omp parallel for schedule(static) num_threads(threads) if (h->nel > 65536)
    for (long long e = 0; e < (long long)h->nel; e++) {
        hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        for (int c = 0; c < 3; c++) {
            x->q[c] += sqrt(x->d[c]);
            x->T[c] = rad_dmax(x->q[c], x->T[c]);
        }
    }
    int it;
    double last = 0.0, last_rel = -1.0; /* the last change, and over its tmax */
    hier_accel_begin(h, CARRY_T, h->p.bound_tol);
    for (it = 0; it < h->p.max_iterations; it++) {
        if (it > 0)
            hier_accel_mix(h);
        if ((st = hier_accel_save(h, last_rel)) != RAD_OK)
            break;
        double change = 0.0, tmax = 0.0; /* one step of T = q + rho K T */
        if ((st = gather_push_pull(h, CARRY_T, &change, &tmax)) != RAD_OK)
            break;
        if (!isfinite(change) || !isfinite(tmax)) {
            st = RAD_ERROR(RAD_ENUMERIC, "hier: the error bound is not finite");
            break;
        }
        hier_working(h, "bounding", (size_t)it + 1);
        h->st.iterations_bound++;
        last = change;
        last_rel = tmax > 0.0 ? change / tmax : 0.0;
        if (change <= h->p.bound_tol * tmax)
            break;
    }
    h->T_tail = fixed_point_tail(h, last);
    if (st == RAD_OK && it == h->p.max_iterations)
        st = RAD_ERROR(RAD_ENUMERIC, "hier: the error transport did not converge in %d steps",
                       h->p.max_iterations);
    /* the figures of the bound */
    double R = hier_reflected_scale(h), total = 0.0, sum = 0.0, leaf_max = 0.0;
    double *face_area = NULL, *face_sum = NULL;
    face_area = calloc(4 * n, sizeof *face_area);
    if (face_area)
        face_sum = face_area + n;
    for (size_t e = 0; e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        total += x->area;
        for (int c = 0; c < 3; c++) {
            double b = hier_leaf_bound(h, x, c), bf = hier_face_part(h, x, c);
            sum += x->area * bf;
            leaf_max = rad_dmax(leaf_max, b);
            if (face_sum)
                face_sum[(size_t)x->face * 3 + (size_t)c] += x->area * bf;
        }
        if (face_area)
            face_area[x->face] += x->area;
    }
    double face_max = 0.0;
    for (size_t f = 0; face_sum && f < n; f++)
        for (int c = 0; c < 3; c++)
            if (face_area[f] > 0.0)
                face_max = rad_dmax(face_max, face_sum[3 * f + (size_t)c] / face_area[f]);
    free(face_area);
    h->st.reflected = R;
    h->st.bound_leaf_max = R > 0.0 ? leaf_max / R : 0.0;
    h->st.bound_face_max = R > 0.0 ? face_max / R : 0.0;
    h->st.bound_mean = R > 0.0 && total > 0.0 ? sum / (3.0 * total * R) : 0.0;
    h->st.target_met = h->st.bound_face_max <= h->p.eps;
    double spent = rad_sys_seconds() - t0;
    h->st.time_solve_s += spent;
    h->st.time_bound_s += spent;
    return st;
}

double rad_hier_solve_tolerance(const rad_hier_params *p, double share, double rho_max, double R,
                                double bmax)
{
    double scale = bmax > 0.0 ? R / bmax : 1.0;
    return rad_dmax(p->tol, share * p->eps * (1.0 - rho_max) / 2.0 * scale);
}

/* A solve to share eps R (rad_hier_solve_tolerance), again while the
 * tolerance from its own R and bmax is tighter than the one it met. */
static rad_status solve_share(rad_hier *h, double share)
{
    for (;;) {
        double t = rad_hier_solve_tolerance(&h->p, share, h->rho_max, hier_reflected_scale(h),
                                            h->last_bmax);
        if (h->stepped && h->last_change <= t)
            return RAD_OK;
        rad_status st = hier_solve_links(h, t);
        if (st != RAD_OK)
            return st;
    }
}

rad_status rad_hier_solve(rad_hier *h)
{
    if (!h)
        return RAD_ERROR(RAD_EINVAL, "hier: no handle");
    rad_status st = solve_share(h, h->p.round_tol);
    int round, settled = 0;
    for (round = 0; st == RAD_OK; round++) {
        if (h->p.progress)
            h->p.progress(round, rad_hier_leaf_count(h), h->nln + h->ncln, h->p.progress_ctx);
        if (round >= h->p.max_rounds)
            break;
        h->round = round + 1;
        long long n = 0;
        double links = (double)(h->nln + h->ncln);
        st = rad_hier_refine(h, &n);
        settled = st == RAD_OK && n > 0 && (double)n < h->p.round_min * links;
        if (settled) {
            /* the few links B's last change pushed over their thresholds:
               settled, as if the round had refined nothing */
            st = solve_share(h, h->p.round_tol);
            n = 0;
        }
        if (st == RAD_OK && n == 0 && h->p.oracle == RAD_HIER_ORACLE_ERROR &&
            h->p.max_tighten > 0) {
            /* nothing left above the thresholds: where the bound still exceeds
               eps R, tighten them (refine.c) and go on */
            int tightened = 0;
            if ((st = hier_error_estimate(h, 0)) == RAD_OK &&
                (st = hier_tighten_failing(h, &tightened)) == RAD_OK && tightened > 0)
                st = rad_hier_refine(h, &n);
        }
        if (st != RAD_OK || n == 0)
            break;
        settled = 0;
        st = solve_share(h, h->p.round_tol);
    }
    h->round = settled ? round + 1 : round; /* the final solve's */
    /* the last report is the final hierarchy, which a settled round changed */
    if (st == RAD_OK && settled && h->p.progress)
        h->p.progress(round + 1, rad_hier_leaf_count(h), h->nln + h->ncln, h->p.progress_ctx);
    if (st == RAD_OK)
        st = solve_share(h, h->p.final_share);
    if (st == RAD_OK)
        st = hier_error_estimate(h, 1);
    return st;
}
