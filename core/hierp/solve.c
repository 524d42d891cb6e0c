/* rad_hierp: gather / push-pull, the rows, and the error estimate.
 *
 * 1. Step (Jacobi): every element gathers H = sum over its links of K b_s
 *    (K^T for the link's other end), with the old coefficients; push: in
 *    index order (a parent comes before its children) an element adds its
 *    parent's H restricted to it (P[child]); a leaf takes b = e + rho H, e
 *    the emission's coefficients (E sqrt(A) on the constant); pull: in
 *    reverse order a parent takes the projection of its children's
 *    functions, sum_c P[c]^T b_c (exact: the parent's functions restricted to
 *    a child lie in the child's space).  A mode the step does not contract
 *    has its loop's couplings beyond the constants' dropped (drop_unstable).
 * 2. Rows: the same gather and push with B = 1 everywhere gives each leaf
 *    its row, the irradiance a uniform unit radiosity would bring (1
 *    everywhere, exactly, in a scene whose every point sees only front
 *    faces).  In such a sealed scene each leaf's irradiance is corrected to
 *    H + (u - row) H_0 / row_0 (u the unit function): a uniform radiosity
 *    then gathers exactly itself, so the hierarchy's approximations move
 *    light around without creating or losing any, which reflectance near 1
 *    would amplify.  A source's power reaches the leaves through the
 *    couplings' columns, which are not exact: in the exact transport of a
 *    sealed scene a slope (a zero-mean variation) sends no power, but the
 *    hierarchy's couplings of a slope do not sum to zero over the
 *    receivers.  Each leaf's send (hp_rows) says what a unit of each of
 *    its coefficients brings the leaves as their normalized irradiance
 *    counts power.  The positivity limiter (limit) cuts slopes, all one
 *    way at narrow gaps: what its cut would send is taken off the constant
 *    the leaf sends (charge, in units of sqrt(A), what a unit constant
 *    sends in the exact transport, not of the leaf's own send, which is
 *    small where the leaf sees little), so that it moves light without
 *    making any.  And each step multiplies every leaf's irradiance by the
 *    gain, the power the leaves send over what their sends count
 *    (copy_sources): 1 for a uniform radiosity, which gathers itself, and
 *    otherwise taking back what the columns' error would make or lose.
 *    In an open scene a row whose mean exceeds the ceiling of
 *    rad_hier_row_ceiling (between 1 and 1 / rho_max) is scaled back to it,
 *    so that the step contracts; what that takes off a leaf is charged to
 *    its error (3).
 * 3. The error estimate: each link brings its receivers the errors of
 *    hp_link_errors (W/m^2, per channel); a leaf's local error q sums those
 *    of the links at it and at its ancestors; T = q + rho F T is solved by
 *    the same gather / push-pull on the constants (to bound_tol), which
 *    carries each local error through every bounce (up to 1 / (1 - rho)).
 *    A leaf's T bounds its pointwise error, an input triangle's area-weighted
 *    mean of T the error of its mean; reported relative to R, the
 *    area-weighted mean reflected radiosity. */
#include "hierp_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_sys.h"

#include <omp.h>

/* The gain stays within HP_GAIN_MAX of 1: the columns' error is a few 1e-4
   of the power, and a mode the step does not contract, which the gain would
   otherwise hold at a large amplitude, must grow for the watch to see it
   (hp_solve_links). */
#define HP_GAIN_MAX 0.01

/* The watch's fast test (hp_solve_links): a change this many times the
   round's lowest, after at least this many steps of the round. */
#define HP_GROWTH 1e3
#define HP_GROWTH_STEPS 20

rad_status hp_incidence(rad_hierp *h)
{
    if (h->inc_valid && h->inc_nel == h->nel)
        return RAD_OK;
    size_t ne = h->nel, nl = h->nln;
    size_t *start = realloc(h->inc_start, (ne + 1) * sizeof *start);
    if (!start)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu elements' links", ne);
    h->inc_start = start;
    if (2 * nl > h->inc_cap) {
        size_t *inc = realloc(h->inc, 2 * nl * sizeof *inc);
        if (inc)
            h->inc = inc;
        int *src = inc ? realloc(h->inc_src, 2 * nl * sizeof *src) : NULL;
        if (!src)
            return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu links", nl);
        h->inc_src = src;
        h->inc_cap = 2 * nl;
    }
    if (ne > h->Bs_cap) {
        double *Bs = realloc(h->Bs, ne * 3 * HP_M * sizeof *Bs);
        if (!Bs)
            return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu elements", ne);
        h->Bs = Bs;
        h->Bs_cap = ne;
    }
    memset(start, 0, (ne + 1) * sizeof *start);
    for (size_t k = 0; k < nl; k++) {
        start[h->ln[k].a + 1]++;
        start[h->ln[k].b + 1]++;
    }
    for (size_t e = 0; e < ne; e++)
        start[e + 1] += start[e];
    for (size_t k = 0; k < nl; k++) { /* start[e] runs ahead, then is restored */
        size_t ia = start[h->ln[k].a]++, ib = start[h->ln[k].b]++;
        h->inc[ia] = 2 * k;
        h->inc_src[ia] = h->ln[k].b;
        h->inc[ib] = 2 * k + 1;
        h->inc_src[ib] = h->ln[k].a;
    }
    for (size_t e = ne; e > 0; e--)
        start[e] = start[e - 1];
    start[0] = 0;
    h->inc_nel = ne;
    h->inc_valid = 1;
    return RAD_OK;
}

