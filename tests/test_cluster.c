/* rad_cluster: the hierarchy's invariants checked by brute force over its
 * triangles (every triangle once, ranges nested, boxes holding their
 * triangles, areas summing, cones holding every normal), each split leaving
 * both sides an eighth at least, determinism, objects kept whole where
 * planes separate them, bad input refused, and the bound of what a node's
 * triangles turn towards a cone of directions against its triangles. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_cluster.h"
#include "rad_geom.h"

/* n small random triangles in the unit cube, random orientations */
static void random_soup(size_t n, unsigned seed, double *xyz, int *tri)
{
    unsigned long long s = seed * 0x9e3779b97f4a7c15ull + 1;
    for (size_t k = 0; k < 9 * n; k++) {
        s = s * 6364136223846793005ull + 1442695040888963407ull;
        double u = (double)(s >> 11) * 0x1.0p-53;
        xyz[k] = (k % 9 < 3) ? u : xyz[k - k % 9 + k % 3] + 0.05 * (u - 0.5);
    }
    for (size_t k = 0; k < 3 * n; k++)
        tri[k] = (int)k;
}

static rad_vec3 vertex(const double *xyz, const int *tri, int t, int v)
{
    const double *p = xyz + 3 * (size_t)tri[3 * t + v];
    return rad_vec3_make(p[0], p[1], p[2]);
}

static void check_tree(const rad_cluster_tree *t, const double *xyz, const int *tri, size_t n,
                       int leaf_size)
{
    const rad_cluster_node *nd = rad_cluster_nodes(t);
    const int *order = rad_cluster_order(t);
    size_t nn = rad_cluster_node_count(t);
    CHECK(nd && order && nn >= 1);
    CHECK(nd[0].parent == -1 && nd[0].first == 0 && (size_t)nd[0].count == n);
    int *seen = calloc(n, sizeof *seen);
    for (size_t i = 0; i < n; i++)
        seen[order[i]]++;
    int once = 1;
    for (size_t i = 0; i < n; i++)
        once &= seen[i] == 1;
    CHECK_MSG(once, "every triangle appears once in the order");
    free(seen);
    int leaves = 0, bad_box = 0, bad_area = 0, bad_cone = 0, bad_nest = 0;
    for (size_t k = 0; k < nn; k++) {
        const rad_cluster_node *x = &nd[k];
        double area = 0.0;
        rad_vec3 axis = rad_vec3_make(x->normal[0], x->normal[1], x->normal[2]);
        double len = rad_vec3_norm(axis);
        for (int i = x->first; i < x->first + x->count; i++) {
            int tr = order[i];
            rad_vec3 p[3] = {vertex(xyz, tri, tr, 0), vertex(xyz, tri, tr, 1), vertex(xyz, tri, tr, 2)};
            area += rad_geom_triangle_area(p[0], p[1], p[2]);
            for (int v = 0; v < 3; v++) {
                double c[3] = {p[v].x, p[v].y, p[v].z};
                for (int a = 0; a < 3; a++)
                    bad_box += c[a] < x->lo[a] || c[a] > x->hi[a];
            }
            if (len > 1e-12) {
                rad_vec3 nrm = rad_geom_triangle_normal(p[0], p[1], p[2]);
                bad_cone += rad_vec3_dot(nrm, rad_vec3_scale(axis, 1.0 / len)) < x->cone_cos - 1e-12;
            }
        }
        bad_area += fabs(area - x->area) > 1e-12 * area;
        if (x->child[0] < 0) {
            leaves++;
            bad_nest += x->count > leaf_size || x->count < 1;
        } else {
            const rad_cluster_node *l = &nd[x->child[0]], *r = &nd[x->child[1]];
            bad_nest += l->parent != (int)k || r->parent != (int)k || l->first != x->first ||
                        r->first != l->first + l->count || l->count + r->count != x->count ||
                        l->depth != x->depth + 1;
        }
    }
    CHECK_MSG(bad_box == 0 && bad_area == 0 && bad_cone == 0 && bad_nest == 0,
              "boxes %d, areas %d, cones %d, nesting %d", bad_box, bad_area, bad_cone, bad_nest);
    CHECK((size_t)leaves == (nn + 1) / 2);
    /* each side of a split keeps at least an eighth of the node, so the
       depth stays within log_{8/7} n */
    int lopsided = 0, depth = 0;
    for (size_t k = 0; k < nn; k++) {
        const rad_cluster_node *x = &nd[k];
        depth = depth > x->depth ? depth : x->depth;
        if (x->child[0] >= 0) {
            int l = nd[x->child[0]].count, r = nd[x->child[1]].count;
            lopsided += (l < r ? l : r) < x->count / 8;
        }
    }
    CHECK_MSG(lopsided == 0, "%d splits leave one side less than an eighth", lopsided);
    CHECK_MSG(depth == rad_cluster_max_depth(t) &&
                  depth <= (int)ceil(log((double)n / leaf_size + 1.0) / log(8.0 / 7.0)) + 1,
              "depth %d (reported %d) for %zu triangles", depth, rad_cluster_max_depth(t), n);
}

