/* Dense assembly of G = A F V against identities: closed-scene row sums,
 * the regular tetrahedron, exact reciprocity, thread-count independence, and
 * occlusion by a blocker that covers all, none or some of a pair's shaft. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_radiosity.h"
#include "rad_scene.h"

/* An inward-facing box [0,sx] x [0,sy] x [0,sz]: 6 faces, 2 triangles each.
 * Each face is o + a u + b v with u x v pointing into the box. */
static int make_box(double sx, double sy, double sz, double *xyz, int *tri)
{
    double faces[6][9] = {
        {0, 0, 0, sx, 0, 0, 0, sy, 0},   /* z = 0, normal +z */
        {0, 0, sz, 0, sy, 0, sx, 0, 0},  /* z = sz, normal -z */
        {0, 0, 0, 0, sy, 0, 0, 0, sz},   /* x = 0, normal +x */
        {sx, 0, 0, 0, 0, sz, 0, sy, 0},  /* x = sx, normal -x */
        {0, 0, 0, 0, 0, sz, sx, 0, 0},   /* y = 0, normal +y */
        {0, sy, 0, sx, 0, 0, 0, 0, sz},  /* y = sy, normal -y */
    };
    int nv = 0, nt = 0;
    for (int f = 0; f < 6; f++) {
        double *o = faces[f], *u = faces[f] + 3, *v = faces[f] + 6;
        for (int k = 0; k < 3; k++) {
            xyz[3 * nv + k] = o[k];
            xyz[3 * (nv + 1) + k] = o[k] + u[k];
            xyz[3 * (nv + 2) + k] = o[k] + u[k] + v[k];
            xyz[3 * (nv + 3) + k] = o[k] + v[k];
        }
        int t[6] = {nv, nv + 1, nv + 2, nv, nv + 2, nv + 3};
        memcpy(tri + 3 * nt, t, sizeof t);
        nv += 4;
        nt += 2;
    }
    return nt;
}

static double row_sum_error(const double *G, const double *areas, int n)
{
    double worst = 0.0;
    for (int i = 0; i < n; i++) {
        double s = 0.0;
        for (int j = 0; j < n; j++)
            s += G[i + j * n];
        worst = fmax(worst, fabs(s / areas[i] - 1.0));
    }
    return worst;
}

TEST(radiosity_closed_box_rows_sum_to_one)
{
    double xyz[24 * 3], G[144], areas[12];
    int tri[36];
    int n = make_box(1.7, 2.385, 0.93, xyz, tri);
    rad_radiosity_params p;
    rad_radiosity_params_default(&p);
    CHECK(rad_ff_rule_parse("exact", &p.rule) == RAD_OK);
    rad_radiosity_stats st;
    CHECK(rad_radiosity_assemble(xyz, tri, n, NULL, &p, G, areas, &st) == RAD_OK);
    double err = row_sum_error(G, areas, n);
    CHECK_MSG(err < 1e-11, "exact: worst |row sum - 1| = %.3g", err);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            CHECK(G[i + j * n] == G[j + i * n]); /* reciprocity, bit for bit */
    /* The two triangles of one face are coplanar: no coupling, no integration. */
    CHECK(G[0 + 1 * n] == 0.0);
    CHECK(st.pairs == 66 && st.pairs_not_facing >= 6);
    CHECK(st.rays == 0);

    CHECK(rad_ff_rule_parse("auto", &p.rule) == RAD_OK);
    p.ff.tol = 1e-6;
    CHECK(rad_radiosity_assemble(xyz, tri, n, NULL, &p, G, areas, &st) == RAD_OK);
    err = row_sum_error(G, areas, n);
    CHECK_MSG(err < 1e-5, "auto 1e-6: worst |row sum - 1| = %.3g", err);
}