/* H[c] += M b[c] per channel, M the m x m matrix M_rt = K[r rs + t cs]
 * (K itself or its transpose); inlined with constants, the loops unroll. */
static inline void add_product(double H[3][HP_M], const double *K, const double *b, const int m,
                               const int rs, const int cs)
{
    for (int c = 0; c < 3; c++)
#pragma GCC unroll 6
        for (int r = 0; r < m; r++) {
            double v = 0.0;
#pragma GCC unroll 6
            for (int t = 0; t < m; t++)
                v += K[r * rs + t * cs] * b[c * m + t];
            H[c][r] += v;
        }
}

/* Element x's H from its own links, with m a constant at each call (below)
 * so that the m x m products unroll; the sources' B from the copy Bs. */
static inline void gather_elem(const rad_hierp *h, size_t e, int unit, const int m)
{
    hp_elem *x = &h->el[e];
    const size_t mm = (size_t)m * (size_t)m;
    double H[3][HP_M] = {{0.0}};
    for (size_t i = h->inc_start[e]; i < h->inc_start[e + 1]; i++) {
        const double *K = h->K + (h->inc[i] >> 1) * mm;
        const int is_b = (int)(h->inc[i] & 1);
        int s = h->inc_src[i];
        if (unit) {
            /* B = 1: coefficients sqrt(A) on the constant, in channel 0 */
            double u = sqrt(h->el[s].area);
            for (int r = 0; r < m; r++)
                H[0][r] += K[is_b ? r : r * m] * u;
            continue;
        }
        const double *b = h->Bs + (size_t)s * 3 * (size_t)m;
        if (is_b)
            add_product(H, K, b, m, 1, m); /* K^T b_s */
        else
            add_product(H, K, b, m, m, 1); /* K b_s */
    }
    memcpy(x->H, H, sizeof H);
}

/* Every element's H from its own links, in parallel over the elements, each
 * summing its links in link order: the result does not depend on the
 * thread count.  The sources are the copy Bs (unit: B = 1 everywhere).  The
 * push follows, per tree (push_rows, step_tree). */
static void gather(rad_hierp *h, int unit)
{
    int m = h->m;
    int threads = h->p.threads > 0 ? h->p.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads) if (h->nel > 64)
    for (long long e = 0; e < (long long)h->nel; e++) {
        switch (m) {
        case 1: gather_elem(h, (size_t)e, unit, 1); break;
        case 3: gather_elem(h, (size_t)e, unit, 3); break;
        default: gather_elem(h, (size_t)e, unit, HP_M); break; /* p2: m = 6 */
        }
    }
}

/* What leaf x sends in channel c, into v: its B, and sealed with what the
 * limiter's change of its slopes sends taken off its constant (2 in the
 * header). */
static void sent(const rad_hierp *h, const hp_elem *x, int c, double *v)
{
    memcpy(v, x->B[c], (size_t)h->m * sizeof *v);
    if (h->p.sealed && h->m > 1)
        v[0] -= x->charge[c];
}

/* Each inner element's copy in Bs: the projection of its children's. */
static void pull_sources(rad_hierp *h)
{
    int m = h->m;
    for (size_t e = h->nel; e-- > 0;) { /* a parent comes before its children */
        const hp_elem *x = &h->el[e];
        if (x->first_child < 0)
            continue;
        double *v = h->Bs + e * 3 * (size_t)m;
        for (int c = 0; c < 3; c++)
            for (int r = 0; r < m; r++) {
                double t = 0.0;
                for (int ch = 0; ch < 4; ch++) {
                    const double *y = h->Bs + (size_t)(x->first_child + ch) * 3 * (size_t)m;
                    for (int s = 0; s < m; s++)
                        t += h->P[ch][s][r] * y[c * m + s];
                }
                v[c * m + r] = t;
            }
    }
}

/* The gather's sources: every element's B into Bs; sealed, what the leaves
 * send and, on the inner elements, its projection, and the step's gain. */
static void copy_sources(rad_hierp *h)
{
    int m = h->m, send = h->p.sealed;
    double leave[3] = {0.0}, counted[3] = {0.0};
    for (size_t e = 0; e < h->nel; e++) {
        const hp_elem *x = &h->el[e];
        if (send && x->first_child >= 0)
            continue; /* pull_sources writes it */
        for (int c = 0; c < 3; c++) {
            double *v = h->Bs + (e * 3 + (size_t)c) * (size_t)m;
            if (!send) {
                memcpy(v, x->B[c], (size_t)m * sizeof *v);
                continue;
            }
            sent(h, x, c, v);
            leave[c] += sqrt(x->area) * x->B[c][0];
            for (int k = 0; k < m; k++)
                counted[c] += x->send[k] * v[k];
        }
    }
    if (!send)
        return;
    pull_sources(h);
    h->st.gain = 1.0;
    for (int c = 0; c < 3; c++) {
        h->gain[c] = counted[c] > 0.0 && leave[c] > 0.0
                         ? rad_dmin(1.0 + HP_GAIN_MAX,
                                    rad_dmax(1.0 - HP_GAIN_MAX, leave[c] / counted[c]))
                         : 1.0;
        if (fabs(h->gain[c] - 1.0) > fabs(h->st.gain - 1.0))
            h->st.gain = h->gain[c];
    }
}

