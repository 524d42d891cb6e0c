// Refinement and export for the CGAL shim (plain index arithmetic; no CGAL
// type is needed here, so this file compiles quickly).
//
// Uniform refinement (rad_mesh_refine_uniform), per level:
//  1. Give every undirected edge one midpoint vertex (a map keyed by the
//     edge's vertex pair), so both faces of an edge share it: the result is
//     conforming.
//  2. Replace triangle (a, b, c) with midpoints ab, bc, ca by (a, ab, ca),
//     (ab, b, bc), (ca, bc, c) and (ab, bc, ca): each has the parent's
//     winding, a quarter of its area, and the parent's input face.
// Refinement to a maximum edge length (rad_mesh_refine_max_edge), per pass:
//  1. Mark every edge longer than max_edge and give it a midpoint.
//  2. A triangle with no marked edge is kept; with one, it is bisected from
//     the midpoint to the opposite corner; with two, it is split into three
//     (the corner between the marked edges cut off, the rest bisected along
//     the diagonal from the first midpoint); with three, it is split as in
//     the uniform rule.  Marked edges are split identically on both sides, so
//     the mesh stays conforming.  Passes repeat until no edge is too long;
//     every pass at least halves each marked edge, so they terminate.
// The sum of child areas equals the parent area exactly in exact arithmetic
// (midpoint splits are affine); in floating point to rounding.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <vector>

#include "mesh_internal.hpp"

namespace {

struct Soup {
    std::vector<double> xyz;
    std::vector<int> tri, input;
};

std::uint64_t edge_key(int a, int b)
{
    std::uint32_t lo = (std::uint32_t)std::min(a, b), hi = (std::uint32_t)std::max(a, b);
    return ((std::uint64_t)lo << 32) | hi;
}

int midpoint(Soup &s, std::unordered_map<std::uint64_t, int> &mids, int a, int b)
{
    auto it = mids.find(edge_key(a, b));
    if (it != mids.end())
        return it->second;
    int v = (int)(s.xyz.size() / 3);
    for (int k = 0; k < 3; k++)
        s.xyz.push_back(0.5 * (s.xyz[3 * (size_t)a + (size_t)k] + s.xyz[3 * (size_t)b + (size_t)k]));
    mids.emplace(edge_key(a, b), v);
    return v;
}

double edge_length(const Soup &s, int a, int b)
{
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        double d = s.xyz[3 * (size_t)a + (size_t)k] - s.xyz[3 * (size_t)b + (size_t)k];
        d2 += d * d;
    }
    return std::sqrt(d2);
}

void push(std::vector<int> &tri, std::vector<int> &input, int a, int b, int c, int face)
{
    tri.insert(tri.end(), {a, b, c});
    input.push_back(face);
}

Soup soup_of(const rad_mesh *m)
{
    return Soup{m->xyz, m->tri, m->input_face};
}

rad_status finish(const Soup &s, rad_mesh **out)
{
    *out = radmesh::build(s.xyz.data(), (int)(s.xyz.size() / 3), s.tri.data(),
                          (int)(s.tri.size() / 3), s.input.data());
    return RAD_OK;
}

void split_all(Soup &s, size_t f, std::unordered_map<std::uint64_t, int> &mids,
               std::vector<int> &tri, std::vector<int> &input)
{
    int a = s.tri[3 * f], b = s.tri[3 * f + 1], c = s.tri[3 * f + 2], face = s.input[f];
    int ab = midpoint(s, mids, a, b), bc = midpoint(s, mids, b, c), ca = midpoint(s, mids, c, a);
    push(tri, input, a, ab, ca, face);
    push(tri, input, ab, b, bc, face);
    push(tri, input, ca, bc, c, face);
    push(tri, input, ab, bc, ca, face);
}

} // namespace

