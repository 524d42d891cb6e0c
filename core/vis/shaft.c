/* rad_vis: tests that prove a pair (or the whole scene) needs no rays.
 *
 * Shaft test of a pair (i, j), after Haines and Wallace's shaft culling
 * \cite{haines1994shaft}, with the shaft taken as the exact convex hull of the
 * two triangles:
 * 1. Every segment from a point of i to a point of j lies in the convex hull H
 *    of their six vertices.  A face plane of H contains three of the six points
 *    and has all six on one side; it is therefore the plane of i, the plane of
 *    j, or a plane through an edge of one triangle and a vertex of the other:
 *    20 candidates.  Keep each candidate (oriented outward) whose six points all
 *    lie on its inner side within tol; the kept planes bound H exactly.  The
 *    pair's bounding box is tested first: redundant for H, but it rejects most
 *    hierarchy nodes with six comparisons.
 * 2. A segment joining interior points of i and j meets a face plane of H only
 *    at its end points unless both triangles lie in that plane (a coplanar pair:
 *    then no plane is kept and the test answers 1).  So a
 *    triangle k whose three vertices lie on or outside one kept plane (signed
 *    distance >= -tol) cannot cross the open segment: it is dismissed.
 *    Only segments along which the form-factor kernel is positive matter to
 *    the callers: such a segment's ends lie strictly in front of each
 *    other's plane, so the open segment lies in front of both, and the
 *    planes of i and j (outside = behind) are kept too, first: they dismiss
 *    i's and j's own objects, which a walk meets most.  (rad_vis_pair_fraction
 *    counts every segment and walks without them.)
 * 3. Walk a bounding-volume hierarchy of the boxes of the potential blockers
 *    (below; split along the longest axis of the centroids by the binned
 *    surface-area heuristic, which keeps nodes' boxes from overlapping where
 *    a median would cut an object in two, leaves of at most 4): a node
 *    whose box lies on or outside one kept plane is skipped whole; the first
 *    triangle of a leaf other than i and j that is not dismissed makes the
 *    answer 1.  The pair's box is tested against the root's box before any
 *    plane is built: most pairs of a room never come near its furniture.
 * Cost: O(1) for pairs away from every blocker, O(log n) nodes for pairs with
 * nothing near their shaft, O(n) at worst.
 *
 * Which triangles can block at all: a triangle k whose plane has every vertex
 * of the scene on one side (within tol) lies on the scene's convex hull, and a
 * segment between two points of the scene stays in that closed half-space and
 * touches k's plane at most at an end point: k blocks nothing.  The walls,
 * floor and ceiling of a room are such triangles; only the furniture is left
 * in the hierarchy.  When every plane has every vertex in front (a convex
 * enclosure seen from inside: the effects plan's "no occlusion") the whole
 * scene is unoccluded.  Coplanar triangles share a plane, so the distinct
 * planes are checked (a refined room has a handful); if their count times the
 * vertex count exceeds a work budget every triangle is kept as a possible
 * blocker and the scene counts as occluded, the conservative answers. */
#include "vis_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { LEAF_SIZE = 4 };

/* rad_dmin/rad_dmax: the inputs here are finite (checked in rad_vis_create). */

/* ---- bounding-volume hierarchy over triangle boxes -------------------------- */

typedef struct build_ctx {
    rad_vis *vis;
    double *cen; /* centroids, 3 per triangle */
    double *box; /* boxes, 6 per triangle (low corner, high corner): read at every level */
    int cap;
} build_ctx;

static void box_of(const rad_vis *vis, size_t t, double *box)
{
    for (int c = 0; c < 3; c++) {
        box[c] = INFINITY;
        box[3 + c] = -INFINITY;
    }
    for (int v = 0; v < 3; v++) {
        const double *p = vis->xyz + 3 * (size_t)vis->tri[3 * t + (size_t)v];
        for (int c = 0; c < 3; c++) {
            box[c] = rad_dmin(box[c], p[c]);
            box[3 + c] = rad_dmax(box[3 + c], p[c]);
        }
    }
}

/* Partial sort of order[first..first+count) so that the element at the middle
 * has the median centroid coordinate on `axis` (quickselect, deterministic). */
