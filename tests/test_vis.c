/* rad_vis against an analytic occluder configuration and an independent
 * brute-force ray-triangle test (Moller-Trumbore in double, written here). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_ff.h"
#include "rad_geom.h"
#include "rad_mesh.h"
#include "rad_scene.h"
#include "rad_sys.h"
#include "rad_vis.h"

/* Scene: bottom unit square z = 0 facing +z (triangles 0, 1), top unit square
 * z = D facing -z (triangles 2, 3), and a centred occluder square of side S at
 * z = D/2 (triangles 4, 5), shifted by `shift` in x (0: centred). */
#define D 1.385
#define S 0.4137

static void occluder_scene(double scale, double shift, double xyz[36], int tri[18])
{
    const double lo = 0.5 - S / 2, hi = 0.5 + S / 2;
    const double v[12][3] = {
        {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
        {0, 0, D}, {1, 0, D}, {1, 1, D}, {0, 1, D},
        {lo + shift, lo, D / 2}, {hi + shift, lo, D / 2}, {hi + shift, hi, D / 2}, {lo + shift, hi, D / 2},
    };
    const int t[18] = {0, 1, 2, 0, 2, 3, /* bottom, normal +z */
                       4, 6, 5, 4, 7, 6, /* top, normal -z */
                       8, 9, 10, 8, 10, 11};
    for (int k = 0; k < 12; k++)
        for (int c = 0; c < 3; c++)
            xyz[3 * k + c] = v[k][c] * scale;
    memcpy(tri, t, sizeof t);
}

/* Moller-Trumbore \cite{moller1997fast}: does the open segment p -> q cross
 * triangle (a, b, c)?  Closed triangles (edges count), in double. */
static int segment_hits(const double *p, const double *q, const double *a, const double *b,
                        const double *c)
{
    double d[3], e1[3], e2[3], s[3], h[3], qq[3];
    for (int k = 0; k < 3; k++) {
        d[k] = q[k] - p[k];
        e1[k] = b[k] - a[k];
        e2[k] = c[k] - a[k];
        s[k] = p[k] - a[k];
    }
    h[0] = d[1] * e2[2] - d[2] * e2[1];
    h[1] = d[2] * e2[0] - d[0] * e2[2];
    h[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
    if (fabs(det) < 1e-300)
        return 0;
    double u = (s[0] * h[0] + s[1] * h[1] + s[2] * h[2]) / det;
    const double slack = 1e-12; /* closed triangles: a shared edge cannot leak */
    if (u < -slack || u > 1 + slack)
        return 0;
    qq[0] = s[1] * e1[2] - s[2] * e1[1];
    qq[1] = s[2] * e1[0] - s[0] * e1[2];
    qq[2] = s[0] * e1[1] - s[1] * e1[0];
    double v = (d[0] * qq[0] + d[1] * qq[1] + d[2] * qq[2]) / det;
    if (v < -slack || u + v > 1 + slack)
        return 0;
    double t = (e2[0] * qq[0] + e2[1] * qq[1] + e2[2] * qq[2]) / det;
    return t > 1e-9 && t < 1 - 1e-9;
}

/* Brute-force visible fraction of pair (i, j) on rad_vis's own samples. */
static double brute_fraction(const rad_vis *vis, const double *xyz, const int *tri, int ntri,
                             int i, int j)
{
    int m = rad_vis_sample_count(vis);
    double *pi = malloc(6 * (size_t)m * sizeof *pi), *pj = pi + 3 * m;
    rad_vis_triangle_samples(vis, (size_t)i, pi);
    rad_vis_triangle_samples(vis, (size_t)j, pj);
    long visible = 0;
    for (int a = 0; a < m; a++)
        for (int b = 0; b < m; b++) {
            int hit = 0;
            for (int k = 0; k < ntri && !hit; k++)
                if (k != i && k != j)
                    hit = segment_hits(pi + 3 * a, pj + 3 * b, xyz + 3 * tri[3 * k],
                                       xyz + 3 * tri[3 * k + 1], xyz + 3 * tri[3 * k + 2]);
            visible += !hit;
        }
    free(pi);
    return (double)visible / ((double)m * m);
}

TEST(vis_point_queries_on_the_occluder_scene)
{
    double xyz[36];
    int tri[18];
    occluder_scene(1.0, 0.0, xyz, tri);
    for (int packet = 1; packet <= 16; packet *= 2) {
        if (packet == 2)
            continue;
        rad_vis_params p;
        rad_vis_params_default(&p);
        p.packet = packet;
        rad_vis *vis = NULL;
        CHECK(rad_vis_create(xyz, 12, tri, 6, &p, &vis) == RAD_OK);
        if (!vis)
            return;
        CHECK(!rad_vis_is_unoccluded(vis));
        /* Axis: blocked.  Corner to corner: free.  Then 203 random segments
         * between the two squares against the brute-force test. */
        enum { N = 205 };
        double from[3 * N], to[3 * N];
        unsigned char blocked[N];
        double axis_from[3] = {0.5, 0.5, 0}, axis_to[3] = {0.5, 0.5, D};
        double corner_from[3] = {0, 0, 0}, corner_to[3] = {0, 0, D};
        memcpy(from, axis_from, sizeof axis_from);
        memcpy(to, axis_to, sizeof axis_to);
        memcpy(from + 3, corner_from, sizeof corner_from);
        memcpy(to + 3, corner_to, sizeof corner_to);
        unsigned long long seed = 12345;
        for (int k = 2; k < N; k++)
            for (int c = 0; c < 3; c++) {
                seed = seed * 6364136223846793005ull + 1442695040888963407ull;
                double r1 = (double)(seed >> 11) * 0x1.0p-53;
                seed = seed * 6364136223846793005ull + 1442695040888963407ull;
                double r2 = (double)(seed >> 11) * 0x1.0p-53;
                from[3 * k + c] = c == 2 ? 0.0 : r1;
                to[3 * k + c] = c == 2 ? D : r2;
            }
        rad_vis_stats st = {0};
        CHECK(rad_vis_occluded(vis, N, from, to, blocked, &st) == RAD_OK);
        CHECK(blocked[0] == 1);
        CHECK(blocked[1] == 0);
        CHECK(st.rays == N);
        int nblocked = 0, mismatches = 0;
        for (int k = 0; k < N; k++) {
            int want = 0;
            for (int t = 0; t < 6 && !want; t++)
                want = segment_hits(from + 3 * k, to + 3 * k, xyz + 3 * tri[3 * t],
                                    xyz + 3 * tri[3 * t + 1], xyz + 3 * tri[3 * t + 2]);
            nblocked += want;
            mismatches += want != blocked[k];
        }
        CHECK_MSG(mismatches == 0, "packet %d: %d of %d segments disagree with brute force",
                  packet, mismatches, N);
        CHECK(nblocked > 10 && nblocked < N - 10); /* the test sees both outcomes */
        rad_vis_destroy(vis);
    }
}

TEST(vis_pair_fraction_matches_brute_force_and_analytic_value)
{
    double xyz[36];
    int tri[18];
    occluder_scene(1.0, 0.0, xyz, tri);
    rad_vis_params p;
    rad_vis_params_default(&p);
    p.strata_per_edge = 5;
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 12, tri, 6, &p, &vis) == RAD_OK);
    if (!vis)
        return;
    for (int i = 0; i < 2; i++)
        for (int j = 2; j < 4; j++) {
            double f = -1;
            rad_vis_stats st = {0};
            CHECK(rad_vis_pair_can_block(vis, (size_t)i, (size_t)j));
            CHECK(rad_vis_pair_fraction(vis, (size_t)i, (size_t)j, &f, &st) == RAD_OK);
            CHECK(st.rays == 625 && st.pairs_traced == 1);
            double want = brute_fraction(vis, xyz, tri, 6, i, j);
            CHECK_NEAR(f, want, 0.0, 1e-15);
            CHECK(want > 0.1 && want < 0.99);
            /* The same segments through rad_vis_occluded_between. */
            int m = rad_vis_sample_count(vis);
            double *si = malloc(6 * (size_t)m * sizeof *si), *sj = si + 3 * m;
            double *from = malloc(6 * (size_t)(m * m) * sizeof *from), *to = from + 3 * m * m;
            unsigned char *bl = malloc((size_t)(m * m));
            rad_vis_triangle_samples(vis, (size_t)i, si);
            rad_vis_triangle_samples(vis, (size_t)j, sj);
            for (int a = 0; a < m; a++)
                for (int b = 0; b < m; b++)
                    for (int c = 0; c < 3; c++) {
                        from[3 * (a * m + b) + c] = si[3 * a + c];
                        to[3 * (a * m + b) + c] = sj[3 * b + c];
                    }
            CHECK(rad_vis_occluded_between(vis, (size_t)i, (size_t)j, (size_t)(m * m), from, to, bl, NULL) == RAD_OK);
            int nvis = 0;
            for (int k = 0; k < m * m; k++)
                nvis += !bl[k];
            CHECK_NEAR((double)nvis / (m * m), want, 0.0, 1e-15);
            free(si);
            free(from);
            free(bl);
            double g = -1; /* symmetric */
            CHECK(rad_vis_pair_fraction(vis, (size_t)j, (size_t)i, &g, NULL) == RAD_OK);
            CHECK_NEAR(g, f, 0.0, 1e-15);
        }
    rad_vis_destroy(vis);

    /* Square to square: a segment from (x1,y1,0) to (x2,y2,D) crosses the
     * occluder plane at the midpoint; per axis the midpoint of two uniforms is
     * triangular on [0,1], so P(|m - 1/2| < S/2) = 1 - (1 - S)^2 and the blocked
     * fraction is that squared.  The four triangle pairs have equal weight. */
    p.strata_per_edge = 12;
    p.jitter = 1;
    CHECK(rad_vis_create(xyz, 12, tri, 6, &p, &vis) == RAD_OK);
    if (!vis)
        return;
    double sum = 0.0;
    for (int i = 0; i < 2; i++)
        for (int j = 2; j < 4; j++) {
            double f = 0;
            CHECK(rad_vis_pair_fraction(vis, (size_t)i, (size_t)j, &f, NULL) == RAD_OK);
            sum += f / 4.0;
        }
    double per_axis = 1.0 - (1.0 - S) * (1.0 - S);
    CHECK_NEAR(1.0 - sum, per_axis * per_axis, 0.0, 5e-3);
    rad_vis_destroy(vis);
}

