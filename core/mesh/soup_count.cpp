// Polygon counts of a mesh file by CGAL's own reader (CGAL::IO::read_polygon_soup:
// OFF, PLY, STL, OBJ, ...), an importer that shares no code with radkit's: the
// corpus test compares radkit's triangle counts with these.
#include <array>
#include <cstddef>
#include <vector>

#include "cgal_warnings_off.hpp"
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/IO/polygon_soup_io.h>
#include "cgal_warnings_on.hpp"

#include "mesh_internal.hpp"

using Point = CGAL::Exact_predicates_inexact_constructions_kernel::Point_3;

extern "C" rad_status rad_mesh_count_polygon_soup(const char *path, long *polygons,
                                                  long *triangles_if_fanned)
{
    if (!path || !polygons || !triangles_if_fanned)
        return RAD_ERROR(RAD_EINVAL, "rad_mesh_count_polygon_soup: NULL argument");
    return radmesh::guarded("rad_mesh_count_polygon_soup", [&]() -> rad_status {
        std::vector<Point> points;
        std::vector<std::vector<std::size_t>> faces;
        if (!CGAL::IO::read_polygon_soup(path, points, faces, CGAL::parameters::verbose(false)))
            return RAD_ERROR(RAD_EINPUT, "%s: CGAL's reader refuses the file", path);
        long t = 0;
        for (const auto &f : faces)
            if (f.size() >= 3)
                t += static_cast<long>(f.size()) - 2;
        *polygons = static_cast<long>(faces.size());
        *triangles_if_fanned = t;
        return RAD_OK;
    });
}