static void select_median(int *order, const double *cen, int axis, int first, int count)
{
    int lo = first, hi = first + count - 1, mid = first + count / 2;
    while (lo < hi) {
        double pivot = cen[3 * order[(lo + hi) / 2] + axis];
        int a = lo, b = hi;
        while (a <= b) {
            while (cen[3 * order[a] + axis] < pivot)
                a++;
            while (cen[3 * order[b] + axis] > pivot)
                b--;
            if (a <= b) {
                int tmp = order[a];
                order[a] = order[b];
                order[b] = tmp;
                a++;
                b--;
            }
        }
        if (mid <= b)
            hi = b;
        else if (mid >= a)
            lo = a;
        else
            break;
    }
}

/* SAH_BINS candidate planes per split; from depth SAH_DEPTH on, medians */
enum { SAH_BINS = 16, SAH_DEPTH = 64 };

static double box_half_area(const double lo[3], const double hi[3])
{
    double d[3];
    for (int c = 0; c < 3; c++)
        d[c] = hi[c] > lo[c] ? hi[c] - lo[c] : 0.0;
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* Binned surface-area split of order[first..first+count) along axis (the
 * centroids span [clo, chi]): the triangles are partitioned, the left count
 * returned; 0 where no bin boundary separates them. */
static int sah_split(const build_ctx *bc, int axis, int first, int count, double clo, double chi)
{
    const rad_vis *vis = bc->vis;
    const double *cen = bc->cen;
    if (!(chi > clo))
        return 0;
    int n[SAH_BINS] = {0};
    double blo[SAH_BINS][3], bhi[SAH_BINS][3];
    for (int b = 0; b < SAH_BINS; b++)
        for (int c = 0; c < 3; c++) {
            blo[b][c] = INFINITY;
            bhi[b][c] = -INFINITY;
        }
    double scale = SAH_BINS / (chi - clo);
    if (!isfinite(scale))
        return 0; /* centroids a few ulps apart: no bins to tell them */
    for (int k = first; k < first + count; k++) {
        int t = vis->order[k];
        int b = (int)((cen[3 * t + axis] - clo) * scale);
        b = b < 0 ? 0 : b >= SAH_BINS ? SAH_BINS - 1 : b;
        const double *box = bc->box + 6 * (size_t)t;
        n[b]++;
        for (int c = 0; c < 3; c++) {
            blo[b][c] = rad_dmin(blo[b][c], box[c]);
            bhi[b][c] = rad_dmax(bhi[b][c], box[3 + c]);
        }
    }
    double right_area[SAH_BINS];
    int right_n[SAH_BINS];
    double rlo[3] = {INFINITY, INFINITY, INFINITY}, rhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    int rn = 0;
    for (int b = SAH_BINS - 1; b > 0; b--) {
        rn += n[b];
        for (int c = 0; c < 3; c++) {
            rlo[c] = rad_dmin(rlo[c], blo[b][c]);
            rhi[c] = rad_dmax(rhi[c], bhi[b][c]);
        }
        right_n[b] = rn;
        right_area[b] = box_half_area(rlo, rhi);
    }
    double llo[3] = {INFINITY, INFINITY, INFINITY}, lhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    int ln = 0, best = 0;
    double best_cost = INFINITY;
    for (int b = 1; b < SAH_BINS; b++) {
        ln += n[b - 1];
        for (int c = 0; c < 3; c++) {
            llo[c] = rad_dmin(llo[c], blo[b - 1][c]);
            lhi[c] = rad_dmax(lhi[c], bhi[b - 1][c]);
        }
        if (ln == 0 || right_n[b] == 0)
            continue;
        double cost = ln * box_half_area(llo, lhi) + right_n[b] * right_area[b];
        if (cost < best_cost) {
            best_cost = cost;
            best = b;
        }
    }
    if (best == 0)
        return 0;
    int i = first, j = first + count - 1;
    while (i <= j) {
        int t = vis->order[i];
        int b = (int)((cen[3 * t + axis] - clo) * scale);
        b = b < 0 ? 0 : b >= SAH_BINS ? SAH_BINS - 1 : b;
        if (b < best)
            i++;
        else {
            vis->order[i] = vis->order[j];
            vis->order[j--] = t;
        }
    }
    return i - first;
}

static int build_node(build_ctx *bc, int first, int count, int depth)
{
    rad_vis *vis = bc->vis;
    int id = vis->nnodes++;
    vis_node *node = &vis->nodes[id];
    double clo[3] = {INFINITY, INFINITY, INFINITY}, chi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int c = 0; c < 3; c++) {
        node->lo[c] = INFINITY;
        node->hi[c] = -INFINITY;
    }
    for (int k = first; k < first + count; k++) {
        const double *box = bc->box + 6 * (size_t)vis->order[k];
        for (int c = 0; c < 3; c++) {
            node->lo[c] = rad_dmin(node->lo[c], box[c]);
            node->hi[c] = rad_dmax(node->hi[c], box[3 + c]);
            clo[c] = rad_dmin(clo[c], bc->cen[3 * vis->order[k] + c]);
            chi[c] = rad_dmax(chi[c], bc->cen[3 * vis->order[k] + c]);
        }
    }
    node->first = first;
    node->count = count;
    node->left = node->right = -1;
    if (count <= LEAF_SIZE)
        return id;
    int axis = 0;
    for (int c = 1; c < 3; c++)
        if (chi[c] - clo[c] > chi[axis] - clo[axis])
            axis = c;
    /* below SAH_DEPTH, median splits: the depth (the recursion's and the
       walk's stack) stays under SAH_DEPTH + log2 n whatever the heuristic did */
    int half = depth < SAH_DEPTH ? sah_split(bc, axis, first, count, clo[axis], chi[axis]) : 0;
    if (half <= 0 || half >= count) {
        select_median(vis->order, bc->cen, axis, first, count);
        half = count / 2;
    }
    int left = build_node(bc, first, half, depth + 1);
    int right = build_node(bc, first + half, count - half, depth + 1);
    /* build_node may not reallocate: nodes was sized for the worst case. */
    vis->nodes[id].left = left;
    vis->nodes[id].right = right;
    return id;
}