/* The per-element parts of the push, the step and the pull, with m (the
 * basis size) a constant in each (visit dispatches on it once per element)
 * so that the loops over the basis unroll. */

/* x's H plus its parent's, restricted to x (channels 0 .. channels - 1). */
static inline void push_elem(const rad_hierp *h, hp_elem *x, int channels, const int m)
{
    if (x->parent < 0)
        return;
    const hp_elem *p = &h->el[x->parent];
    for (int c = 0; c < channels; c++)
        for (int r = 0; r < m; r++) {
            double v = 0.0;
            for (int s = 0; s < m; s++)
                v += h->P[x->child][r][s] * p->H[c][s];
            x->H[c][r] += v;
        }
}

/* The positivity limiter: v's non-constant part scaled so that the function
 * is >= 0 at the rule's nodes, its mean kept; a negative mean is raised to 0. */
static inline void limit(const rad_hierp *h, double *v, const int m)
{
    double lo = INFINITY;
    for (int i = 0; i < h->nodes; i++) {
        double f = 0.0;
        for (int k = 0; k < m; k++)
            f += v[k] * h->rq[i][k];
        lo = rad_dmin(lo, f);
    }
    if (!(lo < 0.0))
        return;
    if (!(v[0] > 0.0)) {
        for (int k = 0; k < m; k++)
            v[k] = 0.0;
        return;
    }
    double theta = v[0] / (v[0] - lo); /* q_0 = 1: the mean's coefficient */
    for (int k = 1; k < m; k++)
        v[k] *= theta;
}

/* An inner element's B: the projection of its children's functions. */
static inline void pull_elem(const rad_hierp *h, hp_elem *x, const int m)
{
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < m; r++) {
            double v = 0.0;
            for (int ch = 0; ch < 4; ch++) {
                const hp_elem *y = &h->el[x->first_child + ch];
                for (int s = 0; s < m; s++)
                    v += h->P[ch][s][r] * y->B[c][s];
            }
            x->B[c][r] = v;
        }
}

/* A leaf's new B from its gathered H; the change of its mean and the mean
 * (per channel, the largest) into *change and *vmax. */
static inline void leaf_update(const rad_hierp *h, hp_elem *x, double *change, double *vmax,
                               const int m)
{
    size_t n = h->nroots;
    double sa = sqrt(x->area), r0 = x->row[0];
    for (int c = 0; c < 3; c++) {
        double t[HP_M];
        memcpy(t, x->H[c], sizeof t);
        if (h->p.sealed && r0 > 0.0) {
            double s = t[0] / r0;
            for (int k = 0; k < m; k++)
                t[k] = (t[k] + ((k == 0 ? sa : 0.0) - x->row[k]) * s) * h->gain[c];
        } else if (r0 > h->row_ceiling * sa) {
            for (int k = 0; k < m; k++)
                t[k] *= h->row_ceiling * sa / r0;
        }
        int charged = h->p.sealed && m > 1; /* the limiter's cut is charged */
        double u[HP_M];
        if (charged)
            memcpy(u, t, sizeof u);
        if (m > 1 || t[0] < 0.0)
            limit(h, t, m);
        size_t f = (size_t)x->face + (size_t)c * n;
        double rho = h->rho[f];
        if (charged) {
            double d = 0.0;
            for (int k = 1; k < m; k++)
                d += x->send[k] * (t[k] - u[k]);
            x->charge[c] = rho * d / sa;
        }
        double old = x->B[c][0];
        for (int k = 0; k < m; k++)
            x->B[c][k] = rho * t[k] + x->Em[c][k];
        double d = fabs(x->B[c][0] - old) / sa, v = fabs(x->B[c][0]) / sa;
        *change = isfinite(d) ? rad_dmax(*change, d) : INFINITY;
        *vmax = rad_dmax(*vmax, v);
    }
}

enum visit_part { VISIT_PUSH_ROWS, VISIT_PUSH_SEND, VISIT_PUSH, VISIT_LEAF, VISIT_PULL };

/* always inlined: each case of visit gets its own copy with m constant */
__attribute__((always_inline)) static inline void visit_m(const rad_hierp *h, hp_elem *x,
                                                          enum visit_part part, double *change,
                                                          double *vmax, const int m)
{
    switch (part) {
    case VISIT_PUSH_ROWS:
        push_elem(h, x, 1, m);
        memcpy(x->row, x->H[0], sizeof x->row);
        break;
    case VISIT_PUSH_SEND:
        push_elem(h, x, 1, m);
        memcpy(x->send, x->H[0], sizeof x->send);
        break;
    case VISIT_PUSH: push_elem(h, x, 3, m); break;
    case VISIT_LEAF: leaf_update(h, x, change, vmax, m); break;
    case VISIT_PULL: pull_elem(h, x, m); break;
    }
}

