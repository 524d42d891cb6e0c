/* The CGAL shim, tested from C: adjacency against hand counts, closedness,
 * convexity seen from inside, refinement (area and input faces preserved,
 * conforming), PLY/OFF export and their round trip through the importer,
 * and the exception barrier. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "rad_geom.h"
#include "rad_io.h"
#include "rad_mesh.h"
#include "rad_scene.h"

static rad_mesh *mesh_of(const rad_scene *s)
{
    rad_mesh *m = NULL;
    if (!s)
        return NULL;
    rad_status st = rad_mesh_create(rad_scene_vertices(s), rad_scene_vertex_count(s),
                                    rad_scene_triangles(s), rad_scene_triangle_count(s),
                                    rad_scene_triangle_faces(s), &m);
    CHECK_MSG(st == RAD_OK, "mesh: %s", rad_error_message());
    return m;
}

static double mesh_area(const rad_mesh *m)
{
    const double *x = rad_mesh_vertices(m);
    const int *t = rad_mesh_triangles(m);
    double area = 0.0;
    for (int f = 0; f < rad_mesh_face_count(m); f++) {
        const int *v = t + 3 * f;
        area += rad_geom_triangle_area(rad_vec3_make(x[3 * v[0]], x[3 * v[0] + 1], x[3 * v[0] + 2]),
                                       rad_vec3_make(x[3 * v[1]], x[3 * v[1] + 1], x[3 * v[1] + 2]),
                                       rad_vec3_make(x[3 * v[2]], x[3 * v[2] + 1], x[3 * v[2] + 2]));
    }
    return area;
}

/* Sum over vertices of C(d_v, 2), d_v = number of faces at v: an independent
 * count of touching pairs (edge pairs are counted twice, vertex pairs once). */
static long incidence_pairs(const int *tri, int nt, int nv)
{
    int *deg = calloc((size_t)nv, sizeof *deg);
    for (int i = 0; i < 3 * nt; i++)
        deg[tri[i]]++;
    long sum = 0;
    for (int v = 0; v < nv; v++)
        sum += (long)deg[v] * (deg[v] - 1) / 2;
    free(deg);
    return sum;
}

/* Hand count, furnace cube (12 triangles, 8 corners, closed):
 *   Euler: V - E + F = 2 gives E = 8 + 12 - 2 = 18 edges, each shared by
 *   exactly two triangles, so 18 edge-adjacent pairs.  Six of them are the
 *   two halves of one square side (the diagonals): coplanar.  The other 12
 *   are the cube's edges, at right angles: not coplanar.
 *   Vertex-only pairs: at a corner where d triangles meet there are C(d, 2)
 *   pairs; an edge pair is seen at both of its corners, a vertex pair at one,
 *   so vertex pairs = sum_v C(d_v, 2) - 2 E.  In cube.obj the corners
 *   (0,0,0), (0,h,h), (h,0,h), (h,h,0) have 5 triangles each and the other
 *   four have 4 (count the 'f' lines), so the sum is 4*10 + 4*6 = 64 and
 *   there are 64 - 36 = 28 vertex pairs, none coplanar (two triangles in the
 *   same side share the diagonal, hence an edge).
 * Tetrahedron: any two of the four faces share exactly one edge: 6 edge
 *   pairs, no vertex pair, none coplanar; 6 edges. */