static int cmp_plane(const void *a, const void *b)
{
    const double *x = a, *y = b;
    for (int c = 0; c < 4; c++)
        if (x[c] != y[c])
            return x[c] < y[c] ? -1 : 1;
    return 0;
}

/* Whether the m planes pl (5 doubles each, cmp_plane's 4 first) hold more
 * than `most` distinct ones, found with a hash set that stops there: a
 * large scene has far more planes than the budget lets it test, and need
 * not sort them to learn it.  -1 when out of memory. */
static int planes_exceed(const double *pl, size_t m, size_t most)
{
    size_t cap = 16;
    while (cap < 2 * (most + 1))
        cap *= 2;
    size_t *slot = malloc(cap * sizeof *slot); /* index + 1 into pl, 0: empty */
    if (!slot)
        return -1;
    memset(slot, 0, cap * sizeof *slot);
    size_t distinct = 0;
    int over = 0;
    for (size_t k = 0; k < m && !over; k++) {
        const double *x = pl + 5 * k;
        uint64_t hash = 0;
        for (int c = 0; c < 4; c++) {
            double v = x[c] + 0.0; /* -0 as +0: cmp_plane takes them as equal */
            uint64_t bits;
            memcpy(&bits, &v, sizeof bits);
            hash = rad_sys_mix64(hash ^ bits);
        }
        size_t i = (size_t)hash & (cap - 1);
        while (slot[i] && cmp_plane(pl + 5 * (slot[i] - 1), x) != 0)
            i = (i + 1) & (cap - 1);
        if (!slot[i]) {
            slot[i] = k + 1;
            over = ++distinct > most;
        }
    }
    free(slot);
    return over;
}

/* Mark never_blocks[t] for triangles on a supporting plane of the scene, and
 * set vis->unoccluded when every plane has the whole scene in front.  Returns 0
 * on allocation failure. */