TEST(vis_unblockable_pairs_trace_no_rays)
{
    double xyz[36];
    int tri[18];
    /* Two facing squares alone: a convex configuration, nothing can block. */
    occluder_scene(1.0, 0.0, xyz, tri);
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 8, tri, 4, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    CHECK(rad_vis_is_unoccluded(vis));
    rad_vis_stats st = {0};
    double f = 0;
    CHECK(rad_vis_pair_fraction(vis, 0, 3, &f, &st) == RAD_OK);
    CHECK(f == 1.0 && st.rays == 0 && st.pairs_skipped == 1);
    rad_vis_destroy(vis);

    /* The occluder moved aside by 2.5: the scene is no longer convex, but the
     * shaft between the squares is empty. */
    occluder_scene(1.0, 2.5, xyz, tri);
    CHECK(rad_vis_create(xyz, 12, tri, 6, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    CHECK(!rad_vis_is_unoccluded(vis));
    memset(&st, 0, sizeof st);
    for (int i = 0; i < 2; i++)
        for (int j = 2; j < 4; j++) {
            CHECK(!rad_vis_pair_can_block(vis, (size_t)i, (size_t)j));
            CHECK(rad_vis_pair_fraction(vis, (size_t)i, (size_t)j, &f, &st) == RAD_OK);
            CHECK(f == 1.0);
        }
    CHECK(st.rays == 0 && st.pairs_skipped == 4);
    /* The occluder and the bottom square: shaft between them is empty too. */
    CHECK(!rad_vis_pair_can_block(vis, 0, 4));
    rad_vis_destroy(vis);

    /* Moved by only 0.45: it still reaches into the shaft of some pairs. */
    occluder_scene(1.0, 0.45, xyz, tri);
    CHECK(rad_vis_create(xyz, 12, tri, 6, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    int blockable = 0;
    for (int i = 0; i < 2; i++)
        for (int j = 2; j < 4; j++)
            blockable += rad_vis_pair_can_block(vis, (size_t)i, (size_t)j);
    CHECK(blockable > 0);
    rad_vis_destroy(vis);
}

TEST(vis_shaft_test_is_conservative_on_random_scenes)
{
    /* 40 random small triangles around two fixed ones: whenever the shaft test
     * says "nothing can block", the brute-force fraction must be exactly 1. */
    enum { NT = 42 };
    double xyz[9 * NT];
    int tri[3 * NT];
    unsigned long long seed = 987654321;
    for (int k = 0; k < 9 * NT; k++) {
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        xyz[k] = 3.1 * ((double)(seed >> 11) * 0x1.0p-53) - 0.7;
    }
    for (int k = 0; k < 3 * NT; k++)
        tri[k] = k;
    for (int t = 2; t < NT; t++) /* shrink the clutter to 0.12 of its size */
        for (int v = 1; v < 3; v++)
            for (int c = 0; c < 3; c++)
                xyz[9 * t + 3 * v + c] = xyz[9 * t + c] + 0.12 * (xyz[9 * t + 3 * v + c] - xyz[9 * t + c]);
    rad_vis_params p;
    rad_vis_params_default(&p);
    p.strata_per_edge = 3;
    p.jitter = 1;
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 3 * NT, tri, NT, &p, &vis) == RAD_OK);
    if (!vis)
        return;
    int skipped = 0, traced = 0, wrong = 0, mismatch = 0;
    for (int i = 0; i < NT; i++)
        for (int j = i + 1; j < NT; j++) {
            double f = 0, want = brute_fraction(vis, xyz, tri, NT, i, j);
            rad_vis_stats st = {0};
            rad_vis_pair_fraction(vis, (size_t)i, (size_t)j, &f, &st);
            if (st.rays == 0) {
                skipped++;
                wrong += want != 1.0;
            } else {
                traced++;
                mismatch += fabs(f - want) > 2.5 / 81.0; /* float rays may differ on grazing ones */
            }
        }
    CHECK_MSG(wrong == 0, "%d skipped pairs are in fact blocked", wrong);
    CHECK_MSG(mismatch == 0, "%d traced pairs differ from brute force", mismatch);
    CHECK_MSG(skipped > 30 && traced > 30, "skipped %d, traced %d", skipped, traced);
    rad_vis_destroy(vis);
}

TEST(vis_epsilon_scales_with_the_scene)
{
    double scales[3] = {1e-3, 1.0, 1e3}, fr[3][4];
    double xyz[36];
    int tri[18];
    for (int s = 0; s < 3; s++) {
        occluder_scene(scales[s], 0.0, xyz, tri);
        rad_vis *vis = NULL;
        CHECK(rad_vis_create(xyz, 12, tri, 6, NULL, &vis) == RAD_OK);
        if (!vis)
            return;
        double L = rad_vis_scale(vis);
        CHECK_NEAR(rad_vis_epsilon(vis), 1e-5 * L, 1e-15, 0.0);
        CHECK_NEAR(L, scales[s] * sqrt(2.0 + D * D), 1e-12, 0.0);
        for (int i = 0; i < 2; i++)
            for (int j = 2; j < 4; j++)
                CHECK(rad_vis_pair_fraction(vis, (size_t)i, (size_t)j, &fr[s][2 * i + j - 2], NULL) == RAD_OK);
        /* A point just above the bottom square's centre, by 10 eps, still sees
         * the occluder; a segment of 1.5 eps is too short to be blocked. */
        double e = rad_vis_epsilon(vis);
        double a[3] = {0.5 * scales[s], 0.5 * scales[s], 10 * e};
        double b[3] = {0.5 * scales[s], 0.5 * scales[s], D * scales[s]};
        unsigned char bl = 9;
        rad_vis_occluded(vis, 1, a, b, &bl, NULL);
        CHECK(bl == 1);
        rad_vis_destroy(vis);
    }
    for (int k = 0; k < 4; k++) {
        CHECK(fr[0][k] < 1.0);
        CHECK_NEAR(fr[0][k], fr[1][k], 0.0, 1e-15);
        CHECK_NEAR(fr[2][k], fr[1][k], 0.0, 1e-15);
    }
}

TEST(vis_parallel_queries_match_serial)
{
    double xyz[36];
    int tri[18];
    occluder_scene(1.0, 0.1, xyz, tri);
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 12, tri, 6, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    double serial[36], parallel[36];
    unsigned long long rays_serial = 0, rays_parallel = 0;
    for (int k = 0; k < 36; k++) {
        rad_vis_stats st = {0};
        rad_vis_pair_fraction(vis, (size_t)(k / 6), (size_t)(k % 6), &serial[k], &st);
        rays_serial += st.rays;
    }
#pragma omp parallel for num_threads(2) reduction(+ : rays_parallel) schedule(dynamic)
    for (int k = 0; k < 36; k++) {
        rad_vis_stats st = {0};
        rad_vis_pair_fraction(vis, (size_t)(k / 6), (size_t)(k % 6), &parallel[k], &st);
        rays_parallel += st.rays;
    }
    for (int k = 0; k < 36; k++)
        CHECK(serial[k] == parallel[k]);
    CHECK(rays_serial == rays_parallel && rays_serial > 0);
    rad_vis_destroy(vis);
}

/* Embree's structures are made by the first ray (rad_vis_prepare_rays):
 * here by eight threads at once, each of whose first query must find them
 * made exactly once and answer as a serial query does (the axis through the
 * occluder blocked, a corner-to-corner segment open); and a prepare after
 * that is a no-op that still succeeds. */
TEST(vis_rays_are_made_on_first_use_by_any_thread)
{
    double xyz[36];
    int tri[18];
    occluder_scene(1.0, 0.0, xyz, tri);
    for (int round = 0; round < 4; round++) {
        rad_vis *vis = NULL;
        CHECK(rad_vis_create(xyz, 12, tri, 6, NULL, &vis) == RAD_OK);
        if (!vis)
            return;
        int wrong = 0, failed = 0;
#pragma omp parallel for num_threads(8) reduction(+ : wrong, failed) schedule(static, 1)
        for (int k = 0; k < 64; k++) {
            double from[6] = {0.5, 0.5, 0, 0, 0, 0}, to[6] = {0.5, 0.5, D, 0, 0, D};
            unsigned char blocked[2] = {9, 9};
            if (k % 2) {
                double p[3] = {0.5, 0.5, 0}, q[3] = {0.5, 0.5, D};
                failed += rad_vis_prepare_rays(vis) != RAD_OK;
                wrong += rad_vis_segment_blocked(vis, p, q, -1, -1) != 1;
            } else {
                failed += rad_vis_occluded(vis, 2, from, to, blocked, NULL) != RAD_OK;
                wrong += blocked[0] != 1 || blocked[1] != 0;
            }
        }
        CHECK_MSG(failed == 0 && wrong == 0, "round %d: %d queries failed, %d answered wrong",
                  round, failed, wrong);
        CHECK(rad_vis_prepare_rays(vis) == RAD_OK);
        rad_vis_destroy(vis);
    }
}

TEST(vis_closest_hit_barycentrics)
{
    double xyz[36];
    int tri[18];
    occluder_scene(1.0, 0.0, xyz, tri);
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 12, tri, 6, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    /* Straight down at (0.8125, 0.3125) from z = 0.5, below the occluder: hits
     * bottom triangle 0 = (0,0,0),(1,0,0),(1,1,0) where x = u + v, y = v.
     * Straight up from the centre: hits the occluder. */
    double org[6] = {0.8125, 0.3125, 0.5, 0.5, 0.5, 0.5}, dir[6] = {0, 0, -2.0, 0, 0, 1.0};
    int t[2];
    double th[2], u[2], v[2];
    CHECK(rad_vis_intersect(vis, 2, org, dir, 0.0, t, th, u, v, NULL) == RAD_OK);
    CHECK(t[0] == 0);
    CHECK_NEAR(th[0], 0.25, 1e-6, 0.0);
    CHECK_NEAR(u[0], 0.5, 0.0, 1e-6);
    CHECK_NEAR(v[0], 0.3125, 0.0, 1e-6);
    CHECK(t[1] == 4 || t[1] == 5); /* the centre is over the occluder */
    CHECK_NEAR(th[1], D / 2 - 0.5, 1e-6, 0.0);
    double up[3] = {0, 0, 1}, above[3] = {0.5, 0.5, D + 0.25};
    CHECK(rad_vis_intersect(vis, 1, above, up, 0.0, t, NULL, NULL, NULL, NULL) == RAD_OK);
    CHECK(t[0] == -1);
    rad_vis_destroy(vis);
}

TEST(vis_rejects_bad_input)
{
    double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, NAN};
    int tri[3] = {0, 1, 2}, bad[3] = {0, 1, 3};
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 3, tri, 1, NULL, &vis) == RAD_EINPUT);
    CHECK(vis == NULL);
    xyz[8] = 0.0;
    CHECK(rad_vis_create(xyz, 3, bad, 1, NULL, &vis) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "triangle 0") != NULL);
    rad_vis_params p;
    rad_vis_params_default(&p);
    p.packet = 3;
    CHECK(rad_vis_create(xyz, 3, tri, 1, &p, &vis) == RAD_EINVAL);
    rad_vis_params_default(&p);
    p.eps_rel = 0.0;
    CHECK(rad_vis_create(xyz, 3, tri, 1, &p, &vis) == RAD_EINVAL);
    rad_vis_destroy(NULL);
    /* An empty scene is valid: nothing blocks anything. */
    CHECK(rad_vis_create(NULL, 0, NULL, 0, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    double a[3] = {0, 0, 0}, b[3] = {1, 2, 3};
    unsigned char bl = 7;
    CHECK(rad_vis_occluded(vis, 1, a, b, &bl, NULL) == RAD_OK && bl == 0);
    CHECK(rad_vis_is_unoccluded(vis));
    rad_vis_destroy(vis);
}

TEST(vis_geom_normal_follows_the_winding_in_every_branch)
{
    /* rad_geom_triangle_normal takes its cross product from the vertex opposite
     * the longest edge; each of the three choices must give the winding's
     * normal (b - a) x (c - a).  Here the longest edge is ab, bc, ca in turn. */
    rad_vec3 tris[3][3] = {
        {{0, 0, 0}, {2.385, 0, 0}, {1.1, 0.7, 0}},   /* ab longest */
        {{0.2, 0.1, 0}, {2.385, 0, 0}, {0, 1.9, 0}}, /* bc longest */
        {{0, 0, 0}, {1, 0, 0}, {1, 1.3, 0}},         /* ca longest */
    };
    for (int k = 0; k < 3; k++) {
        rad_vec3 n = rad_geom_triangle_normal(tris[k][0], tris[k][1], tris[k][2]);
        CHECK_MSG(n.z > 0.999, "case %d: normal z = %g, want +1", k, n.z);
    }
}

/* The Cornell box refined once (the boxes among the walls, each wall in
 * coplanar pieces) and its visibility over the refined triangles, *n of
 * them; NULL (after a failed check) when it cannot be made.  Released by
 * cornell_close whatever it returned. */
typedef struct cornell_refined {
    rad_scene *scene;
    rad_mesh *base, *mesh;
    rad_vis *vis;
} cornell_refined;

static rad_vis *cornell_open(cornell_refined *c, size_t *n)
{
    memset(c, 0, sizeof *c);
    *n = 0;
    if (!(c->scene = harness_scene_load("scenes/cornell/cornell.obj", NULL)))
        return NULL;
    CHECK(rad_mesh_create(rad_scene_vertices(c->scene), rad_scene_vertex_count(c->scene),
                          rad_scene_triangles(c->scene), rad_scene_triangle_count(c->scene),
                          NULL, &c->base) == RAD_OK);
    if (!c->base)
        return NULL;
    CHECK(rad_mesh_refine_uniform(c->base, 1, 100000, &c->mesh) == RAD_OK);
    if (!c->mesh)
        return NULL;
    *n = (size_t)rad_mesh_face_count(c->mesh);
    CHECK(rad_vis_create(rad_mesh_vertices(c->mesh), (size_t)rad_mesh_vertex_count(c->mesh),
                         rad_mesh_triangles(c->mesh), *n, NULL, &c->vis) == RAD_OK);
    return c->vis;
}

static void cornell_close(cornell_refined *c)
{
    rad_vis_destroy(c->vis);
    rad_mesh_destroy(c->mesh);
    rad_mesh_destroy(c->base);
    rad_scene_destroy(c->scene);
}

/* The shaft test may only skip what no ray can find blocked: on the refined
 * Cornell box, every pair it clears must have all its sample segments that
 * carry light (both cosines positive) free when they are traced.  (Segments
 * with a zero kernel, such as those between two floor elements that run in
 * the floor's plane past the blocks' bottom edges, do not matter.)  Walls,
 * floor and ceiling lie on the scene's convex hull and are never blockers, so
 * most pairs are cleared without a plane. */
TEST(vis_shaft_test_is_conservative_on_the_cornell_box)
{
    cornell_refined cb;
    size_t n;
    rad_vis *vis = cornell_open(&cb, &n);
    if (!vis) {
        cornell_close(&cb);
        return;
    }
    rad_mesh *mesh = cb.mesh;
    int ns = rad_vis_sample_count(vis);
    double *si = malloc(3 * (size_t)ns * sizeof *si), *sj = malloc(3 * (size_t)ns * sizeof *sj);
    double *from = malloc(3 * (size_t)ns * ns * sizeof *from), *to = malloc(3 * (size_t)ns * ns * sizeof *to);
    unsigned char *blocked = malloc((size_t)ns * ns);
    rad_vis_stats st = {0, 0, 0};
    long cleared = 0, wrong = 0, total = 0, carrying = 0;
    const double *xyz = rad_mesh_vertices(mesh);
    const int *tri = rad_mesh_triangles(mesh);
    for (size_t i = 0; i < n; i++) {
        rad_vis_triangle_samples(vis, i, si);
        rad_vec3 ni = rad_geom_triangle_normal(
            rad_vec3_make(xyz[3 * tri[3 * i]], xyz[3 * tri[3 * i] + 1], xyz[3 * tri[3 * i] + 2]),
            rad_vec3_make(xyz[3 * tri[3 * i + 1]], xyz[3 * tri[3 * i + 1] + 1], xyz[3 * tri[3 * i + 1] + 2]),
            rad_vec3_make(xyz[3 * tri[3 * i + 2]], xyz[3 * tri[3 * i + 2] + 1], xyz[3 * tri[3 * i + 2] + 2]));
        for (size_t j = i + 1; j < n; j++) {
            total++;
            if (rad_vis_pair_can_block(vis, i, j))
                continue;
            cleared++;
            rad_vis_triangle_samples(vis, j, sj);
            rad_vec3 nj = rad_geom_triangle_normal(
                rad_vec3_make(xyz[3 * tri[3 * j]], xyz[3 * tri[3 * j] + 1], xyz[3 * tri[3 * j] + 2]),
                rad_vec3_make(xyz[3 * tri[3 * j + 1]], xyz[3 * tri[3 * j + 1] + 1], xyz[3 * tri[3 * j + 1] + 2]),
                rad_vec3_make(xyz[3 * tri[3 * j + 2]], xyz[3 * tri[3 * j + 2] + 1], xyz[3 * tri[3 * j + 2] + 2]));
            for (int a = 0; a < ns; a++)
                for (int b = 0; b < ns; b++) {
                    memcpy(from + 3 * (a * ns + b), si + 3 * a, 3 * sizeof *si);
                    memcpy(to + 3 * (a * ns + b), sj + 3 * b, 3 * sizeof *sj);
                }
            /* Hits on i and j themselves are ignored, as in rad_vis_pair_fraction:
             * the measured red wall is folded, and rays between its halves
             * graze their own (float) triangle. */
            rad_vis_occluded_between(vis, i, j, (size_t)ns * ns, from, to, blocked, &st);
            for (int k = 0; k < ns * ns; k++) {
                rad_vec3 d = rad_vec3_make(to[3 * k] - from[3 * k], to[3 * k + 1] - from[3 * k + 1],
                                           to[3 * k + 2] - from[3 * k + 2]);
                double tol = 1e-9 * rad_vec3_norm(d);
                if (!(rad_vec3_dot(ni, d) > tol) || !(rad_vec3_dot(nj, d) < -tol))
                    continue; /* zero kernel (within the shaft's tolerance): visibility does not matter */
                carrying++;
                wrong += blocked[k];
            }
        }
    }
    CHECK_MSG(wrong == 0, "%ld sample segments blocked in pairs the shaft test cleared", wrong);
    /* What clearing promises: the blocks (input faces 18..37) are the only
     * blockers, so every pair whose box misses the blocks' box is cleared
     * without a plane. */
    const int *parent = rad_mesh_input_faces(mesh);
    double blo[3] = {INFINITY, INFINITY, INFINITY}, bhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t t = 0; t < n; t++)
        if (parent[t] >= 18)
            for (int v = 0; v < 3; v++)
                for (int c = 0; c < 3; c++) {
                    blo[c] = fmin(blo[c], xyz[3 * tri[3 * t + v] + c]);
                    bhi[c] = fmax(bhi[c], xyz[3 * tri[3 * t + v] + c]);
                }
    long away = 0, away_cleared = 0;
    for (size_t i = 0; i < n; i++)
        for (size_t j = i + 1; j < n; j++) {
            double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (int v = 0; v < 3; v++)
                for (int c = 0; c < 3; c++) {
                    lo[c] = fmin(lo[c], fmin(xyz[3 * tri[3 * i + v] + c], xyz[3 * tri[3 * j + v] + c]));
                    hi[c] = fmax(hi[c], fmax(xyz[3 * tri[3 * i + v] + c], xyz[3 * tri[3 * j + v] + c]));
                }
            int apart = 0;
            for (int c = 0; c < 3; c++)
                apart |= lo[c] > bhi[c] + 1e-3 || hi[c] < blo[c] - 1e-3;
            if (apart) {
                away++;
                away_cleared += !rad_vis_pair_can_block(vis, i, j);
            }
        }
    CHECK_MSG(away > 500 && away_cleared == away, "%ld of %ld pairs away from the blocks cleared",
              away_cleared, away);
    CHECK(cleared < total); /* and the pairs behind the blocks are not */
    CHECK(carrying > 100000); /* the check looked at many segments */
    CHECK(!rad_vis_is_unoccluded(vis)); /* the blocks do occlude */
    free(si);
    free(sj);
    free(from);
    free(to);
    free(blocked);
    cornell_close(&cb);
}