TEST(mesh_cube_adjacency_matches_hand_count)
{
    rad_scene *s = harness_scene_load("scenes/furnace_cube/cube.obj", NULL);
    rad_mesh *m = mesh_of(s);
    if (!m) {
        rad_scene_destroy(s);
        return;
    }
    rad_mesh_info info;
    rad_mesh_get_info(m, &info);
    CHECK(info.faces == 12 && info.vertices == 8);
    CHECK(info.edges == 18);
    CHECK(info.pairs_edge == 18);
    CHECK(info.pairs_edge_coplanar == 6);
    CHECK(info.pairs_vertex == 28);
    CHECK(info.pairs_vertex_coplanar == 0);
    CHECK(incidence_pairs(rad_mesh_triangles(m), 12, 8) == 64);
    CHECK(rad_mesh_pair_count(m) == 18 + 28);
    /* Each listed pair really shares what it says, and a < b, sorted. */
    const rad_mesh_pair *p = rad_mesh_pairs(m);
    for (int i = 0; i < rad_mesh_pair_count(m); i++) {
        const int *ta = rad_mesh_triangles(m) + 3 * p[i].a, *tb = rad_mesh_triangles(m) + 3 * p[i].b;
        int shared = 0;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                shared += ta[a] == tb[b];
        CHECK(p[i].a < p[i].b);
        CHECK(shared == (p[i].contact == RAD_MESH_SHARED_EDGE ? 2 : 1));
        if (i > 0)
            CHECK(p[i - 1].a < p[i].a || (p[i - 1].a == p[i].a && p[i - 1].b < p[i].b));
    }
    CHECK(info.closed == 1 && info.components == 1 && info.closed_components == 1);
    CHECK(info.convex_inside == 1);
    rad_mesh_surface_check sc;
    CHECK(rad_mesh_check_surface(m, &sc) == RAD_OK);
    CHECK(sc.surface_mesh == 1 && sc.closed == 1 && sc.components == 1);
    CHECK(rad_mesh_check_surface(NULL, &sc) == RAD_EINVAL);
    CHECK(rad_mesh_component_closed(m, 0) == 1 && rad_mesh_component_convex(m, 0) == 1);
    CHECK(rad_mesh_component_closed(m, 1) == -1);
    rad_mesh_destroy(m);
    rad_scene_destroy(s);
}

TEST(mesh_tetrahedron_adjacency_matches_hand_count)
{
    rad_scene *s = harness_scene_load("scenes/tetrahedron/tetrahedron.obj", NULL);
    rad_mesh *m = mesh_of(s);
    if (!m) {
        rad_scene_destroy(s);
        return;
    }
    rad_mesh_info info;
    rad_mesh_get_info(m, &info);
    CHECK(info.edges == 6);
    CHECK(info.pairs_edge == 6 && info.pairs_edge_coplanar == 0);
    CHECK(info.pairs_vertex == 0);
    CHECK(info.closed == 1 && info.convex_inside == 1);
    rad_mesh_destroy(m);
    rad_scene_destroy(s);
}

/* The same cube wound outward is closed but not convex seen from inside;
 * one face flipped breaks closedness (two misoriented edges... three: a
 * triangle's three edges each meet a neighbour in the same direction). */
TEST(mesh_orientation_decides_convexity_and_closedness)
{
    rad_scene *s = harness_scene_load("scenes/furnace_cube/cube.obj", NULL);
    if (!s)
        return;
    int nt = rad_scene_triangle_count(s);
    int *flipped = malloc(3 * (size_t)nt * sizeof *flipped);
    memcpy(flipped, rad_scene_triangles(s), 3 * (size_t)nt * sizeof *flipped);
    for (int t = 0; t < nt; t++) {
        int x = flipped[3 * t + 1];
        flipped[3 * t + 1] = flipped[3 * t + 2];
        flipped[3 * t + 2] = x;
    }
    rad_mesh *m = NULL;
    CHECK(rad_mesh_create(rad_scene_vertices(s), rad_scene_vertex_count(s), flipped, nt, NULL, &m) == RAD_OK);
    rad_mesh_info info;
    rad_mesh_get_info(m, &info);
    CHECK(info.closed == 1);
    CHECK(info.convex_inside == 0);
    rad_mesh_destroy(m);
    /* Flip back only triangle 0. */
    memcpy(flipped + 3, rad_scene_triangles(s) + 3, 3 * (size_t)(nt - 1) * sizeof *flipped);
    CHECK(rad_mesh_create(rad_scene_vertices(s), rad_scene_vertex_count(s), flipped, nt, NULL, &m) == RAD_OK);
    rad_mesh_get_info(m, &info);
    CHECK(info.closed == 0);
    CHECK(info.misoriented_edges == 3);
    CHECK(info.convex_inside == 0);
    rad_mesh_destroy(m);
    free(flipped);
    rad_scene_destroy(s);
}