TEST(radiosity_tetrahedron_faces_see_a_third)
{
    /* A regular tetrahedron, faces wound to face inward. */
    double s = 2.385, xyz[12] = {s, s, s, s, -s, -s, -s, s, -s, -s, -s, s};
    int tri[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
    /* Orient each face so its normal points at the centre (the origin). */
    for (int f = 0; f < 4; f++) {
        int *t = tri + 3 * f;
        double a[3], b[3], c[3], n[3], g[3];
        for (int k = 0; k < 3; k++) {
            a[k] = xyz[3 * t[1] + k] - xyz[3 * t[0] + k];
            b[k] = xyz[3 * t[2] + k] - xyz[3 * t[0] + k];
            g[k] = -xyz[3 * t[0] + k];
        }
        n[0] = a[1] * b[2] - a[2] * b[1];
        n[1] = a[2] * b[0] - a[0] * b[2];
        n[2] = a[0] * b[1] - a[1] * b[0];
        (void)c;
        if (n[0] * g[0] + n[1] * g[1] + n[2] * g[2] < 0) {
            int tmp = t[1];
            t[1] = t[2];
            t[2] = tmp;
        }
    }
    double G[16], areas[4];
    rad_radiosity_params p;
    rad_radiosity_params_default(&p);
    rad_ff_rule_parse("exact", &p.rule);
    CHECK(rad_radiosity_assemble(xyz, tri, 4, NULL, &p, G, areas, NULL) == RAD_OK);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            if (i != j)
                CHECK_NEAR(G[i + 4 * j] / areas[i], 1.0 / 3.0, 1e-12, 0.0);
}

TEST(radiosity_assembly_does_not_depend_on_threads)
{
    double xyz[24 * 3], G1[144], G2[144], areas[12];
    int tri[36];
    int n = make_box(1.3, 0.77, 2.1, xyz, tri);
    rad_radiosity_params p;
    rad_radiosity_params_default(&p);
    rad_ff_rule_parse("gauss:4", &p.rule);
    p.threads = 1;
    CHECK(rad_radiosity_assemble(xyz, tri, n, NULL, &p, G1, areas, NULL) == RAD_OK);
    p.threads = 2;
    CHECK(rad_radiosity_assemble(xyz, tri, n, NULL, &p, G2, areas, NULL) == RAD_OK);
    CHECK(memcmp(G1, G2, sizeof G1) == 0);
}

/* Two parallel squares facing each other (z = 0 up, z = 1 down), split in two
 * triangles each, and a blocker square at z = 0.5 facing down. */
static int plates(double blocker_half, double blocker_dx, double *xyz, int *tri)
{
    double v[12][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                       {0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}};
    double c = 0.5 + blocker_dx, h = blocker_half;
    double b[4][3] = {{c - h, 0.5 - h, 0.5}, {c - h, 0.5 + h, 0.5}, {c + h, 0.5 + h, 0.5}, {c + h, 0.5 - h, 0.5}};
    memcpy(v[8], b, sizeof b);
    memcpy(xyz, v, sizeof v);
    int t[24] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7, 8, 9, 10, 8, 10, 11};
    memcpy(tri, t, sizeof t);
    return blocker_half > 0 ? 6 : 4;
}

