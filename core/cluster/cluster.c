/* rad_cluster: the bounding-volume hierarchy (rad_cluster.h), each node
 * split at the plane that cuts the fewest triangles, nearest the median.
 * Nodes are made depth-first (a node's left subtree directly follows it),
 * keys sorted with ties broken by triangle index, so the tree depends on the
 * input alone. */
#include "rad_cluster.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rad_geom.h"
#include "rad_sys.h"

struct rad_cluster_tree {
    rad_cluster_node *node;
    size_t nnodes, cap;
    int *order;
    int max_depth;
    double *ends; /* while building: split_at's box ends, two per triangle */
};

typedef struct tri_info {
    rad_vec3 c, n; /* centroid, unit normal */
    double area;
    double lo[3], hi[3];
} tri_info;

typedef struct keyed {
    double key;
    int tri;
} keyed;

static int by_key(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return (x->tri > y->tri) - (x->tri < y->tri);
}

static double axis_of(rad_vec3 v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

/* Fill node k from the triangles order[first .. first + count). */
static void summarize(rad_cluster_node *nd, const tri_info *ti, const int *order, int first,
                      int count)
{
    for (int a = 0; a < 3; a++) {
        nd->lo[a] = INFINITY;
        nd->hi[a] = -INFINITY;
    }
    rad_vec3 sum = {0.0, 0.0, 0.0};
    double area = 0.0;
    for (int i = first; i < first + count; i++) {
        const tri_info *t = &ti[order[i]];
        for (int a = 0; a < 3; a++) {
            nd->lo[a] = rad_dmin(nd->lo[a], t->lo[a]);
            nd->hi[a] = rad_dmax(nd->hi[a], t->hi[a]);
        }
        sum = rad_vec3_add(sum, rad_vec3_scale(t->n, t->area));
        area += t->area;
    }
    nd->area = area;
    rad_vec3 mean = rad_vec3_scale(sum, area > 0.0 ? 1.0 / area : 0.0);
    nd->normal[0] = mean.x;
    nd->normal[1] = mean.y;
    nd->normal[2] = mean.z;
    double len = rad_vec3_norm(mean);
    nd->cone_cos = -1.0;
    if (len > 1e-12) {
        rad_vec3 axis = rad_vec3_scale(mean, 1.0 / len);
        double c = 1.0;
        for (int i = first; i < first + count; i++)
            c = rad_dmin(c, rad_vec3_dot(ti[order[i]].n, axis));
        nd->cone_cos = rad_dmax(-1.0, c);
    }
}

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Where to split count triangles sorted by centroid along axis (order, key):
 * at the plane between two consecutive centroids that cuts the fewest
 * triangles, the one nearest the median among those, within the middle
 * three quarters (SPLIT_SHARE: each side keeps at least an eighth, so the
 * depth stays within log_{8/7} n).  A plane that cuts none leaves the
 * sides' boxes apart; one that cuts only a room's walls keeps the objects
 * between them whole.  The median where no plane separates two centroids
 * or memory is short (lo, room for 2 count box ends, NULL). */
enum { SPLIT_SHARE = 8 };
static int split_at(const tri_info *ti, const keyed *key, int count, int axis, double *lo)
{
    int half = count / 2, first = count / SPLIT_SHARE, last = count - count / SPLIT_SHARE;
    if (first < 1 || !lo)
        return half;
    double *hi = lo + count;
    for (int i = 0; i < count; i++) {
        lo[i] = ti[key[i].tri].lo[axis];
        hi[i] = ti[key[i].tri].hi[axis];
    }
    qsort(lo, (size_t)count, sizeof *lo, by_value);
    qsort(hi, (size_t)count, sizeof *hi, by_value);
    int best = -1, best_cut = INT_MAX, nlo = 0, nhi = 0;
    for (int i = first; i <= last; i++) {
        if (!(key[i - 1].key < key[i].key))
            continue;
        double plane = 0.5 * (key[i - 1].key + key[i].key);
        while (nlo < count && lo[nlo] < plane)
            nlo++;
        while (nhi < count && hi[nhi] <= plane)
            nhi++;
        int cut = nlo - nhi; /* lo < plane < hi */
        if (cut < best_cut || (cut == best_cut && abs(i - half) < abs(best - half))) {
            best_cut = cut;
            best = i;
        }
    }
    return best > 0 ? best : half;
}

static rad_status add_node(rad_cluster_tree *t, int *index)
{
    if (!rad_sys_grow((void **)&t->node, &t->cap, t->nnodes, t->nnodes + 1, sizeof *t->node, 64))
        return RAD_ERROR(RAD_ENOMEM, "cluster: no memory for %zu nodes", t->nnodes + 1);
    *index = (int)t->nnodes++;
    return RAD_OK;
}

static rad_status build(rad_cluster_tree *t, const tri_info *ti, keyed *scratch, int first,
                        int count, int parent, int depth, int leaf_size, int *out)
{
    int k = -1;
    rad_status st = add_node(t, &k);
    if (st != RAD_OK)
        return st;
    *out = k;
    rad_cluster_node *nd = &t->node[k];
    summarize(nd, ti, t->order, first, count);
    nd->first = first;
    nd->count = count;
    nd->parent = parent;
    nd->depth = depth;
    nd->child[0] = nd->child[1] = -1;
    if (depth > t->max_depth)
        t->max_depth = depth;
    if (count <= leaf_size)
        return RAD_OK;
    /* the longest axis of the centroids' box, then the median centroid */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = first; i < first + count; i++)
        for (int a = 0; a < 3; a++) {
            double v = axis_of(ti[t->order[i]].c, a);
            lo[a] = rad_dmin(lo[a], v);
            hi[a] = rad_dmax(hi[a], v);
        }
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (hi[a] - lo[a] > hi[axis] - lo[axis])
            axis = a;
    for (int i = 0; i < count; i++) {
        int tr = t->order[first + i];
        scratch[i] = (keyed){axis_of(ti[tr].c, axis), tr};
    }
    qsort(scratch, (size_t)count, sizeof *scratch, by_key);
    for (int i = 0; i < count; i++)
        t->order[first + i] = scratch[i].tri;
    int half = split_at(ti, scratch, count, axis, t->ends), left, right;
    if ((st = build(t, ti, scratch, first, half, k, depth + 1, leaf_size, &left)) != RAD_OK ||
        (st = build(t, ti, scratch, first + half, count - half, k, depth + 1, leaf_size,
                    &right)) != RAD_OK)
        return st;
    t->node[k].child[0] = left; /* t->node may have moved: index, never keep nd */
    t->node[k].child[1] = right;
    return RAD_OK;
}