/* In an L-shaped room the walls of the inner corner are not on the hull: they
 * must stay blockers, and a pair seen across the corner must be blocked.  The
 * receivers are turned towards each other (the kernel between them is
 * positive). */
TEST(vis_inner_corner_walls_still_block)
{
    /* Floor plan: the L = [0,2]x[0,1] u [0,1]x[1,2], height 1; the two walls of
     * its inner corner are x = 1 (y in [1,2]) and y = 1 (x in [1,2]).  Upright
     * receivers centred near (1.8, 0.8) and (0.8, 1.8) are joined by segments
     * near x + y = 2.6, which cross both walls (at y = 1.6 and at x = 1.6). */
    double xyz[] = {
        1, 1, 0, 1, 2, 0, 1, 2, 1, 1, 1, 1,          /* wall x = 1 */
        1, 1, 0, 1, 1, 1, 2, 1, 1, 2, 1, 0,          /* wall y = 1 */
        1.7, 0.7, 0.05, 1.9, 0.7, 0.05, 1.8, 0.9, 1.0, /* receiver i, upright */
        0.7, 1.7, 0.05, 0.9, 1.8, 1.0, 0.7, 1.9, 0.05, /* receiver j, upright */
        0, 0, -0.5, 3, 0, -0.5, 0, 3, -0.5,          /* a floor far below: one plane */
    };
    int tri[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 10, 9, 11, 13, 12, 14, 15, 16};
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 17, tri, 7, NULL, &vis) == RAD_OK);
    CHECK(rad_vis_pair_can_block(vis, 4, 5) == 1);
    double frac = 1.0;
    rad_vis_stats st = {0, 0, 0};
    CHECK(rad_vis_pair_fraction(vis, 4, 5, &frac, &st) == RAD_OK);
    CHECK_MSG(frac < 0.5, "fraction across the inner corner = %g", frac);
    rad_vis_destroy(vis);
}

