/* Dense assembly of the symmetric coupling G_ij = int_i int_j K V.
 *
 * 1. Areas first (one pass), so a degenerate triangle fails before any work.
 * 2. Rows i in parallel (OpenMP, dynamic schedule: row i has n-1-i pairs);
 *    for j > i one rad_ff_compute gives the unoccluded G = A_i F_ij; pairs
 *    flagged NOT_FACING are zero with no integration.
 * 3. With a visibility structure, a pair with G > 0 whose shaft holds
 *    possible blockers takes the visible integral rad_vis_pair_visible (with
 *    the unoccluded G as the scale of its tolerance); a pair with an empty
 *    shaft keeps rad_ff's value.
 * 4. G_ij and G_ji receive the same value: reciprocity is exact by
 *    construction.  Counters are summed by OpenMP reductions, so the result and
 *    the counts do not depend on the number of threads. */
#include "rad_radiosity.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rad_geom.h"
#include "rad_sys.h"

#ifdef _OPENMP
#include <omp.h>
#endif

void rad_radiosity_params_default(rad_radiosity_params *params)
{
    memset(params, 0, sizeof *params);
    params->rule.scheme = RAD_FF_AUTO;
    params->rule.order = 0;
    rad_ff_params_default(&params->ff);
    rad_vis_visible_params_default(&params->visible);
}

static void load_triangle(const double *xyz, const int *tri, int k, rad_vec3 t[3])
{
    for (int v = 0; v < 3; v++) {
        const double *p = xyz + 3 * (size_t)tri[3 * (size_t)k + v];
        t[v] = rad_vec3_make(p[0], p[1], p[2]);
    }
}

/* One pair's work, counted: steps 2 and 3 above. */
typedef struct pair_count {
    long long not_facing, tested, sampled, out_of_range, evals;
    unsigned long long rays;
    double vis_err, vis_G;
} pair_count;

static rad_status pair_coupling(const double *xyz, const int *tri, int i, int j,
                                const rad_vis *vis, const rad_radiosity_params *p, double *G,
                                pair_count *c)
{
    rad_vec3 ti[3], tj[3];
    load_triangle(xyz, tri, i, ti);
    load_triangle(xyz, tri, j, tj);
    rad_ff_result r;
    rad_status s = rad_ff_compute(ti, tj, p->rule, &p->ff, &r);
    double g = r.G;
    if (s == RAD_OK && vis && g > 0.0) {
        rad_vis_visible_result vr;
        s = rad_vis_pair_visible(vis, ti, p->face_of ? p->face_of[i] : i, tj,
                                 p->face_of ? p->face_of[j] : j, g, &p->visible, &vr);
        if (s == RAD_OK && vr.blockers > 0) {
            g = vr.G;
            c->tested++;
            c->sampled += vr.status == RAD_VIS_VISIBLE_SAMPLED;
            c->evals += vr.evals;
            c->rays += (unsigned long long)vr.rays;
            c->vis_err += vr.error;
            c->vis_G += vr.G;
        }
    }
    if (s == RAD_OK && !isfinite(g))
        s = RAD_ERROR(RAD_ENUMERIC, "assembly: the coupling of triangles %d and %d is not "
                                    "finite", i, j);
    c->not_facing += (r.flags & RAD_FF_FLAG_NOT_FACING) != 0;
    c->out_of_range += (r.flags & RAD_FF_FLAG_OUT_OF_RANGE) != 0;
    c->evals += r.evals;
    *G = s == RAD_OK ? g : 0.0;
    return s;
}

rad_status rad_radiosity_pair(const double *xyz, const int *tri, int i, int j, const rad_vis *vis,
                              const rad_radiosity_params *params, double *G,
                              rad_radiosity_stats *stats)
{
    rad_radiosity_params p;
    if (params)
        p = *params;
    else
        rad_radiosity_params_default(&p);
    if (!xyz || !tri || !G || i < 0 || j < 0 || i == j)
        return RAD_ERROR(RAD_EINVAL, "assembly: bad pair (%d, %d)", i, j);
    pair_count c = {0, 0, 0, 0, 0, 0, 0.0, 0.0};
    /* the smaller index first, as the assembly does: G_ij and G_ji agree to the bit */
    rad_status st = pair_coupling(xyz, tri, i < j ? i : j, i < j ? j : i, vis, &p, G, &c);
    if (stats) {
        stats->pairs++;
        stats->pairs_not_facing += c.not_facing;
        stats->pairs_occlusion_tested += c.tested;
        stats->pairs_sampled += c.sampled;
        stats->pairs_out_of_range += c.out_of_range;
        stats->kernel_evals += c.evals;
        stats->rays += c.rays;
    }
    return st;
}

