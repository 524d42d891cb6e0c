/* rad_mc: the driver: tables, stratified start points, batches, threads and
 * the standard errors.
 *
 * 1. Per triangle: corner, edges, unit normal and tangent frame, area,
 *    reflectance, emission, and the next-event density (path.c).  Emitters
 *    get an alias table over area x summed emission.
 * 2. Each triangle's N paths form B batches of m = N / B (N rounded up).  A
 *    batch cuts the triangle into k^2 cells, k = floor(sqrt(m))
 *    (rad_geom_triangle_stratum): its first k^2 floor(m / k^2) samples go
 *    round the cells in order, the rest to uniformly drawn cells.  The first
 *    direction and the first emitter point are stratified too, in rounds of
 *    kd^2 samples (kd = min(k, MC_MAX_STRATA)): in a round, sample c takes
 *    the cells dir[c] and light[c] of a kd x kd grid of the unit square, dir
 *    and light two random permutations drawn per round (padded
 *    stratification); samples after the last whole round draw plain random
 *    numbers.  Every sample is thus uniform in every dimension, each batch
 *    mean is an unbiased estimate of the area-average irradiance, and
 *    stratification reduces its variance where the integrand is smooth.
 * 3. A batch is one unit of work for OpenMP (dynamic schedule); its sum is
 *    formed in sample order and stored; each triangle's batch means are
 *    combined in batch order.  Triangles are processed in blocks so that the
 *    stored batch means stay small for any scene.
 * 4. B_i = E_i + rho_i mean(H), se_i = rho_i sd(batch means of H) / sqrt(B).
 * Batch means for the standard error of a stratified estimator: the batches
 * are independent and identically distributed, which the samples within a
 * stratified batch are not \cite{owen2013mc}. */
#include "mc_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "rad_sys.h"

/* Strata per edge of the direction and emitter grids at most (rounds of up
 * to 1024 samples, whose permutations live on the stack), and the key space
 * of the rounds' permutations. */
#define MC_MAX_STRATA 32
#define MC_ROUND_KEY (1ull << 63)

void rad_mc_params_default(rad_mc_params *params)
{
    memset(params, 0, sizeof *params); /* every field a later one adds starts at 0 */
    params->samples = 4096;
    params->seed = 1;
    params->batches = 32;
    params->max_depth = 100000;
    params->occlusion = 1;
    params->next_event = 1;
    params->rr_weight = 0.5;
    params->progress = NULL;
    params->progress_ctx = NULL;
    params->threads = 0;
}

static rad_status check_params(const rad_mc_params *p)
{
    if (p->samples < 2)
        return RAD_ERROR(RAD_EINVAL, "Monte Carlo: %lld samples per triangle; at least 2 are "
                                     "needed for a standard error", p->samples);
    if (p->samples > (1ll << 40))
        return RAD_ERROR(RAD_EINVAL, "Monte Carlo: %lld samples per triangle is beyond 2^40",
                         p->samples);
    if (p->batches < 2 || p->batches > 1024)
        return RAD_ERROR(RAD_EINVAL, "Monte Carlo: %d batches; use 2 to 1024", p->batches);
    if (!(p->rr_weight > 0.0 && p->rr_weight <= 1.0))
        return RAD_ERROR(RAD_EINVAL, "Monte Carlo: roulette weight %g must lie in (0, 1]",
                         p->rr_weight);
    if (p->max_depth < 1)
        return RAD_ERROR(RAD_EINVAL, "Monte Carlo: max_depth %d must be at least 1", p->max_depth);
    return RAD_OK;
}

/* Vose's construction of the alias table for the probabilities w[0..n)
 * (summing to 1), using small[] and large[] (n each) as work space. */