/* A triangle behind the plane of one end blocks only segments along which
 * the kernel vanishes: a floor triangle i (z = 0, facing up) and a wall
 * triangle j (x = 2, facing -x) reaching below the floor, with a blocker k
 * below the floor inside their hull.  The shaft test clears the pair (no
 * blockers listed), every sample segment of positive kernel is free when
 * traced, and some of zero kernel are blocked (k does lie in the shaft); the
 * same blocker above the floor is found. */
TEST(vis_blockers_behind_an_end_carry_nothing)
{
    for (int above = 0; above < 2; above++) {
        double zk = above ? 0.3 : -0.3;
        double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0,                  /* i: floor, +z */
                        2, 0, -1, 2, 0, 1, 2, 1, 0,                 /* j: wall, -x */
                        1.2, 0, zk, 1.8, 0, zk, 1.5, 1, zk};        /* k */
        int tri[] = {0, 1, 2, 3, 4, 5, 6, 7, 8};
        rad_vis *vis = NULL;
        CHECK(rad_vis_create(xyz, 9, tri, 3, NULL, &vis) == RAD_OK);
        if (!vis)
            return;
        int blk[4];
        rad_vec3 a[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, b[3] = {{2, 0, -1}, {2, 0, 1}, {2, 1, 0}};
        CHECK(rad_vis_pair_can_block(vis, 0, 1) == above);
        CHECK(rad_vis_blockers(vis, a, 0, b, 1, blk, 4) == above);
        int ns = rad_vis_sample_count(vis);
        double *si = malloc(3 * (size_t)ns * sizeof *si), *sj = malloc(3 * (size_t)ns * sizeof *sj);
        double *from = malloc(3 * (size_t)ns * ns * sizeof *from);
        double *to = malloc(3 * (size_t)ns * ns * sizeof *to);
        unsigned char *blocked = malloc((size_t)ns * ns);
        rad_vis_triangle_samples(vis, 0, si);
        rad_vis_triangle_samples(vis, 1, sj);
        for (int p = 0; p < ns; p++)
            for (int q = 0; q < ns; q++) {
                memcpy(from + 3 * (p * ns + q), si + 3 * p, 3 * sizeof *si);
                memcpy(to + 3 * (p * ns + q), sj + 3 * q, 3 * sizeof *sj);
            }
        rad_vis_stats st = {0, 0, 0};
        CHECK(rad_vis_occluded_between(vis, 0, 1, (size_t)ns * ns, from, to, blocked, &st) == RAD_OK);
        long carrying_blocked = 0, idle_blocked = 0;
        for (int k = 0; k < ns * ns; k++) {
            /* the kernel is positive where j's point lies above the floor
               (i's normal +z) and i's point in front of the wall (always) */
            if (to[3 * k + 2] > 0.0)
                carrying_blocked += blocked[k];
            else
                idle_blocked += blocked[k];
        }
        if (above) {
            CHECK_MSG(carrying_blocked > 0, "the blocker above the floor blocks %ld segments",
                      carrying_blocked);
        } else {
            CHECK_MSG(carrying_blocked == 0 && idle_blocked > 0,
                      "below the floor: %ld segments of positive kernel blocked, %ld of zero",
                      carrying_blocked, idle_blocked);
        }
        free(si);
        free(sj);
        free(from);
        free(to);
        free(blocked);
        rad_vis_destroy(vis);
    }
}

/* rad_vis_point_visible_limited: a point 2 above the unit square z = 0 sees it
 * through a screen at z = 1 of n x n small squares on a checkerboard (2 n^2
 * triangles).  The squares are disjoint, so their shadows from the point are
 * disjoint squares twice their size, and the visible form factor is the open
 * one minus each shadow's (the closed form of rad_ff_point_polygon, clipped
 * to the unit square here).  Unlimited, the clipping gives that value; a
 * budget it needs less than gives the same bits; a budget it exceeds
 * refuses, so that the caller falls back to rays. */