TEST(mesh_closed_scenes_are_closed)
{
    const char *closed[] = {"scenes/furnace_cube/cube.obj", "scenes/tetrahedron/tetrahedron.obj",
                            "scenes/sphere/sphere_0.obj", "scenes/sphere/sphere_1.obj",
                            "scenes/sphere/sphere_2.obj", "scenes/sphere/sphere_3.obj",
                            "scenes/many_objects/many_64.obj"};
    for (size_t k = 0; k < sizeof closed / sizeof closed[0]; k++) {
        rad_scene *s = harness_scene_load(closed[k], NULL);
        rad_mesh *m = mesh_of(s);
        rad_mesh_info info;
        rad_mesh_get_info(m, &info);
        CHECK_MSG(info.closed == 1, "%s not closed", closed[k]);
        CHECK_MSG(info.edges * 2 == info.faces * 3, "%s: E != 3F/2", closed[k]);
        int spheres = strstr(closed[k], "sphere") != NULL;
        if (spheres) {
            /* Every icosphere is convex from inside; Euler: V = F/2 + 2. */
            CHECK_MSG(info.convex_inside == 1, "%s not convex", closed[k]);
            CHECK(info.vertices == info.faces / 2 + 2);
            /* Vertex pairs: 12 corners of degree 5, the rest of degree 6. */
            long sum = 12 * 10 + (long)(info.vertices - 12) * 15;
            CHECK(info.pairs_vertex == sum - 2 * info.edges);
        }
        if (strstr(closed[k], "many")) {
            CHECK(info.components == 65 && info.closed_components == 65);
            CHECK(info.convex_inside == 0);
            /* The room (component 0, faces inward) is convex from inside;
             * every small cube faces outward, so it is not. */
            CHECK(rad_mesh_component_convex(m, 0) == 1);
            for (int c = 1; c < 65; c++)
                CHECK(rad_mesh_component_convex(m, c) == 0 && rad_mesh_component_closed(m, c) == 1);
            CHECK(rad_mesh_component_convex(m, 65) == -1);
        }
        rad_mesh_destroy(m);
        rad_scene_destroy(s);
    }
    /* And the open ones are not. */
    const char *open[] = {"scenes/cornell/cornell.obj", "scenes/plates_parallel/plates.obj",
                          "scenes/plates_perpendicular/plates.obj", "scenes/occluder/occluder.obj"};
    for (size_t k = 0; k < sizeof open / sizeof open[0]; k++) {
        rad_scene *s = harness_scene_load(open[k], NULL);
        rad_mesh *m = mesh_of(s);
        rad_mesh_info info;
        rad_mesh_get_info(m, &info);
        CHECK_MSG(info.closed == 0 && info.boundary_edges > 0, "%s closed?", open[k]);
        rad_mesh_destroy(m);
        rad_scene_destroy(s);
    }
}

/* The perpendicular plates: one edge where they meet at a right angle; the
 * two squares' diagonals make 2 coplanar edge pairs; the corner triangles
 * touching the shared edge at one end only give vertex pairs. */
TEST(mesh_perpendicular_plates_pairs)
{
    rad_scene *s = harness_scene_load("scenes/plates_perpendicular/plates.obj", NULL);
    rad_mesh *m = mesh_of(s);
    rad_mesh_info info;
    rad_mesh_get_info(m, &info);
    CHECK(info.pairs_edge == 3 && info.pairs_edge_coplanar == 2);
    /* The four triangles all touch the shared edge: every one of the
     * 2 x 2 cross pairs touches; one shares the edge, three a vertex. */
    CHECK(info.pairs_vertex == 3 && info.pairs_vertex_coplanar == 0);
    CHECK(info.components == 1 && info.convex_inside == 1);
    rad_mesh_destroy(m);
    rad_scene_destroy(s);
}