static int classify_planes(rad_vis *vis, unsigned char *never_blocks)
{
    size_t n = vis->ntris;
    vis->unoccluded = 1;
    memset(never_blocks, 0, n);
    /* Each triangle's plane (unit normal, offset) rounded to group coplanar
     * ones, and the triangle: 5 doubles a record. */
    double *pl = malloc(5 * n * sizeof *pl);
    if (!pl)
        return 0;
    size_t m = 0;
    const double quantum = 1e-9; /* relative rounding that merges equal planes */
    for (size_t t = 0; t < n; t++) {
        rad_vec3 a = vis_vertex(vis, t, 0), b = vis_vertex(vis, t, 1), c = vis_vertex(vis, t, 2);
        rad_vec3 nn = rad_geom_triangle_normal(a, b, c);
        if (rad_vec3_norm(nn) == 0.0) {
            never_blocks[t] = 1; /* a degenerate triangle blocks nothing of positive measure */
            continue;
        }
        double d = rad_vec3_dot(nn, a) / vis->scale;
        pl[5 * m + 0] = round(nn.x / quantum) * quantum;
        pl[5 * m + 1] = round(nn.y / quantum) * quantum;
        pl[5 * m + 2] = round(nn.z / quantum) * quantum;
        pl[5 * m + 3] = round(d / quantum) * quantum;
        pl[5 * m + 4] = (double)t;
        m++;
    }
    const double budget = 4e8; /* plane-vertex tests we are willing to spend */
    /* the most distinct planes the budget tests against every vertex */
    double most = vis->nverts ? floor(budget / (double)vis->nverts) : (double)m;
    int over = most < (double)m ? planes_exceed(pl, m, (size_t)most) : 0;
    if (over < 0) {
        free(pl);
        return 0;
    }
    if (over) {
        vis->unoccluded = 0;
        free(pl);
        return 1;
    }
    qsort(pl, m, 5 * sizeof *pl, cmp_plane);
    /* The rounded plane is within ~1e-9 L of the true one, far inside 1e3 tol. */
    double slack = vis->tol + 4.0 * quantum * vis->scale;
    for (size_t k = 0; k < m;) {
        size_t end = k + 1;
        while (end < m && cmp_plane(pl + 5 * end, pl + 5 * k) == 0)
            end++;
        rad_vec3 nn = rad_vec3_make(pl[5 * k], pl[5 * k + 1], pl[5 * k + 2]);
        double d = pl[5 * k + 3] * vis->scale, lo = INFINITY, hi = -INFINITY;
        for (size_t v = 0; v < vis->nverts; v++) {
            const double *x = vis->xyz + 3 * v;
            double s = nn.x * x[0] + nn.y * x[1] + nn.z * x[2] - d;
            lo = rad_dmin(lo, s);
            hi = rad_dmax(hi, s);
        }
        if (lo < -slack)
            vis->unoccluded = 0;
        if (lo >= -slack || hi <= slack)
            for (size_t q = k; q < end; q++)
                never_blocks[(size_t)pl[5 * q + 4]] = 1;
        k = end;
    }
    free(pl);
    return 1;
}

int vis_bvh_build(rad_vis *vis)
{
    size_t n = vis->ntris;
    vis->nnodes = 0;
    vis->unoccluded = 1;
    if (n == 0)
        return 1;
    /* A median-split tree with leaves of >= 1 triangle has fewer than 2n nodes. */
    vis->nodes = malloc(2 * n * sizeof *vis->nodes);
    vis->order = malloc(n * sizeof *vis->order);
    double *cen = malloc(9 * n * sizeof *cen), *box = cen ? cen + 3 * n : NULL;
    unsigned char *never = malloc(n);
    if (!vis->nodes || !vis->order || !cen || !never || !classify_planes(vis, never)) {
        free(cen);
        free(never);
        return 0;
    }
    size_t blockers = 0;
    for (size_t t = 0; t < n; t++) {
        if (never[t])
            continue;
        vis->order[blockers++] = (int)t;
        for (int c = 0; c < 3; c++)
            cen[3 * t + c] = (vis->xyz[3 * (size_t)vis->tri[3 * t] + c] +
                              vis->xyz[3 * (size_t)vis->tri[3 * t + 1] + c] +
                              vis->xyz[3 * (size_t)vis->tri[3 * t + 2] + c]) / 3.0;
        box_of(vis, t, box + 6 * t);
    }
    vis->blockers = blockers;
    if (blockers > 0) {
        build_ctx bc = {vis, cen, box, (int)(2 * blockers)};
        build_node(&bc, 0, (int)blockers, 0);
    }
    free(cen);
    free(never);
    return 1;
}

