/* rad_hier: Anderson acceleration of the gather / push-pull iteration.
 *
 * A step of solve.c maps the leaves' state x (B and its slope gB, or the
 * transported error T) to M(x) = E + rho cap K x: an affine map that
 * contracts, whose slowest modes (light bouncing around a closed room, or
 * between surfaces that face each other across a gap) shrink by only about
 * rho a step.  Anderson's method (Walker and Ni 2011, type II) keeps the
 * last `depth` differences of the steps' residuals f = M(x) - x and outputs
 * g = M(x), and takes as the next state
 *   x' = g_k - sum_j gamma_j (g_{j+1} - g_j),
 * gamma minimising |f_k - sum_j gamma_j (f_{j+1} - f_j)|_2 over the
 * leaves' values (the residual part: B or T, three channels).  For an
 * affine map this is GMRES in disguise: the residual falls much faster
 * than rho^k where the slow modes are few.
 *
 * What it does not change: each step is a plain step from the state it
 * starts from, whose largest change |f|_inf the caller tests, and whose
 * output M(x) is what a converged solve keeps; so the stopping test and the
 * fixed-point tail (solve.c: a contraction by q leaves M(x) within
 * q / (1 - q) |f| of the fixed point) hold whatever x the mixing chose.
 *
 * The slope gB is mixed with the same gammas as B (M's gB is linear in the
 * state, so the mixed state is the one M's outputs combine to); inner
 * elements take their children's area-weighted mean, as push-pull makes
 * them.  The gram matrix's dot products are summed per fixed block of
 * leaves and the blocks in order, so the result does not depend on the
 * thread count.  A column that makes the gram matrix singular (Cholesky
 * pivot below 1e-12 of its diagonal) is dropped, oldest first; a residual
 * that grew tenfold over the smallest seen restarts the history, and one
 * that has not fallen below it in 2 depth + 1 steps (noise at the rounding
 * level, where T of a furnace lies) ends the mixing: plain steps contract
 * from any state.  A mixed
 * state is projected onto the set the fixed point lies in, B >= 0 and
 * T >= q (T = q + rho K T with K >= 0): a large cluster's gather brackets
 * its intensity with the square root of moments of what it carries, real
 * only where those values are non-negative.
 * Mixing of B starts after HIER_ACCEL_WARMUP_B plain steps: most solves
 * between refinement rounds end before (each step shrinking the change two-
 * or threefold), and their history would cost memory (about 600 bytes a
 * leaf) for nothing.  The error transport runs to bound_tol from q, never
 * in so few steps, and its history is a quarter of B's (T has no slope):
 * its mixing starts after HIER_ACCEL_WARMUP_T.  Past the warm-up, mixing
 * starts only where plain steps, contracting by the bound the fixed-point
 * tail takes (hier_contraction), could not meet the solve's test within
 * that many more steps: a solve that plain steps end in a few more (light
 * at reflectance 0.7, a round's solve near its tolerance) would fill the
 * history for no gain, while one that contracts slowly (reflectance near 1)
 * starts as soon as before.  A solve whose arrays the machine has not the
 * memory for goes on with plain steps.
 * Shared among processes (split_gather), every process holds every
 * element's values after a step's exchange, and mixes all of them alike. */
#include "hier_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rad_sys.h"

enum { ACCEL_BLOCK = 8192 };

static int width_of(int carry) { return carry == CARRY_B ? 12 : 3; }

static size_t accel_doubles(int carry, int depth)
{
    int w = width_of(carry);
    return (size_t)(3 + w + 3 + depth * (3 + w));
}

/* The state of leaf x into s (width doubles: the residual part first). */
static void get_state(const hier_elem *x, int carry, double *s)
{
    if (carry == CARRY_T) {
        memcpy(s, x->T, 3 * sizeof *s);
        return;
    }
    memcpy(s, x->B, 3 * sizeof *s);
    for (int c = 0; c < 3; c++) {
        s[3 + 3 * c] = x->gB[c].x;
        s[4 + 3 * c] = x->gB[c].y;
        s[5 + 3 * c] = x->gB[c].z;
    }
}

