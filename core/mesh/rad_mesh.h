/* rad_mesh: the C face of the CGAL shim (STYLE.md point 8).
 *
 * A rad_mesh is a triangle mesh (vertex positions and triangles, copied in),
 * analysed once when it is created:
 *   - which faces touch: every pair sharing an edge or only a vertex, and
 *     whether the two are coplanar, decided with CGAL's exact predicates;
 *   - connected components (faces joined through shared edges);
 *   - closedness: every edge used by exactly two faces, traversed in opposite
 *     directions (consistent orientation);
 *   - convexity seen from inside: every vertex lies on the front side of (or
 *     on) every face's plane, i.e. the normals face inwards.
 * On request (rad_mesh_check_surface), a CGAL Surface_mesh cross-checks
 * closedness and the component count where the triangles form a manifold
 * polygon mesh.
 * Refinement makes a new mesh whose elements each remember the input face they
 * lie in.  Leaves of midpoint-split quadtrees are turned into a conforming
 * mesh (hanging vertices resolved).  Export writes OFF; PLY with vertex
 * colours is rad_io_write_ply's.
 *
 * Every function is safe to call from C; no exception crosses this header:
 * std::bad_alloc becomes RAD_ENOMEM and any other exception RAD_EGEOM, with
 * its message kept (rad_error_message). */
#ifndef RAD_MESH_H
#define RAD_MESH_H

#include <stddef.h>

#include "rad_error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rad_mesh rad_mesh;

typedef enum rad_mesh_contact {
    RAD_MESH_SHARED_EDGE = 1,  /* the two faces share two vertices (an edge) */
    RAD_MESH_SHARED_VERTEX = 2 /* the two faces share exactly one vertex */
} rad_mesh_contact;

/* One touching pair, a < b.  shared[] are the shared vertex indices
 * (shared[1] = -1 for a vertex contact). */
typedef struct rad_mesh_pair {
    int a, b;
    int contact;  /* rad_mesh_contact */
    int coplanar; /* 1: all four (or five) corner points lie in one plane, exactly */
    int shared[2];
} rad_mesh_pair;

typedef struct rad_mesh_info {
    int vertices, faces;
    int edges;                 /* distinct undirected edges */
    int boundary_edges;        /* used by one face */
    int nonmanifold_edges;     /* used by three or more faces */
    int misoriented_edges;     /* used by two faces in the same direction */
    int components;            /* through shared edges */
    int closed_components;
    int closed;                /* every edge shared by two consistently oriented faces */
    int convex_inside;         /* every vertex on the front side of every face's plane */
    int pairs_edge, pairs_edge_coplanar;
    int pairs_vertex, pairs_vertex_coplanar;
} rad_mesh_info;

/* CGAL's cross-check of closed and components (rad_mesh_check_surface). */
typedef struct rad_mesh_surface_check {
    int surface_mesh; /* 1 when a CGAL Surface_mesh could be built (a manifold polygon mesh) */
    int closed;       /* CGAL::is_closed on it (-1 when not built) */
    int components;   /* PMP::connected_components on it (-1 when not built) */
} rad_mesh_surface_check;

/* Copy xyz (3*nv doubles) and tri (3*nt indices) and analyse them.  Indices
 * must be in range; degenerate triangles are allowed here (rad_scene rejects
 * them before).  input_face (nt ints or NULL: 0..nt-1) is remembered per face. */
rad_status rad_mesh_create(const double *xyz, int nv, const int *tri, int nt,
                           const int *input_face, rad_mesh **out);
void rad_mesh_destroy(rad_mesh *mesh);

int rad_mesh_vertex_count(const rad_mesh *mesh);
int rad_mesh_face_count(const rad_mesh *mesh);
const double *rad_mesh_vertices(const rad_mesh *mesh);   /* 3 per vertex */
const int *rad_mesh_triangles(const rad_mesh *mesh);     /* 3 per face */
const int *rad_mesh_input_faces(const rad_mesh *mesh);   /* 1 per face */
/* The figures above.  convex_inside is computed on the first call (it costs
 * up to faces x vertices orientation tests, less when a local test fails;
 * above 4e8 tests it is not run and convex_inside is -1, unknown); that first
 * call is not thread-safe. */
void rad_mesh_get_info(const rad_mesh *mesh, rad_mesh_info *info);

/* Build a CGAL Surface_mesh from the triangles, where they form a manifold
 * polygon mesh, and check closedness and components on it.  Not part of
 * rad_mesh_create: for a million faces it takes seconds, and only `radkit
 * info` and the tests ask.  RAD_EINVAL for NULL, RAD_ENOMEM, RAD_EGEOM. */
rad_status rad_mesh_check_surface(const rad_mesh *mesh, rad_mesh_surface_check *out);

/* Touching pairs, sorted by (a, b); owned by the mesh.  Two faces with the
 * same three corners (duplicates) are not listed; rad_scene warns about them. */
int rad_mesh_pair_count(const rad_mesh *mesh);
const rad_mesh_pair *rad_mesh_pairs(const rad_mesh *mesh);

/* Component of each face (0..components-1, numbered by first face). */
const int *rad_mesh_face_components(const rad_mesh *mesh);
/* Closed / convex-from-inside for one component (0 or 1; -1 for a bad index,
 * and for convexity too costly to decide, as above). */
int rad_mesh_component_closed(const rad_mesh *mesh, int component);
int rad_mesh_component_convex(const rad_mesh *mesh, int component);