/* ---- the shaft of a pair ---------------------------------------------------- */

typedef struct plane {
    rad_vec3 n; /* outward unit normal */
    double d;   /* signed distance of x: dot(n, x) - d */
} plane;

enum { MAX_PLANES = 22 };

/* Try the plane through a, b, c as a face of the hull of pts[6]. */
static void try_plane(rad_vec3 a, rad_vec3 b, rad_vec3 c, const rad_vec3 pts[6], double tol,
                      plane *out, int *count)
{
    rad_vec3 n = rad_vec3_cross(rad_vec3_sub(b, a), rad_vec3_sub(c, a));
    double len = rad_vec3_norm(n);
    if (!(len > 0.0))
        return;
    n = rad_vec3_scale(n, 1.0 / len);
    double d = rad_vec3_dot(n, a), smin = INFINITY, smax = -INFINITY;
    for (int k = 0; k < 6; k++) {
        double s = rad_vec3_dot(n, pts[k]) - d;
        smin = rad_dmin(smin, s);
        smax = rad_dmax(smax, s);
    }
    if (smax <= tol && smin >= -tol)
        return; /* all six in the plane: the hull is flat, this plane bounds nothing */
    if (smax <= tol) {
        /* all on the negative side: n already points outward */
    } else if (smin >= -tol) {
        n = rad_vec3_scale(n, -1.0);
        d = -d;
    } else {
        return; /* points on both sides: not a hull face */
    }
    out[(*count)++] = (plane){n, d};
}

/* The kept face planes of the hull of the triangles pts[0..2] and pts[3..5]
 * (the caller has the pair's bounding box already); -1 when none is kept (a
 * coplanar pair). */
static int shaft_planes(const rad_vis *vis, const rad_vec3 pts[6], plane *pl)
{
    int count = 0;
    try_plane(pts[0], pts[1], pts[2], pts, vis->tol, pl, &count);
    try_plane(pts[3], pts[4], pts[5], pts, vis->tol, pl, &count);
    for (int side = 0; side < 2; side++) {
        const rad_vec3 *e = pts + 3 * side, *o = pts + 3 * (1 - side);
        for (int k = 0; k < 3; k++)
            for (int v = 0; v < 3; v++)
                try_plane(e[k], e[(k + 1) % 3], o[v], pts, vis->tol, pl, &count);
    }
    return count == 0 ? -1 : count;
}

/* Nonzero when a box [blo, bhi] touches the pair's box [lo, hi] at most
 * within tol, i.e. lies on or outside one of its six planes. */
static int boxes_apart(const double blo[3], const double bhi[3], const double lo[3],
                       const double hi[3], double tol)
{
    for (int c = 0; c < 3; c++)
        if (blo[c] >= hi[c] - tol || bhi[c] <= lo[c] + tol)
            return 1;
    return 0;
}

/* Nonzero when the node's box lies on or outside the pair's box or a hull plane. */
static int box_outside(const vis_node *node, const plane *pl, int count, const double lo[3],
                       const double hi[3], double tol)
{
    if (boxes_apart(node->lo, node->hi, lo, hi, tol))
        return 1;
    for (int p = 0; p < count; p++) {
        /* The smallest signed distance over the box is at the corner against n. */
        double x = pl[p].n.x > 0 ? node->lo[0] : node->hi[0];
        double y = pl[p].n.y > 0 ? node->lo[1] : node->hi[1];
        double z = pl[p].n.z > 0 ? node->lo[2] : node->hi[2];
        if (pl[p].n.x * x + pl[p].n.y * y + pl[p].n.z * z - pl[p].d >= -tol)
            return 1;
    }
    return 0;
}