static void build_alias(size_t n, const double *w, double *prob, int *alias, int *small, int *large)
{
    size_t ns = 0, nl = 0;
    for (size_t k = 0; k < n; k++) {
        prob[k] = w[k] * (double)n;
        if (prob[k] < 1.0)
            small[ns++] = (int)k;
        else
            large[nl++] = (int)k;
    }
    while (ns && nl) {
        int sm = small[--ns], lg = large[nl - 1];
        alias[sm] = lg;
        prob[lg] -= 1.0 - prob[sm];
        if (prob[lg] < 1.0) {
            nl--;
            small[ns++] = lg;
        }
    }
    while (nl) { /* rounding leaves these at (about) 1 */
        int k = large[--nl];
        prob[k] = 1.0;
        alias[k] = k;
    }
    while (ns) {
        int k = small[--ns];
        prob[k] = 1.0;
        alias[k] = k;
    }
}

/* The tables of step 1 (cdf receives the emitters' probabilities).
 * Returns RAD_EINPUT for bad materials. */
static rad_status build_tables(const double *xyz, const int *tri, size_t nt, const double *rho,
                               const double *E, mc_tri *tris, int *emitters, double *cdf,
                               size_t *nemitters)
{
    double total = 0.0;
    size_t ne = 0;
    for (size_t i = 0; i < nt; i++) {
        mc_tri *m = &tris[i];
        const double *p0 = xyz + 3 * (size_t)tri[3 * i], *p1 = xyz + 3 * (size_t)tri[3 * i + 1],
                     *p2 = xyz + 3 * (size_t)tri[3 * i + 2];
        rad_vec3 a = rad_vec3_make(p0[0], p0[1], p0[2]), b = rad_vec3_make(p1[0], p1[1], p1[2]),
                 c = rad_vec3_make(p2[0], p2[1], p2[2]);
        m->a = a;
        m->ab = rad_vec3_sub(b, a);
        m->ac = rad_vec3_sub(c, a);
        m->area = rad_geom_triangle_area(a, b, c);
        m->n = rad_geom_triangle_normal(a, b, c);
        if (!(m->area > 0.0) || !(rad_vec3_norm(m->n) > 0.5))
            return RAD_ERROR(RAD_EINPUT, "Monte Carlo: triangle %zu is degenerate", i);
        /* a frame for any unit normal without a branch on its direction */
        double sign = m->n.z >= 0.0 ? 1.0 : -1.0;
        double aa = -1.0 / (sign + m->n.z), bb = m->n.x * m->n.y * aa;
        m->t1 = rad_vec3_make(1.0 + sign * m->n.x * m->n.x * aa, sign * bb, -sign * m->n.x);
        m->t2 = rad_vec3_make(bb, sign + m->n.y * m->n.y * aa, -m->n.y);
        double power = 0.0;
        for (int ch = 0; ch < 3; ch++) {
            m->rho[ch] = rho[i + ch * nt];
            m->E[ch] = E[i + ch * nt];
            if (!(m->rho[ch] >= 0.0 && m->rho[ch] < 1.0))
                return RAD_ERROR(RAD_EINPUT, "Monte Carlo: triangle %zu: reflectance %g is "
                                             "outside [0, 1)", i, m->rho[ch]);
            if (!(m->E[ch] >= 0.0) || !isfinite(m->E[ch]))
                return RAD_ERROR(RAD_EINPUT, "Monte Carlo: triangle %zu: emission %g is not a "
                                             "finite number >= 0", i, m->E[ch]);
            power += m->E[ch];
        }
        m->light_pdf = power; /* divided by the total below */
        if (power > 0.0) {
            emitters[ne] = (int)i;
            total += m->area * power;
            cdf[ne++] = m->area * power;
        }
    }
    for (size_t k = 0; k < ne; k++) {
        cdf[k] /= total;
        tris[emitters[k]].light_pdf /= total;
    }
    *nemitters = ne;
    return RAD_OK;
}

/* A uniform point of cell `cell` of the k x k grid on the unit square. */
static void square_cell(int k, int cell, mc_rng *rng, double *u)
{
    u[0] = ((double)(cell % k) + mc_uniform(rng)) / k;
    u[1] = ((double)(cell / k) + mc_uniform(rng)) / k;
}

/* A random permutation of 0..n-1 (Fisher-Yates). */
static void shuffle(int *perm, int n, mc_rng *rng)
{
    for (int i = 0; i < n; i++)
        perm[i] = i;
    for (int i = n - 1; i > 0; i--) {
        int j = (int)(mc_uniform(rng) * (i + 1));
        if (j > i)
            j = i;
        int tmp = perm[i];
        perm[i] = perm[j];
        perm[j] = tmp;
    }
}