/* A random soup of n triangles (random_soup, seed) in *xyz and *tri, which
 * the caller frees, and its tree of leaves of leaf triangles (NULL after a
 * failed build). */
static rad_cluster_tree *soup_tree(size_t n, unsigned seed, int leaf, double **xyz, int **tri)
{
    *xyz = malloc(9 * n * sizeof **xyz);
    *tri = malloc(3 * n * sizeof **tri);
    random_soup(n, seed, *xyz, *tri);
    rad_cluster_tree *t = NULL;
    CHECK(rad_cluster_build(*xyz, 3 * n, *tri, n, leaf, 1, &t) == RAD_OK);
    return t;
}

TEST(cluster_hierarchy_invariants_on_random_soups)
{
    const size_t sizes[3] = {1, 37, 100000};
    const int leaves[3] = {1, 1, 4};
    for (int c = 0; c < 3; c++) {
        size_t n = sizes[c];
        double *xyz;
        int *tri;
        rad_cluster_tree *t = soup_tree(n, (unsigned)c + 1, leaves[c], &xyz, &tri);
        if (t)
            check_tree(t, xyz, tri, n, leaves[c]);
        /* the same input gives the same tree, on one thread or two (100 000
           triangles: enough tasks at once that two subtrees sharing a
           buffer would show it) */
        rad_cluster_tree *u = NULL;
        CHECK(rad_cluster_build(xyz, 3 * n, tri, n, leaves[c], 2, &u) == RAD_OK);
        if (t && u) {
            CHECK(rad_cluster_node_count(t) == rad_cluster_node_count(u));
            CHECK(memcmp(rad_cluster_order(t), rad_cluster_order(u), n * sizeof(int)) == 0);
            CHECK(memcmp(rad_cluster_nodes(t), rad_cluster_nodes(u),
                         rad_cluster_node_count(t) * sizeof(rad_cluster_node)) == 0);
        }
        rad_cluster_destroy(t);
        rad_cluster_destroy(u);
        free(xyz);
        free(tri);
    }
}

/* The tree of scene s, one triangle per leaf, its invariants checked;
 * NULL after a failed check. */
static rad_cluster_tree *scene_tree(const rad_scene *s)
{
    size_t n = (size_t)rad_scene_triangle_count(s);
    rad_cluster_tree *t = NULL;
    CHECK(rad_cluster_build(rad_scene_vertices(s), (size_t)rad_scene_vertex_count(s),
                            rad_scene_triangles(s), n, 1, 1, &t) == RAD_OK);
    if (t)
        check_tree(t, rad_scene_vertices(s), rad_scene_triangles(s), n, 1);
    return t;
}