static void check_refined(const rad_mesh *coarse, const rad_mesh *fine, int expect_faces)
{
    CHECK_NEAR(mesh_area(fine), mesh_area(coarse), 1e-13, 0.0);
    if (expect_faces > 0)
        CHECK(rad_mesh_face_count(fine) == expect_faces);
    /* Per input face, the children's areas add up to the parent's. */
    int nc = rad_mesh_face_count(coarse);
    double *area = calloc((size_t)nc, sizeof *area);
    const double *x = rad_mesh_vertices(fine);
    for (int f = 0; f < rad_mesh_face_count(fine); f++) {
        int parent = rad_mesh_input_faces(fine)[f];
        CHECK(parent >= 0 && parent < nc);
        if (parent < 0 || parent >= nc)
            continue;
        const int *v = rad_mesh_triangles(fine) + 3 * f;
        rad_vec3 a = rad_vec3_make(x[3 * v[0]], x[3 * v[0] + 1], x[3 * v[0] + 2]);
        rad_vec3 b = rad_vec3_make(x[3 * v[1]], x[3 * v[1] + 1], x[3 * v[1] + 2]);
        rad_vec3 c = rad_vec3_make(x[3 * v[2]], x[3 * v[2] + 1], x[3 * v[2] + 2]);
        area[parent] += rad_geom_triangle_area(a, b, c);
        /* The child keeps its parent's winding: same normal. */
        const int *pv = rad_mesh_triangles(coarse) + 3 * parent;
        const double *px = rad_mesh_vertices(coarse);
        rad_vec3 n = rad_geom_triangle_normal(
            rad_vec3_make(px[3 * pv[0]], px[3 * pv[0] + 1], px[3 * pv[0] + 2]),
            rad_vec3_make(px[3 * pv[1]], px[3 * pv[1] + 1], px[3 * pv[1] + 2]),
            rad_vec3_make(px[3 * pv[2]], px[3 * pv[2] + 1], px[3 * pv[2] + 2]));
        CHECK_NEAR(rad_vec3_dot(n, rad_geom_triangle_normal(a, b, c)), 1.0, 0.0, 1e-12);
    }
    for (int f = 0; f < nc; f++) {
        const int *v = rad_mesh_triangles(coarse) + 3 * f;
        const double *px = rad_mesh_vertices(coarse);
        double want = rad_geom_triangle_area(
            rad_vec3_make(px[3 * v[0]], px[3 * v[0] + 1], px[3 * v[0] + 2]),
            rad_vec3_make(px[3 * v[1]], px[3 * v[1] + 1], px[3 * v[1] + 2]),
            rad_vec3_make(px[3 * v[2]], px[3 * v[2] + 1], px[3 * v[2] + 2]));
        CHECK_NEAR(area[f], want, 1e-13, 0.0);
    }
    free(area);
}

TEST(mesh_uniform_refinement_preserves_area_faces_and_closedness)
{
    rad_scene *s = harness_scene_load("scenes/furnace_cube/cube.obj", NULL);
    rad_mesh *m = mesh_of(s), *fine = NULL;
    if (!m) {
        rad_scene_destroy(s);
        return;
    }
    CHECK(rad_mesh_refine_uniform(m, 3, 1000000, &fine) == RAD_OK);
    check_refined(m, fine, 12 * 64);
    rad_mesh_info info;
    rad_mesh_get_info(fine, &info);
    /* Conforming: still closed, V = F/2 + 2, still convex from inside. */
    CHECK(info.closed == 1);
    CHECK(info.vertices == 12 * 64 / 2 + 2);
    CHECK(info.convex_inside == 1);
    rad_mesh_destroy(fine);
    CHECK(rad_mesh_refine_uniform(m, 20, 1000000, &fine) == RAD_ETOOBIG);
    CHECK(fine == NULL);
    rad_mesh_destroy(m);
    rad_scene_destroy(s);
}