extern "C" {

rad_status rad_mesh_refine_uniform(const rad_mesh *mesh, int levels, size_t max_faces, rad_mesh **out)
{
    if (!mesh || !out || levels < 0)
        return RAD_ERROR(RAD_EINVAL, "rad_mesh_refine_uniform: bad arguments (levels = %d)", levels);
    *out = nullptr;
    double faces = (double)mesh->tri.size() / 3 * std::pow(4.0, levels);
    if (faces > (double)max_faces || faces > 2e9)
        return RAD_ERROR(RAD_ETOOBIG, "refine: %d levels would make %.3g faces (limit %zu)", levels,
                         faces, max_faces);
    return radmesh::guarded("refine", [&]() -> rad_status {
        Soup s = soup_of(mesh);
        for (int level = 0; level < levels; level++) {
            std::unordered_map<std::uint64_t, int> mids;
            std::vector<int> tri, input;
            tri.reserve(4 * s.tri.size());
            for (size_t f = 0; f < s.tri.size() / 3; f++)
                split_all(s, f, mids, tri, input);
            s.tri.swap(tri);
            s.input.swap(input);
        }
        return finish(s, out);
    });
}

rad_status rad_mesh_refine_max_edge(const rad_mesh *mesh, double max_edge, size_t max_faces,
                                    rad_mesh **out)
{
    if (!mesh || !out || !(max_edge > 0.0) || !std::isfinite(max_edge))
        return RAD_ERROR(RAD_EINVAL, "refine: the maximum edge length must be positive, got %g", max_edge);
    *out = nullptr;
    return radmesh::guarded("refine", [&]() -> rad_status {
        Soup s = soup_of(mesh);
        for (;;) {
            std::unordered_map<std::uint64_t, int> mids;
            std::vector<int> tri, input;
            bool split = false;
            for (size_t f = 0; f < s.tri.size() / 3; f++) {
                int v[3] = {s.tri[3 * f], s.tri[3 * f + 1], s.tri[3 * f + 2]};
                int mark[3], nm = 0;
                for (int k = 0; k < 3; k++) {
                    mark[k] = edge_length(s, v[k], v[(k + 1) % 3]) > max_edge;
                    nm += mark[k];
                }
                int face = s.input[f];
                if (nm == 0) {
                    push(tri, input, v[0], v[1], v[2], face);
                } else if (nm == 3) {
                    split_all(s, f, mids, tri, input);
                } else if (nm == 1) {
                    int k = mark[0] ? 0 : mark[1] ? 1 : 2; // edge v[k] -> v[k+1]
                    int a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
                    int m = midpoint(s, mids, a, b);
                    push(tri, input, a, m, c, face);
                    push(tri, input, m, b, c, face);
                } else {
                    int k = !mark[0] ? 0 : !mark[1] ? 1 : 2; // the unmarked edge v[k] -> v[k+1]
                    int a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
                    int mbc = midpoint(s, mids, b, c), mca = midpoint(s, mids, c, a);
                    push(tri, input, mbc, c, mca, face); // the corner at c
                    push(tri, input, a, b, mbc, face);   // the rest: quad a b mbc mca
                    push(tri, input, a, mbc, mca, face);
                }
                split |= nm > 0;
                if (tri.size() / 3 > max_faces)
                    return RAD_ERROR(RAD_ETOOBIG, "refine: edges <= %g need more than %zu faces",
                                     max_edge, max_faces);
            }
            s.tri.swap(tri);
            s.input.swap(input);
            if (!split)
                break;
        }
        return finish(s, out);
    });
}

rad_status rad_mesh_write_off(const rad_mesh *mesh, const char *path)
{
    if (!mesh || !path)
        return RAD_ERROR(RAD_EINVAL, "rad_mesh_write_off: NULL argument");
    return radmesh::guarded("OFF export", [&]() -> rad_status {
        FILE *f = std::fopen(path, "w");
        if (!f)
            return RAD_ERROR(RAD_EIO, "%s: cannot open for writing", path);
        size_t nv = mesh->xyz.size() / 3, nt = mesh->tri.size() / 3;
        std::fprintf(f, "OFF\n%zu %zu 0\n", nv, nt);
        for (size_t v = 0; v < nv; v++)
            std::fprintf(f, "%.17g %.17g %.17g\n", mesh->xyz[3 * v], mesh->xyz[3 * v + 1],
                         mesh->xyz[3 * v + 2]);
        for (size_t t = 0; t < nt; t++)
            std::fprintf(f, "3 %d %d %d\n", mesh->tri[3 * t], mesh->tri[3 * t + 1], mesh->tri[3 * t + 2]);
        if (std::fclose(f) != 0)
            return RAD_ERROR(RAD_EIO, "%s: write failed", path);
        return RAD_OK;
    });
}

} // extern "C"