static void visit(const rad_hierp *h, hp_elem *x, enum visit_part part, double *change,
                  double *vmax)
{
    switch (h->m) {
    case 1: visit_m(h, x, part, change, vmax, 1); break;
    case 3: visit_m(h, x, part, change, vmax, 3); break;
    default: visit_m(h, x, part, change, vmax, HP_M); break; /* p2: m = 6 */
    }
}

/* The rows' (or the sends') push down the tree of element e. */
static void push_rows(rad_hierp *h, int e, enum visit_part part)
{
    hp_elem *x = &h->el[e];
    visit(h, x, part, NULL, NULL);
    if (x->first_child >= 0)
        for (int ch = 0; ch < 4; ch++)
            push_rows(h, x->first_child + ch, part);
}

static void push_all(rad_hierp *h, enum visit_part part)
{
    int threads = h->p.threads > 0 ? h->p.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (h->nel > 64)
    for (long long t = 0; t < (long long)h->nroots; t++)
        push_rows(h, (int)t, part);
}

void hp_rows(rad_hierp *h)
{
    gather(h, 1);
    push_all(h, VISIT_PUSH_ROWS);
    if (!h->p.sealed)
        return;
    /* send = L g, L the gather with its push and pull (symmetric: a link's
       K one way and K^T the other, the push P and the pull P^T) and g the
       leaves' weights as their normalized irradiance counts power, A / row_0
       on the constant: a leaf receives A t_0 / sqrt(A) = A H_0 / row_0 */
    int m = h->m;
    memset(h->Bs, 0, h->nel * 3 * (size_t)m * sizeof *h->Bs);
    for (size_t e = 0; e < h->nel; e++) {
        const hp_elem *x = &h->el[e];
        if (x->first_child < 0)
            h->Bs[e * 3 * (size_t)m] = x->row[0] > 0.0 ? x->area / x->row[0] : sqrt(x->area);
    }
    pull_sources(h);
    gather(h, 0);
    push_all(h, VISIT_PUSH_SEND);
}

/* Push, leaf update and pull over the tree of element e (parents are pushed
 * before their children and pulled after them). */
static void step_tree(rad_hierp *h, int e, double *change, double *vmax)
{
    hp_elem *x = &h->el[e];
    visit(h, x, VISIT_PUSH, change, vmax);
    if (x->first_child < 0) {
        visit(h, x, VISIT_LEAF, change, vmax);
        return;
    }
    for (int ch = 0; ch < 4; ch++)
        step_tree(h, x->first_child + ch, change, vmax);
    visit(h, x, VISIT_PULL, change, vmax);
}

/* One Jacobi step; the largest change of a leaf's mean and the largest mean.
 * The trees are independent after the gather: in parallel over them. */
static void step(rad_hierp *h, double *change, double *vmax)
{
    copy_sources(h);
    gather(h, 0);
    int threads = h->p.threads > 0 ? h->p.threads : omp_get_max_threads();
    double ch = 0.0, vm = 0.0;
#pragma omp parallel for schedule(dynamic, 1) reduction(max : ch, vm) num_threads(threads) if (h->nel > 64)
    for (long long t = 0; t < (long long)h->nroots; t++) {
        double c = 0.0, v = 0.0;
        step_tree(h, (int)t, &c, &v);
        ch = ch > c ? ch : c;
        vm = vm > v ? vm : v;
    }
    *change = ch;
    *vmax = vm;
}

/* Link k's couplings beyond the constants' dropped: what they could bring,
 * sqrt(A_a A_b) sum over the dropped (r, t) of qmax_r qmax_t |K_rt| per unit
 * of the source's bound, joins its integration error dG, which the estimate,
 * the oracle and the choice of the element to split all charge. */
static void drop_couplings(rad_hierp *h, size_t k)
{
    hp_link *l = &h->ln[k];
    int m = h->m;
    double *K = h->K + k * (size_t)(m * m), d = 0.0;
    for (int r = 0; r < m; r++)
        for (int t = 0; t < m; t++)
            if (r > 0 || t > 0) {
                d += h->qmax[r] * h->qmax[t] * fabs(K[r * m + t]);
                K[r * m + t] = 0.0;
            }
    l->dG += sqrt(h->el[l->a].area * h->el[l->b].area) * d;
    l->constant = 1;
}

/* How far the last step moved what leaf e sends: a bound over the element
 * and the channels against the step's copy of the one before (Bs). */
static double moved(const rad_hierp *h, size_t e)
{
    const hp_elem *x = &h->el[e];
    const double *old = h->Bs + e * 3 * (size_t)h->m;
    double v = 0.0;
    for (int c = 0; c < 3; c++) {
        double d[HP_M];
        sent(h, x, c, d);
        for (int k = 0; k < h->m; k++)
            d[k] -= old[c * h->m + k];
        v = rad_dmax(v, hp_poly_bound(h, d, x->area));
    }
    return v;
}