TEST(mesh_max_edge_refinement_bounds_edges_and_conforms)
{
    rad_scene *s = harness_scene_load("scenes/cornell/cornell.obj", NULL);
    rad_mesh *m = mesh_of(s), *fine = NULL;
    if (!m) {
        rad_scene_destroy(s);
        return;
    }
    const double h = 0.0785;
    CHECK(rad_mesh_refine_max_edge(m, h, 1000000, &fine) == RAD_OK);
    check_refined(m, fine, 0);
    const double *x = rad_mesh_vertices(fine);
    double longest = 0.0;
    for (int f = 0; f < rad_mesh_face_count(fine); f++)
        for (int k = 0; k < 3; k++) {
            int a = rad_mesh_triangles(fine)[3 * f + k], b = rad_mesh_triangles(fine)[3 * f + (k + 1) % 3];
            rad_vec3 d = rad_vec3_make(x[3 * a] - x[3 * b], x[3 * a + 1] - x[3 * b + 1], x[3 * a + 2] - x[3 * b + 2]);
            longest = fmax(longest, rad_vec3_norm(d));
        }
    CHECK_MSG(longest <= h, "longest edge %g > %g", longest, h);
    /* Conforming: refinement adds no boundary edge inside the input surface.
     * Each input boundary edge is split into 2^k pieces, so boundary edges
     * only grow where the input had boundary; none may be non-manifold. */
    rad_mesh_info coarse_info, info;
    rad_mesh_get_info(m, &coarse_info);
    rad_mesh_get_info(fine, &info);
    CHECK(info.nonmanifold_edges == 0 && info.misoriented_edges == 0);
    CHECK(info.components == coarse_info.components);
    rad_mesh_destroy(fine);
    CHECK(rad_mesh_refine_max_edge(m, 0.0, 1000, &fine) == RAD_EINVAL);
    CHECK(rad_mesh_refine_max_edge(m, 1e-4, 1000, &fine) == RAD_ETOOBIG);
    rad_mesh_destroy(m);
    rad_scene_destroy(s);
}

/* Write PLY (rad_io_write_ply) and OFF, read them back through the importer,
 * compare. */
TEST(mesh_ply_and_off_round_trip)
{
    rad_scene *s = harness_scene_load("scenes/sphere/sphere_1.obj", NULL);
    rad_mesh *m = mesh_of(s);
    if (!m) {
        rad_scene_destroy(s);
        return;
    }
    char ply[64], off[64];
    snprintf(ply, sizeof ply, "/tmp/radkit-test-%ld.ply", (long)getpid());
    snprintf(off, sizeof off, "/tmp/radkit-test-%ld.off", (long)getpid());
    int nv = rad_mesh_vertex_count(m), nt = rad_mesh_face_count(m);
    /* One radiosity per channel on every face, so every vertex takes it;
     * exposure 1 and gamma 1 make the colour 255 B. */
    double *B = malloc(3 * (size_t)nt * sizeof *B);
    const double channel[3] = {0.05, 0.25, 0.6};
    for (int i = 0; i < 3 * nt; i++)
        B[i] = channel[i / nt];
    rad_io_tonemap tm = {1.0, 1.0};
    CHECK(rad_io_write_ply(ply, (size_t)nv, rad_mesh_vertices(m), (size_t)nt, rad_mesh_triangles(m),
                           B, &tm, 0) == RAD_OK);
    CHECK(rad_mesh_write_off(m, off) == RAD_OK);
    const char *paths[2] = {ply, off};
    for (int k = 0; k < 2; k++) {
        rad_scene *back = NULL;
        CHECK_MSG(rad_scene_load(paths[k], NULL, &back) == RAD_OK, "%s: %s", paths[k], rad_error_message());
        if (!back)
            continue;
        CHECK(rad_scene_triangle_count(back) == nt);
        CHECK(rad_scene_vertex_count(back) == nv);
        /* Same triangles in the same order (coordinates pass through
         * Assimp's single precision: compare to float accuracy). */
        const double *xa = rad_mesh_vertices(m), *xb = rad_scene_vertices(back);
        for (int t = 0; t < nt && t < rad_scene_triangle_count(back); t++)
            for (int c = 0; c < 3; c++) {
                int va = rad_mesh_triangles(m)[3 * t + c], vb = rad_scene_triangles(back)[3 * t + c];
                for (int d = 0; d < 3; d++)
                    CHECK_NEAR(xb[3 * vb + d], xa[3 * va + d], 0.0, 1e-6);
            }
        rad_scene_destroy(back);
    }
    /* The colours are in the PLY as written: check one vertex line by hand. */
    FILE *f = fopen(ply, "r");
    char line[256];
    int in_body = 0, found = 0;
    while (f && fgets(line, sizeof line, f)) {
        if (in_body) {
            double x, y, z;
            int r, g, b;
            CHECK(sscanf(line, "%lf %lf %lf %d %d %d", &x, &y, &z, &r, &g, &b) == 6);
            CHECK(r == 13 && g == 64 && b == 153); /* (0.05, 0.25, 0.6) * 255, rounded */
            found = 1;
            break;
        }
        in_body = strcmp(line, "end_header\n") == 0;
    }
    if (f)
        fclose(f);
    CHECK(found);
    remove(ply);
    remove(off);
    free(B);
    rad_mesh_destroy(m);
    rad_scene_destroy(s);
}