static int triangle_outside(const rad_vis *vis, size_t k, const plane *pl, int count,
                            const double lo[3], const double hi[3])
{
    rad_vec3 v[3] = {vis_vertex(vis, k, 0), vis_vertex(vis, k, 1), vis_vertex(vis, k, 2)};
    double tlo[3] = {rad_dmin(v[0].x, rad_dmin(v[1].x, v[2].x)), rad_dmin(v[0].y, rad_dmin(v[1].y, v[2].y)),
                     rad_dmin(v[0].z, rad_dmin(v[1].z, v[2].z))};
    double thi[3] = {rad_dmax(v[0].x, rad_dmax(v[1].x, v[2].x)), rad_dmax(v[0].y, rad_dmax(v[1].y, v[2].y)),
                     rad_dmax(v[0].z, rad_dmax(v[1].z, v[2].z))};
    if (boxes_apart(tlo, thi, lo, hi, vis->tol))
        return 1;
    for (int p = 0; p < count; p++) {
        int out = 1;
        for (int c = 0; c < 3 && out; c++)
            out = rad_vec3_dot(pl[p].n, v[c]) - pl[p].d >= -vis->tol;
        if (out)
            return 1;
    }
    return 0;
}

/* Add the plane of input triangle t as a shaft plane whose outside is t's
 * back: where the kernel is positive, the other end lies strictly in front
 * of t's plane, so the open segment does too, and a triangle on or behind
 * that plane cannot cross it. */
static void add_support_plane(const rad_vis *vis, size_t t, plane *pl, int *count)
{
    if (t >= vis->ntris)
        return;
    rad_vec3 v0 = vis_vertex(vis, t, 0);
    rad_vec3 n = rad_vec3_cross(rad_vec3_sub(vis_vertex(vis, t, 1), v0),
                                rad_vec3_sub(vis_vertex(vis, t, 2), v0));
    double len = rad_vec3_norm(n);
    if (!(len > 0.0))
        return;
    n = rad_vec3_scale(n, -1.0 / len);
    pl[(*count)++] = (plane){n, rad_vec3_dot(n, v0)};
}

/* Walk the hierarchy for the shaft of pts[0..2] and pts[3..5]: the triangles
 * other than ignore0 and ignore1 that the test does not dismiss, up to max of
 * them into out (out may be NULL with max 0: stop at the first).  With
 * kernel set, the ends lie on input triangles ignore0 and ignore1 (where
 * those are indices) and only segments along which the kernel is positive
 * count, so their planes dismiss what lies behind them too.  Returns their
 * count (at most max + 1: more than max), or -1 for a flat hull. */
static int shaft_walk(const rad_vis *vis, const rad_vec3 pts[6], size_t ignore0, size_t ignore1,
                      int kernel, int *out, int max)
{
    if (vis->unoccluded || vis->nnodes == 0)
        return 0; /* nothing in the scene can block */
    double lo[3], hi[3];
    for (int c = 0; c < 3; c++) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
    }
    for (int v = 0; v < 6; v++) {
        double q[3] = {pts[v].x, pts[v].y, pts[v].z};
        for (int c = 0; c < 3; c++) {
            lo[c] = rad_dmin(lo[c], q[c]);
            hi[c] = rad_dmax(hi[c], q[c]);
        }
    }
    if (boxes_apart(vis->nodes[0].lo, vis->nodes[0].hi, lo, hi, vis->tol))
        return 0;
    /* the ends' own planes first: they dismiss the ends' own objects, the
       triangles a walk meets most */
    plane pl[MAX_PLANES];
    int count = 0;
    if (kernel) {
        add_support_plane(vis, ignore0, pl, &count);
        add_support_plane(vis, ignore1, pl, &count);
    }
    int hull = shaft_planes(vis, pts, pl + count);
    if (hull < 0)
        return -1;
    count += hull;
    int stack[128], top = 0, found = 0;
    stack[top++] = 0;
    while (top > 0) {
        const vis_node *node = &vis->nodes[stack[--top]];
        if (box_outside(node, pl, count, lo, hi, vis->tol))
            continue;
        if (node->left < 0) {
            for (int m = node->first; m < node->first + node->count; m++) {
                size_t k = (size_t)vis->order[m];
                if (k == ignore0 || k == ignore1 || triangle_outside(vis, k, pl, count, lo, hi))
                    continue;
                if (found >= max)
                    return max + 1;
                out[found++] = (int)k;
            }
        } else {
            if (top + 2 > (int)(sizeof stack / sizeof stack[0]))
                return max + 1; /* deeper than the build makes: answer safely */
            stack[top++] = node->right;
            stack[top++] = node->left;
        }
    }
    return found;
}