/* A flat cluster: the normals agree, the mean normal has length 1 and the
 * cone is a line; a closed cube: the mean normal vanishes (cone_cos -1),
 * while each face's pair of triangles is flat. */

TEST(cluster_normals_and_cones)
{
    rad_scene *s = harness_scene_load("scenes/furnace_cube/cube.obj", NULL);
    if (!s)
        return;
    size_t n = (size_t)rad_scene_triangle_count(s);
    rad_cluster_tree *t = scene_tree(s);
    if (t) {
        const rad_cluster_node *root = rad_cluster_nodes(t);
        double len = sqrt(root->normal[0] * root->normal[0] + root->normal[1] * root->normal[1] +
                          root->normal[2] * root->normal[2]);
        CHECK_MSG(len < 1e-12 && root->cone_cos == -1.0, "closed cube: |mean normal| %g", len);
        int flat = 0;
        for (size_t k = 0; k < rad_cluster_node_count(t); k++) {
            const rad_cluster_node *x = &rad_cluster_nodes(t)[k];
            if (x->count == 1)
                flat += fabs(x->cone_cos - 1.0) < 1e-12;
        }
        CHECK(flat == (int)n);
    }
    rad_cluster_destroy(t);
    rad_scene_destroy(s);
}

/* A room of 64 cubes on a 4 x 4 x 4 grid, none touching: each split is made
 * at a plane between the cubes (cutting only the room's walls), so every
 * cube's 12 triangles are one node, whose box is the cube's own.  A median
 * split cuts cubes in two: their halves' boxes overlap the neighbours'. */
TEST(cluster_keeps_separated_objects_whole)
{
    rad_scene *s = harness_scene_load("scenes/many_objects/many_64.obj", NULL);
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 12 + 64 * 12);
    rad_cluster_tree *t = scene_tree(s);
    if (t) {
        const rad_cluster_node *nd = rad_cluster_nodes(t);
        const int *order = rad_cluster_order(t);
        int whole = 0;
        for (size_t k = 0; k < rad_cluster_node_count(t); k++) {
            const rad_cluster_node *x = &nd[k];
            if (x->count != 12 || order[x->first] < 12)
                continue;
            int cube = (order[x->first] - 12) / 12, same = 1;
            for (int i = x->first; i < x->first + x->count; i++)
                same &= order[i] >= 12 && (order[i] - 12) / 12 == cube;
            whole += same;
        }
        CHECK_MSG(whole == 64, "%d of 64 cubes are one node each", whole);
    }
    rad_cluster_destroy(t);
    rad_scene_destroy(s);
}

/* A unit vector uniform on the cap of angle beta about unit w. */
static rad_vec3 cap_direction(rad_vec3 w, double beta, unsigned long long *s)
{
    double r[2];
    for (int k = 0; k < 2; k++) {
        *s = *s * 6364136223846793005ull + 1442695040888963407ull;
        r[k] = (double)(*s >> 11) * 0x1.0p-53;
    }
    double ct = 1.0 - r[0] * (1.0 - cos(beta)), st = sqrt(fmax(0.0, 1.0 - ct * ct));
    rad_vec3 a = fabs(w.x) < 0.9 ? rad_vec3_make(1, 0, 0) : rad_vec3_make(0, 1, 0);
    rad_vec3 e1 = rad_vec3_cross(w, a);
    e1 = rad_vec3_scale(e1, 1.0 / rad_vec3_norm(e1));
    rad_vec3 e2 = rad_vec3_cross(w, e1);
    double ph = 2.0 * RAD_PI * r[1];
    return rad_vec3_add(rad_vec3_scale(w, ct),
                        rad_vec3_add(rad_vec3_scale(e1, st * cos(ph)), rad_vec3_scale(e2, st * sin(ph))));
}