/* A mode the step does not contract (the couplings' quadrature and the rows'
 * normalization can lift one above 1 / rho where the transport's own
 * eigenvalues come close to 1, as in a narrow gap at high reflectance, or
 * where a leaf that sees little, its row the tail of an ancestor's fit,
 * extrapolates its sources' slopes): the leaves the last step moved most
 * (a tenth of the largest move or more) mark themselves and their
 * ancestors, and the links that join two marked elements, the loop the
 * mode runs through, keep only their constants' coupling.  With constants only, a link is a nonnegative form factor, and
 * rows so made contract as p0's do.  When no such link is left, the links
 * with one marked end go, then every link.  The number dropped. */
static size_t drop_unstable(rad_hierp *h)
{
    unsigned char *mark = calloc(h->nel, 1);
    double *move = malloc(h->nel * sizeof *move);
    if (!mark || !move) {
        free(mark);
        free(move);
        return 0;
    }
    double top = 0.0;
    for (size_t e = 0; e < h->nel; e++) {
        move[e] = h->el[e].first_child < 0 ? moved(h, e) : 0.0;
        top = rad_dmax(top, move[e]);
    }
    for (size_t e = 0; e < h->nel; e++)
        mark[e] = h->el[e].first_child < 0 && move[e] >= 0.1 * top;
    for (size_t e = h->nel; e-- > 0;) /* a parent comes before its children */
        if (mark[e] && h->el[e].parent >= 0)
            mark[h->el[e].parent] = 1;
    size_t dropped = 0;
    for (int pass = 0; pass < 3 && dropped == 0; pass++)
        for (size_t k = 0; k < h->nln; k++) {
            const hp_link *l = &h->ln[k];
            int ends = mark[l->a] + mark[l->b];
            if (!l->constant && (pass == 2 || ends >= 2 - pass)) {
                drop_couplings(h, k);
                dropped++;
            }
        }
    free(mark);
    free(move);
    return dropped;
}

/* Every element's coefficients and charges, saved into `good` (into != 0)
 * or restored from it (hp_solve_links saves them whenever the change falls
 * to half the saved state's). */
static void keep_state(rad_hierp *h, double *good, int into)
{
    size_t w = 3 * (size_t)HP_M + 3;
    for (size_t e = 0; e < h->nel; e++) {
        hp_elem *x = &h->el[e];
        double *g = good + e * w;
        if (into) {
            memcpy(g, x->B, sizeof x->B);
            memcpy(g + 3 * HP_M, x->charge, sizeof x->charge);
        } else {
            memcpy(x->B, g, sizeof x->B);
            memcpy(x->charge, g + 3 * HP_M, sizeof x->charge);
        }
    }
}

rad_status hp_solve_links(rad_hierp *h, double tol)
{
    double t0 = rad_sys_seconds();
    rad_status st = RAD_OK;
    /* a step contracts the error by q or better (3 below), so over w steps
       the change falls by e^-2 or more: a change that has not fallen at all
       over w steps belongs to a mode that does not contract.  One that grows
       fast is seen sooner: a contracting step's change does not rise far
       above the lowest it reached, so a change HP_GROWTH times that lowest
       belongs to such a mode too.  After its couplings are dropped the solve
       goes on from the state of that lowest change, which the mode had not
       yet swamped (a mode grown large would take ln(size) / (1 - rho) steps
       to decay). */
    double q = h->p.sealed ? h->rho_max : 0.5 * (1.0 + h->rho_max);
    int w = q < 1.0 ? (int)rad_dmin(4000.0, rad_dmax(20.0, ceil(2.0 / (1.0 - q)))) : 4000;
    double *past = h->m > 1 ? malloc((size_t)w * sizeof *past) : NULL;
    if (h->m > 1 && h->nel > h->good_cap) {
        double *g = realloc(h->good, h->nel * (3 * (size_t)HP_M + 3) * sizeof *g);
        if (g) {
            h->good = g;
            h->good_cap = h->nel;
        }
    }
    double *good = h->good;
    if (h->m > 1 && (!past || h->nel > h->good_cap)) {
        free(past);
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the solve's watch (%zu elements)",
                         h->nel);
    }
    int since = 0;
    double low = INFINITY, kept = INFINITY; /* the round's lowest change; the saved state's */
    for (int it = 0;; it++, since++) {
        if (it >= h->p.max_iterations) {
            st = RAD_ERROR(RAD_ENUMERIC, "hier: gather/push-pull did not converge in %d steps "
                                         "(last change %.3g of the largest radiosity)",
                           h->p.max_iterations, h->last_change);
            break;
        }
        double change, vmax;
        step(h, &change, &vmax);
        h->st.iterations++;
        if (!isfinite(change) || !isfinite(vmax)) {
            st = RAD_ERROR(RAD_ENUMERIC, "hier: a radiosity is not finite after %d steps", it + 1);
            break;
        }
        h->last_change = vmax > 0.0 ? change / vmax : 0.0;
        h->last_vmax = vmax;
        if (change <= tol * vmax)
            break;
        if (past) {
            int slow = since >= w && change >= past[since % w];
            int fast = since >= HP_GROWTH_STEPS && change > HP_GROWTH * low;
            if ((slow || fast) && change > 1e-10 * vmax && drop_unstable(h) > 0) {
                if (kept < INFINITY)
                    keep_state(h, good, 0);
                hp_rows(h);
                since = -1;
                low = kept = INFINITY;
                continue;
            }
            past[since % w] = change;
            low = rad_dmin(low, change);
            if (change < 0.5 * kept) { /* saves at most log2 of the round's fall */
                keep_state(h, good, 1);
                kept = change;
            }
        }
    }
    free(past);
    h->st.residual = h->last_change;
    h->st.time_solve_s += rad_sys_seconds() - t0;
    return st;
}