/* Strata per edge of the triangle for m samples: the largest k with k^2 <= m. */
static long long strata_for(long long m)
{
    long long k = (long long)floor(sqrt((double)m));
    while (k > 1 && k * k > m)
        k--;
    while ((k + 1) * (k + 1) <= m)
        k++;
    return k < 1 ? 1 : k;
}

/* The mean irradiance of one batch (step 2). */
static void run_batch(const mc_scene *s, uint64_t seed, size_t t, int batch, long long m,
                      double Hmean[3], mc_counts *counts)
{
    const mc_tri *tr = &s->tris[t];
    long long k = strata_for(m), cells = k * k, balanced = cells * (m / cells);
    int kd = k < MC_MAX_STRATA ? (int)k : MC_MAX_STRATA, dcells = kd * kd;
    long long drounds = m / dcells;
    int dir_perm[MC_MAX_STRATA * MC_MAX_STRATA], light_perm[MC_MAX_STRATA * MC_MAX_STRATA];
    double sum[3] = {0.0, 0.0, 0.0};
    for (long long j = 0; j < m; j++) {
        long long dround = j / dcells;
        int dcell = (int)(j % dcells);
        if (dcell == 0 && dround < drounds) { /* a new round of pairings */
            mc_rng prng;
            mc_rng_seed(&prng, seed, (uint64_t)t,
                        MC_ROUND_KEY | ((uint64_t)batch << 40) | (uint64_t)dround);
            shuffle(dir_perm, dcells, &prng);
            shuffle(light_perm, dcells, &prng);
        }
        mc_rng rng;
        mc_rng_seed(&rng, seed, (uint64_t)t, (uint64_t)batch * (uint64_t)m + (uint64_t)j);
        double first[4], ss, rr;
        if (dround < drounds) {
            square_cell(kd, dir_perm[dcell], &rng, first);
            square_cell(kd, light_perm[dcell], &rng, first + 2);
        } else {
            for (int d = 0; d < 4; d++)
                first[d] = mc_uniform(&rng);
        }
        long long cell = j < balanced ? j % cells : (long long)(mc_uniform(&rng) * (double)cells);
        if (cell >= cells)
            cell = cells - 1;
        double w1 = mc_uniform(&rng), w2 = mc_uniform(&rng);
        rad_geom_triangle_stratum((int)k, cell, w1, w2, &ss, &rr);
        rad_vec3 x = rad_vec3_add(tr->a, rad_vec3_add(rad_vec3_scale(tr->ab, ss),
                                                      rad_vec3_scale(tr->ac, rr)));
        double H[3];
        mc_path_irradiance(s, (int)t, x, &rng, first, H, counts);
        for (int c = 0; c < 3; c++)
            sum[c] += H[c];
    }
    for (int c = 0; c < 3; c++)
        Hmean[c] = sum[c] / (double)m;
}