static void set_state(hier_elem *x, int carry, const double *s)
{
    if (carry == CARRY_T) {
        for (int c = 0; c < 3; c++)
            x->T[c] = rad_dmax(s[c], x->q[c]);
        return;
    }
    for (int c = 0; c < 3; c++)
        x->B[c] = rad_dmax(s[c], 0.0);
    for (int c = 0; c < 3; c++)
        x->gB[c] = rad_vec3_make(s[3 + 3 * c], s[4 + 3 * c], s[5 + 3 * c]);
}

void hier_accel_begin(rad_hier *h, int carry, double tol)
{
    hier_accel *a = &h->acc;
    a->on = a->began = 0;
    a->carry = carry;
    a->steps = 0;
    a->tol = tol;
    a->last = -1.0;
}

/* Whether plain steps contracting by q could take the last change down to
 * the test in `steps` steps or fewer: then 0 (or without a change yet, or
 * q not below 1: 1). */
static int far_from_end(const hier_accel *a, double q, int steps)
{
    if (!(a->last > 0.0) || !(a->tol > 0.0) || !(q < 1.0))
        return 1;
    if (a->last <= a->tol)
        return 0;
    return q <= 0.0 || log(a->tol / a->last) / log(q) > (double)steps;
}

/* Start mixing: the leaves, the arrays (0 when the machine has not the
 * memory for them: the solve goes on with plain steps). */
static rad_status start(rad_hier *h)
{
    hier_accel *a = &h->acc;
    size_t n = 0;
    for (size_t e = 0; e < h->nel; e++)
        n += h->el[e].first_child < 0;
    a->depth = h->p.anderson; /* at most HIER_ACCEL_MAX: rad_hier_params_check */
    size_t per = accel_doubles(a->carry, a->depth);
    double bytes = (double)n * (double)per * sizeof *a->buf;
    double more = rad_dmax(0.0, bytes - h->gather_touched[HIER_GATHER_ACCEL]), would, have;
    /* shared among processes each would decide from its own memory: all mix */
    if (!hier_shared(h) && !rad_sys_memory_allows(more, &would, &have))
        return RAD_OK;
    if (!rad_sys_grow((void **)&a->leaf, &a->leaf_cap, 0, n ? n : 1, sizeof *a->leaf, 1024) ||
        !rad_sys_grow((void **)&a->buf, &a->buf_cap, 0, n > 0 ? n * per : 1, sizeof *a->buf,
                      1024))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the solve's history of %zu leaves",
                         n);
    hier_gather_touch(h, HIER_GATHER_ACCEL, n * per * sizeof *a->buf);
    n = 0;
    for (size_t e = 0; e < h->nel; e++)
        if (h->el[e].first_child < 0)
            a->leaf[n++] = (int)e;
    a->n = n;
    a->width = width_of(a->carry);
    a->cols = 0;
    a->next = 0;
    a->have_prev = 0;
    a->best = INFINITY;
    a->stall = 0;
    a->on = 1;
    return RAD_OK;
}

/* The arrays in buf: xr (3 a leaf), gp (width), fp (3), then per column
 * df (3) and dg (width). */
static double *xr_of(const hier_accel *a) { return a->buf; }
static double *gp_of(const hier_accel *a) { return a->buf + 3 * a->n; }
static double *fp_of(const hier_accel *a) { return a->buf + (size_t)(3 + a->width) * a->n; }
static double *df_of(const hier_accel *a, int j)
{
    return a->buf + (size_t)(6 + a->width) * a->n + (size_t)j * (size_t)(3 + a->width) * a->n;
}
static double *dg_of(const hier_accel *a, int j) { return df_of(a, j) + 3 * a->n; }