/* What an error of the form factor between receiver r and source s is
 * multiplied by (a bound over s): s's B, or in a sealed scene, where every
 * row is normalized so that such an error only moves light between the
 * sources of a receiver, how far s's B lies from r's irradiance. */
static double weight(const rad_hierp *h, const hp_elem *r, const hp_elem *s, int c)
{
    if (!h->p.sealed)
        return s->Bmax[c];
    double v[HP_M];
    memcpy(v, s->B[c], sizeof v);
    size_t f = (size_t)r->face + (size_t)c * h->nroots;
    double rho = h->rho[f];
    if (h->p.sealed && rho > 0.0)
        v[0] -= (r->B[c][0] / sqrt(r->area) - hp_emitted(r, c)) / rho * sqrt(s->area);
    return hp_poly_bound(h, v, s->area);
}

/* Link l's reflectances and error weights in channel c, each receiver's. */
typedef struct link_channel {
    double ra, rb; /* rho of a and b */
    double wa, wb; /* a as the source of b's errors, b as the source of a's (weight) */
} link_channel;

static link_channel channel(const rad_hierp *h, const hp_link *l, int c)
{
    const hp_elem *a = &h->el[l->a], *b = &h->el[l->b];
    size_t n = h->nroots;
    link_channel x = {h->rho[(size_t)a->face + (size_t)c * n],
                      h->rho[(size_t)b->face + (size_t)c * n], weight(h, b, a, c),
                      weight(h, a, b, c)};
    return x;
}

void hp_link_errors(const rad_hierp *h, const hp_link *l, double ea[3], double eb[3],
                    double ma[3], double mb[3])
{
    const hp_elem *a = &h->el[l->a], *b = &h->el[l->b];
    for (int c = 0; c < 3; c++) {
        link_channel x = channel(h, l, c);
        if (ea)
            ea[c] = x.ra * (l->dG / a->area * x.wb + l->ka * b->dev[c]);
        if (eb)
            eb[c] = x.rb * (l->dG / b->area * x.wa + l->kb * a->dev[c]);
        if (ma)
            ma[c] = x.ra * l->fa1 * x.wb;
        if (mb)
            mb[c] = x.rb * l->fb1 * x.wa;
    }
}

void hp_link_oracle(const rad_hierp *h, const hp_link *l, double *oa, double *ob)
{
    const hp_elem *a = &h->el[l->a], *b = &h->el[l->b];
    *oa = *ob = 0.0;
    for (int c = 0; c < 3; c++) {
        link_channel x = channel(h, l, c);
        double da = h->face_reach[a->face] * l->fa1, db = h->face_reach[b->face] * l->fb1;
        *oa = rad_dmax(*oa, x.ra * ((da + l->dG / a->area) * x.wb + l->kma * b->detail[c]));
        *ob = rad_dmax(*ob, x.rb * ((db + l->dG / b->area) * x.wa + l->kmb * a->detail[c]));
    }
}

void hp_pull_dev(rad_hierp *h)
{
    int m = h->m;
    /* a leaf departs from its polynomial by the departures its links and its
       ancestors' bring (dep, pushed down) */
    int threads = h->p.threads > 0 ? h->p.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads) if (h->nel > 64)
    for (long long e = 0; e < (long long)h->nel; e++) {
        hp_elem *x = &h->el[e];
        memset(x->dep, 0, sizeof x->dep);
        memset(x->dep1, 0, sizeof x->dep1);
        for (size_t i = h->inc_start[e]; i < h->inc_start[e + 1]; i++) {
            const hp_link *l = &h->ln[h->inc[i] >> 1];
            /* the departure terms at this end only (hp_link_errors gives
               their means for both ends): x receives from the other end */
            int at_b = (int)(h->inc[i] & 1);
            const hp_elem *s = &h->el[at_b ? l->a : l->b];
            double f = at_b ? l->fb : l->fa, f1 = at_b ? l->fb1 : l->fa1;
            for (int c = 0; c < 3; c++) {
                double rho = h->rho[(size_t)x->face + (size_t)c * h->nroots], w = weight(h, x, s, c);
                x->dep[c] += rho * f * w;
                x->dep1[c] += rho * f1 * w;
            }
        }
    }
    for (size_t e = 0; e < h->nel; e++) {
        hp_elem *x = &h->el[e];
        if (x->parent >= 0)
            for (int c = 0; c < 3; c++) {
                x->dep[c] += h->el[x->parent].dep[c];
                x->dep1[c] += h->el[x->parent].dep1[c];
            }
    }
    for (size_t e = h->nel; e-- > 0;) {
        hp_elem *x = &h->el[e];
        if (x->first_child < 0) {
            memcpy(x->dev, x->dep1, sizeof x->dev);
            memset(x->detail, 0, sizeof x->detail);
            continue;
        }
        for (int c = 0; c < 3; c++) {
            double d = 0.0, dd = 0.0;
            for (int ch = 0; ch < 4; ch++) {
                const hp_elem *y = &h->el[x->first_child + ch];
                double r[HP_M];
                for (int k = 0; k < m; k++) {
                    double v = 0.0;
                    for (int t = 0; t < m; t++)
                        v += h->P[ch][k][t] * x->B[c][t];
                    r[k] = y->B[c][k] - v;
                }
                double b = hp_poly_bound(h, r, y->area);
                d += 0.25 * (b + y->dev[c]);
                dd = rad_dmax(dd, b + y->detail[c]);
            }
            x->dev[c] = d;
            x->detail[c] = dd;
        }
    }
}

