// Conforming triangulation of hierarchical-radiosity leaves (rad_mesh_conform_leaves).
//
// The leaves come from repeated 1->4 midpoint splits (core/hier/hier.c,
// [hanrahan1991]): a midpoint is (p + q) * 0.5 per coordinate, and since IEEE
// addition is commutative, the midpoint of one edge computed in two elements
// is the same double triple.  Neighbouring leaves may be at different depths, so a coarse
// leaf's edge can carry "hanging" vertices of its finer neighbours.
//
// Algorithm:
//  1. Check every leaf: finite corners, not collinear (CGAL::collinear, an
//     exact predicate, so only truly degenerate leaves are refused).
//  2. Vertices: every corner goes into a hash map keyed by the bit patterns of
//     its three coordinates (with -0.0 read as +0.0, so equal doubles make one
//     vertex), numbered in order of first appearance.
//  3. Hanging vertices of a leaf edge (p, q): m = (p + q) * 0.5 exactly as
//     hier.c computes it; if m is a vertex (and not p or q, which happens only
//     for adjacent doubles), it hangs on the edge and (p, m) and (m, q) are
//     searched the same way.  This finds every vertex a finer neighbour made on
//     the edge, in order from p to q.  A T-junction that is not a recursive
//     midpoint (two input triangles meeting at a T) is not found: the input is
//     assumed conforming.
//  4. A leaf without hanging vertices is copied as it is (same corner order).
//  5. Otherwise its boundary polygon (corners and hanging vertices in order)
//     is triangulated by a CGAL constrained Delaunay triangulation
//     [cgal:triangulation2] in 2D.  The 2D points drop the coordinate along
//     which the leaf's normal is largest: that copies doubles without
//     rounding, and the projection is an affine bijection of the leaf's plane,
//     so collinearity and orientation are decided exactly on the true points.
//     A rounded midpoint may lie a hair off its edge, inside or outside the
//     leaf; so the faces kept are those inside the constrained polygon (a
//     flood fill from the infinite face that stops at constraints), not all
//     finite faces: a sliver between the edge and a vertex just inside it
//     would cover part of the neighbour.
//  6. CGAL's faces are counter-clockwise in 2D; where the leaf is clockwise
//     in the projection, each face is reversed, so every output triangle
//     keeps the leaf's orientation.
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "cdt.hpp"
#include "mesh_internal.hpp"

namespace {

using Kernel = radmesh::CdtKernel;
using Point3 = Kernel::Point_3;
using Point2 = Kernel::Point_2;
using CDT = radmesh::CDT;

struct Key {
    std::uint64_t bits[3];
    bool operator==(const Key &o) const
    {
        return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
    }
};

struct KeyHash {
    std::size_t operator()(const Key &k) const
    {
        // splitmix64-style mixing of the three words
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (std::uint64_t w : k.bits) {
            h ^= w + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
            h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
            h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
            h ^= h >> 31;
        }
        return (std::size_t)h;
    }
};

struct Vertices {
    std::vector<double> xyz;
    std::unordered_map<Key, int, KeyHash> index;

