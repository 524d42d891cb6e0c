// The CGAL shim: mesh construction and analysis behind the C header rad_mesh.h.
//
// Algorithm (rad_mesh_create):
//  1. Copy the arrays; check that every index is in range.
//  2. Edges: list the 3 nt directed half-edges keyed by their undirected vertex
//     pair, sort, and walk the groups.  A group of two half-edges in opposite
//     directions is an interior edge; one is a boundary edge; three or more is
//     non-manifold; two in the same direction is misoriented.
//  3. Components: union-find over faces joined by a shared edge.  A component
//     is closed when none of its edges is boundary, non-manifold or
//     misoriented (the definition of a closed, consistently oriented surface).
//  4. Touching pairs: for each vertex, every pair of faces around it; the pair
//     is recorded at its smallest shared vertex only, so each pair appears
//     once, as an edge contact (two shared vertices) or a vertex contact (one).
//     Coplanarity is CGAL::coplanar on the corner points, an exact predicate
//     (filtered interval arithmetic, falling back to exact arithmetic), so a
//     pair is coplanar only when it really is [cgal:kernel; shewchuk97].
//  5. On request (rad_mesh_check_surface), where the triangles form a
//     manifold polygon mesh (PMP::is_polygon_soup_a_polygon_mesh), build a
//     CGAL Surface_mesh and
//     cross-check closedness (CGAL::is_closed) and the component count
//     (PMP::connected_components) [cgal:surfacemesh; cgal:pmp].
//  6. Convexity from inside (on first request): a component is convex seen
//     from inside when every one of its vertices is on the front side of, or
//     on, every one of its faces' planes: CGAL::orientation(a, b, c, v) is not
//     NEGATIVE (the front is where the counter-clockwise normal points).  A
//     cheap local test runs first: for each interior edge, the far vertex of
//     one face must not be behind the other; one failure decides "not convex".
//     The full test costs faces x vertices orientation tests; above
//     kConvexTestBudget it is not run and convexity is "unknown" (-1), which
//     every caller treats as "may occlude": a scene of a few hundred thousand
//     triangles would otherwise spend minutes proving what only saves rays.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

#include "cgal_warnings_off.hpp"
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Surface_mesh.h>
#include "cgal_warnings_on.hpp"

#include "mesh_internal.hpp"

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using SurfaceMesh = CGAL::Surface_mesh<Point>;
namespace PMP = CGAL::Polygon_mesh_processing;

struct HalfEdge {
    std::uint64_t key; // (min << 32) | max
    int face;
    int forward;       // 1 when the face goes min -> max
};