int rad_vis_pair_can_block(const rad_vis *vis, size_t i, size_t j)
{
    int can_block;
    rad_vis_pair_blockers(vis, i, j, NULL, 0, &can_block);
    return can_block;
}

/* The shaft walk of the pair of input triangles i and j (shaft_walk's
 * answer; 1, as for a possible blocker, for a bad pair), from the lower
 * index: the hull's planes are rounded differently from the two ends, and
 * the pair's answer must not depend on which end asks (the pair table
 * keeps one answer for both orders). */
static int pair_walk(const rad_vis *vis, size_t i, size_t j, int kernel, int *out, int max)
{
    if (!vis || i >= vis->ntris || j >= vis->ntris)
        return 1;
    if (i > j) {
        size_t k = i;
        i = j;
        j = k;
    }
    rad_vec3 pts[6];
    for (int v = 0; v < 3; v++) {
        pts[v] = vis_vertex(vis, i, v);
        pts[3 + v] = vis_vertex(vis, j, v);
    }
    return shaft_walk(vis, pts, i, j, kernel, out, max);
}

int vis_pair_segments_can_block(const rad_vis *vis, size_t i, size_t j)
{
    return pair_walk(vis, i, j, 0, NULL, 0) != 0;
}

int rad_vis_pair_blockers(const rad_vis *vis, size_t i, size_t j, int *out, int max,
                          int *can_block)
{
    *can_block = 1;
    if (!vis || i >= vis->ntris || j >= vis->ntris || max < 0 || (max > 0 && !out))
        return 0;
    int n = pair_walk(vis, i, j, 1, out, max);
    *can_block = n != 0;
    return n < 0 ? 0 : n;
}

int vis_shaft_filter(const rad_vis *vis, const rad_vec3 a[3], const rad_vec3 b[3], const int *in,
                     int n, int *out)
{
    rad_vec3 pts[6] = {a[0], a[1], a[2], b[0], b[1], b[2]};
    double lo[3], hi[3];
    for (int c = 0; c < 3; c++) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
    }
    for (int v = 0; v < 6; v++) {
        double q[3] = {pts[v].x, pts[v].y, pts[v].z};
        for (int c = 0; c < 3; c++) {
            lo[c] = rad_dmin(lo[c], q[c]);
            hi[c] = rad_dmax(hi[c], q[c]);
        }
    }
    plane pl[MAX_PLANES];
    int count = shaft_planes(vis, pts, pl);
    if (count < 0)
        return 0;
    int kept = 0;
    for (int k = 0; k < n; k++)
        if (!triangle_outside(vis, (size_t)in[k], pl, count, lo, hi))
            out[kept++] = in[k];
    return kept;
}

int rad_vis_blockers_within(const rad_vis *vis, const rad_vec3 a[3], const rad_vec3 b[3],
                            const int *in, int n, int *out)
{
    return vis && n > 0 ? vis_shaft_filter(vis, a, b, in, n, out) : 0;
}

int rad_vis_blockers(const rad_vis *vis, const rad_vec3 a[3], int face_a, const rad_vec3 b[3],
                     int face_b, int *out, int max)
{
    if (!vis || max < 0 || (max > 0 && !out))
        return -1;
    rad_vec3 pts[6] = {a[0], a[1], a[2], b[0], b[1], b[2]};
    size_t ia = face_a < 0 ? (size_t)-1 : (size_t)face_a, ib = face_b < 0 ? (size_t)-1 : (size_t)face_b;
    int n = shaft_walk(vis, pts, ia, ib, 1, out, max);
    return n < 0 ? 0 : n; /* a flat pair: the kernel vanishes, nothing to block */
}