    static Key key_of(const double *p)
    {
        Key k;
        for (int i = 0; i < 3; i++) {
            double x = p[i] + 0.0; // -0.0 + 0.0 = +0.0: equal doubles, one key
            std::memcpy(&k.bits[i], &x, sizeof x);
        }
        return k;
    }
    int find(const double *p) const
    {
        auto it = index.find(key_of(p));
        return it == index.end() ? -1 : it->second;
    }
    int add(const double *p)
    {
        auto ins = index.emplace(key_of(p), (int)(xyz.size() / 3));
        if (ins.second)
            for (int i = 0; i < 3; i++)
                xyz.push_back(p[i] + 0.0);
        return ins.first->second;
    }
    const double *at(int v) const { return &xyz[3 * (size_t)v]; }
};

// Append the vertices hanging on edge (p, q), in order from p to q (step 3).
void hanging(const Vertices &V, int p, int q, std::vector<int> &out)
{
    double m[3];
    for (int i = 0; i < 3; i++)
        m[i] = (V.at(p)[i] + V.at(q)[i]) * 0.5; // as hier.c: rad_vec3_scale(rad_vec3_add(p, q), 0.5)
    int v = V.find(m);
    if (v < 0 || v == p || v == q)
        return;
    hanging(V, p, v, out);
    out.push_back(v);
    hanging(V, v, q, out);
}

Point3 point3(const double *p) { return Point3(p[0], p[1], p[2]); }

// The coordinate to drop (step 5): the largest component of the leaf's normal,
// or the next ones if the exact 2D orientation is zero there (possible only
// when rounding misjudged which component is largest).  Returns the
// orientation of (a, b, c) in the remaining two coordinates, never COLLINEAR
// for a leaf that is not collinear in 3D.
CGAL::Orientation projection(const double *a, const double *b, const double *c, int *axis)
{
    double u[3], w[3];
    for (int i = 0; i < 3; i++) {
        u[i] = b[i] - a[i];
        w[i] = c[i] - a[i];
    }
    double n[3] = {std::fabs(u[1] * w[2] - u[2] * w[1]), std::fabs(u[2] * w[0] - u[0] * w[2]),
                   std::fabs(u[0] * w[1] - u[1] * w[0])};
    int order[3] = {0, 1, 2};
    for (int i = 0; i < 3; i++) // sort the axes by decreasing |n|
        for (int j = i + 1; j < 3; j++)
            if (n[order[j]] > n[order[i]])
                std::swap(order[i], order[j]);
    for (int k : order) {
        int i0 = (k + 1) % 3, i1 = (k + 2) % 3;
        CGAL::Orientation o = CGAL::orientation(Point2(a[i0], a[i1]), Point2(b[i0], b[i1]),
                                                Point2(c[i0], c[i1]));
        if (o != CGAL::COLLINEAR) {
            *axis = k;
            return o;
        }
    }
    throw std::logic_error("a leaf that is not collinear projects to a segment on every axis");
}

// Triangulate one leaf's boundary polygon (steps 5 and 6), appending to tri.
// corner[] are the leaf's corners; poly is the polygon (corners and hanging
// vertices in order, starting at corner[0]).
void triangulate(const Vertices &V, const int corner[3], const std::vector<int> &poly, size_t leaf,
                 std::vector<int> &tri)
{
    int axis = 0;
    CGAL::Orientation leaf_orientation = projection(V.at(corner[0]), V.at(corner[1]), V.at(corner[2]), &axis);
    const int i0 = (axis + 1) % 3, i1 = (axis + 2) % 3;
    CDT cdt;
    std::vector<CDT::Vertex_handle> vh;
    vh.reserve(poly.size());
    for (int v : poly) {
        const double *p = V.at(v);
        CDT::Vertex_handle h = cdt.insert(Point2(p[i0], p[i1]));
        h->info() = v;
        vh.push_back(h);
    }
    // Two polygon vertices at one 2D point would make the polygon not simple
    // (only for a leaf thin enough that a hanging vertex meets the far corner).
    if (cdt.number_of_vertices() != poly.size())
        throw std::runtime_error("leaf " + std::to_string(leaf) +
                                 ": two boundary vertices coincide in the leaf's plane");
    for (size_t k = 0; k < vh.size(); k++)
        cdt.insert_constraint(vh[k], vh[(k + 1) % vh.size()]);
    // Crossing constraints would have added vertices at their intersections.
    if (cdt.number_of_vertices() != poly.size())
        throw std::runtime_error("leaf " + std::to_string(leaf) +
                                 ": its boundary polygon crosses itself in the leaf's plane");
    radmesh::cdt_mark_outside(cdt); // info 1: outside
    size_t before = tri.size();
    for (CDT::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (f->info() != 0)
            continue;
        int v0 = f->vertex(0)->info(), v1 = f->vertex(1)->info(), v2 = f->vertex(2)->info();
        if (leaf_orientation == CGAL::CLOCKWISE)
            std::swap(v1, v2);
        tri.insert(tri.end(), {v0, v1, v2});
    }
    // A simple polygon of n vertices has n - 2 triangles: a check that the
    // fill found exactly the inside.
    if ((tri.size() - before) / 3 + 2 != poly.size())
        throw std::runtime_error("leaf " + std::to_string(leaf) + ": " +
                                 std::to_string((tri.size() - before) / 3) + " triangles for a polygon of " +
                                 std::to_string(poly.size()) + " vertices");
}

} // namespace

