// Input triangles split along contact lines (rad_mesh_split_contacts).
//
// Where a surface stands on a triangle (a box on a floor), the radiosity of
// the triangle jumps along the line of contact: what lies under the box
// sees nothing and is seen by nothing.  An element that straddles the line
// carries the dark part in its mean (or its polynomial) to every receiver,
// also to the box's side, which sees only the lit part; refining only
// approaches the line.  So the triangle is cut along it before meshing:
//  1. Candidate pairs: axis-aligned boxes (grown by the tolerance) that
//     overlap, found through a uniform grid.
//  2. For triangles A and B, an edge of B on A's plane (both ends within
//     tol of it), or else hovering over it (both ends within near, B's
//     near_rel times its longest edge: under a box a hair above the floor
//     the floor is as dark as under one standing on it; near_rel_large
//     times it over an A at least RAD_MESH_HOVER_LARGE times B's size, whose
//     elements average the patch B sees with much else), is a contact
//     segment on A, projected onto A's plane, when the rest of B lies in
//     front of A and the edge passes through A's inside (its part within A
//     is not on A's boundary).  A triangle that passes through another (vertices
//     on both sides of its plane) cuts nothing: pieces cut along a crossing
//     have corners on the other surface, where the visibility clipping of
//     point form factors is not robust (non-finite values on interpenetrating
//     boxes), so crossings stay inside elements.  tol = rel_tol times the longer of the two
//     triangles' longest edges.  A triangle without a normal (degenerate,
//     not finite, or so small that its cross product underflows) neither
//     cuts nor is cut.
//  3. A triangle with contact segments is triangulated by a CGAL constrained
//     Delaunay triangulation [cgal:triangulation2] in the plane of its two
//     coordinates away from the largest normal component (exact predicates,
//     so the segments may cross each other and A's edges: the crossings are
//     constructed), with A's edges and the segments, not clipped to A, as
//     constraints; long slivers inside A are bisected (split()); the faces
//     whose centroids lie inside A are kept, in A's orientation, and new
//     vertices are lifted onto A's plane.  A piece the scene's degenerate
//     test refuses (a sliver where segments cross at a hair's angle) is
//     dropped and counted.
#include "rad_mesh.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <climits>
#include <cstring>
#include <stdexcept>
#include <new>
#include <vector>

#include <omp.h>

#include "cdt.hpp"
#include "mesh_internal.hpp"
#include "rad_geom.h"