TEST(vis_point_visible_within_a_work_budget)
{
    enum { N = 12 }; /* squares per row: N^2 / 2 on the checkerboard */
    const double side = 0.4 / N, h = 1.0;
    double xyz[3 * (4 + 4 * N * N)];
    int tri[3 * (2 + 2 * N * N)], nv = 0, nt = 0, sq = 0;
    const double floor_v[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    for (int k = 0; k < 4; k++)
        for (int c = 0; c < 3; c++)
            xyz[3 * nv + 3 * k + c] = floor_v[k][c];
    nv = 4;
    tri[0] = 0; tri[1] = 1; tri[2] = 2;
    tri[3] = 0; tri[4] = 2; tri[5] = 3;
    nt = 2;
    /* the screen's squares sit over the middle of the floor, where their
       doubled shadows (about the point (0.5, 0.5, 2)) land inside it */
    double lo[N * N][2];
    sq = harness_checkerboard(N, 0.3, side, lo);
    for (int s = 0; s < sq; s++) {
        double x0 = lo[s][0], y0 = lo[s][1];
        const double v[4][2] = {{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
        for (int k = 0; k < 4; k++) {
            xyz[3 * (nv + k)] = v[k][0];
            xyz[3 * (nv + k) + 1] = v[k][1];
            xyz[3 * (nv + k) + 2] = h;
        }
        int t[6] = {nv, nv + 2, nv + 1, nv, nv + 3, nv + 2};
        memcpy(tri + 3 * nt, t, sizeof t);
        nv += 4;
        nt += 2;
    }
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, (size_t)nv, tri, (size_t)nt, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    int blockers[2 * N * N];
    for (int k = 2; k < nt; k++)
        blockers[k - 2] = k;
    int nb = nt - 2;
    /* the point, a little off the centre so that shadows do not meet the
       floor's diagonal edge at a corner; it faces down */
    rad_vec3 x = rad_vec3_make(0.5 + 1e-3, 0.5 - 2e-3, 2.0 * h), nx = rad_vec3_make(0, 0, -1);
    rad_vec3 b[2][3];
    for (int t = 0; t < 2; t++)
        for (int v = 0; v < 3; v++)
            b[t][v] = rad_vec3_make(xyz[3 * tri[3 * t + v]], xyz[3 * tri[3 * t + v] + 1],
                                    xyz[3 * tri[3 * t + v] + 2]);
    /* the expected value over the whole floor (both triangles): open minus the
       shadows, each the square doubled about x's foot */
    rad_vec3 quad[4] = {rad_vec3_make(0, 0, 0), rad_vec3_make(1, 0, 0), rad_vec3_make(1, 1, 0),
                        rad_vec3_make(0, 1, 0)};
    double expect = rad_ff_point_polygon(x, nx, quad, 4);
    for (int s = 0; s < sq; s++) {
        rad_vec3 shadow[4];
        const double c[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
        for (int k = 0; k < 4; k++) {
            double px = lo[s][0] + c[k][0] * side, py = lo[s][1] + c[k][1] * side;
            shadow[k] = rad_vec3_make(x.x + 2.0 * (px - x.x), x.y + 2.0 * (py - x.y), 0.0);
        }
        expect -= rad_ff_point_polygon(x, nx, shadow, 4);
    }
    double unlimited = 0.0, within = 0.0, F, Fo;
    long evals = 0;
    int ok_unlimited = 1, ok_within = 1, refused = 0;
    for (int t = 0; t < 2; t++) {
        ok_unlimited &= rad_vis_point_visible_limited(vis, x, nx, b[t], blockers, nb, 0, &F, &Fo, &evals);
        unlimited += F;
        double G;
        ok_within &= rad_vis_point_visible_limited(vis, x, nx, b[t], blockers, nb, 1L << 30, &G, &Fo,
                                                   &evals);
        ok_within &= G == F; /* the same clipping, to the bit */
        within += G;
        refused += !rad_vis_point_visible_limited(vis, x, nx, b[t], blockers, nb,
                                                  RAD_VIS_LINK_POINT_WORK, &G, &Fo, &evals);
    }
    CHECK_MSG(ok_unlimited && fabs(unlimited - expect) <= 1e-10 * expect,
              "unlimited: %.15g, expected %.15g (ok %d)", unlimited, expect, ok_unlimited);
    CHECK_MSG(ok_within && within == unlimited, "a budget it needs less than: %.15g vs %.15g",
              within, unlimited);
    CHECK_MSG(refused == 2, "the links' budget refused %d of 2 halves (%d blockers)", refused, nb);
    printf("# %d blockers: F_vis %.12g (open %.6g), expected %.12g; refused within %d tests\n", nb,
           unlimited, rad_ff_point_polygon(x, nx, quad, 4), expect, RAD_VIS_LINK_POINT_WORK);
    rad_vis_destroy(vis);
}

/* A screen over a floor whose pieces are pairs of triangles sharing an
 * edge: a convex quad (clipped as one, partner.c), a dart (not convex: two
 * shadows; pairing it fails this test), and a pair folded by 1e-6 along
 * its shared edge.  The floor's visible form factor from a point above must equal
 * the open one minus every triangle's shadow in closed form (the screen's
 * triangles do not overlap, nor do their shadows); and the parts call, on
 * the four midpoint children of each floor triangle, must tile it: each
 * child as clipped alone, their sum the whole. */
TEST(vis_quads_and_parts_clip_exactly)
{
    const double h = 1.0;
    const double xyz[] = {
        0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,                 /* floor 0..3 */
        0.30, 0.30, h, 0.45, 0.30, h, 0.45, 0.42, h, 0.30, 0.42, h, /* quad 4..7 */
        0.55, 0.30, h, 0.70, 0.30, h, 0.60, 0.36, h, 0.62, 0.45, h, /* dart 8..11 */
        0.35, 0.55, h, 0.50, 0.55, h, 0.50, 0.70, h, 0.35, 0.70, h + 1e-6, /* fold 12..15 */
    };
    const int tri[] = {0, 1, 2, 0, 2, 3,                    /* floor, facing up */
                       4, 6, 5, 4, 7, 6,                    /* facing down */
                       8, 10, 9, 10, 11, 9,                 /* dart: 8-10-9 and 10-11-9 share 10-9 */
                       12, 14, 13, 12, 15, 14};
    int nt = (int)(sizeof tri / sizeof tri[0] / 3);
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, sizeof xyz / sizeof xyz[0] / 3, tri, (size_t)nt, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    int blockers[8], nb = 0;
    for (int k = 2; k < nt; k++)
        blockers[nb++] = k;
    rad_vec3 x = rad_vec3_make(0.5 + 1e-3, 0.5 - 2e-3, 2.0 * h), nx = rad_vec3_make(0, 0, -1);
    rad_vec3 quad[4] = {rad_vec3_make(0, 0, 0), rad_vec3_make(1, 0, 0), rad_vec3_make(1, 1, 0),
                        rad_vec3_make(0, 1, 0)};
    double expect = rad_ff_point_polygon(x, nx, quad, 4);
    for (int k = 2; k < nt; k++) {
        rad_vec3 s[3];
        for (int v = 0; v < 3; v++) {
            const double *p = xyz + 3 * tri[3 * k + v];
            double t = x.z / (x.z - p[2]); /* from x through p down to z = 0 */
            s[v] = rad_vec3_make(x.x + t * (p[0] - x.x), x.y + t * (p[1] - x.y), 0.0);
        }
        if (rad_vec3_cross(rad_vec3_sub(s[1], s[0]), rad_vec3_sub(s[2], s[0])).z < 0.0) {
            rad_vec3 swap = s[1]; /* facing up, towards x, as the floor */
            s[1] = s[2];
            s[2] = swap;
        }
        expect -= rad_ff_point_polygon(x, nx, s, 3);
    }
    double whole = 0.0, parts_sum = 0.0, worst = 0.0;
    int ok = 1;
    long evals = 0;
    for (int t = 0; t < 2; t++) {
        rad_vec3 b[3], mid[3], parts[12];
        for (int v = 0; v < 3; v++)
            b[v] = rad_vec3_make(xyz[3 * tri[3 * t + v]], xyz[3 * tri[3 * t + v] + 1],
                                 xyz[3 * tri[3 * t + v] + 2]);
        for (int v = 0; v < 3; v++)
            mid[v] = rad_vec3_scale(rad_vec3_add(b[v], b[(v + 1) % 3]), 0.5);
        const rad_vec3 ch[12] = {b[0], mid[0], mid[2], mid[0], b[1], mid[1],
                                 mid[2], mid[1], b[2], mid[0], mid[1], mid[2]};
        memcpy(parts, ch, sizeof parts);
        double F, Fo, Fp[4], Fpo[4];
        ok &= rad_vis_point_visible(vis, x, nx, b, blockers, nb, &F, &Fo, &evals);
        whole += F;
        ok &= rad_vis_point_visible_parts(vis, x, nx, b, parts, 4, blockers, nb, 0, Fp, Fpo,
                                          &evals);
        for (int i = 0; i < 4; i++) {
            double alone, alone_open;
            ok &= rad_vis_point_visible(vis, x, nx, parts + 3 * i, blockers, nb, &alone,
                                        &alone_open, &evals);
            worst = fmax(worst, fabs(Fp[i] - alone) + fabs(Fpo[i] - alone_open));
            parts_sum += Fp[i];
        }
    }
    CHECK_MSG(ok && fabs(whole - expect) <= 1e-12 * expect, "whole floor %.15g, expected %.15g",
              whole, expect);
    CHECK_MSG(fabs(parts_sum - expect) <= 1e-12 * expect, "the parts %.15g, expected %.15g",
              parts_sum, expect);
    CHECK_MSG(worst <= 1e-13, "a part differs from its own clipping by %.3g", worst);
    printf("# quads, dart and fold: F_vis %.15g, expected %.15g, parts %.15g\n", whole, expect,
           parts_sum);
    rad_vis_destroy(vis);
}

/* A uniform number in [0, 1) from a counter-based stream. */
static double unit_draw(unsigned long long *state)
{
    *state += 0x9E3779B97F4A7C15ull;
    return rad_sys_hash_unit(*state);
}

/* A random box (eight corners of a rotated, scaled, shifted cube) as twelve
 * triangles with the corners repeated per face, as files write them, facing
 * out. */
static void random_box(rad_vec3 c, double size, unsigned long long *seed, double *xyz,
                       int *tri, int v0)
{
    double q[4];
    for (int k = 0; k < 4; k++)
        q[k] = 2.0 * unit_draw(seed) - 1.0;
    double qn = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; k++)
        q[k] /= qn;
    double w = q[0], a = q[1], b = q[2], cc = q[3];
    double R[3][3] = {{1 - 2 * (b * b + cc * cc), 2 * (a * b - w * cc), 2 * (a * cc + w * b)},
                      {2 * (a * b + w * cc), 1 - 2 * (a * a + cc * cc), 2 * (b * cc - w * a)},
                      {2 * (a * cc - w * b), 2 * (b * cc + w * a), 1 - 2 * (a * a + b * b)}};
    double ext[3];
    for (int k = 0; k < 3; k++)
        ext[k] = size * (0.3 + 0.7 * unit_draw(seed));
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    int v = 0;
    for (int f = 0; f < 6; f++) {
        for (int k = 0; k < 4; k++) {
            int corner = faces[f][k];
            double l[3] = {(corner & 1 ? 0.5 : -0.5) * ext[0], (corner & 2 ? 0.5 : -0.5) * ext[1],
                           (corner & 4 ? 0.5 : -0.5) * ext[2]};
            double *p = xyz + 3 * (size_t)(v0 + v + k);
            p[0] = c.x + R[0][0] * l[0] + R[0][1] * l[1] + R[0][2] * l[2];
            p[1] = c.y + R[1][0] * l[0] + R[1][1] * l[1] + R[1][2] * l[2];
            p[2] = c.z + R[2][0] * l[0] + R[2][1] * l[1] + R[2][2] * l[2];
        }
        int t[6] = {v0 + v, v0 + v + 1, v0 + v + 2, v0 + v, v0 + v + 2, v0 + v + 3};
        memcpy(tri + 6 * f, t, sizeof t);
        v += 4;
    }
}

/* A closed convex solid casts the union of its faces' shadows (solid.c): a
 * floor seen from points above it past random boxes (rotated, some cut by
 * the floor's plane or by the point's height, some around the point) has
 * the same visible form factor whether each box subtracts one hull or
 * twelve faces, up to rounding; from inside a box it sees nothing.  And a
 * blocker behind a point's own plane hides nothing from it: from a point on
 * a box's face, the floor's visible form factor is the same with the box
 * listed as a blocker (one hull, or its faces) and without it. */
TEST(vis_solids_cast_the_union_of_their_faces_shadows)
{
    enum { BOXES = 6, NV = 4 + 24 * BOXES, NT = 2 + 12 * BOXES };
    unsigned long long seed = 20261202;
    double worst = 0.0, total = 0.0, on_face_worst = 0.0;
    int cases = 0, inside_cases = 0, on_face_cases = 0, ok = 1;
    for (int scene = 0; scene < 40; scene++) {
        double xyz[3 * NV] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        int tri[3 * NT] = {0, 1, 2, 0, 2, 3};
        for (int k = 0; k < BOXES; k++) {
            rad_vec3 c = rad_vec3_make(unit_draw(&seed), unit_draw(&seed),
                                       (scene % 4 == 0 ? 0.02 : 0.1) + unit_draw(&seed));
            random_box(c, 0.1 + 0.3 * unit_draw(&seed), &seed, xyz, tri + 6 + 36 * k,
                       4 + 24 * k);
        }
        rad_vis *hull = NULL, *faces = NULL;
        rad_vis_params p;
        rad_vis_params_default(&p);
        CHECK(rad_vis_create(xyz, NV, tri, NT, &p, &hull) == RAD_OK);
        p.no_solids = 1;
        CHECK(rad_vis_create(xyz, NV, tri, NT, &p, &faces) == RAD_OK);
        if (!hull || !faces) {
            rad_vis_destroy(hull);
            rad_vis_destroy(faces);
            return;
        }
        int blockers[NT];
        for (int k = 0; k < NT - 2; k++)
            blockers[k] = k + 2;
        for (int pt = 0; pt < 20; pt++) {
            /* a box's centre now and then: the point inside it */
            rad_vec3 x = rad_vec3_make(unit_draw(&seed), unit_draw(&seed),
                                       0.05 + 1.2 * unit_draw(&seed));
            if (pt % 7 == 0) {
                int k = pt / 7 % BOXES;
                rad_vec3 s = rad_vec3_make(0, 0, 0);
                for (int v = 0; v < 24; v++)
                    s = rad_vec3_add(s, rad_vec3_make(xyz[3 * (4 + 24 * k + v)],
                                                      xyz[3 * (4 + 24 * k + v) + 1],
                                                      xyz[3 * (4 + 24 * k + v) + 2]));
                x = rad_vec3_scale(s, 1.0 / 24.0);
            }
            if (!(x.z > 0.0))
                continue;
            rad_vec3 nx = rad_vec3_make(unit_draw(&seed) - 0.5, unit_draw(&seed) - 0.5, -1.0);
            nx = rad_vec3_scale(nx, 1.0 / rad_vec3_norm(nx));
            for (int t = 0; t < 2; t++) {
                rad_vec3 b[3];
                for (int v = 0; v < 3; v++)
                    b[v] = rad_vec3_make(xyz[3 * tri[3 * t + v]], xyz[3 * tri[3 * t + v] + 1],
                                         xyz[3 * tri[3 * t + v] + 2]);
                double Fh, Ff, Fo;
                long ev = 0;
                ok &= rad_vis_point_visible(hull, x, nx, b, blockers, NT - 2, &Fh, &Fo, &ev);
                ok &= rad_vis_point_visible(faces, x, nx, b, blockers, NT - 2, &Ff, &Fo, &ev);
                worst = fmax(worst, fabs(Fh - Ff) / fmax(Fo, 1e-300));
                total += Ff;
                cases++;
                inside_cases += pt % 7 == 0 && Ff == 0.0 && Fh == 0.0;
            }
        }
        /* from a point on a box's face, facing out and down, the box lies
           behind the point's plane: listed or not, it hides nothing */
        for (int k = 0; k < BOXES; k++)
            for (int face = 0; face < 6; face++) {
                const double *q0 = xyz + 3 * (4 + 24 * k + 4 * face);
                rad_vec3 c[4], x = rad_vec3_make(0, 0, 0);
                for (int v = 0; v < 4; v++) {
                    c[v] = rad_vec3_make(q0[3 * v], q0[3 * v + 1], q0[3 * v + 2]);
                    x = rad_vec3_add(x, rad_vec3_scale(c[v], 0.25));
                }
                rad_vec3 nx = rad_vec3_cross(rad_vec3_sub(c[1], c[0]), rad_vec3_sub(c[2], c[0]));
                nx = rad_vec3_scale(nx, 1.0 / rad_vec3_norm(nx));
                if (!(nx.z < -0.1) || !(x.z > 0.0))
                    continue;
                int others[NT], no = 0;
                for (int j = 0; j < NT - 2; j++)
                    if ((blockers[j] - 2) / 12 != k)
                        others[no++] = blockers[j];
                for (int t = 0; t < 2; t++) {
                    rad_vec3 b[3];
                    for (int v = 0; v < 3; v++)
                        b[v] = rad_vec3_make(xyz[3 * tri[3 * t + v]], xyz[3 * tri[3 * t + v] + 1],
                                             xyz[3 * tri[3 * t + v] + 2]);
                    double F[3], Fo;
                    long ev = 0;
                    ok &= rad_vis_point_visible(hull, x, nx, b, blockers, NT - 2, &F[0], &Fo, &ev);
                    ok &= rad_vis_point_visible(faces, x, nx, b, blockers, NT - 2, &F[1], &Fo, &ev);
                    ok &= rad_vis_point_visible(faces, x, nx, b, others, no, &F[2], &Fo, &ev);
                    for (int m = 0; m < 2; m++)
                        on_face_worst = fmax(on_face_worst, fabs(F[m] - F[2]) / fmax(Fo, 1e-300));
                    on_face_cases++;
                }
            }
        rad_vis_destroy(hull);
        rad_vis_destroy(faces);
    }
    printf("# %d cases from a box's face: with and without the box apart by %.3g of the open F\n",
           on_face_cases, on_face_worst);
    CHECK(on_face_cases > 0);
    CHECK_MSG(on_face_worst <= 1e-10, "from a box's face, the box itself hides %.3g of the open F",
              on_face_worst);
    printf("# %d point-to-triangle cases (%d from inside a box): visible F apart by at most "
           "%.3g of the open F (mean visible %.4g)\n", cases, inside_cases, worst,
           total / (cases > 0 ? cases : 1));
    CHECK(ok);
    CHECK(inside_cases > 0);
    CHECK_MSG(worst <= 1e-10, "hull and faces apart by %.3g of the open F", worst);
}

/* Appends the quad q (planar, counter-clockwise seen from its front) as two
 * triangles, split along the diagonal that keeps both inside it. */
static void add_quad(double *xyz, int *tri, int *nv, int *nt, const double q[4][3])
{
    rad_vec3 p[4];
    for (int v = 0; v < 4; v++) {
        p[v] = rad_vec3_make(q[v][0], q[v][1], q[v][2]);
        for (int i = 0; i < 3; i++)
            xyz[3 * (*nv + v) + i] = q[v][i];
    }
    rad_vec3 n = rad_vec3_cross(rad_vec3_sub(p[2], p[0]), rad_vec3_sub(p[3], p[1]));
    /* the diagonal 0-2 serves when 1 and 3 lie on either side of it */
    int d02 = rad_vec3_dot(rad_vec3_cross(rad_vec3_sub(p[1], p[0]), rad_vec3_sub(p[2], p[0])), n) > 0.0 &&
              rad_vec3_dot(rad_vec3_cross(rad_vec3_sub(p[2], p[0]), rad_vec3_sub(p[3], p[0])), n) > 0.0;
    const int a[6] = {0, 1, 2, 0, 2, 3}, b[6] = {0, 1, 3, 1, 2, 3};
    for (int k = 0; k < 6; k++)
        tri[3 * *nt + k] = *nv + (d02 ? a[k] : b[k]);
    *nv += 4;
    *nt += 2;
}

/* Whether the open segment p -> q crosses triangle t (Moller-Trumbore). */
static int segment_crosses(rad_vec3 p, rad_vec3 q, const rad_vec3 t[3])
{
    rad_vec3 d = rad_vec3_sub(q, p), e1 = rad_vec3_sub(t[1], t[0]), e2 = rad_vec3_sub(t[2], t[0]);
    rad_vec3 h = rad_vec3_cross(d, e2);
    double det = rad_vec3_dot(e1, h);
    if (fabs(det) < 1e-300)
        return 0;
    rad_vec3 s = rad_vec3_sub(p, t[0]), g = rad_vec3_cross(s, e1);
    double u = rad_vec3_dot(s, h) / det, v = rad_vec3_dot(d, g) / det,
           w = rad_vec3_dot(e2, g) / det;
    return u >= 0.0 && v >= 0.0 && u + v <= 1.0 && w > 1e-12 && w < 1.0 - 1e-12;
}

/* A shadow whose clipping repeats a corner to within rounding (a corner a
 * hair in front of a clipping plane keeps itself and adds the crossing next
 * to it) must still be subtracted.  Split along that edge of zero length,
 * every point of a piece lies on its line and both sides are the whole
 * rest: a subtraction that kept it as "outside" the shadow would count b
 * as seen.  The case is
 * one the Cornell box met (hier, eps 0.33): a point on the floor, an
 * element of the tall block's face behind the short block, whose top (a
 * triangle, its partner unlisted) and one side (a quad of two) are the
 * blockers, in the order the shaft gave them.  Reference: the kernel over
 * a fine grid on b, each sample's segment tested against every triangle. */
TEST(vis_shadow_with_a_repeated_corner_is_subtracted)
{
    const double xyz[] = {
        0.42299999999999999, 0, 0.247, 0.26500000000000001, 0.33000000000000002,
        0.29599999999999999, 0.42299999999999999, 0.33000000000000002, 0.247, /* b */
        0.13, 0.16500000000000001, 0.065000000000000002, 0.082000000000000003,
        0.16500000000000001, 0.22500000000000001, 0.23999999999999999, 0.16500000000000001,
        0.27200000000000002, /* the short block's top, half not listed */
        0.13, 0.16500000000000001, 0.065000000000000002, 0.23999999999999999,
        0.16500000000000001, 0.27200000000000002, 0.28999999999999998, 0.16500000000000001,
        0.114, /* the listed half */
        0.23999999999999999, 0, 0.27200000000000002, 0.28999999999999998, 0, 0.114,
        0.28999999999999998, 0.16500000000000001, 0.114, /* a side, two halves */
        0.23999999999999999, 0, 0.27200000000000002, 0.28999999999999998, 0.16500000000000001,
        0.114, 0.23999999999999999, 0.16500000000000001, 0.27200000000000002};
    const int tri[] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14};
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 15, tri, 5, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    rad_vec3 t[5][3];
    for (int k = 0; k < 5; k++)
        for (int v = 0; v < 3; v++)
            t[k][v] = rad_vec3_make(xyz[9 * k + 3 * v], xyz[9 * k + 3 * v + 1], xyz[9 * k + 3 * v + 2]);
    rad_vec3 x = rad_vec3_make(0.2504060925473105, 0, 0.17916281367448703);
    rad_vec3 nx = rad_vec3_make(0, 1, 0);
    rad_vec3 nb = rad_vec3_cross(rad_vec3_sub(t[0][1], t[0][0]), rad_vec3_sub(t[0][2], t[0][0]));
    nb = rad_vec3_scale(nb, 1.0 / rad_vec3_norm(nb));
    const int blockers[] = {2, 3, 4};
    double F = -1.0, Fo = 0.0;
    long evals = 0;
    CHECK(rad_vis_point_visible(vis, x, nx, t[0], blockers, 3, &F, &Fo, &evals));
    enum { CELLS = 300 }; /* CELLS^2 cells of b, one centre each */
    double sum = 0.0, sum_open = 0.0;
    for (int j = 0; j < CELLS * CELLS; j++) {
        double s, u;
        rad_geom_triangle_stratum(CELLS, j, 0.5, 0.5, &s, &u);
        rad_vec3 y = rad_geom_triangle_point(t[0][0], t[0][1], t[0][2], s, u);
        double k = rad_ff_kernel(x, nx, y, nb, NULL);
        sum_open += k;
        int open = 1;
        for (int o = 1; o < 5 && open; o++)
            open = !segment_crosses(x, y, t[o]);
        sum += open ? k : 0.0;
    }
    double area = 0.5 * rad_vec3_norm(rad_vec3_cross(rad_vec3_sub(t[0][1], t[0][0]),
                                                     rad_vec3_sub(t[0][2], t[0][0])));
    double ref = area * sum / (CELLS * CELLS), ref_open = area * sum_open / (CELLS * CELLS);
    CHECK_MSG(fabs(Fo - ref_open) <= 5e-3 * ref_open, "open %.6g, sampled %.6g", Fo, ref_open);
    CHECK_MSG(fabs(F - ref) <= 3e-3 * ref_open, "visible %.6g, sampled %.6g (open %.6g)", F, ref,
              Fo);
    printf("# a shadow with a repeated corner: F_vis %.4g, sampled %.4g, open %.4g\n", F, ref, Fo);
    rad_vis_destroy(vis);
}

/* Child k of t's midpoint subdivision (corners k = 0, 1, 2; 3 the middle). */
static void sub_triangle(const rad_vec3 t[3], int k, rad_vec3 out[3])
{
    rad_vec3 m[3];
    for (int v = 0; v < 3; v++)
        m[v] = rad_vec3_scale(rad_vec3_add(t[v], t[(v + 1) % 3]), 0.5);
    const rad_vec3 ch[4][3] = {{t[0], m[0], m[2]}, {m[0], t[1], m[1]}, {m[2], m[1], t[2]},
                               {m[0], m[1], m[2]}};
    memcpy(out, ch[k], sizeof ch[k]);
}

/* In a closed room the parts of every triangle a point sees tile its
 * hemisphere: sum_b F_vis(x, b) = 1, here over the 16 grandchildren of every
 * triangle (hier's elements).  The room is the Cornell box's with its short
 * block, open below, standing on a floor whose triangles meet the block's
 * corners as the contact cut makes them: the floor under the block is hidden
 * from every point outside, by shadows that meet the floor's plane along
 * the pieces' edges and at their corners, where clipping repeats corners to
 * within rounding. */
TEST(vis_closed_room_with_a_block_tiles_every_hemisphere)
{
    double xyz[3 * 4 * 16];
    int tri[3 * 2 * 16], nv = 0, nt = 0;
    /* y up in the Cornell box, z up here */
    const double w = 0.556, d = 0.5592, top_z = 0.5488, bh = 0.165;
    const double O[4][2] = {{0, 0}, {w, 0}, {w, d}, {0, d}};
    const double I[4][2] = {{0.13, 0.065}, {0.29, 0.114}, {0.24, 0.272}, {0.082, 0.225}};
    for (int k = 0; k < 4; k++) { /* the floor around the block, facing up */
        int n = (k + 1) % 4;
        const double q[4][3] = {{O[k][0], O[k][1], 0}, {O[n][0], O[n][1], 0},
                                {I[n][0], I[n][1], 0}, {I[k][0], I[k][1], 0}};
        add_quad(xyz, tri, &nv, &nt, q);
    }
    const double under[4][3] = {{I[0][0], I[0][1], 0}, {I[1][0], I[1][1], 0},
                                {I[2][0], I[2][1], 0}, {I[3][0], I[3][1], 0}};
    add_quad(xyz, tri, &nv, &nt, under);
    const int nfloor = nt;
    const double room[5][4][3] = {
        {{0, 0, top_z}, {0, d, top_z}, {w, d, top_z}, {w, 0, top_z}}, /* ceiling, facing down */
        {{0, 0, 0}, {0, 0, top_z}, {w, 0, top_z}, {w, 0, 0}},         /* y = 0, facing +y */
        {{w, d, 0}, {w, d, top_z}, {0, d, top_z}, {0, d, 0}},         /* y = d */
        {{0, d, 0}, {0, d, top_z}, {0, 0, top_z}, {0, 0, 0}},         /* x = 0 */
        {{w, 0, 0}, {w, 0, top_z}, {w, d, top_z}, {w, d, 0}}};        /* x = w */
    for (int k = 0; k < 5; k++)
        add_quad(xyz, tri, &nv, &nt, room[k]);
    const double lid[4][3] = {{I[0][0], I[0][1], bh}, {I[1][0], I[1][1], bh},
                              {I[2][0], I[2][1], bh}, {I[3][0], I[3][1], bh}};
    add_quad(xyz, tri, &nv, &nt, lid);
    for (int k = 0; k < 4; k++) { /* the block's sides, facing out */
        int n = (k + 1) % 4;
        const double q[4][3] = {{I[k][0], I[k][1], 0}, {I[n][0], I[n][1], 0},
                                {I[n][0], I[n][1], bh}, {I[k][0], I[k][1], bh}};
        add_quad(xyz, tri, &nv, &nt, q);
    }
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, (size_t)nv, tri, (size_t)nt, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    unsigned long long state = 20261202;
    double worst = 0.0;
    int ok = 1, points = 0;
    for (int s = nfloor; s < nt; s++) { /* points on the room's walls and the block */
        rad_vec3 c[3];
        for (int v = 0; v < 3; v++)
            c[v] = rad_vec3_make(xyz[3 * tri[3 * s + v]], xyz[3 * tri[3 * s + v] + 1],
                                 xyz[3 * tri[3 * s + v] + 2]);
        rad_vec3 nx = rad_vec3_cross(rad_vec3_sub(c[1], c[0]), rad_vec3_sub(c[2], c[0]));
        nx = rad_vec3_scale(nx, 1.0 / rad_vec3_norm(nx));
        for (int i = 0; i < 12; i++) {
            double r1 = unit_draw(&state), r2 = unit_draw(&state);
            if (r1 + r2 > 1.0) {
                r1 = 1.0 - r1;
                r2 = 1.0 - r2;
            }
            rad_vec3 x = rad_geom_triangle_point(c[0], c[1], c[2], r1, r2);
            double sum = 0.0;
            for (int b = 0; b < nt; b++) {
                if (b == s)
                    continue;
                int blockers[32], nb = 0;
                for (int k = 0; k < nt; k++)
                    if (k != b && k != s)
                        blockers[nb++] = k;
                rad_vec3 tb[3];
                for (int v = 0; v < 3; v++)
                    tb[v] = rad_vec3_make(xyz[3 * tri[3 * b + v]], xyz[3 * tri[3 * b + v] + 1],
                                          xyz[3 * tri[3 * b + v] + 2]);
                /* b's 16 grandchildren (midpoint subdivision twice), as hier's
                   elements meet them */
                for (int g = 0; g < 16; g++) {
                    rad_vec3 c1[3], c2[3];
                    sub_triangle(tb, g / 4, c1);
                    sub_triangle(c1, g % 4, c2);
                    double F = 0.0, Fo = 0.0;
                    long evals = 0;
                    ok &= rad_vis_point_visible(vis, x, nx, c2, blockers, nb, &F, &Fo, &evals);
                    sum += F;
                }
            }
            worst = fmax(worst, fabs(sum - 1.0));
            points++;
        }
    }
    CHECK(ok && points == 12 * (nt - nfloor));
    CHECK_MSG(worst <= 1e-9, "a hemisphere sums to 1 %+.3g", worst);
    printf("# closed room with a block: %d points, |sum_b F_vis - 1| <= %.3g\n", points, worst);
    rad_vis_destroy(vis);
}

/* rad_vis_segment_blocked_by against the pair's blockers answers as
 * Embree's ray against the whole scene does, for segments between points of
 * two triangles with random boxes between them (the shaft lists every
 * triangle that can cross such a segment); a segment along a blocker's plane
 * crosses nothing, one through its inside is blocked. */
TEST(vis_segment_blocked_by_the_blockers_equals_the_ray)
{
    enum { BOXES = 8, NV = 6 + 24 * BOXES, NT = 2 + 12 * BOXES };
    unsigned long long seed = 20261203;
    int segments = 0, blocked = 0, differ = 0;
    for (int scene = 0; scene < 20; scene++) {
        /* a floor triangle and a ceiling triangle facing it, boxes between */
        double xyz[3 * NV] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0.2, 0.1, 1, 0.1, 1.1, 1, 1.2, 0.3, 1};
        int tri[3 * NT] = {0, 1, 2, 3, 4, 5};
        for (int k = 0; k < BOXES; k++) {
            rad_vec3 c = rad_vec3_make(unit_draw(&seed), unit_draw(&seed),
                                       0.2 + 0.6 * unit_draw(&seed));
            random_box(c, 0.25, &seed, xyz, tri + 6 + 36 * k, 6 + 24 * k);
        }
        rad_vis_params p;
        rad_vis_params_default(&p);
        rad_vis *vis = NULL;
        CHECK(rad_vis_create(xyz, NV, tri, NT, &p, &vis) == RAD_OK);
        if (!vis || rad_vis_prepare_rays(vis) != RAD_OK) {
            rad_vis_destroy(vis);
            continue;
        }
        rad_vec3 a[3], b[3];
        for (int v = 0; v < 3; v++) {
            a[v] = rad_vec3_make(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
            b[v] = rad_vec3_make(xyz[9 + 3 * v], xyz[10 + 3 * v], xyz[11 + 3 * v]);
        }
        int blk[NT];
        int nb = rad_vis_blockers(vis, a, 0, b, 1, blk, NT);
        CHECK(nb >= 0 && nb <= NT);
        for (int k = 0; k < 200 && nb >= 0 && nb <= NT; k++) {
            double s1 = unit_draw(&seed), t1 = unit_draw(&seed) * (1 - s1);
            double s2 = unit_draw(&seed), t2 = unit_draw(&seed) * (1 - s2);
            rad_vec3 x = rad_geom_triangle_point(a[0], a[1], a[2], s1, t1);
            rad_vec3 y = rad_geom_triangle_point(b[0], b[1], b[2], s2, t2);
            double px[3] = {x.x, x.y, x.z}, py[3] = {y.x, y.y, y.z};
            int ray = rad_vis_segment_blocked(vis, px, py, 0, 1);
            int by = rad_vis_segment_blocked_by(vis, x, y, blk, nb);
            segments++;
            blocked += by;
            differ += ray != by;
        }
        rad_vis_destroy(vis);
    }
    /* Embree tests in single precision: a segment that grazes an edge may
       fall either way, a handful in thousands */
    CHECK_MSG(differ <= segments / 1000, "%d of %d segments differ", differ, segments);
    CHECK(blocked > segments / 10 && blocked < segments - segments / 10);
    /* one triangle: through its inside, along its plane, past it */
    double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    int tri[3] = {0, 1, 2}, one[1] = {0};
    rad_vis_params p;
    rad_vis_params_default(&p);
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 3, tri, 1, &p, &vis) == RAD_OK);
    if (vis) {
        CHECK(rad_vis_segment_blocked_by(vis, rad_vec3_make(0.2, 0.2, -1), rad_vec3_make(0.2, 0.2, 1),
                                         one, 1) == 1);
        CHECK(rad_vis_segment_blocked_by(vis, rad_vec3_make(-1, 0.2, 0), rad_vec3_make(2, 0.2, 0),
                                         one, 1) == 0);
        CHECK(rad_vis_segment_blocked_by(vis, rad_vec3_make(0.8, 0.8, -1), rad_vec3_make(0.8, 0.8, 1),
                                         one, 1) == 0);
        CHECK(rad_vis_segment_blocked_by(vis, rad_vec3_make(0.2, 0.2, -1), rad_vec3_make(0.2, 0.2, 1),
                                         one, 0) == 0);
        rad_vis_destroy(vis);
    }
}

