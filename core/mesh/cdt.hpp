// Internal to the CGAL shim: the constrained Delaunay triangulation that
// conform.cpp and contact.cpp cut polygons with [cgal:triangulation2], and
// (for conform.cpp, whose constraints are a polygon's boundary only) which
// of its faces lie outside that boundary.
#ifndef RAD_MESH_CDT_HPP
#define RAD_MESH_CDT_HPP

#include <deque>

#include "cgal_warnings_off.hpp"
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include "cgal_warnings_on.hpp"

namespace radmesh {

using CdtKernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using CdtVb = CGAL::Triangulation_vertex_base_with_info_2<int, CdtKernel>;
using CdtFb = CGAL::Triangulation_face_base_with_info_2<int, CdtKernel,
                                                        CGAL::Constrained_triangulation_face_base_2<CdtKernel>>;
using CdtTds = CGAL::Triangulation_data_structure_2<CdtVb, CdtFb>;
// Exact predicates; where constraints cross, the crossing is constructed.
using CDT = CGAL::Constrained_Delaunay_triangulation_2<CdtKernel, CdtTds, CGAL::Exact_predicates_tag>;

// Every face's info: 1 outside the constrained boundary (reached by a flood
// fill from the infinite face that stops at constraints), 0 inside.
inline void cdt_mark_outside(CDT &cdt)
{
    for (CDT::All_faces_iterator f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
        f->info() = 0;
    std::deque<CDT::Face_handle> queue{cdt.infinite_face()};
    cdt.infinite_face()->info() = 1;
    while (!queue.empty()) {
        CDT::Face_handle f = queue.front();
        queue.pop_front();
        for (int e = 0; e < 3; e++) {
            CDT::Face_handle g = f->neighbor(e);
            if (g->info() == 0 && !cdt.is_constrained(CDT::Edge(f, e))) {
                g->info() = 1;
                queue.push_back(g);
            }
        }
    }
}

} // namespace radmesh

#endif