TEST(radiosity_occlusion_all_none_some)
{
    double xyz[36], G[36], Gfree[36], areas[6];
    int tri[24];
    rad_radiosity_params p;
    rad_radiosity_params_default(&p);
    rad_ff_rule_parse("gauss:6", &p.rule);
    /* Without a blocker: the unoccluded coupling (Howell C-11 gives F = 0.1998). */
    int n = plates(0.0, 0.0, xyz, tri);
    CHECK(rad_radiosity_assemble(xyz, tri, n, NULL, &p, Gfree, areas, NULL) == RAD_OK);
    double F = (Gfree[0 + 2 * n] + Gfree[0 + 3 * n] + Gfree[1 + 2 * n] + Gfree[1 + 3 * n]) / (areas[0] + areas[1]);
    CHECK_NEAR(F, 0.19982, 1e-3, 0.0);

    /* A blocker wider than the plates, between them: nothing passes. */
    n = plates(2.0, 0.0, xyz, tri);
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(xyz, 12, tri, (size_t)n, NULL, &vis) == RAD_OK);
    rad_radiosity_stats st;
    CHECK(rad_radiosity_assemble(xyz, tri, n, vis, &p, G, areas, &st) == RAD_OK);
    for (int i = 0; i < 2; i++)
        for (int j = 2; j < 4; j++)
            CHECK(G[i + j * n] == 0.0);
    CHECK(st.pairs_occlusion_tested > 0);
    rad_vis_destroy(vis);

    /* A blocker far to the side: the shaft is empty, no rays, G unchanged. */
    n = plates(0.2, 5.0, xyz, tri);
    CHECK(rad_vis_create(xyz, 12, tri, (size_t)n, NULL, &vis) == RAD_OK);
    CHECK(rad_radiosity_assemble(xyz, tri, n, vis, &p, G, areas, &st) == RAD_OK);
    for (int i = 0; i < 2; i++)
        for (int j = 2; j < 4; j++)
            CHECK_NEAR(G[i + j * n], Gfree[i + j * 4], 1e-15, 0.0);
    rad_vis_destroy(vis);

    /* A centred 0.5 x 0.5 blocker (the occluder scene): the visible integral
     * against the independent Monte Carlo estimate of the blocked form
     * factor (relative standard error about 5e-4), at its default tolerance
     * and tighter; its error estimate holds. */
    n = plates(0.25, 0.0, xyz, tri);
    CHECK(rad_vis_create(xyz, 12, tri, (size_t)n, NULL, &vis) == RAD_OK);
    double reference = harness_occluder_form_factor_mc(4000000);
    for (int k = 0; k < 2; k++) {
        p.visible.tol = k ? 1e-4 : 1e-2;
        CHECK(rad_radiosity_assemble(xyz, tri, n, vis, &p, G, areas, &st) == RAD_OK);
        double Fb = (G[0 + 2 * n] + G[0 + 3 * n] + G[1 + 2 * n] + G[1 + 3 * n]) / (areas[0] + areas[1]);
        CHECK_MSG(fabs(Fb - reference) < (k ? 2e-3 : 1e-2) * reference,
                  "blocked F = %.6f, Monte Carlo %.6f (tol %g)", Fb, reference, p.visible.tol);
        CHECK(st.pairs_occlusion_tested == 4 && st.pairs_sampled == 0);
        CHECK(st.visibility_error > 0.0 && st.visibility_error < 10 * p.visible.tol);
    }
    rad_vis_destroy(vis);
}

TEST(radiosity_assembly_rejects_degenerate_triangles)
{
    double xyz[9] = {0, 0, 0, 1, 1, 1, 2, 2, 2}, G[1], areas[1];
    int tri[3] = {0, 1, 2};
    CHECK(rad_radiosity_assemble(xyz, tri, 1, NULL, NULL, G, areas, NULL) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "triangle 0") != NULL);
}

/* Closed rooms with occluders (a box on the floor; a box 1 mm from a wall; 27
 * boxes): every row of the visible-integral assembly sums to 1 within what
 * the outer rule is asked for, tol times the row's unoccluded coupling
 * (sum_j G_open_ij / A_i), plus auto's 1e-6 per pair.  (The plain share of
 * open rays, F times V, missed rows by percents near contacts.)  Then the same
 * at a tenth of the tolerance: the error follows it. */