int find_root(std::vector<int> &parent, int x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

Point point_of(const rad_mesh &m, int v)
{
    return Point(m.xyz[3 * v], m.xyz[3 * v + 1], m.xyz[3 * v + 2]);
}

// CGAL::orientation(a, b, c, v) for face f's corners and vertex v.
CGAL::Orientation side_of(const rad_mesh &m, int f, int v)
{
    const int *t = &m.tri[3 * f];
    return CGAL::orientation(point_of(m, t[0]), point_of(m, t[1]), point_of(m, t[2]), point_of(m, v));
}

void classify_edges(rad_mesh &m, std::vector<HalfEdge> &half, std::vector<int> &parent)
{
    const int nt = (int)(m.tri.size() / 3);
    half.reserve(3 * (size_t)nt);
    for (int f = 0; f < nt; f++)
        for (int k = 0; k < 3; k++) {
            std::uint32_t a = (std::uint32_t)m.tri[3 * f + k], b = (std::uint32_t)m.tri[3 * f + (k + 1) % 3];
            std::uint32_t lo = std::min(a, b), hi = std::max(a, b);
            half.push_back({((std::uint64_t)lo << 32) | hi, f, a < b ? 1 : 0});
        }
    std::sort(half.begin(), half.end(), [](const HalfEdge &x, const HalfEdge &y) {
        return x.key != y.key ? x.key < y.key : x.face < y.face;
    });
    parent.resize((size_t)nt);
    std::iota(parent.begin(), parent.end(), 0);
    std::vector<char> bad_face((size_t)nt, 0);
    for (size_t i = 0; i < half.size();) {
        size_t j = i;
        while (j < half.size() && half[j].key == half[i].key)
            j++;
        size_t n = j - i;
        m.info.edges++;
        if (n == 1)
            m.info.boundary_edges++;
        else if (n > 2)
            m.info.nonmanifold_edges++;
        else if (half[i].forward == half[i + 1].forward)
            m.info.misoriented_edges++;
        bool bad = n != 2 || half[i].forward == half[i + 1].forward;
        for (size_t k = i; k < j; k++) {
            if (bad)
                bad_face[(size_t)half[k].face] = 1;
            if (k > i) {
                int ra = find_root(parent, half[i].face), rb = find_root(parent, half[k].face);
                if (ra != rb)
                    parent[(size_t)std::max(ra, rb)] = std::min(ra, rb);
            }
        }
        i = j;
    }
    // Number the components by their first face.
    std::vector<int> number((size_t)nt, -1);
    m.component.assign((size_t)nt, 0);
    int count = 0;
    for (int f = 0; f < nt; f++) {
        int r = find_root(parent, f);
        if (number[(size_t)r] < 0)
            number[(size_t)r] = count++;
        m.component[(size_t)f] = number[(size_t)r];
    }
    m.info.components = count;
    m.comp_closed.assign((size_t)count, 1);
    for (int f = 0; f < nt; f++)
        if (bad_face[(size_t)f])
            m.comp_closed[(size_t)m.component[(size_t)f]] = 0;
    m.info.closed_components = (int)std::count(m.comp_closed.begin(), m.comp_closed.end(), 1);
    m.info.closed = nt > 0 && m.info.boundary_edges == 0 && m.info.nonmanifold_edges == 0 &&
                    m.info.misoriented_edges == 0;
    m.comp_convex.assign((size_t)count, -1);
}

void find_pairs(rad_mesh &m)
{
    const int nv = (int)(m.xyz.size() / 3), nt = (int)(m.tri.size() / 3);
    // Vertex -> faces (compressed rows).
    std::vector<int> start((size_t)nv + 1, 0), faces(3 * (size_t)nt);
    for (int v : m.tri)
        start[(size_t)v + 1]++;
    for (int v = 0; v < nv; v++)
        start[(size_t)v + 1] += start[(size_t)v];
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int f = 0; f < nt; f++)
        for (int k = 0; k < 3; k++)
            faces[(size_t)fill[(size_t)m.tri[3 * f + k]]++] = f;
    for (int v = 0; v < nv; v++) {
        for (int i = start[(size_t)v]; i < start[(size_t)v + 1]; i++)
            for (int j = i + 1; j < start[(size_t)v + 1]; j++) {
                int fa = std::min(faces[(size_t)i], faces[(size_t)j]);
                int fb = std::max(faces[(size_t)i], faces[(size_t)j]);
                if (fa == fb)
                    continue; // a face using v twice (only for degenerate input)
                const int *ta = &m.tri[3 * fa], *tb = &m.tri[3 * fb];
                int shared[3], ns = 0;
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++)
                        if (ta[a] == tb[b] && ns < 3 &&
                            std::find(shared, shared + ns, ta[a]) == shared + ns)
                            shared[ns++] = ta[a];
                if (ns >= 3 || *std::min_element(shared, shared + ns) != v)
                    continue; // duplicates are counted elsewhere; other vertex records it
                rad_mesh_pair p{};
                p.a = fa;
                p.b = fb;
                p.contact = ns == 2 ? RAD_MESH_SHARED_EDGE : RAD_MESH_SHARED_VERTEX;
                p.shared[0] = std::min(shared[0], ns == 2 ? shared[1] : shared[0]);
                p.shared[1] = ns == 2 ? std::max(shared[0], shared[1]) : -1;
                Point a0 = point_of(m, ta[0]), a1 = point_of(m, ta[1]), a2 = point_of(m, ta[2]);
                p.coplanar = 1;
                for (int b = 0; b < 3; b++)
                    if (!CGAL::coplanar(a0, a1, a2, point_of(m, tb[b])))
                        p.coplanar = 0;
                m.pairs.push_back(p);
                if (ns == 2) {
                    m.info.pairs_edge++;
                    m.info.pairs_edge_coplanar += p.coplanar;
                } else {
                    m.info.pairs_vertex++;
                    m.info.pairs_vertex_coplanar += p.coplanar;
                }
            }
    }
    std::sort(m.pairs.begin(), m.pairs.end(), [](const rad_mesh_pair &x, const rad_mesh_pair &y) {
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    });
}

// Group faces and pairs by component (counting sort, stable).
void group_by_component(rad_mesh &m)
{
    const size_t nc = (size_t)m.info.components;
    m.comp_face_start.assign(nc + 1, 0);
    m.comp_pair_start.assign(nc + 1, 0);
    for (int c : m.component)
        m.comp_face_start[(size_t)c + 1]++;
    for (const rad_mesh_pair &p : m.pairs)
        m.comp_pair_start[(size_t)m.component[(size_t)p.a] + 1]++;
    for (size_t c = 0; c < nc; c++) {
        m.comp_face_start[c + 1] += m.comp_face_start[c];
        m.comp_pair_start[c + 1] += m.comp_pair_start[c];
    }
    m.comp_faces.resize(m.component.size());
    m.comp_pairs.resize(m.pairs.size());
    std::vector<int> fill(m.comp_face_start.begin(), m.comp_face_start.end() - 1);
    for (size_t f = 0; f < m.component.size(); f++)
        m.comp_faces[(size_t)fill[(size_t)m.component[f]]++] = (int)f;
    fill.assign(m.comp_pair_start.begin(), m.comp_pair_start.end() - 1);
    for (size_t i = 0; i < m.pairs.size(); i++)
        m.comp_pairs[(size_t)fill[(size_t)m.component[(size_t)m.pairs[i].a]]++] = (int)i;
}