rad_status rad_mc_solve(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                        const double *rho, const double *E, const rad_vis *vis,
                        const rad_mc_params *params, double *B, double *se,
                        rad_mc_stats *stats)
{
    if (!xyz || !tri || !rho || !E || !vis || !B || !se)
        return RAD_ERROR(RAD_EINVAL, "Monte Carlo: NULL argument");
    rad_mc_params p;
    if (params)
        p = *params;
    else
        rad_mc_params_default(&p);
    rad_status st = check_params(&p);
    if (st != RAD_OK)
        return st;
    if (rad_vis_triangle_count(vis) != ntris)
        return RAD_ERROR(RAD_EINVAL, "Monte Carlo: the visibility holds %zu triangles, the scene "
                                     "%zu", rad_vis_triangle_count(vis), ntris);
    rad_status rays_ready = rad_vis_prepare_rays(vis); /* every path casts them */
    if (rays_ready != RAD_OK)
        return rays_ready;
    for (size_t k = 0; k < 3 * ntris; k++)
        if (tri[k] < 0 || (size_t)tri[k] >= nverts)
            return RAD_ERROR(RAD_EINPUT, "Monte Carlo: triangle %zu refers to vertex %d of %zu",
                             k / 3, tri[k], nverts);
    double t0 = rad_sys_seconds();
    int nb = p.samples < p.batches ? (int)p.samples : p.batches;
    long long m = (p.samples + nb - 1) / nb;

    /* step 3's block: this many triangles' batch means are kept at once */
    const size_t block = 4096;
    mc_tri *tris = malloc((ntris + 1) * sizeof *tris);
    int *emitters = malloc((ntris + 1) * sizeof *emitters);
    double *cdf = malloc((ntris + 1) * sizeof *cdf), *prob = malloc((ntris + 1) * sizeof *prob);
    int *alias = malloc(3 * (ntris + 1) * sizeof *alias);
    double *means = malloc(block * (size_t)nb * 3 * sizeof *means);
    if (!tris || !emitters || !cdf || !prob || !alias || !means) {
        st = RAD_ERROR(RAD_ENOMEM, "Monte Carlo: no memory for %zu triangles", ntris);
        goto done;
    }
    size_t ne = 0;
    if ((st = build_tables(xyz, tri, ntris, rho, E, tris, emitters, cdf, &ne)) != RAD_OK)
        goto done;
    build_alias(ne, cdf, prob, alias, alias + ntris + 1, alias + 2 * (ntris + 1));
    mc_scene s = {tris, ntris, emitters, prob, alias, ne, vis, p.occlusion, p.next_event,
                  p.max_depth, p.rr_weight, rad_vis_epsilon(vis)};

    long long rays = 0, bounces = 0, too_long = 0, done_units = 0;
    long long total_units = (long long)ntris * nb;
    int reported = 0;
    int threads = p.threads > 0 ? p.threads : omp_get_max_threads();
    for (size_t first = 0; first < ntris; first += block) {
        size_t count = ntris - first < block ? ntris - first : block;
        long long units = (long long)count * nb;
#pragma omp parallel reduction(+ : rays, bounces, too_long) num_threads(threads)
        {
            mc_counts cnt = {0, 0, 0};
#pragma omp for schedule(dynamic, 1)
            for (long long u = 0; u < units; u++) {
                size_t t = first + (size_t)(u / nb);
                int b = (int)(u % nb);
                run_batch(&s, p.seed, t, b, m, means + 3 * (size_t)u, &cnt);
                long long now;
#pragma omp atomic capture
                now = ++done_units;
                if (p.progress && omp_get_thread_num() == 0) {
                    int pct = (int)(100 * now / total_units);
                    if (pct > reported) {
                        reported = pct;
                        p.progress((double)now / (double)total_units, p.progress_ctx);
                    }
                }
            }
            rays += cnt.rays;
            bounces += cnt.bounces;
            too_long += cnt.too_long;
        }
        for (size_t i = 0; i < count; i++) {
            size_t t = first + i;
            for (int c = 0; c < 3; c++) {
                const double *mb = means + 3 * i * (size_t)nb + c;
                double mean = 0.0, var = 0.0;
                for (int b = 0; b < nb; b++)
                    mean += mb[3 * b];
                mean /= nb;
                for (int b = 0; b < nb; b++)
                    var += (mb[3 * b] - mean) * (mb[3 * b] - mean);
                var /= (double)nb * (nb - 1);
                B[t + c * ntris] = tris[t].E[c] + tris[t].rho[c] * mean;
                se[t + c * ntris] = tris[t].rho[c] * sqrt(var);
            }
        }
    }
    if (too_long) {
        st = RAD_ERROR(RAD_ENUMERIC, "Monte Carlo: %lld paths went beyond %d bounces: the "
                                     "reflectance is too close to 1 for path tracing", too_long,
                       p.max_depth);
        goto done;
    }
    if (stats) {
        stats->samples_per_face = m * nb;
        stats->batches = nb;
        stats->paths = (long long)ntris * m * nb;
        stats->rays = rays;
        stats->bounces = bounces;
        stats->seconds = rad_sys_seconds() - t0;
    }
done:
    free(tris);
    free(emitters);
    free(cdf);
    free(prob);
    free(alias);
    free(means);
    return st;
}