/* Uniform refinement: every triangle split into 4 at its edge midpoints,
 * `levels` times (4^levels children each).  Conforming: a midpoint is shared
 * by both faces of an edge.  Children keep the winding and the input face of
 * their parent.  RAD_ETOOBIG beyond max_faces. */
rad_status rad_mesh_refine_uniform(const rad_mesh *mesh, int levels, size_t max_faces,
                                   rad_mesh **out);
/* Split edges longer than max_edge at their midpoints (a triangle with 1, 2 or
 * 3 split edges becomes 2, 3 or 4 triangles) until no edge is longer; the
 * result is conforming and keeps windings and input faces. */
rad_status rad_mesh_refine_max_edge(const rad_mesh *mesh, double max_edge, size_t max_faces,
                                    rad_mesh **out);

/* Conforming triangulation of leaf triangles made by repeated midpoint splits
 * (the leaves of rad_hier's quadtrees, whose midpoints are (p + q) * 0.5 per
 * coordinate), for output with smooth vertex colours.
 * corners: 9 doubles per leaf (a, b, c; the leaf's winding is kept), nleaves
 * leaves.  Output (malloc'ed, caller frees; NULL when empty): vertices
 * deduplicated by exact coordinates (-0.0 equals +0.0), numbered by first
 * appearance among the corners (*xyz_out, 3 per vertex, *nv_out of them),
 * triangles (*tri_out, 3 ints each, *nt_out of them) and for each output
 * triangle the leaf it lies in (*leaf_out), in leaf order.
 * A vertex hangs on a leaf edge (p, q) when it is (p + q) * 0.5 or,
 * recursively, a midpoint of (p, m) or (m, q) with m hanging.  A leaf with
 * hanging vertices is triangulated with them by a CGAL constrained Delaunay
 * triangulation in its plane (n - 2 triangles for n boundary vertices); other
 * leaves are copied as they are (same corners in the same order), so leaves
 * all at one depth come back unchanged.  Every output triangle keeps its
 * leaf's orientation.  T-junctions of the input triangles themselves (a
 * vertex on an edge that is not a recursive midpoint of it) are not found:
 * the input triangles must be conforming.
 * RAD_EINVAL for a NULL argument, RAD_EINPUT for a non-finite or degenerate
 * (exactly collinear) leaf, naming it, RAD_ETOOBIG beyond INT_MAX / 3 leaves,
 * RAD_ENOMEM / RAD_EGEOM from the geometry kernel. */
rad_status rad_mesh_conform_leaves(const double *corners, size_t nleaves, double **xyz_out,
                                   size_t *nv_out, int **tri_out, int **leaf_out, size_t *nt_out);

/* A triangle whose longest edge is at least this many times another's is
 * large beside it (rad_mesh_split_contacts' near_rel_large). */
#define RAD_MESH_HOVER_LARGE 4.0

/* Input triangles cut along their contact lines (contact.cpp): where an
 * edge of another triangle lies on a triangle's plane (within rel_tol times
 * the longer of the two triangles' longest edges), or failing that hovers
 * over it (within near_rel times its own triangle's longest edge, or
 * near_rel_large times it over a triangle large beside its own:
 * RAD_MESH_HOVER_LARGE), with the rest of it in front, and that edge
 * (projected onto the plane) passes through the triangle's inside, the
 * triangle is triangulated with it as a constraint (a box standing on a
 * floor, or a hair above it, cuts the floor along its footprint).
 * Triangles that pass through each other cut nothing.  The output holds the
 * input's vertices and then the new ones; every piece keeps its input
 * triangle's orientation and names it in parent[]; a sliver that the
 * scene's degenerate test would refuse is dropped and counted; triangles
 * without contact are copied as they are, in order; a triangle without a
 * normal (degenerate, not finite) neither cuts nor is cut.  The candidate
 * pairs are examined on `threads` OpenMP threads (0: OpenMP's default);
 * the cut is the same for any count.  RAD_EINVAL for
 * a NULL argument, a tolerance outside [0, 1) (an infinite one would ask
 * the candidate grid for no end of cells) or near_rel_large below
 * near_rel; RAD_EINPUT for a bad index (naming its triangle); RAD_ENOMEM;
 * RAD_EGEOM from the geometry kernel. */
typedef struct rad_mesh_contacts {
    double *xyz;
    size_t nv;
    int *tri;
    size_t nt;
    int *parent;
    size_t faces_split; /* input triangles cut */
    size_t segments;    /* contact segments found (on the cut triangles) */
    size_t slivers;     /* pieces dropped as degenerate (area <= 1e-12 of their
                           longest edge squared) */
} rad_mesh_contacts;
rad_status rad_mesh_split_contacts(const double *xyz, size_t nv, const int *tri, size_t nt,
                                   double rel_tol, double near_rel, double near_rel_large,
                                   int threads, rad_mesh_contacts *out);
void rad_mesh_contacts_free(rad_mesh_contacts *c);

/* OFF with full double precision. */
rad_status rad_mesh_write_off(const rad_mesh *mesh, const char *path);

/* The polygons of a mesh file as CGAL's own reader (CGAL::IO::read_polygon_soup;
 * OFF, PLY, STL, OBJ by extension) sees them, and the triangles their fans
 * would make (sum of n - 2 over polygons of n >= 3 corners): an importer
 * independent of radkit's, for tests.  RAD_EINPUT when CGAL refuses the file. */
rad_status rad_mesh_count_polygon_soup(const char *path, long *polygons, long *triangles_if_fanned);

#ifdef __cplusplus
}
#endif
#endif