/* The exception barrier: bad input to the C++ side comes back as a status
 * with the message, never as an exception or a crash. */
TEST(mesh_barrier_maps_exceptions_to_status)
{
    const double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const int bad[3] = {0, 1, 7};
    rad_mesh *m = NULL;
    rad_error_clear();
    CHECK(rad_mesh_create(xyz, 3, bad, 1, NULL, &m) == RAD_EGEOM);
    CHECK(m == NULL);
    CHECK(strstr(rad_error_message(), "vertex 7") != NULL);
    CHECK(rad_mesh_create(xyz, 3, NULL, 1, NULL, &m) == RAD_EGEOM);
    CHECK(rad_mesh_create(xyz, 3, bad, 1, NULL, NULL) == RAD_EINVAL);
    rad_mesh_destroy(NULL);
    CHECK(rad_mesh_write_off(NULL, "/tmp/x.off") == RAD_EINVAL);
    /* A non-manifold fan (three triangles on one edge) is analysed, not refused. */
    const double fan[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1};
    const int tri[9] = {0, 1, 2, 0, 1, 3, 0, 1, 4};
    CHECK(rad_mesh_create(fan, 5, tri, 3, NULL, &m) == RAD_OK);
    rad_mesh_info info;
    rad_mesh_get_info(m, &info);
    rad_mesh_surface_check sc;
    CHECK(rad_mesh_check_surface(m, &sc) == RAD_OK);
    CHECK(info.nonmanifold_edges == 1 && sc.surface_mesh == 0 && sc.closed == -1 && info.closed == 0);
    CHECK(info.pairs_edge == 3);
    rad_mesh_destroy(m);
}

/* Convexity costs faces x vertices tests; a big scene is not worth minutes
 * of proof.  A flat 150 x 150 grid (45 000 faces, 22 801 vertices: 1e9 tests)
 * is reported unknown at once, a small grid of the same kind convex. */
TEST(mesh_convexity_of_a_big_scene_is_unknown_not_ground_through)
{
    const int sizes[2] = {10, 150};
    for (int k = 0; k < 2; k++) {
        int n = sizes[k], nv = (n + 1) * (n + 1), nt = 2 * n * n;
        double *xyz = malloc(sizeof *xyz * 3 * (size_t)nv);
        int *tri = malloc(sizeof *tri * 3 * (size_t)nt);
        if (!xyz || !tri) {
            CHECK(0);
            free(xyz);
            free(tri);
            return;
        }
        for (int j = 0; j <= n; j++)
            for (int i = 0; i <= n; i++) {
                double *p = xyz + 3 * (size_t)(j * (n + 1) + i);
                p[0] = (double)i / n;
                p[1] = (double)j / n;
                p[2] = 0.0;
            }
        for (int j = 0, t = 0; j < n; j++)
            for (int i = 0; i < n; i++, t += 2) {
                int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
                int q[6] = {a, b, d, a, d, c};
                memcpy(tri + 3 * (size_t)t, q, sizeof q);
            }
        rad_mesh *m = NULL;
        CHECK(rad_mesh_create(xyz, nv, tri, nt, NULL, &m) == RAD_OK);
        rad_mesh_info info;
        rad_mesh_get_info(m, &info);
        CHECK_MSG(info.convex_inside == (k == 0 ? 1 : -1), "grid %d: convex_inside %d", n,
                  info.convex_inside);
        CHECK(rad_mesh_component_convex(m, 0) == (k == 0 ? 1 : -1));
        rad_mesh_destroy(m);
        free(xyz);
        free(tri);
    }
}