rad_status hier_accel_save(rad_hier *h, double change)
{
    hier_accel *a = &h->acc;
    int warmup = a->carry == CARRY_B ? HIER_ACCEL_WARMUP_B : HIER_ACCEL_WARMUP_T;
    a->last = change;
    if (h->p.anderson > 0 && ++a->steps > warmup && !a->began &&
        far_from_end(a, hier_contraction(h), warmup)) {
        a->began = 1;
        rad_status st = start(h);
        if (st != RAD_OK)
            return st;
    }
    if (!a->on)
        return RAD_OK;
    double *xr = xr_of(a);
#pragma omp parallel for schedule(static) num_threads(hier_threads(h)) if (a->n > 65536)
    for (long long i = 0; i < (long long)a->n; i++) {
        const hier_elem *x = &h->el[a->leaf[i]];
        memcpy(xr + 3 * i, a->carry == CARRY_B ? x->B : x->T, 3 * sizeof *xr);
    }
    return RAD_OK;
}

/* Column j's position in the ring, oldest first (k = 0 .. cols - 1). */
static int col(const hier_accel *a, int k)
{
    return (a->next - a->cols + k + 2 * HIER_ACCEL_MAX) % a->depth;
}

/* Solve gram gamma = rhs over the newest `use` columns (Cholesky); 0 when a
 * pivot falls below 1e-12 of its diagonal entry. */
static int solve_gram(const hier_accel *a, int use, const double *rhs, double *gamma)
{
    double L[HIER_ACCEL_MAX][HIER_ACCEL_MAX];
    int off = a->cols - use;
    for (int i = 0; i < use; i++)
        for (int j = 0; j <= i; j++) {
            double s = a->gram[col(a, off + i)][col(a, off + j)];
            for (int k = 0; k < j; k++)
                s -= L[i][k] * L[j][k];
            if (i == j) {
                double d = a->gram[col(a, off + i)][col(a, off + i)];
                if (!(s > 1e-12 * d))
                    return 0;
                L[i][i] = sqrt(s);
            } else {
                L[i][j] = s / L[j][j];
            }
        }
    double y[HIER_ACCEL_MAX];
    for (int i = 0; i < use; i++) {
        double s = rhs[off + i];
        for (int k = 0; k < i; k++)
            s -= L[i][k] * y[k];
        y[i] = s / L[i][i];
    }
    for (int i = use - 1; i >= 0; i--) {
        double s = y[i];
        for (int k = i + 1; k < use; k++)
            s -= L[k][i] * gamma[k];
        gamma[i] = s / L[i][i];
    }
    for (int i = 0; i < use; i++)
        if (!isfinite(gamma[i]))
            return 0;
    return 1;
}

