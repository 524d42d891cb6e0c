// Internal to the CGAL shim: the mesh object and the exception barrier.
// Not a public header: C code never sees it.
#ifndef RAD_MESH_INTERNAL_HPP
#define RAD_MESH_INTERNAL_HPP

#include <exception>
#include <new>
#include <vector>

#include "rad_mesh.h"

struct rad_mesh {
    std::vector<double> xyz;       // 3 per vertex
    std::vector<int> tri;          // 3 per face
    std::vector<int> input_face;   // 1 per face
    std::vector<rad_mesh_pair> pairs;
    std::vector<int> component;    // per face
    std::vector<char> comp_closed; // per component
    // Faces and touching pairs grouped by component (compressed rows), so a
    // per-component question costs that component's size only.
    std::vector<int> comp_face_start, comp_faces, comp_pair_start, comp_pairs;
    // Convexity is computed on first request (it costs faces x vertices).
    mutable std::vector<signed char> comp_convex; // per component: -1 unknown
    mutable int convex_inside = -1;
    rad_mesh_info info{};
};

namespace radmesh {

// Run `body` (returning rad_status) inside the one exception barrier every
// exported function uses: std::bad_alloc -> RAD_ENOMEM, anything else ->
// RAD_EGEOM, with the exception's message kept.
template <class Body> rad_status guarded(const char *what, Body &&body) noexcept
{
    try {
        return body();
    } catch (const std::bad_alloc &) {
        return RAD_ERROR(RAD_ENOMEM, "%s: out of memory", what);
    } catch (const std::exception &e) {
        return RAD_ERROR(RAD_EGEOM, "%s: %s", what, e.what());
    } catch (...) {
        return RAD_ERROR(RAD_EGEOM, "%s: unknown exception in the geometry kernel", what);
    }
}

// Build and analyse a mesh (mesh.cpp); throws on failure.
rad_mesh *build(const double *xyz, int nv, const int *tri, int nt, const int *input_face);

} // namespace radmesh
#endif
