/* rad_vis: the visible fraction of a triangle pair from stratified samples.
 *
 * 1. Cut each triangle into k^2 congruent sub-triangles (k = strata_per_edge)
 *    by the lattice of points a + (p/k)(b - a) + (q/k)(c - a), p + q <= k:
 *    k(k+1)/2 "upward" cells (p,q),(p+1,q),(p,q+1) and k(k-1)/2 "downward"
 *    cells (p+1,q),(p,q+1),(p+1,q+1).  All have area A/k^2, so every sample
 *    carries the same weight.
 * 2. One point per cell: its centroid, or (jitter) a uniform point of the cell
 *    from a hash of (triangle, cell, seed), so results do not depend on threads.
 * 3. Join every sample of i to every sample of j (k^4 segments) and count the
 *    segments no triangle blocks.  Hits on i and j are rejected by primitive id
 *    in the geometry's occlusion filter (vis.c), on top of the epsilon shortening; the
 *    fraction is symmetric in (i, j) up to float rounding of the rays.
 * 4. Skip all rays when the scene is unoccluded or the shaft test proves that
 *    nothing can block the pair (shaft.c).
 * The visible fraction estimates (1/(A_i A_j)) int int V dA dA; the midpoint
 * rule on k^2 cells converges as the cells shrink, at a rate set by the
 * smoothness of the shadow boundary \cite{cohen1993}. */
#include "vis_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

int rad_vis_sample_count(const rad_vis *vis)
{
    return vis ? vis->params.strata_per_edge * vis->params.strata_per_edge : 0;
}

rad_status rad_vis_triangle_samples(const rad_vis *vis, size_t t, double *pts)
{
    if (!vis || !pts || t >= vis->ntris)
        return RAD_ERROR(RAD_EINVAL, "visibility: bad triangle %zu for sampling", t);
    int k = vis->params.strata_per_edge;
    rad_vec3 a = vis_vertex(vis, t, 0), b = vis_vertex(vis, t, 1), c = vis_vertex(vis, t, 2);
    rad_vec3 ab = rad_vec3_sub(b, a), ac = rad_vec3_sub(c, a);
    int cell = 0;
    for (int up = 1; up >= 0; up--)
        for (int p = 0; p < k; p++)
            for (int q = 0; p + q < k - (up ? 0 : 1); q++) {
                /* Cell corners in lattice units (s along ab, r along ac). */
                double s0, r0, s1, r1, s2, r2;
                if (up) {
                    s0 = p; r0 = q; s1 = p + 1; r1 = q; s2 = p; r2 = q + 1;
                } else {
                    s0 = p + 1; r0 = q; s1 = p; r1 = q + 1; s2 = p + 1; r2 = q + 1;
                }
                double w1 = 1.0 / 3.0, w2 = 1.0 / 3.0;
                if (vis->params.jitter) {
                    uint64_t h = rad_sys_hash64(((uint64_t)t << 20) ^ (uint64_t)cell ^
                                                ((uint64_t)vis->params.seed << 44));
                    w1 = rad_sys_unit(h);
                    w2 = rad_sys_hash_unit(h);
                    if (w1 + w2 > 1.0) { /* fold the square onto the triangle */
                        w1 = 1.0 - w1;
                        w2 = 1.0 - w2;
                    }
                }
                double s = (s0 + w1 * (s1 - s0) + w2 * (s2 - s0)) / k;
                double r = (r0 + w1 * (r1 - r0) + w2 * (r2 - r0)) / k;
                rad_vec3 x = rad_vec3_add(a, rad_vec3_add(rad_vec3_scale(ab, s), rad_vec3_scale(ac, r)));
                pts[3 * cell] = x.x;
                pts[3 * cell + 1] = x.y;
                pts[3 * cell + 2] = x.z;
                cell++;
            }
    return RAD_OK;
}

enum { MAX_STACK_SAMPLES = 256 };

rad_status rad_vis_pair_fraction(const rad_vis *vis, size_t i, size_t j, double *fraction,
                                 rad_vis_stats *stats)
{
    if (!vis || !fraction || i >= vis->ntris || j >= vis->ntris)
        return RAD_ERROR(RAD_EINVAL, "visibility: bad pair (%zu, %zu)", i, j);
    *fraction = 1.0;
    if (vis->unoccluded || !vis_pair_segments_can_block(vis, i, j)) {
        if (stats)
            stats->pairs_skipped++;
        return RAD_OK;
    }
    int m = rad_vis_sample_count(vis);
    /* Sample arrays on the stack for the usual counts; the heap beyond. */
    double stack_pts[2 * 3 * MAX_STACK_SAMPLES];
    double *pts = m <= MAX_STACK_SAMPLES ? stack_pts : malloc(2 * 3 * (size_t)m * sizeof *pts);
    if (!pts)
        return RAD_ERROR(RAD_ENOMEM, "visibility: no memory for %d samples", m);
    double *pi = pts, *pj = pts + 3 * (size_t)m;
    rad_vis_triangle_samples(vis, i, pi);
    rad_vis_triangle_samples(vis, j, pj);

    rad_status st = rad_vis_prepare_rays(vis);
    if (st != RAD_OK) {
        if (pts != stack_pts)
            free(pts);
        return st;
    }
    vis_context vc;
    vis_context_init(&vc, (unsigned)i, (unsigned)j);
    /* Segments in batches of BATCH through the packet path of rad_vis_occluded. */
    enum { BATCH = 256 };
    double from[3 * BATCH], to[3 * BATCH];
    unsigned char blocked[BATCH];
    unsigned long long visible = 0, rays = 0;
    size_t total = (size_t)m * (size_t)m, filled = 0;
    for (size_t s = 0; s < total; s++) {
        memcpy(from + 3 * filled, pi + 3 * (s / (size_t)m), 3 * sizeof *from);
        memcpy(to + 3 * filled, pj + 3 * (s % (size_t)m), 3 * sizeof *to);
        if (++filled == BATCH || s + 1 == total) {
            vis_occluded_ctx(vis, &vc, filled, from, to, blocked, &rays); /* prepared above */
            for (size_t k = 0; k < filled; k++)
                visible += !blocked[k]; /* too-short segments count as visible */
            filled = 0;
        }
    }
    if (pts != stack_pts)
        free(pts);
    *fraction = (double)visible / ((double)m * (double)m);
    if (stats) {
        stats->rays += rays;
        stats->pairs_traced++;
    }
    return RAD_OK;
}