/* rad_cluster_projected_upper on every node of t against its triangles:
 * with each triangle i seen from its own direction u_i within beta of w,
 * sum_i a_i max(n_i . u_i, 0) and max_i n_i . u_i, each u_i either the
 * cap's direction nearest n_i (angle max(0, theta_i - beta)) or the best of
 * 16 drawn uniformly on the cap; and a node of one triangle at beta 0 gets
 * its exact projected area. */
static void check_projected_upper(const rad_cluster_tree *t, const double *xyz, const int *tri,
                                  unsigned seed)
{
    const rad_cluster_node *nd = rad_cluster_nodes(t);
    const int *order = rad_cluster_order(t);
    const double betas[5] = {0.0, 0.02, 0.3, 1.0, 0.5 * RAD_PI};
    unsigned long long s = seed * 0x9e3779b97f4a7c15ull + 7;
    int bad = 0, loose_leaf = 0;
    double worst = 0.0;
    for (size_t k = 0; k < rad_cluster_node_count(t); k++) {
        const rad_cluster_node *x = &nd[k];
        double len = sqrt(x->normal[0] * x->normal[0] + x->normal[1] * x->normal[1] +
                          x->normal[2] * x->normal[2]);
        double N[3], axis[3];
        for (int a = 0; a < 3; a++) {
            N[a] = x->area * x->normal[a];
            axis[a] = len > 0.0 ? x->normal[a] / len : 0.0;
        }
        double alpha = x->cone_cos >= -1.0 && len > 0.0 ? acos(fmin(1.0, x->cone_cos)) : 4.0;
        for (int b = 0; b < 5; b++) {
            rad_vec3 w = cap_direction(rad_vec3_make(0, 0, 1), RAD_PI, &s);
            const double wv[3] = {w.x, w.y, w.z};
            double cmax = -1.0;
            double U = rad_cluster_projected_upper(x->area, N, axis, alpha, wv, betas[b], &cmax);
            double nearest = 0.0, drawn = 0.0, cos_nearest = 0.0, cos_drawn = 0.0;
            for (int i = x->first; i < x->first + x->count; i++) {
                int tr = order[i];
                rad_vec3 p0 = vertex(xyz, tri, tr, 0), p1 = vertex(xyz, tri, tr, 1),
                         p2 = vertex(xyz, tri, tr, 2);
                rad_vec3 c = rad_vec3_cross(rad_vec3_sub(p1, p0), rad_vec3_sub(p2, p0));
                double a2 = rad_vec3_norm(c);
                rad_vec3 n = rad_vec3_scale(c, 1.0 / a2);
                double th = acos(fmax(-1.0, fmin(1.0, rad_vec3_dot(n, w))));
                double cn = cos(fmax(0.0, th - betas[b])), cd = -1.0;
                for (int j = 0; j < 16; j++)
                    cd = fmax(cd, rad_vec3_dot(n, cap_direction(w, betas[b], &s)));
                nearest += 0.5 * a2 * fmax(0.0, cn);
                drawn += 0.5 * a2 * fmax(0.0, cd);
                cos_nearest = fmax(cos_nearest, cn);
                cos_drawn = fmax(cos_drawn, cd);
            }
            double tol = 1e-12 * x->area;
            if (!(nearest <= U + tol && drawn <= U + tol && cos_nearest <= cmax + 1e-12 &&
                  cos_drawn <= cmax + 1e-12)) {
                if (bad++ < 3)
                    fprintf(stderr, "node %zu (%d triangles), beta %g: bound %.17g, cosmax %.17g; "
                                    "triangles %.17g (drawn %.17g), cos %.17g (drawn %.17g)\n",
                            k, x->count, betas[b], U, cmax, nearest, drawn, cos_nearest, cos_drawn);
            }
            worst = fmax(worst, x->area > 0.0 ? (nearest - U) / x->area : 0.0);
            if (x->count == 1 && b == 0) {
                /* its cone a line (cone_cos may round below 1) */
                double U0 = rad_cluster_projected_upper(x->area, N, axis, 0.0, wv, 0.0, NULL);
                loose_leaf += fabs(U0 - nearest) > 1e-12 * x->area;
            }
        }
    }
    CHECK_MSG(bad == 0, "%d node and direction pairs exceed the bound (worst by %g of the area)",
              bad, worst);
    CHECK_MSG(loose_leaf == 0, "%d one-triangle nodes' bound at beta 0 is not their projected area",
              loose_leaf);
}