void hier_accel_mix(rad_hier *h)
{
    hier_accel *a = &h->acc;
    if (!a->on)
        return;
    size_t n = a->n;
    int w = a->width, threads = hier_threads(h);
    double *xr = xr_of(a), *gp = gp_of(a), *fp = fp_of(a);
    int fresh = a->have_prev ? a->next : -1; /* the column this step adds */
    if (fresh >= 0) {
        a->next = (a->next + 1) % a->depth;
        if (a->cols < a->depth)
            a->cols++;
    }
    /* one pass: the new column (f - fp, g - gp), fp and gp moved on, and
       the dot products the gram matrix and the right-hand side need, per
       block */
    size_t nb = (n + ACCEL_BLOCK - 1) / ACCEL_BLOCK;
    enum { DOTS = 2 * HIER_ACCEL_MAX + 1 };
    double *part = calloc(nb ? nb * DOTS : 1, sizeof *part);
    if (!part) {
        a->on = 0; /* plain steps from here: still correct, only slower */
        return;
    }
    double *df[HIER_ACCEL_MAX], *dg[HIER_ACCEL_MAX];
    for (int j = 0; j < a->depth; j++) {
        df[j] = df_of(a, j);
        dg[j] = dg_of(a, j);
    }
    int cols = a->cols;
    int ring[HIER_ACCEL_MAX];
    for (int k = 0; k < cols; k++)
        ring[k] = col(a, k);
#pragma omp parallel for schedule(static) num_threads(threads) if (n > 65536)
    for (long long b = 0; b < (long long)nb; b++) {
        double *p = part + (size_t)b * DOTS;
        size_t lo = (size_t)b * ACCEL_BLOCK, hi = lo + ACCEL_BLOCK < n ? lo + ACCEL_BLOCK : n;
        for (size_t i = lo; i < hi; i++) {
            double g[12], f[3];
            get_state(&h->el[a->leaf[i]], a->carry, g);
            for (int c = 0; c < 3; c++)
                f[c] = g[c] - xr[3 * i + c];
            if (fresh >= 0) {
                for (int c = 0; c < 3; c++)
                    df[fresh][3 * i + c] = f[c] - fp[3 * i + c];
                for (int c = 0; c < w; c++)
                    dg[fresh][(size_t)w * i + c] = g[c] - gp[(size_t)w * i + c];
            }
            memcpy(fp + 3 * i, f, sizeof f);
            memcpy(gp + (size_t)w * i, g, (size_t)w * sizeof *g);
            for (int k = 0; k < cols; k++) {
                const double *dk = df[ring[k]] + 3 * i;
                p[k] += dk[0] * f[0] + dk[1] * f[1] + dk[2] * f[2];
                if (fresh >= 0) {
                    const double *dn = df[fresh] + 3 * i;
                    p[HIER_ACCEL_MAX + k] += dk[0] * dn[0] + dk[1] * dn[1] + dk[2] * dn[2];
                }
            }
            p[DOTS - 1] += f[0] * f[0] + f[1] * f[1] + f[2] * f[2];
        }
    }
    double dots[DOTS] = {0};
    for (size_t b = 0; b < nb; b++)
        for (int k = 0; k < DOTS; k++)
            dots[k] += part[(size_t)b * DOTS + k];
    free(part);
    a->have_prev = 1;
    if (fresh >= 0)
        for (int k = 0; k < cols; k++)
            a->gram[fresh][ring[k]] = a->gram[ring[k]][fresh] = dots[HIER_ACCEL_MAX + k];
    double norm = dots[DOTS - 1];
    if (norm < a->best) {
        a->best = norm;
        a->stall = 0;
    } else if (++a->stall > 2 * a->depth) {
        /* no progress in that many steps (a residual at the rounding
           level, where the differences are noise): plain steps from here,
           which contract */
        a->on = 0;
        return;
    }
    if (norm > 100.0 * a->best) {
        /* the residual grew tenfold: the history leads astray; plain step */
        a->cols = 0;
        return;
    }
    double gamma[HIER_ACCEL_MAX];
    int use = cols;
    while (use > 0 && !solve_gram(a, use, dots, gamma))
        use--;
    a->cols = use; /* the dropped columns are the oldest: forgotten */
    if (use == 0)
        return; /* the plain step's output stands */
    for (int k = 0; k < use; k++)
        ring[k] = col(a, k);
#pragma omp parallel for schedule(static) num_threads(threads) if (n > 65536)
    for (long long i = 0; i < (long long)n; i++) {
        double s[12];
        memcpy(s, gp + (size_t)w * i, (size_t)w * sizeof *s);
        for (int k = 0; k < use; k++) {
            const double *d = dg[ring[k]] + (size_t)w * i;
            for (int c = 0; c < w; c++)
                s[c] -= gamma[k] * d[c];
        }
        set_state(&h->el[a->leaf[i]], a->carry, s);
    }
    int chunk = hier_root_chunk(h->nroots, threads);
#pragma omp parallel for schedule(dynamic, chunk) num_threads(threads) if (h->nroots > 1)
    for (long long t = 0; t < (long long)h->nroots; t++)
        hier_pull_means(h, (int)t, a->carry);
}

void hier_accel_destroy(rad_hier *h)
{
    free(h->acc.leaf);
    free(h->acc.buf);
    memset(&h->acc, 0, sizeof h->acc);
}