rad_status rad_radiosity_assemble(const double *xyz, const int *tri, int n, const rad_vis *vis,
                                  const rad_radiosity_params *params, double *G, double *areas,
                                  rad_radiosity_stats *stats)
{
    rad_radiosity_params p;
    if (params)
        p = *params;
    else
        rad_radiosity_params_default(&p);
    if (!xyz || !tri || n < 1 || !G || !areas)
        return RAD_ERROR(RAD_EINVAL, "assembly: bad arguments (n = %d)", n);
    double t0 = rad_sys_seconds();
    rad_radiosity_stats st;
    memset(&st, 0, sizeof st);

    for (int k = 0; k < n; k++) {
        rad_vec3 t[3];
        load_triangle(xyz, tri, k, t);
        if (rad_geom_triangle_is_degenerate(t[0], t[1], t[2], p.ff.degenerate_rel_tol))
            return RAD_ERROR(RAD_EINPUT, "assembly: triangle %d is degenerate (zero area or "
                                         "collinear vertices)", k);
        areas[k] = rad_geom_triangle_area(t[0], t[1], t[2]);
    }
    size_t nn = (size_t)n;
    for (size_t k = 0; k < nn; k++)
        G[k + k * nn] = 0.0;

    long long not_facing = 0, tested = 0, sampled = 0, out_of_range = 0, evals = 0;
    unsigned long long rays = 0;
    double vis_err = 0.0, vis_G = 0.0;
    long long rows_done = 0;
    rad_status first_error = RAD_OK;
    int bad_i = -1, bad_j = -1;
    char bad_message[512] = ""; /* messages are thread-local: copy the worker's */
#ifdef _OPENMP
    /* The caller's thread count for this region only: the library leaves
     * the process-wide OpenMP setting alone. */
    int threads = p.threads > 0 ? p.threads : omp_get_max_threads();
#endif

#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) \
    reduction(+ : not_facing, tested, sampled, out_of_range, evals, rays, vis_err, vis_G)
    for (int i = 0; i < n; i++) {
        for (int j = i + 1; j < n; j++) {
            pair_count c = {0, 0, 0, 0, 0, 0, 0.0, 0.0};
            double g = 0.0;
            rad_status s = pair_coupling(xyz, tri, i, j, vis, &p, &g, &c);
            if (s != RAD_OK) {
#pragma omp critical(rad_radiosity_error)
                if (first_error == RAD_OK) {
                    first_error = s;
                    bad_i = i;
                    bad_j = j;
                    snprintf(bad_message, sizeof bad_message, "%s", rad_error_message());
                }
            }
            not_facing += c.not_facing;
            tested += c.tested;
            sampled += c.sampled;
            out_of_range += c.out_of_range;
            evals += c.evals;
            rays += c.rays;
            vis_err += c.vis_err;
            vis_G += c.vis_G;
            G[(size_t)i + (size_t)j * nn] = g;
            G[(size_t)j + (size_t)i * nn] = g;
        }
        long long done;
#pragma omp atomic capture
        done = ++rows_done;
        if (p.progress && (done % 64 == 0 || done == n)) {
            /* pairs done = sum over finished rows, approximated by rows from the top */
            double frac = 1.0 - (double)(n - done) * (double)(n - done) / ((double)n * (double)n);
#pragma omp critical(rad_radiosity_progress)
            p.progress(frac, p.progress_ctx);
        }
    }

    st.pairs = (long long)n * (n - 1) / 2;
    st.pairs_not_facing = not_facing;
    st.pairs_occlusion_tested = tested;
    st.pairs_sampled = sampled;
    st.visibility_error = vis_G > 0.0 ? vis_err / vis_G : 0.0;
    st.pairs_out_of_range = out_of_range;
    st.kernel_evals = evals;
    st.rays = rays;
    st.seconds = rad_sys_seconds() - t0;
    if (stats)
        *stats = st;
    if (first_error == RAD_ENUMERIC)
        return RAD_ERROR(RAD_ENUMERIC, "assembly: the coupling of triangles %d and %d is not finite",
                         bad_i, bad_j);
    if (first_error != RAD_OK)
        return RAD_ERROR(first_error, "assembly: triangles %d and %d: %s", bad_i, bad_j,
                         bad_message);
    return RAD_OK;
}

double rad_radiosity_close_rows(double *G, const double *areas, int n)
{
    size_t nn = n > 0 ? (size_t)n : 0;
    double worst = 0.0;
    for (size_t i = 0; i < nn; i++) {
        double r = 0.0;
        for (size_t j = 0; j < nn; j++) /* G is symmetric: row i read as column i */
            r += G[j + i * nn];
        double d = areas[i] - r;
        G[i + i * nn] += d;
        if (areas[i] > 0.0)
            worst = rad_dmax(worst, fabs(d) / areas[i]);
    }
    return worst;
}