/* rad_vis_pair_blockers walks a pair's shaft once for what
 * rad_vis_pair_can_block and rad_vis_blockers each walk it for: on every
 * pair of the Cornell box refined once (boxes among walls, coplanar halves
 * of one wall: flat pairs) the two answers must be theirs, entry by entry,
 * with the list cut at 4 as well as in full. */
TEST(vis_pair_blockers_give_both_answers_of_one_walk)
{
    cornell_refined cb;
    size_t n;
    rad_vis *vis = cornell_open(&cb, &n);
    rad_mesh *mesh = cb.mesh;
    const double *xyz = mesh ? rad_mesh_vertices(mesh) : NULL;
    const int *tri = mesh ? rad_mesh_triangles(mesh) : NULL;
    int *one = malloc((n + 1) * sizeof *one), *two = malloc((n + 1) * sizeof *two);
    long pairs = 0, differ = 0, flat = 0, listed = 0, cut = 0;
    for (size_t i = 0; vis && i < n; i++)
        for (size_t j = i + 1; j < n; j++) {
            rad_vec3 a[3], b[3];
            for (int v = 0; v < 3; v++) {
                const double *p = xyz + 3 * tri[3 * i + v], *q = xyz + 3 * tri[3 * j + v];
                a[v] = rad_vec3_make(p[0], p[1], p[2]);
                b[v] = rad_vec3_make(q[0], q[1], q[2]);
            }
            for (int max = 4; max <= (int)n; max += (int)n - 4) {
                int can = -1;
                int got = rad_vis_pair_blockers(vis, i, j, one, max, &can);
                int want = rad_vis_blockers(vis, a, (int)i, b, (int)j, two, max);
                int ok = can == rad_vis_pair_can_block(vis, i, j) && got == want;
                for (int k = 0; ok && k < got && k < max; k++)
                    ok = one[k] == two[k];
                differ += !ok;
                pairs++;
                flat += can == 1 && got == 0;
                listed += got > 0;
                cut += got > max;
            }
        }
    printf("# %ld pair queries: %ld with blockers (%ld past the cut), %ld flat, %ld differ\n",
           pairs, listed, cut, flat, differ);
    CHECK(pairs > 0 && differ == 0);
    CHECK(listed > 0 && cut > 0 && flat > 0); /* every case met */
    free(one);
    free(two);
    cornell_close(&cb);
}

