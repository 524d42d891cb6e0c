/* rad_mesh_conform_leaves: leaves of midpoint-split quadtrees made into a
 * conforming mesh.  The leaves are built here with hier.c's own midpoint rule
 * ((p + q) * 0.5 through rad_vec3), and the results are checked against hand
 * counts (vertices, triangles, edges by Euler's formula), against the areas
 * of the input, and by brute force: no output vertex inside an output edge,
 * every output triangle inside its leaf with the leaf's normal, closed
 * surfaces closed and consistently oriented. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_geom.h"
#include "rad_hier.h"
#include "rad_mesh.h"
#include "rad_scene.h"

/* ---- building leaves ------------------------------------------------------ */

typedef struct leaves {
    double *c; /* 9 per leaf */
    size_t n, cap;
} leaves;

static void leaf_push(leaves *L, rad_vec3 a, rad_vec3 b, rad_vec3 c)
{
    if (L->n == L->cap) {
        L->cap = L->cap ? 2 * L->cap : 64;
        L->c = realloc(L->c, 9 * L->cap * sizeof *L->c);
    }
    double *p = L->c + 9 * L->n++;
    rad_vec3 v[3] = {a, b, c};
    for (int k = 0; k < 3; k++) {
        p[3 * k] = v[k].x;
        p[3 * k + 1] = v[k].y;
        p[3 * k + 2] = v[k].z;
    }
}

/* hier.c's split: children (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca). */
static void split4(rad_vec3 a, rad_vec3 b, rad_vec3 c, rad_vec3 ch[4][3])
{
    rad_vec3 ab = rad_vec3_scale(rad_vec3_add(a, b), 0.5);
    rad_vec3 bc = rad_vec3_scale(rad_vec3_add(b, c), 0.5);
    rad_vec3 ca = rad_vec3_scale(rad_vec3_add(c, a), 0.5);
    rad_vec3 k[4][3] = {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}};
    memcpy(ch, k, sizeof k);
}

/* All leaves of (a, b, c) split `levels` times, in hier's child order. */
static void uniform(leaves *L, rad_vec3 a, rad_vec3 b, rad_vec3 c, int levels)
{
    if (levels == 0) {
        leaf_push(L, a, b, c);
        return;
    }
    rad_vec3 ch[4][3];
    split4(a, b, c, ch);
    for (int k = 0; k < 4; k++)
        uniform(L, ch[k][0], ch[k][1], ch[k][2], levels - 1);
}

/* Split only towards edge c -> a, `levels` times: children 0 and 2 have their
 * third edge on the parent's edge c -> a and are split again; 1 and 3 stay. */
static void along_ca(leaves *L, rad_vec3 a, rad_vec3 b, rad_vec3 c, int levels)
{
    if (levels == 0) {
        leaf_push(L, a, b, c);
        return;
    }
    rad_vec3 ch[4][3];
    split4(a, b, c, ch);
    for (int k = 0; k < 4; k++) {
        if (k == 0 || k == 2)
            along_ca(L, ch[k][0], ch[k][1], ch[k][2], levels - 1);
        else
            leaf_push(L, ch[k][0], ch[k][1], ch[k][2]);
    }
}

/* ---- the result and its checks -------------------------------------------- */

typedef struct conformed {
    double *xyz;
    int *tri, *leaf;
    size_t nv, nt;
} conformed;

static int conform(const leaves *L, conformed *out)
{
    memset(out, 0, sizeof *out);
    rad_status st = rad_mesh_conform_leaves(L->c, L->n, &out->xyz, &out->nv, &out->tri, &out->leaf,
                                            &out->nt);
    CHECK_MSG(st == RAD_OK, "conform: %s", rad_error_message());
    return st == RAD_OK;
}

static void conformed_free(conformed *m)
{
    free(m->xyz);
    free(m->tri);
    free(m->leaf);
}