double hp_reflected(const rad_hierp *h)
{
    double num = 0.0, den = 0.0;
    for (size_t e = 0; e < h->nel; e++) {
        const hp_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        double sa = sqrt(x->area);
        for (int c = 0; c < 3; c++)
            num += x->area * (x->B[c][0] / sa - hp_emitted(x, c));
        den += 3.0 * x->area;
    }
    double R = den > 0.0 ? num / den : 0.0;
    return R > 0.0 ? R : h->E_max;
}

rad_status hp_estimate_error(rad_hierp *h)
{
    double t0 = rad_sys_seconds();
    rad_status st = hp_incidence(h);
    if (st != RAD_OK)
        return st;
    hp_bound_B(h);
    hp_pull_dev(h);
    for (size_t e = 0; e < h->nel; e++) {
        hp_elem *x = &h->el[e];
        x->q[0] = x->q[1] = x->q[2] = 0.0;
        x->T[0] = x->T[1] = x->T[2] = 0.0;
    }
    /* Sealed, each leaf's irradiance is divided by its own row, which the
       departures of its ancestors' linear couplings (zero-mean over their
       receivers, so elsewhere only pointwise errors) move leaf by leaf:
       there they count in the local error too. */
    for (size_t k = 0; k < h->nln; k++) {
        double ea[3], eb[3], ma[3], mb[3];
        const hp_link *l = &h->ln[k];
        hp_link_errors(h, l, ea, eb, h->p.sealed ? ma : NULL, h->p.sealed ? mb : NULL);
        for (int c = 0; c < 3; c++) {
            h->el[l->a].q[c] += ea[c] + (h->p.sealed ? ma[c] : 0.0);
            h->el[l->b].q[c] += eb[c] + (h->p.sealed ? mb[c] : 0.0);
        }
    }
    size_t n = h->nroots;
    for (size_t e = 0; e < h->nel; e++) {
        hp_elem *x = &h->el[e];
        if (x->parent >= 0)
            for (int c = 0; c < 3; c++)
                x->q[c] += h->el[x->parent].q[c];
        /* the link terms bound the error of a leaf's irradiance before the
           row ceiling scaled it (leaf_update): what that took off is
           charged to the leaf too */
        double sa = sqrt(x->area), row = x->row[0] / sa;
        if (x->first_child >= 0 || h->p.sealed || !(row > h->row_ceiling))
            continue;
        for (int c = 0; c < 3; c++)
            x->q[c] += fabs(x->B[c][0] / sa - hp_emitted(x, c)) *
                       (row / h->row_ceiling - 1.0);
    }
    /* T = q + rho F T, by the constants' gather / push-pull, each leaf's
       F scaled under the row ceiling by its row in that same gather (the
       sum of G / A over its links and its ancestors'), not by the solve's
       polynomial row, which also carries its ancestors' slopes into its
       mean and can lie below the constant row: only the transport's own
       rows held under the ceiling make it contract */
    int threads = h->p.threads > 0 ? h->p.threads : omp_get_max_threads();
    double *rowT = malloc(h->nel * sizeof *rowT);
    if (!rowT)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu elements", h->nel);
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads) if (h->nel > 64)
    for (long long e = 0; e < (long long)h->nel; e++) {
        double r = 0.0;
        for (size_t i = h->inc_start[e]; i < h->inc_start[e + 1]; i++)
            r += h->ln[h->inc[i] >> 1].G / h->el[e].area;
        rowT[e] = r;
    }
    for (size_t e = 0; e < h->nel; e++) /* a parent comes before its children */
        if (h->el[e].parent >= 0)
            rowT[e] += rowT[h->el[e].parent];
    double last = 0.0; /* the transport's last step change */
    for (int it = 0;; it++) {
        if (it >= h->p.max_iterations) {
            st = RAD_ERROR(RAD_ENUMERIC, "hier: the error transport did not converge in %d steps",
                           h->p.max_iterations);
            break;
        }
#pragma omp parallel for schedule(dynamic, 64) num_threads(threads) if (h->nel > 64)
        for (long long e = 0; e < (long long)h->nel; e++) {
            hp_elem *x = &h->el[e];
            memset(x->Tg, 0, sizeof x->Tg);
            for (size_t i = h->inc_start[e]; i < h->inc_start[e + 1]; i++) {
                const hp_link *l = &h->ln[h->inc[i] >> 1];
                const hp_elem *s = &h->el[(h->inc[i] & 1) ? l->a : l->b];
                for (int c = 0; c < 3; c++)
                    x->Tg[c] += l->G / x->area * s->T[c];
            }
        }
        double change = 0.0, tmax = 0.0;
        for (size_t e = 0; e < h->nel; e++) {
            hp_elem *x = &h->el[e];
            if (x->parent >= 0)
                for (int c = 0; c < 3; c++)
                    x->Tg[c] += h->el[x->parent].Tg[c];
            if (x->first_child >= 0)
                continue;
            double s = rowT[e] > h->row_ceiling ? h->row_ceiling / rowT[e] : 1.0;
            for (int c = 0; c < 3; c++) {
                double t = x->q[c] + h->rho[(size_t)x->face + (size_t)c * n] * s * x->Tg[c];
                change = rad_dmax(change, fabs(t - x->T[c]));
                tmax = rad_dmax(tmax, t);
                x->T[c] = t;
            }
        }
        for (size_t e = h->nel; e-- > 0;) {
            hp_elem *x = &h->el[e];
            if (x->first_child < 0)
                continue;
            for (int c = 0; c < 3; c++) {
                double v = 0.0;
                for (int ch = 0; ch < 4; ch++)
                    v += 0.25 * h->el[x->first_child + ch].T[c];
                x->T[c] = v;
            }
        }
        if (!isfinite(change)) {
            st = RAD_ERROR(RAD_ENUMERIC, "hier: the error estimate is not finite");
            break;
        }
        last = change;
        h->st.iterations_bound++;
        if (change <= h->p.bound_tol * tmax)
            break;
    }
    free(rowT);
    /* per leaf, per input triangle, over the scene */
    double R = hp_reflected(h);
    double *face = calloc(2 * n, sizeof *face);
    if (!face)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
    /* the iteration stopped at a step change delta: a step contracts the
       error by q <= rho_max (sealed, rows 1) or (1 + rho_max) / 2, so the
       fixed point lies within delta q / (1 - q); so does the transport's */
    double q = h->p.sealed ? h->rho_max : 0.5 * (1.0 + h->rho_max);
    double iter = q < 1.0 ? (h->last_change * h->last_vmax + last) * q / (1.0 - q) : 0.0;
    double leaf_max = 0.0, sum = 0.0, total = 0.0;
    for (size_t e = 0; e < h->nel; e++) {
        const hp_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        double t = rad_dmax(x->T[0], rad_dmax(x->T[1], x->T[2])) + iter;
        for (int c = 0; c < 3; c++)
            leaf_max = rad_dmax(leaf_max, x->T[c] + x->dep[c] + iter);
        face[x->face] += x->area * t;
        face[n + (size_t)x->face] += x->area;
        sum += x->area * t;
        total += x->area;
    }
    double face_max = 0.0;
    for (size_t f = 0; f < n; f++)
        if (face[n + f] > 0.0)
            face_max = rad_dmax(face_max, face[f] / face[n + f]);
    free(face);
    h->st.reflected = R;
    h->st.bound_leaf_max = leaf_max / R;
    h->st.bound_face_max = face_max / R;
    h->st.bound_mean = total > 0.0 ? sum / total / R : 0.0;
    h->st.target_met = h->st.bound_face_max <= h->p.eps;
    double spent = rad_sys_seconds() - t0;
    h->st.time_solve_s += spent;
    h->st.time_bound_s += spent;
    return st;
}