rad_status rad_cluster_build(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                             int leaf_size, rad_cluster_tree **out)
{
    if (out)
        *out = NULL;
    if (!xyz || !tri || !out || ntris == 0 || ntris > (size_t)1 << 30 || leaf_size < 1)
        return RAD_ERROR(RAD_EINVAL, "cluster: bad arguments (%zu triangles, leaf size %d)",
                         ntris, leaf_size);
    /* on huge pages, and split_at's buffer made once: a large block's
       4 KB pages fault on their first touch, every time it is allocated */
    tri_info *ti = rad_sys_alloc_huge(ntris * sizeof *ti);
    keyed *scratch = rad_sys_alloc_huge(ntris * sizeof *scratch);
    rad_cluster_tree *t = calloc(1, sizeof *t);
    if (t) {
        t->order = rad_sys_alloc_huge(ntris * sizeof *t->order);
        t->ends = rad_sys_alloc_huge(2 * ntris * sizeof *t->ends); /* NULL: median splits */
    }
    rad_status st = RAD_OK;
    if (!ti || !scratch || !t || !t->order) {
        st = RAD_ERROR(RAD_ENOMEM, "cluster: no memory for %zu triangles", ntris);
        goto fail;
    }
    for (size_t k = 0; k < ntris; k++) {
        rad_vec3 p[3];
        for (int v = 0; v < 3; v++) {
            int i = tri[3 * k + (size_t)v];
            if (i < 0 || (size_t)i >= nverts) {
                st = RAD_ERROR(RAD_EINVAL, "cluster: triangle %zu has vertex index %d, outside "
                                           "0..%zu", k, i, nverts - 1);
                goto fail;
            }
            p[v] = rad_vec3_make(xyz[3 * (size_t)i], xyz[3 * (size_t)i + 1], xyz[3 * (size_t)i + 2]);
            if (!rad_vec3_is_finite(p[v])) {
                st = RAD_ERROR(RAD_EINPUT, "cluster: triangle %zu has a non-finite coordinate", k);
                goto fail;
            }
        }
        tri_info *x = &ti[k];
        x->area = rad_geom_triangle_area(p[0], p[1], p[2]);
        if (!(x->area > 0.0)) {
            st = RAD_ERROR(RAD_EINPUT, "cluster: triangle %zu is degenerate (zero area)", k);
            goto fail;
        }
        x->n = rad_geom_triangle_normal(p[0], p[1], p[2]);
        x->c = rad_geom_triangle_centroid(p[0], p[1], p[2]);
        for (int a = 0; a < 3; a++) {
            x->lo[a] = rad_dmin(axis_of(p[0], a), rad_dmin(axis_of(p[1], a), axis_of(p[2], a)));
            x->hi[a] = rad_dmax(axis_of(p[0], a), rad_dmax(axis_of(p[1], a), axis_of(p[2], a)));
        }
        t->order[k] = (int)k;
    }
    int root = -1;
    if ((st = build(t, ti, scratch, 0, (int)ntris, -1, 0, leaf_size, &root)) != RAD_OK)
        goto fail;
    free(ti);
    free(scratch);
    free(t->ends);
    t->ends = NULL;
    *out = t;
    return RAD_OK;
fail:
    free(ti);
    free(scratch);
    rad_cluster_destroy(t);
    return st;
}

void rad_cluster_destroy(rad_cluster_tree *t)
{
    if (!t)
        return;
    free(t->node);
    free(t->order);
    free(t->ends);
    free(t);
}

size_t rad_cluster_node_count(const rad_cluster_tree *t) { return t ? t->nnodes : 0; }
const rad_cluster_node *rad_cluster_nodes(const rad_cluster_tree *t) { return t ? t->node : NULL; }
const int *rad_cluster_order(const rad_cluster_tree *t) { return t ? t->order : NULL; }
int rad_cluster_max_depth(const rad_cluster_tree *t) { return t ? t->max_depth : 0; }