namespace {

using Point2 = radmesh::CdtKernel::Point_2;
using CDT = radmesh::CDT;

struct Tri {
    const double *p[3];
    double n[3];  // unit normal
    double d;     // n . p[0]
    double size;  // longest edge
    double lo[3], hi[3];
    int axis;     // the coordinate dropped in the plane (largest |n|)
    bool ok;      // a normal: a triangle without one (degenerate, or so small
                  // that its cross product underflows) is left as it is
};

double dot(const double *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

struct Segment {
    double a[3], b[3];
};

// Step 2: the contact segment of B on A, if any: B's edge on A's plane
// (within tol), or, failing that, hovering over it (within near), with the
// rest of B in front, projected onto the plane.
bool contact(const Tri &A, const Tri &B, double tol, double near, Segment *out)
{
    double dist[3];
    for (int v = 0; v < 3; v++) {
        dist[v] = dot(A.n, B.p[v]) - A.d;
        if (dist[v] < -tol)
            return false; // behind A's plane: B passes through it, or lies behind
    }
    double pts[3][3];
    int np = 0;
    for (double reach : {tol, near}) {
        int low = 0, high = 0;
        for (int v = 0; v < 3; v++) {
            low += dist[v] <= reach;
            high += dist[v] > reach;
        }
        if (low == 2 && high == 1) {
            for (int v = 0; v < 3; v++)
                if (dist[v] <= reach) {
                    for (int i = 0; i < 3; i++)
                        pts[np][i] = B.p[v][i] - dist[v] * A.n[i];
                    np++;
                }
            break;
        }
        if (low > 0)
            return false; // a corner on the plane, but no edge: B touches at a point
    }
    if (np != 2)
        return false;
    double len2 = 0.0;
    for (int i = 0; i < 3; i++)
        len2 += (pts[1][i] - pts[0][i]) * (pts[1][i] - pts[0][i]);
    if (!(len2 > tol * tol))
        return false;
    // the part of the segment inside A: clip P(t) = P0 + t (P1 - P0) by A's
    // edges' inner half-planes, in 3D with A's normal
    double t0 = 0.0, t1 = 1.0;
    for (int e = 0; e < 3; e++) {
        const double *a = A.p[e], *b = A.p[(e + 1) % 3];
        double ed[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double in[3] = {A.n[1] * ed[2] - A.n[2] * ed[1], A.n[2] * ed[0] - A.n[0] * ed[2],
                        A.n[0] * ed[1] - A.n[1] * ed[0]}; // points into A
        double f0 = 0.0, f1 = 0.0;
        for (int i = 0; i < 3; i++) {
            f0 += in[i] * (pts[0][i] - a[i]);
            f1 += in[i] * (pts[1][i] - a[i]);
        }
        // inside: f >= margin (a hair inside, so that a segment along an edge
        // of A or just outside it is no contact with A's inside)
        double margin = 1e-9 * A.size * std::sqrt(dot(in, in));
        double g0 = f0 - margin, g1 = f1 - margin;
        if (g0 < 0.0 && g1 < 0.0)
            return false;
        if (g0 < 0.0)
            t0 = std::max(t0, g0 / (g0 - g1));
        else if (g1 < 0.0)
            t1 = std::min(t1, g0 / (g0 - g1));
    }
    if (!(t1 - t0 > 1e-9))
        return false;
    std::memcpy(out->a, pts[0], sizeof out->a);
    std::memcpy(out->b, pts[1], sizeof out->b);
    return true;
}

struct Output {
    std::vector<double> xyz;
    std::vector<int> tri, parent;
    size_t slivers = 0;
};

// the scene loader's and the hierarchy's degenerate test (rad_scene_params,
// rad_ff_params degenerate_rel_tol)
const double SLIVER_REL = 1e-12;

// At most this many points added to one input triangle to bisect its long
// slivers: a bound on the work, far above what a cut needs.
const size_t REFINE_POINTS = 20000;

// Step 3: triangle t of the input (corners v[3]) cut by its segments.
void split(const Tri &A, const int v[3], int t, const std::vector<Segment> &segs, Output &out)
{
    const int k = A.axis, i0 = (k + 1) % 3, i1 = (k + 2) % 3;
    CDT cdt;
    CDT::Vertex_handle c[3];
    for (int j = 0; j < 3; j++)
        c[j] = cdt.insert(Point2(A.p[j][i0], A.p[j][i1]));
    if (cdt.number_of_vertices() != 3)
        throw std::runtime_error("a triangle projects to fewer than three points");
    for (int j = 0; j < 3; j++)
        cdt.insert_constraint(c[j], c[(j + 1) % 3]);
    for (const Segment &s : segs)
        cdt.insert_constraint(Point2(s.a[i0], s.a[i1]), Point2(s.b[i0], s.b[i1]));
    // A face is kept when its centroid lies inside A (A's edges are
    // constraints, so no face straddles them).  A flood fill from outside
    // that stops at constraints would keep a region outside A that
    // segments close against one of A's edges (a footprint's corner across
    // the edge).
    const CGAL::Orientation turn = CGAL::orientation(c[0]->point(), c[1]->point(), c[2]->point());
    bool ccw = turn == CGAL::LEFT_TURN;
    auto inside = [&](CDT::Face_handle f) {
        const Point2 &p = f->vertex(0)->point(), &q = f->vertex(1)->point(),
                     &r = f->vertex(2)->point();
        Point2 m((p.x() + q.x() + r.x()) / 3.0, (p.y() + q.y() + r.y()) / 3.0);
        for (int j = 0; j < 3; j++)
            if (CGAL::orientation(c[j]->point(), c[(j + 1) % 3]->point(), m) != turn)
                return false;
        return true;
    };
    // The plain triangulation of a large triangle cut by a few short
    // segments joins the segments' ends to A's far corners by slivers as
    // long as A, which as elements no hierarchy can split below its
    // smallest area and no bounding sphere fits (such a piece is linked to
    // every object standing near it, through shafts across A).  So a
    // piece inside A longer than span (a sixteenth of A, and four times
    // A's longest segment: the scale of what stands on it) with an angle
    // under about 20.7 degrees (squared sine under 0.125, CGAL's mesh
    // criterion) has its longest edge bisected, the midpoint inserted into
    // that edge (the triangulation stays constrained Delaunay; a constraint
    // is split in two), round after round, until no such piece is left or
    // REFINE_POINTS are added.  Shorter slivers are left: refining them
    // would go on towards the crossings.
    double longest = 0.0;
    for (const Segment &sg : segs) {
        double d[3] = {sg.b[0] - sg.a[0], sg.b[1] - sg.a[1], sg.b[2] - sg.a[2]};
        longest = std::max(longest, std::sqrt(dot(d, d)));
    }
    const double span = std::max(A.size / 16.0, 4.0 * longest), span2 = span * span;
    for (size_t added = 0; added < REFINE_POINTS;) {
        std::vector<std::pair<CDT::Vertex_handle, CDT::Vertex_handle>> cut;
        for (CDT::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end();
             ++f) {
            double e2[3];
            for (int j = 0; j < 3; j++)
                e2[j] = CGAL::to_double(CGAL::squared_distance(f->vertex((j + 1) % 3)->point(),
                                                               f->vertex((j + 2) % 3)->point()));
            int j = e2[0] >= e2[1] && e2[0] >= e2[2] ? 0 : e2[1] >= e2[2] ? 1 : 2;
            double area = CGAL::to_double(
                CGAL::area(f->vertex(0)->point(), f->vertex(1)->point(), f->vertex(2)->point()));
            /* the smallest angle's squared sine: (2 area)^2 over the two
               longer edges' squared lengths, as CGAL's mesh criteria */
            /* a piece the scene's test calls degenerate is dropped below
               (its sine is not computed: its edges may be 0) */
            bool flat = std::fabs(area) <= SLIVER_REL * e2[j];
            double shorter = std::max(e2[(j + 1) % 3], e2[(j + 2) % 3]);
            if (flat || !(e2[j] > span2))
                continue;
            double sine2 = 4.0 * area * area / (e2[j] * shorter);
            if (sine2 < 0.125 && inside(f))
                cut.push_back({f->vertex((j + 1) % 3), f->vertex((j + 2) % 3)});
        }
        size_t before = cdt.number_of_vertices();
        for (const auto &e : cut) {
            /* the midpoint goes into the edge itself (a constraint is split
               in two): inserted as a free point it would lie a rounding off
               the edge and leave specks between them.  An edge an earlier
               insertion of the round removed is left to the next. */
            CDT::Face_handle f;
            int j;
            if (!cdt.is_edge(e.first, e.second, f, j))
                continue;
            const Point2 &p = e.first->point(), &q = e.second->point();
            cdt.insert(Point2((p.x() + q.x()) / 2.0, (p.y() + q.y()) / 2.0), CDT::EDGE, f, j);
        }
        if (cdt.number_of_vertices() == before)
            break;
        added += cdt.number_of_vertices() - before;
    }
    for (CDT::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
        f->info() = inside(f) ? 0 : 1;
    // the vertices: A's corners keep theirs, the others are lifted onto A's
    // plane when a kept face first uses them (-1: not yet)
    for (CDT::Finite_vertices_iterator h = cdt.finite_vertices_begin();
         h != cdt.finite_vertices_end(); ++h)
        h->info() = -1;
    for (int j = 0; j < 3; j++)
        c[j]->info() = v[j];
    auto id_of = [&](CDT::Vertex_handle h) {
        if (h->info() >= 0)
            return h->info();
        double u = h->point().x(), w = h->point().y(), x[3];
        x[i0] = u;
        x[i1] = w;
        x[k] = (A.d - A.n[i0] * u - A.n[i1] * w) / A.n[k];
        h->info() = (int)(out.xyz.size() / 3);
        out.xyz.insert(out.xyz.end(), x, x + 3);
        return h->info();
    };
    for (CDT::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
        if (f->info() != 0)
            continue;
        int a = id_of(f->vertex(0)), b = id_of(f->vertex(1)), d = id_of(f->vertex(2));
        // a sliver (segments crossing at a hair's angle) that the scene's
        // own test would call degenerate is dropped: its area is below
        // 1e-12 of its longest edge squared
        auto at = [&](int i) {
            const double *q = &out.xyz[3 * (size_t)i];
            return rad_vec3_make(q[0], q[1], q[2]);
        };
        if (rad_geom_triangle_is_degenerate(at(a), at(b), at(d), SLIVER_REL)) {
            out.slivers++;
            continue;
        }
        if (ccw)
            out.tri.insert(out.tri.end(), {a, b, d});
        else
            out.tri.insert(out.tri.end(), {a, d, b});
        out.parent.push_back(t);
    }
}

} // namespace

extern "C" void rad_mesh_contacts_free(rad_mesh_contacts *c)
{
    if (!c)
        return;
    std::free(c->xyz);
    std::free(c->tri);
    std::free(c->parent);
    std::memset(c, 0, sizeof *c);
}

extern "C" rad_status rad_mesh_split_contacts(const double *xyz, size_t nv, const int *tri,
                                              size_t nt, double rel_tol, double near_rel,
                                              double near_rel_large, int threads,
                                              rad_mesh_contacts *out)
{
    if (!out)
        return RAD_ERROR(RAD_EINVAL, "contacts: NULL argument");
    std::memset(out, 0, sizeof *out);
    if ((!xyz && nv) || (!tri && nt) || !(rel_tol >= 0.0 && rel_tol < 1.0) ||
        !(near_rel >= 0.0 && near_rel < 1.0) ||
        !(near_rel_large >= near_rel && near_rel_large < 1.0))
        return RAD_ERROR(RAD_EINVAL, "contacts: NULL argument, a tolerance outside [0, 1), or "
                                     "near_rel_large below near_rel");
    rad_status st = radmesh::guarded("contacts", [&]() -> rad_status {
        std::vector<Tri> T(nt);
        for (size_t t = 0; t < nt; t++) {
            Tri &A = T[t];
            for (int j = 0; j < 3; j++) {
                int v = tri[3 * t + j];
                if (v < 0 || (size_t)v >= nv)
                    return RAD_ERROR(RAD_EINPUT, "contacts: triangle %zu has a bad vertex index", t);
                A.p[j] = xyz + 3 * (size_t)v;
            }
            double u[3], w[3], size = 0.0;
            for (int i = 0; i < 3; i++) {
                u[i] = A.p[1][i] - A.p[0][i];
                w[i] = A.p[2][i] - A.p[0][i];
                A.lo[i] = std::min({A.p[0][i], A.p[1][i], A.p[2][i]});
                A.hi[i] = std::max({A.p[0][i], A.p[1][i], A.p[2][i]});
            }
            for (int j = 0; j < 3; j++) {
                const double *a = A.p[j], *b = A.p[(j + 1) % 3];
                double e2 = 0.0;
                for (int i = 0; i < 3; i++)
                    e2 += (b[i] - a[i]) * (b[i] - a[i]);
                size = std::max(size, std::sqrt(e2));
            }
            double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                           u[0] * w[1] - u[1] * w[0]};
            double len = std::sqrt(dot(n, n));
            A.ok = len > 0.0 && std::isfinite(len) && std::isfinite(size) &&
                   std::isfinite(A.lo[0] + A.lo[1] + A.lo[2] + A.hi[0] + A.hi[1] + A.hi[2]);
            if (!A.ok) {
                for (int i = 0; i < 3; i++)
                    A.lo[i] = A.hi[i] = 0.0; // out of the sweep's way
                A.size = 0.0;
                continue;
            }
            for (int i = 0; i < 3; i++)
                A.n[i] = n[i] / len;
            A.d = dot(A.n, A.p[0]);
            A.size = size;
            A.axis = 0;
            for (int i = 1; i < 3; i++)
                if (std::fabs(A.n[i]) > std::fabs(A.n[A.axis]))
                    A.axis = i;
        }
        // step 1: candidate pairs from a uniform grid of about 2 n cells,
        // cells about twice the mean triangle's size: every triangle is
        // entered in the cells its box meets, grown by the on-plane reach
        // and by how far it may hover over another (near_rel_large times its
        // own size), and a pair is examined in the one cell that holds the low
        // corner of the two grown boxes' overlap, so once
        double max_size = 0.0, mean_size = 0.0, glo[3] = {0, 0, 0}, ghi[3] = {0, 0, 0};
        size_t nok = 0;
        for (const Tri &A : T) {
            if (!A.ok)
                continue;
            for (int i = 0; i < 3; i++) {
                glo[i] = nok ? std::min(glo[i], A.lo[i]) : A.lo[i];
                ghi[i] = nok ? std::max(ghi[i], A.hi[i]) : A.hi[i];
            }
            max_size = std::max(max_size, A.size);
            mean_size += A.size;
            nok++;
        }
        std::vector<double> grow(nt, 0.0);
        double reach = 0.0; // the largest growth
        for (size_t t = 0; t < nt; t++)
            if (T[t].ok) {
                grow[t] = rel_tol * max_size + near_rel_large * T[t].size;
                reach = std::max(reach, grow[t]);
            }
        // how far, times its own size, B may hover over A and still cut it
        auto hover = [&](const Tri &A, const Tri &B) {
            return A.size >= RAD_MESH_HOVER_LARGE * B.size ? near_rel_large : near_rel;
        };
        double h = nok ? 2.0 * mean_size / (double)nok : 1.0;
        long dim[3];
        for (;;) {
            double cells = 1.0;
            for (int i = 0; i < 3; i++) {
                // clamped before the cast: a scene of tiny and huge triangles
                // may ask for more cells than a long holds
                double want = std::ceil((ghi[i] - glo[i] + 2 * reach) / h);
                dim[i] = want < 1e9 ? std::max(1L, (long)want) : 1000000000L;
                cells *= (double)dim[i];
            }
            if (cells <= 2.0 * (double)nok + 8.0)
                break;
            h *= 1.25;
        }
        auto cell_of = [&](int i, double x) {
            long c = (long)std::floor((x - glo[i] + reach) / h);
            return std::min(dim[i] - 1, std::max(0L, c));
        };
        std::vector<std::pair<long, int>> entries; // (cell, triangle)
        for (size_t t = 0; t < nt; t++) {
            const Tri &A = T[t];
            if (!A.ok)
                continue;
            long c0[3], c1[3];
            for (int i = 0; i < 3; i++) {
                c0[i] = cell_of(i, A.lo[i] - grow[t]);
                c1[i] = cell_of(i, A.hi[i] + grow[t]);
            }
            for (long x = c0[0]; x <= c1[0]; x++)
                for (long y = c0[1]; y <= c1[1]; y++)
                    for (long z = c0[2]; z <= c1[2]; z++)
                        entries.emplace_back((x * dim[1] + y) * dim[2] + z, (int)t);
        }
        std::sort(entries.begin(), entries.end());
        // the cells' runs of entries, examined on every thread; each thread
        // keeps what it finds and the segments go to their triangles after
        std::vector<size_t> runs;
        for (size_t e0 = 0; e0 < entries.size();) {
            runs.push_back(e0);
            long cell = entries[e0].first;
            while (e0 < entries.size() && entries[e0].first == cell)
                e0++;
        }
        runs.push_back(entries.size());
        const long nruns = (long)runs.size() - 1;
        int nthreads = threads > 0 ? threads : omp_get_max_threads();
        std::vector<std::vector<std::pair<int, Segment>>> found((size_t)nthreads);
        bool short_of_memory = false; // an exception may not leave a parallel loop
#pragma omp parallel for schedule(dynamic, 16) num_threads(nthreads) if (nruns > 64)
        for (long r = 0; r < nruns; r++) {
            std::vector<std::pair<int, Segment>> &mine = found[(size_t)omp_get_thread_num()];
            try {
                size_t e0 = runs[(size_t)r], e1 = runs[(size_t)r + 1];
                long cell = entries[e0].first;
                for (size_t ei = e0; ei < e1; ei++)
                    for (size_t ej = ei + 1; ej < e1; ej++) {
                        int ia = entries[ei].second, ib = entries[ej].second;
                        const Tri &A = T[(size_t)ia], &B = T[(size_t)ib];
                        double tol = rel_tol * std::max(A.size, B.size);
                        double ga = grow[(size_t)ia], gb = grow[(size_t)ib];
                        bool overlap = true;
                        long home = 0;
                        for (int i = 0; i < 3; i++) {
                            overlap = overlap && B.lo[i] - gb <= A.hi[i] + ga &&
                                      A.lo[i] - ga <= B.hi[i] + gb;
                            home = home * dim[i] + cell_of(i, std::max(A.lo[i] - ga, B.lo[i] - gb));
                        }
                        if (!overlap || home != cell)
                            continue;
                        Segment sg;
                        if (contact(A, B, tol, std::max(tol, hover(A, B) * B.size), &sg))
                            mine.emplace_back(ia, sg);
                        if (contact(B, A, tol, std::max(tol, hover(B, A) * A.size), &sg))
                            mine.emplace_back(ib, sg);
                    }
            } catch (const std::bad_alloc &) {
#pragma omp atomic write
                short_of_memory = true;
            }
        }
        if (short_of_memory)
            throw std::bad_alloc();
        std::vector<std::vector<Segment>> segs(nt);
        for (const auto &mine : found)
            for (const auto &f : mine)
                segs[(size_t)f.first].push_back(f.second);
        // a triangle's segments in one order, whatever found them first
        for (std::vector<Segment> &v : segs)
            std::sort(v.begin(), v.end(), [](const Segment &x, const Segment &y) {
                return std::lexicographical_compare(x.a, x.a + 3, y.a, y.a + 3) ||
                       (std::equal(x.a, x.a + 3, y.a) &&
                        std::lexicographical_compare(x.b, x.b + 3, y.b, y.b + 3));
            });
        // step 3
        Output o;
        o.xyz.assign(xyz, xyz + 3 * nv);
        size_t split_faces = 0, nseg = 0;
        for (size_t t = 0; t < nt; t++) {
            if (segs[t].empty()) {
                o.tri.insert(o.tri.end(), tri + 3 * t, tri + 3 * t + 3);
                o.parent.push_back((int)t);
                continue;
            }
            split_faces++;
            nseg += segs[t].size();
            split(T[t], tri + 3 * t, (int)t, segs[t], o);
        }
        if (o.xyz.size() / 3 > (size_t)INT_MAX || o.parent.size() > (size_t)INT_MAX / 3)
            return RAD_ERROR(RAD_ETOOBIG, "contacts: too many pieces");
        out->nv = o.xyz.size() / 3;
        out->nt = o.parent.size();
        out->xyz = (double *)std::malloc(o.xyz.size() * sizeof(double));
        out->tri = (int *)std::malloc(o.tri.size() * sizeof(int));
        out->parent = (int *)std::malloc(o.parent.size() * sizeof(int));
        if (!out->xyz || !out->tri || !out->parent)
            return RAD_ERROR(RAD_ENOMEM, "contacts: no memory for %zu pieces", o.parent.size());
        std::memcpy(out->xyz, o.xyz.data(), o.xyz.size() * sizeof(double));
        std::memcpy(out->tri, o.tri.data(), o.tri.size() * sizeof(int));
        std::memcpy(out->parent, o.parent.data(), o.parent.size() * sizeof(int));
        out->faces_split = split_faces;
        out->segments = nseg;
        out->slivers = o.slivers;
        return RAD_OK;
    });
    if (st != RAD_OK)
        rad_mesh_contacts_free(out);
    return st;
}