/* A solve to share eps R (rad_hier_solve_tolerance), again while the
 * tolerance from its own R and largest mean is tighter than the one it met. */
static rad_status solve_share(rad_hierp *h, double share)
{
    for (int first = 1;; first = 0) {
        double t = rad_hier_solve_tolerance(&h->p, share, h->rho_max, hp_reflected(h),
                                            h->last_vmax);
        if (!first && h->last_change <= t)
            return RAD_OK;
        rad_status st = hp_solve_links(h, t);
        if (st != RAD_OK)
            return st;
    }
}

rad_status rad_hierp_solve(rad_hierp *h)
{
    if (!h)
        return RAD_ERROR(RAD_EINVAL, "hier: no handle");
    rad_status st = hp_incidence(h);
    if (st != RAD_OK)
        return st;
    hp_rows(h);
    st = solve_share(h, h->p.round_tol);
    if (st != RAD_OK)
        return st;
    if (h->p.progress)
        h->p.progress(0, rad_hierp_leaf_count(h), h->nln, h->p.progress_ctx);
    for (int round = 1; round <= h->p.max_rounds; round++) {
        long long refined = 0;
        if ((st = hp_refine(h, &refined)) != RAD_OK)
            return st;
        if (refined == 0) {
            /* nothing above the thresholds: tighten where the estimate fails */
            if ((st = hp_estimate_error(h)) != RAD_OK)
                return st;
            if (hp_tighten_failing(h) == 0)
                break;
            continue;
        }
        if ((st = hp_incidence(h)) != RAD_OK)
            return st;
        hp_rows(h);
        if ((st = solve_share(h, h->p.round_tol)) != RAD_OK)
            return st;
        if (h->p.progress)
            h->p.progress(round, rad_hierp_leaf_count(h), h->nln, h->p.progress_ctx);
    }
    if ((st = solve_share(h, h->p.final_share)) != RAD_OK)
        return st;
    return hp_estimate_error(h);
}