/* A room of many triangles (each face of the unit cube a 60 x 60 grid, wound
 * inwards): more triangles than the plane budget lets be tested against
 * every vertex, but six distinct planes, each with the whole scene in
 * front: the scene is unoccluded.  (The planes are counted with a hash set
 * that stops past the budget; a count that overshot would call it
 * occluded.) */
TEST(vis_finely_cut_convex_room_is_unoccluded)
{
    enum { K = 60, NV = 6 * (K + 1) * (K + 1), NT = 6 * 2 * K * K };
    double *xyz = malloc(3 * NV * sizeof *xyz);
    int *tri = malloc(3 * NT * sizeof *tri);
    if (!xyz || !tri) {
        free(xyz);
        free(tri);
        CHECK(0);
        return;
    }
    int nv = 0, nt = 0;
    for (int f = 0; f < 6; f++) {
        int a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3, base = nv;
        for (int i = 0; i <= K; i++)
            for (int j = 0; j <= K; j++, nv++) {
                xyz[3 * nv + a] = f % 2;
                xyz[3 * nv + b] = (double)i / K;
                xyz[3 * nv + c] = (double)j / K;
            }
        for (int i = 0; i < K; i++)
            for (int j = 0; j < K; j++) {
                int v00 = base + i * (K + 1) + j, v10 = v00 + K + 1, q[2][3] = {
                    {v00, v10, v10 + 1}, {v00, v10 + 1, v00 + 1}};
                for (int k = 0; k < 2; k++, nt++) {
                    /* b x c is +a: wound so at the side at 0, flipped at 1 */
                    int flip = f % 2;
                    tri[3 * nt] = q[k][0];
                    tri[3 * nt + 1] = q[k][flip ? 2 : 1];
                    tri[3 * nt + 2] = q[k][flip ? 1 : 2];
                }
            }
    }
    CHECK(nv == NV && nt == NT);
    /* the normals point inwards */
    rad_vec3 p0 = rad_vec3_make(xyz[3 * tri[0]], xyz[3 * tri[0] + 1], xyz[3 * tri[0] + 2]);
    rad_vec3 p1 = rad_vec3_make(xyz[3 * tri[1]], xyz[3 * tri[1] + 1], xyz[3 * tri[1] + 2]);
    rad_vec3 p2 = rad_vec3_make(xyz[3 * tri[2]], xyz[3 * tri[2] + 1], xyz[3 * tri[2] + 2]);
    CHECK(rad_geom_triangle_normal(p0, p1, p2).x > 0.5);
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, NV, tri, NT, NULL, &vis) == RAD_OK);
    CHECK(vis && rad_vis_is_unoccluded(vis));
    /* two facing wall triangles: nothing can block them */
    CHECK(vis && !rad_vis_pair_can_block(vis, 0, 2 * K * K));
    rad_vis_destroy(vis);
    free(xyz);
    free(tri);
}
