/* rad_cluster: a cluster hierarchy over the input triangles (the cluster
 * links, transfer models and their error bounds are rad_hier's cluster
 * layer, hier/cluster.c, which builds this tree with one triangle per
 * leaf).
 *
 * A binary bounding-volume hierarchy built top-down: a node's triangles are
 * sorted by centroid along the longest axis of the centroids' bounding box
 * and split at the plane between two consecutive centroids that cuts the
 * fewest triangles, nearest the median among those, each side keeping at
 * least an eighth of the node; until a node holds at most leaf_size
 * triangles.  Why this choice: it is deterministic (the same tree for the
 * same input, whatever the thread count), its depth stays within
 * log_{8/7} n, and it costs O(n log n).  A plane that cuts no triangle
 * leaves the two sides' boxes apart, so separate objects stay whole, each
 * one node with its own box, and sibling clusters do not overlap; a median
 * split cuts objects in two wherever the median falls, and the halves'
 * boxes overlap their neighbours'.  Where boxes overlap, a cluster link has
 * no bound and is refined whatever eps asks (papers/clustering.md §3).
 *
 * Each node keeps what a cluster transfer needs: its bounding box, total
 * area, area-weighted mean normal (length 1 for a flat cluster, less as
 * orientations spread) and the cone of its normals. */
#ifndef RAD_CLUSTER_H
#define RAD_CLUSTER_H

#include <stddef.h>

#include "rad_error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rad_cluster_node {
    double lo[3], hi[3]; /* bounding box of its triangles */
    double area;         /* their total area */
    double normal[3];    /* sum of area x unit normal, over area: |normal| <= 1 */
    double cone_cos;     /* every unit normal n below has n . axis >= cone_cos, axis =
                            normal / |normal|; -1 when no such cone is narrower than
                            the whole sphere (|normal| = 0 or normals spread too far) */
    int child[2];        /* children (node indices), -1 for a leaf */
    int parent;          /* -1 for the root (node 0) */
    int first, count;    /* its triangles: rad_cluster_order()[first .. first + count) */
    int depth;           /* 0 at the root */
} rad_cluster_node;

typedef struct rad_cluster_tree rad_cluster_tree;

/* The hierarchy over triangles tri[3k..3k+2] (k < ntris) of vertices xyz;
 * leaves hold at most leaf_size >= 1 triangles; built on `threads` OpenMP
 * threads (the same tree for any count).  RAD_EINVAL for no
 * triangles, a bad leaf size or an index out of range (nverts), RAD_EINPUT
 * for a non-finite coordinate or a degenerate (zero-area) triangle, naming
 * it; RAD_ENOMEM. */
rad_status rad_cluster_build(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                             int leaf_size, int threads, rad_cluster_tree **out);
void rad_cluster_destroy(rad_cluster_tree *t);

size_t rad_cluster_node_count(const rad_cluster_tree *t);
const rad_cluster_node *rad_cluster_nodes(const rad_cluster_tree *t);
/* The triangles in leaf order: each node's triangles are a contiguous range. */
const int *rad_cluster_order(const rad_cluster_tree *t);
int rad_cluster_max_depth(const rad_cluster_tree *t);

/* Upper bounds for triangles of total area `area`, sum of area x unit
 * normal N, and every unit normal n_i within angle alpha of the unit axis
 * (alpha > pi: no cone), each seen from its own unit direction u_i within
 * angle beta of the unit w: returns an upper bound of
 * sum_i area_i max(n_i . u_i, 0), the least of area x *cosmax and
 * (area + |N|) / 2 + 2 sin(beta / 2) area; *cosmax (may be NULL) bounds
 * every n_i . u_i, cos(theta - alpha - beta) (theta the angle between axis
 * and w; 1 where that is negative, 0 where the cosine is).  A node's
 * (rad_cluster_node): area, N = area x normal, axis = normal / |normal|,
 * alpha = acos(cone_cos). */
double rad_cluster_projected_upper(double area, const double N[3], const double axis[3],
                                   double alpha, const double w[3], double beta, double *cosmax);

#ifdef __cplusplus
}
#endif
#endif
