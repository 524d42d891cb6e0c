/* rad_cluster: the bounding-volume hierarchy (rad_cluster.h), each node
 * split at the plane that cuts the fewest triangles, nearest the median.
 * Nodes are made depth-first (a node's left subtree directly follows it),
 * keys sorted with ties broken by triangle index, so the tree depends on the
 * input alone.  The triangles are sorted once, per axis, by centroid and by
 * each end of their boxes (a stable radix sort), and each split partitions
 * those nine orders stably: every node finds its triangles already sorted,
 * and the build costs O(n log n), not a sort per node. */
#include "rad_cluster.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <stdint.h>
#include <string.h>

#include "rad_geom.h"
#include "rad_sys.h"

struct rad_cluster_tree {
    rad_cluster_node *node;
    size_t nnodes, cap;
    int *order;
    int max_depth;
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

/* An order-preserving image of a finite double as an unsigned integer
 * (-0 taken as +0, which compares equal to it). */
static uint64_t sortable(double x)
{
    uint64_t u;
    x += 0.0;
    memcpy(&u, &x, sizeof u);
    return u >> 63 ? ~u : u | (uint64_t)1 << 63;
}

/* Sort a[0..n) by key, stably (least significant 16 bits first), using tmp
 * (n entries): entries in triangle order come out sorted by (key, tri). */
static int sort_keyed(keyed *a, keyed *tmp, size_t n)
{
    size_t *count = malloc(65536 * sizeof *count);
    if (!count)
        return 0;
    for (int shift = 0; shift < 64; shift += 16) {
        memset(count, 0, 65536 * sizeof *count);
        for (size_t i = 0; i < n; i++)
            count[(sortable(a[i].key) >> shift) & 0xffff]++;
        size_t sum = 0;
        for (size_t d = 0; d < 65536; d++) {
            size_t c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (size_t i = 0; i < n; i++)
            tmp[count[(sortable(a[i].key) >> shift) & 0xffff]++] = a[i];
        keyed *swap = a;
        a = tmp;
        tmp = swap;
    }
    free(count); /* four passes: the sorted entries are back in a */
    return 1;
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

/* Where to split count triangles sorted by centroid along axis (cen: their
 * order; lo and hi: the same triangles ordered by their boxes' ends): at the
 * plane between two consecutive centroids that cuts the fewest triangles,
 * the one nearest the median among those, within the middle three quarters
 * (SPLIT_SHARE: each side keeps at least an eighth, so the depth stays
 * within log_{8/7} n).  A plane that cuts none leaves the sides' boxes
 * apart; one that cuts only a room's walls keeps the objects between them
 * whole.  The median where no plane separates two centroids. */
enum { SPLIT_SHARE = 8 };
static int split_at(const tri_info *ti, const int *cen, const int *lo, const int *hi, int count,
                    int axis)
{
    int half = count / 2, first = count / SPLIT_SHARE, last = count - count / SPLIT_SHARE;
    if (first < 1)
        return half;
    int best = -1, best_cut = INT_MAX, nlo = 0, nhi = 0;
    for (int i = first; i <= last; i++) {
        double before = axis_of(ti[cen[i - 1]].c, axis), at = axis_of(ti[cen[i]].c, axis);
        if (!(before < at))
            continue;
        double plane = 0.5 * (before + at);
        while (nlo < count && ti[lo[nlo]].lo[axis] < plane)
            nlo++;
        while (nhi < count && ti[hi[nhi]].hi[axis] <= plane)
            nhi++;
        int cut = nlo - nhi; /* lo < plane < hi */
        if (cut < best_cut || (cut == best_cut && abs(i - half) < abs(best - half))) {
            best_cut = cut;
            best = i;
        }
    }
    return best > 0 ? best : half;
}

/* The builder's state: ord[3 k + a] holds the triangles ordered along axis a
 * by centroid (k = 0), by their boxes' low end (1) and high end (2), each
 * node's triangles a contiguous range of each; left marks the side of a
 * split, tmp its partition's buffer (a node uses its own range of it).
 * BUILD_TASK_MIN: the smallest subtree made as a task of its own. */
enum { ORDERS = 9, BUILD_TASK_MIN = 1024 };
typedef struct build_ctx {
    rad_cluster_tree *t;
    const tri_info *ti;
    int *ord[ORDERS];
    int *tmp;
    unsigned char *left;
    int leaf_size;
} build_ctx;

/* Sort the nine orders (ties by triangle index), on threads threads; 0 when
 * out of memory. */
static int sort_orders(build_ctx *bc, size_t n, int threads)
{
    int ok = 1;
#pragma omp parallel num_threads(threads) if (n > 65536) reduction(&& : ok)
    {
        keyed *a = malloc(2 * n * sizeof *a);
        ok = a != NULL;
#pragma omp for schedule(dynamic, 1)
        for (int o = 0; o < ORDERS; o++) {
            int kind = o / 3, axis = o % 3;
            for (size_t i = 0; a && i < n; i++) {
                const tri_info *x = &bc->ti[i];
                a[i].key = kind == 0 ? axis_of(x->c, axis) : kind == 1 ? x->lo[axis] : x->hi[axis];
                a[i].tri = (int)i;
            }
            if (!a || !sort_keyed(a, a + n, n)) {
                ok = 0;
                continue;
            }
            for (size_t i = 0; i < n; i++)
                bc->ord[o][i] = a[i].tri;
        }
        free(a);
    }
    return ok;
}

/* Partition each order's range [first, first + count) stably into the
 * triangles marked left, then the others (the split axis's centroid order,
 * skip, is already). */
static void partition(build_ctx *bc, int first, int count, int skip)
{
    for (int o = 0; o < ORDERS; o++) {
        if (o == skip)
            continue;
        int *r = bc->ord[o] + first, nl = 0, nr = 0;
        for (int i = 0; i < count; i++) {
            if (bc->left[r[i]])
                r[nl++] = r[i];
            else
                bc->tmp[first + nr++] = r[i];
        }
        memcpy(r + nl, bc->tmp + first, (size_t)nr * sizeof *r);
    }
}

/* The nodes a subtree of count triangles may hold at most (leaves of one
 * triangle): where each subtree's nodes start is known before its sibling's
 * are made, so the two are made at once. */
static size_t most_nodes(int count) { return 2 * (size_t)count - 1; }

/* Node k for the triangles [first, first + count) of every order, its left
 * subtree from k + 1 and its right one from k + 1 + most_nodes(left's
 * count) (slots a subtree does not use stay empty: count 0); they are
 * summed in the order their parent split them (by = the centroid order
 * along its axis; the input order at the root), as sorting them there left
 * them.  A large subtree's left half is a task of its own: the two halves
 * touch disjoint ranges of every order, of tmp and of the nodes, and
 * disjoint triangles' marks. */
static void build(build_ctx *bc, const int *by, int first, int count, size_t k, int parent,
                  int depth)
{
    rad_cluster_tree *t = bc->t;
    const tri_info *ti = bc->ti;
    rad_cluster_node *nd = &t->node[k];
    summarize(nd, ti, by, first, count);
    nd->first = first;
    nd->count = count;
    nd->parent = parent;
    nd->depth = depth;
    nd->child[0] = nd->child[1] = -1;
    if (count <= bc->leaf_size) {
        if (by != t->order)
            memcpy(t->order + first, by + first, (size_t)count * sizeof *t->order);
        return;
    }
    /* the longest axis of the centroids' box, then the median centroid */
    int axis = 0;
    double extent[3];
    for (int a = 0; a < 3; a++) {
        const int *c = bc->ord[a] + first;
        extent[a] = axis_of(ti[c[count - 1]].c, a) - axis_of(ti[c[0]].c, a);
    }
    for (int a = 1; a < 3; a++)
        if (extent[a] > extent[axis])
            axis = a;
    const int *cen = bc->ord[axis] + first;
    int half = split_at(ti, cen, bc->ord[3 + axis] + first, bc->ord[6 + axis] + first, count, axis);
    for (int i = 0; i < count; i++)
        bc->left[cen[i]] = i < half;
    partition(bc, first, count, axis);
    size_t left = k + 1, right = left + most_nodes(half);
    nd->child[0] = (int)left;
    nd->child[1] = (int)right;
#pragma omp task if (half > BUILD_TASK_MIN) default(none) firstprivate(bc, axis, first, half, left, k, depth)
    build(bc, bc->ord[axis], first, half, left, (int)k, depth + 1);
    build(bc, bc->ord[axis], first + half, count - half, right, (int)k, depth + 1);
#pragma omp taskwait
}

/* Close the gaps build left (leaf_size > 1), keeping the nodes' order, and
 * find the depth. */
static void compact(rad_cluster_tree *t, size_t slots, int *index)
{
    size_t used = 0;
    for (size_t k = 0; k < slots; k++)
        index[k] = t->node[k].count > 0 ? (int)used++ : -1;
    t->max_depth = 0;
    for (size_t k = 0; k < slots; k++) {
        if (index[k] < 0)
            continue;
        rad_cluster_node nd = t->node[k];
        for (int c = 0; c < 2; c++)
            if (nd.child[c] >= 0)
                nd.child[c] = index[nd.child[c]];
        if (nd.parent >= 0)
            nd.parent = index[nd.parent];
        if (nd.depth > t->max_depth)
            t->max_depth = nd.depth;
        t->node[index[k]] = nd;
    }
    t->nnodes = used;
}

/* Triangle k's tri_info into *x: 0, or what is wrong with it (1: a vertex
 * index out of range, 2: a coordinate not finite, 3: no area). */
static int tri_fill(const double *xyz, size_t nverts, const int *tri, size_t k, tri_info *x)
{
    rad_vec3 p[3];
    for (int v = 0; v < 3; v++) {
        int i = tri[3 * k + (size_t)v];
        if (i < 0 || (size_t)i >= nverts)
            return 1;
        p[v] = rad_vec3_make(xyz[3 * (size_t)i], xyz[3 * (size_t)i + 1], xyz[3 * (size_t)i + 2]);
        if (!rad_vec3_is_finite(p[v]))
            return 2;
    }
    x->area = rad_geom_triangle_area(p[0], p[1], p[2]);
    if (!(x->area > 0.0))
        return 3;
    x->n = rad_geom_triangle_normal(p[0], p[1], p[2]);
    x->c = rad_geom_triangle_centroid(p[0], p[1], p[2]);
    for (int a = 0; a < 3; a++) {
        x->lo[a] = rad_dmin(axis_of(p[0], a), rad_dmin(axis_of(p[1], a), axis_of(p[2], a)));
        x->hi[a] = rad_dmax(axis_of(p[0], a), rad_dmax(axis_of(p[1], a), axis_of(p[2], a)));
    }
    return 0;
}

rad_status rad_cluster_build(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                             int leaf_size, int threads, rad_cluster_tree **out)
{
    if (out)
        *out = NULL;
    if (!xyz || !tri || !out || ntris == 0 || ntris > (size_t)1 << 30 || leaf_size < 1)
        return RAD_ERROR(RAD_EINVAL, "cluster: bad arguments (%zu triangles, leaf size %d)",
                         ntris, leaf_size);
    threads = threads > 1 ? threads : 1;
    size_t slots = most_nodes((int)ntris);
    /* on huge pages: a large block's 4 KB pages fault on their first touch */
    tri_info *ti = rad_sys_alloc_huge(ntris * sizeof *ti);
    int *work = rad_sys_alloc_huge((ORDERS + 1) * ntris * sizeof *work + ntris);
    int *index = malloc(slots * sizeof *index);
    rad_cluster_tree *t = calloc(1, sizeof *t);
    if (t)
        t->order = rad_sys_alloc_huge(ntris * sizeof *t->order);
    rad_status st = RAD_OK;
    if (!ti || !work || !index || !t || !t->order) {
        st = RAD_ERROR(RAD_ENOMEM, "cluster: no memory for %zu triangles", ntris);
        goto fail;
    }
    /* the first triangle with a problem is the one named, on any thread count */
    size_t bad = ntris;
#pragma omp parallel for schedule(static) num_threads(threads) if (ntris > 65536) reduction(min : bad)
    for (size_t k = 0; k < ntris; k++) {
        if (tri_fill(xyz, nverts, tri, k, &ti[k]) && k < bad)
            bad = k;
        t->order[k] = (int)k;
    }
    if (bad < ntris) {
        int i = -1;
        switch (tri_fill(xyz, nverts, tri, bad, &ti[bad])) {
        case 1:
            for (int v = 0; v < 3; v++)
                if (tri[3 * bad + (size_t)v] < 0 || (size_t)tri[3 * bad + (size_t)v] >= nverts)
                    i = i < 0 ? tri[3 * bad + (size_t)v] : i;
            st = RAD_ERROR(RAD_EINVAL, "cluster: triangle %zu has vertex index %d, outside "
                                       "0..%zu", bad, i, nverts - 1);
            break;
        case 2:
            st = RAD_ERROR(RAD_EINPUT, "cluster: triangle %zu has a non-finite coordinate", bad);
            break;
        default:
            st = RAD_ERROR(RAD_EINPUT, "cluster: triangle %zu is degenerate (zero area)", bad);
        }
        goto fail;
    }
    build_ctx bc = {t, ti, {NULL}, work + ORDERS * ntris, (unsigned char *)(work + (ORDERS + 1) * ntris),
                    leaf_size};
    for (int o = 0; o < ORDERS; o++)
        bc.ord[o] = work + (size_t)o * ntris;
    /* a binary tree over n triangles has at most 2 n - 1 nodes: held from
       the start, so that no node is ever copied into a grown block */
    if (!rad_sys_grow((void **)&t->node, &t->cap, 0, slots, sizeof *t->node, 64)) {
        st = RAD_ERROR(RAD_ENOMEM, "cluster: no memory for %zu nodes", slots);
        goto fail;
    }
    if (leaf_size > 1) /* slots a subtree leaves unused are known by their count */
        for (size_t k = 0; k < slots; k++)
            t->node[k].count = 0;
    if (!sort_orders(&bc, ntris, threads)) {
        st = RAD_ERROR(RAD_ENOMEM, "cluster: no memory to sort %zu triangles", ntris);
        goto fail;
    }
#pragma omp parallel num_threads(threads) if (ntris > BUILD_TASK_MIN)
#pragma omp single
    build(&bc, t->order, 0, (int)ntris, 0, -1, 0);
    compact(t, slots, index);
    free(index);
    free(ti);
    free(work);
    *out = t;
    return RAD_OK;
fail:
    free(index);
    free(ti);
    free(work);
    rad_cluster_destroy(t);
    return st;
}

void rad_cluster_destroy(rad_cluster_tree *t)
{
    if (!t)
        return;
    free(t->node);
    free(t->order);
    free(t);
}

size_t rad_cluster_node_count(const rad_cluster_tree *t) { return t ? t->nnodes : 0; }
const rad_cluster_node *rad_cluster_nodes(const rad_cluster_tree *t) { return t ? t->node : NULL; }
const int *rad_cluster_order(const rad_cluster_tree *t) { return t ? t->order : NULL; }
int rad_cluster_max_depth(const rad_cluster_tree *t) { return t ? t->max_depth : 0; }