void check_surface(const rad_mesh &m, rad_mesh_surface_check &out)
{
    out = {0, -1, -1};
    const size_t nv = m.xyz.size() / 3, nt = m.tri.size() / 3;
    std::vector<Point> points;
    points.reserve(nv);
    for (size_t v = 0; v < nv; v++)
        points.push_back(point_of(m, (int)v));
    std::vector<std::array<std::size_t, 3>> polygons(nt);
    for (size_t f = 0; f < nt; f++)
        polygons[f] = {(std::size_t)m.tri[3 * f], (std::size_t)m.tri[3 * f + 1],
                       (std::size_t)m.tri[3 * f + 2]};
    if (nt == 0 || !PMP::is_polygon_soup_a_polygon_mesh(polygons))
        return;
    SurfaceMesh sm;
    PMP::polygon_soup_to_polygon_mesh(points, polygons, sm);
    if (sm.number_of_faces() != nt)
        return;
    out.surface_mesh = 1;
    out.closed = CGAL::is_closed(sm) ? 1 : 0;
    auto fcc = sm.add_property_map<SurfaceMesh::Face_index, std::size_t>("f:cc", 0).first;
    out.components = (int)PMP::connected_components(sm, fcc);
}

// Local convexity at the interior edges of component c (cheap rejection).
// A shared edge joins two faces of the same component, so the pairs grouped
// under c (by their first face) are all of c's edge pairs.
bool locally_convex(const rad_mesh &m, int c)
{
    for (int k = m.comp_pair_start[(size_t)c]; k < m.comp_pair_start[(size_t)c + 1]; k++) {
        const rad_mesh_pair &p = m.pairs[(size_t)m.comp_pairs[(size_t)k]];
        if (p.contact != RAD_MESH_SHARED_EDGE)
            continue;
        for (int b = 0; b < 3; b++) {
            int v = m.tri[3 * (size_t)p.b + (size_t)b];
            if (v != p.shared[0] && v != p.shared[1] && side_of(m, p.a, v) == CGAL::NEGATIVE)
                return false;
        }
    }
    return true;
}

// Every vertex of `verts` on the front side of (or on) every face in `faces`.
bool all_in_front(const rad_mesh &m, const std::vector<int> &faces, const std::vector<int> &verts)
{
    for (int f : faces)
        for (int v : verts)
            if (side_of(m, f, v) == CGAL::NEGATIVE)
                return false;
    return true;
}

} // namespace

namespace radmesh {

rad_mesh *build(const double *xyz, int nv, const int *tri, int nt, const int *input_face)
{
    if (nv < 0 || nt < 0 || (nv > 0 && !xyz) || (nt > 0 && !tri))
        throw std::invalid_argument("rad_mesh_create: bad arrays");
    std::unique_ptr<rad_mesh> m(new rad_mesh);
    m->xyz.assign(xyz, xyz + 3 * (size_t)nv);
    m->tri.assign(tri, tri + 3 * (size_t)nt);
    for (size_t i = 0; i < m->tri.size(); i++)
        if (m->tri[i] < 0 || m->tri[i] >= nv)
            throw std::out_of_range("rad_mesh_create: face " + std::to_string(i / 3) +
                                    " uses vertex " + std::to_string(m->tri[i]) + " of " +
                                    std::to_string(nv));
    m->input_face.resize((size_t)nt);
    for (int f = 0; f < nt; f++)
        m->input_face[(size_t)f] = input_face ? input_face[f] : f;
    m->info.vertices = nv;
    m->info.faces = nt;
    std::vector<HalfEdge> half;
    std::vector<int> parent;
    classify_edges(*m, half, parent);
    find_pairs(*m);
    group_by_component(*m);
    return m.release();
}

} // namespace radmesh

// Cached convexity: 1 convex, 0 not, kUnknown too big to decide.
constexpr int kUnknown = 2;
constexpr double kConvexTestBudget = 4e8;