extern "C" {

rad_status rad_mesh_conform_leaves(const double *corners, size_t nleaves, double **xyz_out,
                                   size_t *nv_out, int **tri_out, int **leaf_out, size_t *nt_out)
{
    if (!corners || !xyz_out || !nv_out || !tri_out || !leaf_out || !nt_out)
        return RAD_ERROR(RAD_EINVAL, "rad_mesh_conform_leaves: NULL argument");
    *xyz_out = nullptr;
    *tri_out = nullptr;
    *leaf_out = nullptr;
    *nv_out = 0;
    *nt_out = 0;
    // Vertex and leaf numbers are ints; 3 corners per leaf bound the vertices.
    if (nleaves > (size_t)INT_MAX / 3)
        return RAD_ERROR(RAD_ETOOBIG, "conform: %zu leaves (at most %d)", nleaves, INT_MAX / 3);
    for (size_t l = 0; l < nleaves; l++) {
        const double *c = corners + 9 * l;
        for (int k = 0; k < 9; k++)
            if (!std::isfinite(c[k]))
                return RAD_ERROR(RAD_EINPUT, "conform: leaf %zu has a non-finite coordinate (corner %d)",
                                 l, k / 3);
    }
    return radmesh::guarded("conform", [&]() -> rad_status {
        Vertices V;
        V.xyz.reserve(9 * nleaves);
        std::vector<int> leaf_corners(3 * nleaves);
        for (size_t l = 0; l < nleaves; l++) {
            const double *c = corners + 9 * l;
            if (CGAL::collinear(point3(c), point3(c + 3), point3(c + 6)))
                return RAD_ERROR(RAD_EINPUT,
                                 "conform: leaf %zu is degenerate (its corners are collinear)", l);
            for (int k = 0; k < 3; k++)
                leaf_corners[3 * l + (size_t)k] = V.add(c + 3 * k);
        }
        std::vector<int> tri, leaf_of;
        tri.reserve(3 * nleaves);
        leaf_of.reserve(nleaves);
        std::vector<int> poly;
        for (size_t l = 0; l < nleaves; l++) {
            const int *corner = &leaf_corners[3 * l];
            poly.clear();
            for (int k = 0; k < 3; k++) {
                poly.push_back(corner[k]);
                hanging(V, corner[k], corner[(k + 1) % 3], poly);
            }
            size_t before = tri.size();
            if (poly.size() == 3)
                tri.insert(tri.end(), corner, corner + 3);
            else
                triangulate(V, corner, poly, l, tri);
            leaf_of.insert(leaf_of.end(), (tri.size() - before) / 3, (int)l);
        }
        size_t nv = V.xyz.size() / 3, nt = leaf_of.size();
        // malloc(0) may return NULL; an empty result is returned as NULL arrays.
        double *xyz = nv ? (double *)std::malloc(V.xyz.size() * sizeof *xyz) : nullptr;
        int *t = nt ? (int *)std::malloc(tri.size() * sizeof *t) : nullptr;
        int *lf = nt ? (int *)std::malloc(nt * sizeof *lf) : nullptr;
        if ((nv && !xyz) || (nt && (!t || !lf))) {
            std::free(xyz);
            std::free(t);
            std::free(lf);
            return RAD_ERROR(RAD_ENOMEM, "conform: out of memory for %zu vertices and %zu triangles", nv, nt);
        }
        if (nv)
            std::memcpy(xyz, V.xyz.data(), V.xyz.size() * sizeof *xyz);
        if (nt) {
            std::memcpy(t, tri.data(), tri.size() * sizeof *t);
            std::memcpy(lf, leaf_of.data(), nt * sizeof *lf);
        }
        *xyz_out = xyz;
        *tri_out = t;
        *leaf_out = lf;
        *nv_out = nv;
        *nt_out = nt;
        return RAD_OK;
    });
}

} // extern "C"