static rad_vec3 vtx(const double *xyz, int v)
{
    return rad_vec3_make(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
}

static rad_vec3 corner(const leaves *L, size_t l, int k)
{
    const double *p = L->c + 9 * l + 3 * k;
    return rad_vec3_make(p[0], p[1], p[2]);
}

static rad_vec3 tri_normal(rad_vec3 a, rad_vec3 b, rad_vec3 c)
{
    return rad_vec3_cross(rad_vec3_sub(b, a), rad_vec3_sub(c, a));
}

static double norm(rad_vec3 v) { return sqrt(rad_vec3_dot(v, v)); }

static double total_area(const conformed *m)
{
    double area = 0.0;
    for (size_t t = 0; t < m->nt; t++) {
        const int *v = m->tri + 3 * t;
        area += rad_geom_triangle_area(vtx(m->xyz, v[0]), vtx(m->xyz, v[1]), vtx(m->xyz, v[2]));
    }
    return area;
}

/* Brute force: the number of (vertex, edge) pairs where the vertex lies inside
 * the edge (not at an end), within a relative tolerance far above rounding
 * (a midpoint is off its edge by rounding only) and far below the spacing of
 * any two vertices here. */
static int t_vertices(const double *xyz, size_t nv, const int *tri, size_t nt)
{
    int count = 0;
    for (size_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int u = tri[3 * t + (size_t)k], w = tri[3 * t + (size_t)(k + 1) % 3];
            rad_vec3 p = vtx(xyz, u), d = rad_vec3_sub(vtx(xyz, w), p);
            double len2 = rad_vec3_dot(d, d);
            for (size_t v = 0; v < nv; v++) {
                if ((int)v == u || (int)v == w)
                    continue;
                rad_vec3 q = rad_vec3_sub(vtx(xyz, (int)v), p);
                double s = rad_vec3_dot(q, d) / len2;
                if (s <= 1e-9 || s >= 1.0 - 1e-9)
                    continue;
                rad_vec3 off = rad_vec3_sub(q, rad_vec3_scale(d, s));
                if (rad_vec3_dot(off, off) <= 1e-18 * len2)
                    count++;
            }
        }
    return count;
}

/* The input leaves as a triangle soup over deduplicated corners (exact
 * equality), for checking that the unconformed leaves do have T-vertices. */
static int leaf_t_vertices(const leaves *L)
{
    double *xyz = malloc(9 * L->n * sizeof *xyz);
    int *tri = malloc(3 * L->n * sizeof *tri);
    size_t nv = 0;
    for (size_t i = 0; i < 3 * L->n; i++) {
        const double *p = L->c + 3 * i;
        size_t v = 0;
        while (v < nv && !(xyz[3 * v] == p[0] && xyz[3 * v + 1] == p[1] && xyz[3 * v + 2] == p[2]))
            v++;
        if (v == nv) {
            memcpy(xyz + 3 * nv, p, 3 * sizeof *p);
            nv++;
        }
        tri[i] = (int)v;
    }
    int count = t_vertices(xyz, nv, tri, L->n);
    free(xyz);
    free(tri);
    return count;
}

/* Every output triangle lies in its leaf (barycentric coordinates >= -1e-12,
 * distance to the leaf's plane <= 1e-12 of its size), has the leaf's normal
 * direction, and the output areas of each leaf add up to the leaf's area. */
static void check_inside_leaves(const leaves *L, const conformed *m)
{
    double *sum = calloc(L->n, sizeof *sum);
    for (size_t t = 0; t < m->nt; t++) {
        int l = m->leaf[t];
        CHECK(l >= 0 && (size_t)l < L->n);
        if (l < 0 || (size_t)l >= L->n)
            continue;
        rad_vec3 a = corner(L, (size_t)l, 0), b = corner(L, (size_t)l, 1), c = corner(L, (size_t)l, 2);
        rad_vec3 n = tri_normal(a, b, c);
        double n2 = rad_vec3_dot(n, n), size = norm(rad_vec3_sub(b, a));
        const int *v = m->tri + 3 * t;
        rad_vec3 p[3] = {vtx(m->xyz, v[0]), vtx(m->xyz, v[1]), vtx(m->xyz, v[2])};
        for (int k = 0; k < 3; k++) {
            double la = rad_vec3_dot(n, tri_normal(p[k], b, c)) / n2;
            double lb = rad_vec3_dot(n, tri_normal(a, p[k], c)) / n2;
            double lc = rad_vec3_dot(n, tri_normal(a, b, p[k])) / n2;
            CHECK_MSG(la >= -1e-12 && lb >= -1e-12 && lc >= -1e-12,
                      "triangle %zu: vertex %d outside leaf %d (%g %g %g)", t, v[k], l, la, lb, lc);
            double dist = fabs(rad_vec3_dot(rad_vec3_sub(p[k], a), n)) / sqrt(n2);
            CHECK_MSG(dist <= 1e-12 * size, "triangle %zu: %g off its leaf's plane", t, dist);
        }
        rad_vec3 nt = tri_normal(p[0], p[1], p[2]);
        CHECK_MSG(rad_vec3_dot(nt, n) > 0.0, "triangle %zu is flipped against leaf %d", t, l);
        CHECK_MSG(norm(rad_vec3_cross(nt, n)) <= 1e-9 * norm(nt) * sqrt(n2),
                  "triangle %zu is not parallel to leaf %d", t, l);
        sum[l] += rad_geom_triangle_area(p[0], p[1], p[2]);
    }
    for (size_t l = 0; l < L->n; l++) {
        double area = rad_geom_triangle_area(corner(L, l, 0), corner(L, l, 1), corner(L, l, 2));
        CHECK_MSG(fabs(sum[l] - area) <= 1e-13 * area, "leaf %zu: output area %.17g, leaf area %.17g",
                  l, sum[l], area);
    }
    free(sum);
}

typedef struct edge_counts {
    int edges;      /* undirected */
    int boundary;   /* used once */
    int interior;   /* used twice, in opposite directions */
    int other;      /* used 3+ times or twice in one direction */
} edge_counts;

static int cmp_edge(const void *x, const void *y)
{
    const int *a = x, *b = y;
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

static edge_counts count_edges(const conformed *m)
{
    int *e = malloc(9 * m->nt * sizeof *e); /* (min, max, forward) per directed edge */
    for (size_t t = 0; t < m->nt; t++)
        for (int k = 0; k < 3; k++) {
            int u = m->tri[3 * t + (size_t)k], w = m->tri[3 * t + (size_t)(k + 1) % 3];
            int *p = e + 3 * (3 * t + (size_t)k);
            p[0] = u < w ? u : w;
            p[1] = u < w ? w : u;
            p[2] = u < w;
        }
    qsort(e, 3 * m->nt, 3 * sizeof *e, cmp_edge);
    edge_counts c = {0, 0, 0, 0};
    for (size_t i = 0; i < 3 * m->nt;) {
        size_t j = i;
        while (j < 3 * m->nt && e[3 * j] == e[3 * i] && e[3 * j + 1] == e[3 * i + 1])
            j++;
        c.edges++;
        if (j - i == 1)
            c.boundary++;
        else if (j - i == 2 && e[3 * i + 2] != e[3 * i + 5])
            c.interior++;
        else
            c.other++;
        i = j;
    }
    free(e);
    return c;
}

/* A tilted parallelogram o, o+u, o+u+v, o+v as two triangles sharing the
 * diagonal o -- o+u+v, both counter-clockwise about u x v. */
static const rad_vec3 sq_o = {0.3125, -1.75, 2.5};
static const rad_vec3 sq_u = {2.385, 0.4, -0.7};
static const rad_vec3 sq_v = {-0.35, 1.9, 0.85};

static void square(rad_vec3 p[4])
{
    p[0] = sq_o;
    p[1] = rad_vec3_add(sq_o, sq_u);
    p[2] = rad_vec3_add(p[1], sq_v);
    p[3] = rad_vec3_add(sq_o, sq_v);
}

static int same_point(const double *xyz, int v, rad_vec3 p)
{
    return xyz[3 * v] == p.x && xyz[3 * v + 1] == p.y && xyz[3 * v + 2] == p.z;
}

/* Triangle t is (a, b, c) up to rotation (same orientation). */
static int is_triangle(const conformed *m, size_t t, rad_vec3 a, rad_vec3 b, rad_vec3 c)
{
    const int *v = m->tri + 3 * t;
    for (int r = 0; r < 3; r++)
        if (same_point(m->xyz, v[r], a) && same_point(m->xyz, v[(r + 1) % 3], b) &&
            same_point(m->xyz, v[(r + 2) % 3], c))
            return 1;
    return 0;
}

/* ---- tests ---------------------------------------------------------------- */

/* Square: T0 = (o, b, c) split once, T1 = (o, c, d) not.  The diagonal's
 * midpoint m hangs on T1, which becomes (o, m, d) and (m, c, d) (o, m, c are
 * collinear, so m -- d is the only diagonal).  Hand count: vertices o, b, c,
 * d and T0's three midpoints = 7; triangles 4 + 2 = 6; edges by Euler for a
 * disk, V - E + F = 1: E = 12, of which 6 on the boundary (o-b and b-c split
 * in two, c-d, d-o) and 6 inside. */
TEST(conform_square_one_hanging_vertex)
{
    rad_vec3 p[4];
    square(p);
    leaves L = {0};
    uniform(&L, p[0], p[1], p[2], 1);
    leaf_push(&L, p[0], p[2], p[3]);
    CHECK(leaf_t_vertices(&L) == 1); /* the checker sees the T-junction in the input */
    conformed m;
    if (conform(&L, &m)) {
        CHECK(m.nv == 7);
        CHECK(m.nt == 6);
        CHECK_NEAR(total_area(&m), norm(rad_vec3_cross(sq_u, sq_v)), 1e-15, 0.0);
        CHECK(t_vertices(m.xyz, m.nv, m.tri, m.nt) == 0);
        check_inside_leaves(&L, &m);
        edge_counts e = count_edges(&m);
        CHECK(e.edges == 12 && e.boundary == 6 && e.interior == 6 && e.other == 0);
        /* the four children come back unchanged, then T1's two triangles */
        for (size_t t = 0; t < 4 && m.nt == 6; t++) {
            CHECK(m.leaf[t] == (int)t);
            CHECK(is_triangle(&m, t, corner(&L, t, 0), corner(&L, t, 1), corner(&L, t, 2)));
        }
        rad_vec3 mid = rad_vec3_scale(rad_vec3_add(p[2], p[0]), 0.5);
        if (m.nt == 6) {
            CHECK(m.leaf[4] == 4 && m.leaf[5] == 4);
            CHECK((is_triangle(&m, 4, p[0], mid, p[3]) && is_triangle(&m, 5, mid, p[2], p[3])) ||
                  (is_triangle(&m, 5, p[0], mid, p[3]) && is_triangle(&m, 4, mid, p[2], p[3])));
        }
    }
    conformed_free(&m);
    free(L.c);
}

/* Uniform depth: nothing hangs, so the output is the input, triangle by
 * triangle and corner by corner.  The tetrahedron (4 faces, outward) split
 * twice: 64 leaves; a closed surface of F = 64 triangles has E = 3F/2 = 96
 * edges and V = 2 + E - F = 34 vertices. */
TEST(conform_uniform_input_is_returned_unchanged)
{
    rad_vec3 A = {0.0, 0.0, 0.0}, B = {1.375, 0.0, 0.0}, C = {0.0, 1.625, 0.0}, D = {0.0, 0.0, 1.1};
    rad_vec3 faces[4][3] = {{A, C, B}, {A, B, D}, {A, D, C}, {B, C, D}};
    leaves L = {0};
    for (int f = 0; f < 4; f++)
        uniform(&L, faces[f][0], faces[f][1], faces[f][2], 2);
    conformed m;
    if (conform(&L, &m)) {
        CHECK(m.nv == 34);
        CHECK(m.nt == L.n && L.n == 64);
        for (size_t t = 0; t < m.nt && t < L.n; t++) {
            CHECK(m.leaf[t] == (int)t);
            for (int k = 0; k < 3; k++)
                CHECK_MSG(same_point(m.xyz, m.tri[3 * t + (size_t)k], corner(&L, t, k)),
                          "triangle %zu corner %d moved", t, k);
        }
    }
    conformed_free(&m);
    free(L.c);

    /* -0.0 and +0.0 are one vertex: two triangles sharing an edge whose end
     * is written (0, 0, 0) in one and (-0, 0, 0) in the other, and a third
     * triangle sharing two corners: 5 vertices. */
    leaves Z = {0};
    leaf_push(&Z, rad_vec3_make(0.0, 0.0, 0.0), rad_vec3_make(1.0, 0.0, 0.0), rad_vec3_make(0.0, 1.0, 0.0));
    leaf_push(&Z, rad_vec3_make(1.0, 0.0, 0.0), rad_vec3_make(1.0, 1.0, 0.0), rad_vec3_make(0.0, 1.0, 0.0));
    leaf_push(&Z, rad_vec3_make(-0.0, 0.0, 0.0), rad_vec3_make(0.0, 1.0, 0.0), rad_vec3_make(-1.0, 0.0, 0.0));
    if (conform(&Z, &m)) {
        CHECK(m.nv == 5);
        CHECK(m.nt == 3);
    }
    conformed_free(&m);
    free(Z.c);
}

/* Closed tetrahedron, faces split to different depths: f0 = (A, C, B) once
 * and its first child once more, f1 = (A, B, D) once, f2 and f3 not at all.
 * Hand count: vertices 4 corners + 3 midpoints of f0 + 3 of f0's first child
 * (two on edges AC, AB, one inside f0) + f1's midpoints of BD and DA (AB's is
 * f0's) = 12.  Leaves 7 + 4 + 1 + 1 = 13; each hanging vertex adds one
 * triangle to its leaf: mid(A, m_AB) on f1's child at A; m_DA, m_AC and
 * mid(A, m_AC) on f3 = (A, D, C); m_CB and m_BD on f2 = (B, C, D); mid(m_AC,
 * m_BA) on f0's middle child: 7, so 20 triangles, as Euler's V - E + F = 2
 * with E = 3F/2 demands for V = 12.  E = 30. */
TEST(conform_tetrahedron_mixed_depths_is_closed)
{
    rad_vec3 A = {0.25, -0.5, 0.125}, B = {2.635, -0.5, 0.125}, C = {0.25, 1.885, 0.125},
             D = {0.25, -0.5, 2.51};
    leaves L = {0};
    rad_vec3 ch[4][3];
    split4(A, C, B, ch);
    uniform(&L, ch[0][0], ch[0][1], ch[0][2], 1);
    for (int k = 1; k < 4; k++)
        leaf_push(&L, ch[k][0], ch[k][1], ch[k][2]);
    uniform(&L, A, B, D, 1);
    leaf_push(&L, B, C, D);
    leaf_push(&L, A, D, C);
    CHECK(L.n == 13);
    CHECK(leaf_t_vertices(&L) == 7);
    conformed m;
    if (conform(&L, &m)) {
        CHECK(m.nv == 12);
        CHECK(m.nt == 20);
        CHECK(t_vertices(m.xyz, m.nv, m.tri, m.nt) == 0);
        check_inside_leaves(&L, &m);
        edge_counts e = count_edges(&m);
        CHECK_MSG(e.edges == 30 && e.boundary == 0 && e.interior == 30 && e.other == 0,
                  "edges %d, boundary %d, interior %d, other %d", e.edges, e.boundary, e.interior,
                  e.other);
        /* total area: the tetrahedron's four faces */
        double area = rad_geom_triangle_area(A, C, B) + rad_geom_triangle_area(A, B, D) +
                      rad_geom_triangle_area(A, D, C) + rad_geom_triangle_area(B, C, D);
        CHECK_NEAR(total_area(&m), area, 1e-14, 0.0);
        rad_mesh *mesh = NULL;
        CHECK(rad_mesh_create(m.xyz, (int)m.nv, m.tri, (int)m.nt, m.leaf, &mesh) == RAD_OK);
        if (mesh) {
            rad_mesh_info info;
            rad_mesh_get_info(mesh, &info);
            CHECK(info.components == 1);
            CHECK(rad_mesh_component_closed(mesh, 0) == 1);
            rad_mesh_surface_check sc;
            CHECK(rad_mesh_check_surface(mesh, &sc) == RAD_OK);
            CHECK(info.closed == 1 && sc.closed == 1);
        }
        rad_mesh_destroy(mesh);
    }
    conformed_free(&m);
    free(L.c);
}

/* Deep mismatch: T0 of the square split 3 times (64 leaves), T1 not.  The
 * diagonal is cut into 8 by T0's leaves, so 7 vertices hang on T1's edge,
 * found by recursion three levels deep; T1's polygon of 10 vertices makes 8
 * triangles.  Hand count: T0's leaves have (8+1)(8+2)/2 = 45 vertices, plus
 * d: 46; triangles 64 + 8 = 72; Euler for a disk: E = V + F - 1 = 117, of
 * which 8 + 8 + 1 + 1 = 18 on the boundary. */
TEST(conform_deep_mismatch_on_one_edge)
{
    rad_vec3 p[4];
    square(p);
    leaves L = {0};
    uniform(&L, p[0], p[1], p[2], 3);
    leaf_push(&L, p[0], p[2], p[3]);
    conformed m;
    if (conform(&L, &m)) {
        CHECK(m.nv == 46);
        CHECK(m.nt == 72);
        size_t on_t1 = 0;
        for (size_t t = 0; t < m.nt; t++)
            on_t1 += m.leaf[t] == 64;
        CHECK(on_t1 == 8);
        CHECK(t_vertices(m.xyz, m.nv, m.tri, m.nt) == 0);
        check_inside_leaves(&L, &m);
        edge_counts e = count_edges(&m);
        CHECK(e.edges == 117 && e.boundary == 18 && e.interior == 99 && e.other == 0);
        CHECK_NEAR(total_area(&m), norm(rad_vec3_cross(sq_u, sq_v)), 1e-14, 0.0);
    }
    conformed_free(&m);
    free(L.c);

    /* Graded: T0 split only towards the diagonal (22 leaves at depths 1 to 3),
     * T1 split once: hanging vertices inside T0 too and on T1's children.  No
     * hand count here; the checks are the invariants: no T-vertex, each leaf
     * covered, a disk (V - E + F = 1) whose boundary is the square's. */
    leaves G = {0};
    along_ca(&G, p[0], p[1], p[2], 3);
    uniform(&G, p[0], p[2], p[3], 1);
    CHECK(G.n == 22 + 4);
    CHECK(leaf_t_vertices(&G) > 0);
    if (conform(&G, &m)) {
        CHECK(t_vertices(m.xyz, m.nv, m.tri, m.nt) == 0);
        check_inside_leaves(&G, &m);
        edge_counts e = count_edges(&m);
        CHECK(e.other == 0);
        CHECK((long)m.nv - e.edges + (long)m.nt == 1);
        /* boundary: along o-b, T0's leaves at o are split 3 times and the
         * rest once each: the segment count obeys S(k) = S(k-1) + 1, S(0) = 1,
         * so 4; the same on b-c; c-d and d-o in two (T1 split once): 12 */
        CHECK(e.boundary == 12);
        CHECK_NEAR(total_area(&m), norm(rad_vec3_cross(sq_u, sq_v)), 1e-14, 0.0);
    }
    conformed_free(&m);
    free(G.c);
}

/* End to end: rad_hier's own leaves of the closed furnace cube at mixed
 * levels (the mixed-level furnace test's settings, eps 0.1).  Its midpoints
 * must be the ones this module looks up, so the conformed mesh is closed and
 * consistently oriented (one component), has no T-vertex although the
 * leaves have some, and keeps the cube's area 6 x 1.25^2 = 9.375. */
TEST(conform_hier_leaves_of_closed_cube)
{
    rad_scene *scene = harness_scene_load("scenes/furnace_cube/cube.obj", NULL);
    if (!scene)
        return;
    int n = rad_scene_triangle_count(scene);
    double *rho = malloc(3 * (size_t)n * sizeof *rho), *E = malloc(3 * (size_t)n * sizeof *E);
    for (int k = 0; k < 3 * n; k++) {
        rho[k] = 0.375;
        E[k] = 2.385;
    }
    rad_hier_params p;
    rad_hier_params_default(&p);
    CHECK(rad_ff_rule_parse("exact", &p.rule) == RAD_OK);
    p.use_rule = 1;
    p.oracle = RAD_HIER_ORACLE_BF; /* refines the cube to mixed levels */
    p.eps = 0.1;
    p.min_area = 1.25 * 1.25 / 2.0 / 64.0 * (1.0 - 1e-9);
    p.tol = 1e-12;
    rad_hier *h = NULL;
    CHECK(rad_hier_create(rad_scene_vertices(scene), (size_t)rad_scene_vertex_count(scene),
                          rad_scene_triangles(scene), (size_t)n, rho, E, NULL, &p, &h) == RAD_OK);
    if (h)
        CHECK_MSG(rad_hier_solve(h) == RAD_OK, "solve: %s", rad_error_message());
    leaves L = {0};
    L.n = L.cap = h ? rad_hier_leaf_count(h) : 0;
    L.c = malloc((9 * L.n + 1) * sizeof *L.c);
    if (h)
        rad_hier_leaves(h, NULL, NULL, L.c, NULL);
    CHECK(leaf_t_vertices(&L) > 0); /* the levels are mixed */
    conformed m;
    if (L.n && conform(&L, &m)) {
        CHECK(m.nt > L.n);
        CHECK(t_vertices(m.xyz, m.nv, m.tri, m.nt) == 0);
        check_inside_leaves(&L, &m);
        edge_counts e = count_edges(&m);
        CHECK(e.boundary == 0 && e.other == 0 && e.interior == e.edges);
        CHECK((long)m.nv - e.edges + (long)m.nt == 2); /* a sphere */
        CHECK_NEAR(total_area(&m), 9.375, 1e-14, 0.0);
        rad_mesh *mesh = NULL;
        CHECK(rad_mesh_create(m.xyz, (int)m.nv, m.tri, (int)m.nt, m.leaf, &mesh) == RAD_OK);
        if (mesh) {
            rad_mesh_info info;
            rad_mesh_get_info(mesh, &info);
            CHECK(info.components == 1 && rad_mesh_component_closed(mesh, 0) == 1);
        }
        rad_mesh_destroy(mesh);
        printf("# conform: cube furnace hier leaves %zu -> %zu vertices, %zu triangles\n", L.n, m.nv,
               m.nt);
        conformed_free(&m);
    }
    free(L.c);
    rad_hier_destroy(h);
    free(rho);
    free(E);
    rad_scene_destroy(scene);
}

TEST(conform_rejects_bad_input)
{
    double good[9] = {0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0};
    double c[27];
    for (int l = 0; l < 3; l++)
        memcpy(c + 9 * l, good, sizeof good);
    double *xyz = (double *)1;
    int *tri = (int *)1, *leaf = (int *)1;
    size_t nv = 99, nt = 99;

    c[9 + 3 + 1] = NAN; /* leaf 1, corner 1 */
    CHECK(rad_mesh_conform_leaves(c, 3, &xyz, &nv, &tri, &leaf, &nt) == RAD_EINPUT);
    CHECK_MSG(strstr(rad_error_message(), "leaf 1") != NULL, "message: %s", rad_error_message());
    CHECK(xyz == NULL && tri == NULL && leaf == NULL && nv == 0 && nt == 0);
    c[9 + 3 + 1] = 0.0;
    c[18 + 8] = INFINITY; /* leaf 2 */
    CHECK(rad_mesh_conform_leaves(c, 3, &xyz, &nv, &tri, &leaf, &nt) == RAD_EINPUT);
    CHECK_MSG(strstr(rad_error_message(), "leaf 2") != NULL, "message: %s", rad_error_message());
    c[18 + 8] = 0.0;

    /* collinear leaf 2: c = a + 2 (b - a), exactly */
    double line[9] = {0.5, 0.25, 1.0, 1.5, 2.25, 4.0, 2.5, 4.25, 7.0};
    memcpy(c + 18, line, sizeof line);
    CHECK(rad_mesh_conform_leaves(c, 3, &xyz, &nv, &tri, &leaf, &nt) == RAD_EINPUT);
    CHECK_MSG(strstr(rad_error_message(), "leaf 2") != NULL &&
                  strstr(rad_error_message(), "degenerate") != NULL,
              "message: %s", rad_error_message());
    CHECK(xyz == NULL && tri == NULL && leaf == NULL);
    /* two equal corners in leaf 0 */
    memcpy(c + 18, good, sizeof good);
    memcpy(c + 3, c, 3 * sizeof *c);
    CHECK(rad_mesh_conform_leaves(c, 3, &xyz, &nv, &tri, &leaf, &nt) == RAD_EINPUT);
    CHECK_MSG(strstr(rad_error_message(), "leaf 0") != NULL, "message: %s", rad_error_message());
    memcpy(c, good, sizeof good);

    CHECK(rad_mesh_conform_leaves(NULL, 3, &xyz, &nv, &tri, &leaf, &nt) == RAD_EINVAL);
    CHECK(rad_mesh_conform_leaves(c, 3, NULL, &nv, &tri, &leaf, &nt) == RAD_EINVAL);
    CHECK(rad_mesh_conform_leaves(c, 3, &xyz, NULL, &tri, &leaf, &nt) == RAD_EINVAL);
    CHECK(rad_mesh_conform_leaves(c, 3, &xyz, &nv, NULL, &leaf, &nt) == RAD_EINVAL);
    CHECK(rad_mesh_conform_leaves(c, 3, &xyz, &nv, &tri, NULL, &nt) == RAD_EINVAL);
    CHECK(rad_mesh_conform_leaves(c, 3, &xyz, &nv, &tri, &leaf, NULL) == RAD_EINVAL);

    /* no leaves: an empty result */
    CHECK(rad_mesh_conform_leaves(c, 0, &xyz, &nv, &tri, &leaf, &nt) == RAD_OK);
    CHECK(xyz == NULL && tri == NULL && leaf == NULL && nv == 0 && nt == 0);
}