static int compute_component_convex(const rad_mesh *m, int c)
{
    if (m->comp_convex[(size_t)c] >= 0)
        return m->comp_convex[(size_t)c];
    int result = 0;
    if (locally_convex(*m, c)) {
        std::vector<int> faces(m->comp_faces.begin() + m->comp_face_start[(size_t)c],
                               m->comp_faces.begin() + m->comp_face_start[(size_t)c + 1]);
        std::vector<int> verts;
        for (int f : faces)
            verts.insert(verts.end(), &m->tri[3 * (size_t)f], &m->tri[3 * (size_t)f] + 3);
        std::sort(verts.begin(), verts.end());
        verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
        if ((double)faces.size() * (double)verts.size() > kConvexTestBudget)
            result = kUnknown;
        else
            result = all_in_front(*m, faces, verts) ? 1 : 0;
    }
    m->comp_convex[(size_t)c] = (signed char)result;
    return result;
}

static int compute_convex_inside(const rad_mesh *m)
{
    if (m->convex_inside >= 0)
        return m->convex_inside;
    const int nt = (int)(m->tri.size() / 3);
    int result = nt > 0;
    for (int c = 0; c < m->info.components && result == 1; c++)
        result = compute_component_convex(m, c);
    if (result == 1 && m->info.components > 1) {
        std::vector<int> faces((size_t)nt), verts;
        std::iota(faces.begin(), faces.end(), 0);
        verts = m->tri;
        std::sort(verts.begin(), verts.end());
        verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
        if ((double)faces.size() * (double)verts.size() > kConvexTestBudget)
            result = kUnknown;
        else
            result = all_in_front(*m, faces, verts) ? 1 : 0;
    }
    m->convex_inside = result;
    return result;
}

extern "C" {

rad_status rad_mesh_create(const double *xyz, int nv, const int *tri, int nt,
                           const int *input_face, rad_mesh **out)
{
    if (!out)
        return RAD_ERROR(RAD_EINVAL, "rad_mesh_create: out is NULL");
    *out = nullptr;
    return radmesh::guarded("mesh", [&]() -> rad_status {
        *out = radmesh::build(xyz, nv, tri, nt, input_face);
        return RAD_OK;
    });
}

void rad_mesh_destroy(rad_mesh *mesh) { delete mesh; }

int rad_mesh_vertex_count(const rad_mesh *mesh) { return mesh ? (int)(mesh->xyz.size() / 3) : 0; }
int rad_mesh_face_count(const rad_mesh *mesh) { return mesh ? (int)(mesh->tri.size() / 3) : 0; }
const double *rad_mesh_vertices(const rad_mesh *mesh) { return mesh ? mesh->xyz.data() : nullptr; }
const int *rad_mesh_triangles(const rad_mesh *mesh) { return mesh ? mesh->tri.data() : nullptr; }
const int *rad_mesh_input_faces(const rad_mesh *mesh) { return mesh ? mesh->input_face.data() : nullptr; }
int rad_mesh_pair_count(const rad_mesh *mesh) { return mesh ? (int)mesh->pairs.size() : 0; }
const rad_mesh_pair *rad_mesh_pairs(const rad_mesh *mesh) { return mesh ? mesh->pairs.data() : nullptr; }
const int *rad_mesh_face_components(const rad_mesh *mesh) { return mesh ? mesh->component.data() : nullptr; }

int rad_mesh_component_closed(const rad_mesh *mesh, int component)
{
    if (!mesh || component < 0 || component >= mesh->info.components)
        return -1;
    return mesh->comp_closed[(size_t)component];
}

int rad_mesh_component_convex(const rad_mesh *mesh, int component)
{
    if (!mesh || component < 0 || component >= mesh->info.components)
        return -1;
    int result = -1;
    rad_status st = radmesh::guarded("mesh convexity", [&]() -> rad_status {
        result = compute_component_convex(mesh, component);
        return RAD_OK;
    });
    return st == RAD_OK && result != kUnknown ? result : -1;
}

void rad_mesh_get_info(const rad_mesh *mesh, rad_mesh_info *info)
{
    if (!info)
        return;
    *info = rad_mesh_info{};
    if (!mesh)
        return;
    int convex = -1;
    radmesh::guarded("mesh convexity", [&]() -> rad_status {
        convex = compute_convex_inside(mesh);
        return RAD_OK;
    });
    *info = mesh->info;
    info->convex_inside = convex == kUnknown ? -1 : convex;
}

rad_status rad_mesh_check_surface(const rad_mesh *mesh, rad_mesh_surface_check *out)
{
    if (!mesh || !out)
        return RAD_ERROR(RAD_EINVAL, "rad_mesh_check_surface: NULL argument");
    *out = {0, -1, -1};
    return radmesh::guarded("mesh surface check", [&]() -> rad_status {
        check_surface(*mesh, *out);
        return RAD_OK;
    });
}

} // extern "C"