TEST(radiosity_occluded_closed_rooms_rows_sum_to_one)
{
    const char *const scenes[] = {"scenes/furnace_room/room_box.obj",
                                  "scenes/furnace_room/room_hair.obj",
                                  "scenes/furnace_room/room_27.obj"};
    for (int k = 0; k < 3; k++) {
        rad_scene_params sp;
        rad_scene_params_default(&sp);
        rad_scene *scene = harness_scene_load(scenes[k], &sp);
        if (!scene)
            continue;
        int n = rad_scene_triangle_count(scene), nv = rad_scene_vertex_count(scene);
        const double *xyz = rad_scene_vertices(scene);
        const int *tri = rad_scene_triangles(scene);
        size_t nn = (size_t)n * (size_t)n;
        double *G = malloc(sizeof *G * 2 * nn), *Gopen = G + nn;
        double *areas = malloc(sizeof *areas * (size_t)n);
        rad_vis *vis = NULL;
        rad_radiosity_params p;
        rad_radiosity_params_default(&p);
        if (!G || !areas || rad_vis_create(xyz, (size_t)nv, tri, (size_t)n, NULL, &vis) != RAD_OK ||
            rad_radiosity_assemble(xyz, tri, n, NULL, &p, Gopen, areas, NULL) != RAD_OK) {
            CHECK_MSG(0, "%s: set-up failed", scenes[k]);
            free(G);
            free(areas);
            rad_vis_destroy(vis);
            rad_scene_destroy(scene);
            continue;
        }
        const double tols[2] = {p.visible.tol, p.visible.tol / 10};
        for (int t = 0; t < 2; t++) {
            p.visible.tol = tols[t];
            rad_radiosity_stats st;
            CHECK(rad_radiosity_assemble(xyz, tri, n, vis, &p, G, areas, &st) == RAD_OK);
            CHECK(st.pairs_occlusion_tested > 0);
            double worst = 0.0, worst_ratio = 0.0;
            for (int i = 0; i < n; i++) {
                double sum = 0.0, open = 0.0;
                for (int j = 0; j < n; j++) {
                    sum += G[i + (size_t)j * n];
                    open += Gopen[i + (size_t)j * n];
                }
                double err = fabs(sum / areas[i] - 1.0);
                double bound = tols[t] * open / areas[i] + 1e-6 * n;
                worst = fmax(worst, err);
                worst_ratio = fmax(worst_ratio, err / bound);
                CHECK_MSG(err <= bound, "%s tol %g: row %d sums to 1 %+.3g, beyond %.3g", scenes[k],
                          tols[t], i, sum / areas[i] - 1.0, bound);
            }
            printf("  %s, tol %g: worst |row sum - 1| = %.3g, at most %.2f of its bound\n", scenes[k],
                   tols[t], worst, worst_ratio);
        }
        rad_vis_destroy(vis);
        free(G);
        free(areas);
        rad_scene_destroy(scene);
    }
}

/* rad_radiosity_pair gives every pair's coupling to the bit as the assembly
 * does, in either order, with visibility (the Cornell box's blocks). */
TEST(radiosity_pair_equals_the_assembly)
{
    rad_scene *scene = harness_scene_load("scenes/cornell/cornell.obj", NULL);
    if (!scene)
        return;
    int n = rad_scene_triangle_count(scene);
    const double *xyz = rad_scene_vertices(scene);
    const int *tri = rad_scene_triangles(scene);
    rad_vis *vis = NULL;
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    CHECK(rad_vis_create(xyz, (size_t)rad_scene_vertex_count(scene), tri, (size_t)n, &vp, &vis) ==
          RAD_OK);
    double *G = malloc((size_t)n * (size_t)n * sizeof *G), *areas = malloc((size_t)n * sizeof *areas);
    rad_radiosity_stats st;
    CHECK(rad_radiosity_assemble(xyz, tri, n, vis, NULL, G, areas, &st) == RAD_OK);
    rad_radiosity_stats ps;
    memset(&ps, 0, sizeof ps);
    int differ = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            if (i == j)
                continue;
            double g = -1.0;
            CHECK(rad_radiosity_pair(xyz, tri, i, j, vis, NULL, &g, j > i ? &ps : NULL) == RAD_OK);
            differ += g != G[(size_t)i + (size_t)j * (size_t)n];
        }
    CHECK_MSG(differ == 0, "%d pairs differ from the assembly", differ);
    CHECK(ps.pairs == st.pairs && ps.pairs_not_facing == st.pairs_not_facing &&
          ps.pairs_occlusion_tested == st.pairs_occlusion_tested && ps.kernel_evals == st.kernel_evals);
    double g;
    CHECK(rad_radiosity_pair(xyz, tri, 3, 3, vis, NULL, &g, NULL) == RAD_EINVAL);
    free(G);
    free(areas);
    rad_vis_destroy(vis);
    rad_scene_destroy(scene);
}