TEST(cluster_projected_area_bound_against_the_triangles)
{
    const size_t sizes[2] = {37, 2000};
    for (int c = 0; c < 2; c++) {
        double *xyz;
        int *tri;
        rad_cluster_tree *t = soup_tree(sizes[c], (unsigned)c + 11, 1, &xyz, &tri);
        if (t)
            check_projected_upper(t, xyz, tri, (unsigned)c + 1);
        rad_cluster_destroy(t);
        free(xyz);
        free(tri);
    }
    /* boxes: nodes whose normals spread over the whole sphere (no cone), and
       flat pairs; a closed cube seen along an axis turns a sixth of its area
       towards it, and the bound, (area + |N|) / 2, is half */
    rad_scene *s = harness_scene_load("scenes/many_objects/many_64.obj", NULL);
    if (!s)
        return;
    rad_cluster_tree *t = scene_tree(s);
    if (t)
        check_projected_upper(t, rad_scene_vertices(s), rad_scene_triangles(s), 3);
    rad_cluster_destroy(t);
    rad_scene_destroy(s);
}

TEST(cluster_bad_input_refused)
{
    double xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    int tri[3] = {0, 1, 2}, bad[3] = {0, 1, 3}, same[3] = {0, 1, 1};
    rad_cluster_tree *t = (rad_cluster_tree *)1;
    CHECK(rad_cluster_build(xyz, 3, tri, 0, 1, 1, &t) == RAD_EINVAL && t == NULL);
    CHECK(rad_cluster_build(xyz, 3, tri, 1, 0, 1, &t) == RAD_EINVAL);
    CHECK(rad_cluster_build(xyz, 3, bad, 1, 1, 1, &t) == RAD_EINVAL);
    CHECK(strstr(rad_error_message(), "vertex index 3") != NULL);
    CHECK(rad_cluster_build(xyz, 3, same, 1, 1, 1, &t) == RAD_EINPUT);
    xyz[4] = NAN;
    CHECK(rad_cluster_build(xyz, 3, tri, 1, 1, 1, &t) == RAD_EINPUT);
    CHECK(rad_cluster_build(NULL, 3, tri, 1, 1, 1, &t) == RAD_EINVAL);
    /* among many, on two threads, the first bad triangle is the one named */
    size_t n = 100000;
    double *many = malloc(9 * n * sizeof *many);
    int *idx = malloc(3 * n * sizeof *idx);
    if (!many || !idx) {
        free(many);
        free(idx);
        CHECK(0);
        return;
    }
    random_soup(n, 7, many, idx);
    idx[3 * 90000 + 2] = idx[3 * 90000];         /* degenerate, in the second thread's half */
    many[3 * (size_t)idx[3 * 30000 + 1]] = NAN; /* not finite, in the first's */
    CHECK(rad_cluster_build(many, 3 * n, idx, n, 1, 2, &t) == RAD_EINPUT);
    CHECK_MSG(strstr(rad_error_message(), "triangle 30000 ") != NULL, "%s", rad_error_message());
    many[3 * (size_t)idx[3 * 30000 + 1]] = 0.5;
    CHECK(rad_cluster_build(many, 3 * n, idx, n, 1, 2, &t) == RAD_EINPUT);
    CHECK_MSG(strstr(rad_error_message(), "triangle 90000 is degenerate") != NULL, "%s",
              rad_error_message());
    free(many);
    free(idx);
}
