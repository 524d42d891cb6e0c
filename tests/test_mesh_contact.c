/* rad_mesh_split_contacts: triangles cut along the lines where others stand
 * on them.  A box on a floor must cut the floor so that the pieces inside
 * its footprint cover exactly the footprint's area (no piece straddles the
 * line); the pieces of every triangle cover its area and keep its plane and
 * orientation; a box hovering within 1% of its size cuts the floor as if
 * it stood on it; a box lifted farther, a wall along a floor's edge, a
 * triangle in the floor's plane or below it, and a triangle passing through
 * the floor, cut nothing; a bad index is refused, a degenerate triangle left
 * alone. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_geom.h"
#include "rad_mesh.h"

typedef struct soup {
    double xyz[3 * 64];
    int tri[3 * 64];
    int nv, nt;
} soup;

static int vert(soup *s, double x, double y, double z)
{
    s->xyz[3 * s->nv] = x;
    s->xyz[3 * s->nv + 1] = y;
    s->xyz[3 * s->nv + 2] = z;
    return s->nv++;
}

static void face(soup *s, int a, int b, int c)
{
    s->tri[3 * s->nt] = a;
    s->tri[3 * s->nt + 1] = b;
    s->tri[3 * s->nt + 2] = c;
    s->nt++;
}

/* The floor [0, L]^2 at z = 0 facing +z, cut by its diagonal from (0, 0) to
 * (L, L): triangles 0 and 1. */
static void floor_of(soup *s, double L)
{
    int a = vert(s, 0, 0, 0), b = vert(s, L, 0, 0), c = vert(s, L, L, 0), d = vert(s, 0, L, 0);
    face(s, a, b, c);
    face(s, a, c, d);
}

static void floor2(soup *s)
{
    floor_of(s, 2.0);
}

/* A box of half side h around (x, y) turned by deg degrees, from z0 to z0
 * + 0.7, four sides and a top facing out (no bottom, as the Cornell box's);
 * its footprint's corners in fp[4][2]. */
static void box_at(soup *s, double x, double y, double deg, double h, double z0, double fp[4][2])
{
    double r = deg * 3.14159265358979323846 / 180.0, c = cos(r), sn = sin(r);
    double u[4][2] = {{-h, -h}, {h, -h}, {h, h}, {-h, h}};
    int lo[4], hi[4];
    for (int k = 0; k < 4; k++) {
        fp[k][0] = x + c * u[k][0] - sn * u[k][1];
        fp[k][1] = y + sn * u[k][0] + c * u[k][1];
        lo[k] = vert(s, fp[k][0], fp[k][1], z0);
        hi[k] = vert(s, fp[k][0], fp[k][1], z0 + 0.7);
    }
    for (int k = 0; k < 4; k++) {
        int j = (k + 1) % 4;
        face(s, lo[k], lo[j], hi[j]);
        face(s, lo[k], hi[j], hi[k]);
    }
    face(s, hi[0], hi[1], hi[2]);
    face(s, hi[0], hi[2], hi[3]);
}

/* The box around (1, 1) turned by 30 degrees: two corners on each side of
 * the floor's diagonal. */
static void box(soup *s, double h, double z0, double fp[4][2])
{
    box_at(s, 1.0, 1.0, 30.0, h, z0, fp);
}

static rad_vec3 at(const double *xyz, int v)
{
    return rad_vec3_make(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
}

static rad_vec3 normal_of(const double *xyz, const int *t)
{
    rad_vec3 a = at(xyz, t[0]), b = at(xyz, t[1]), c = at(xyz, t[2]);
    return rad_vec3_cross(rad_vec3_sub(b, a), rad_vec3_sub(c, a));
}

/* Inside the convex footprint (counter-clockwise corners). */
static int in_footprint(double fp[4][2], double x, double y)
{
    for (int k = 0; k < 4; k++) {
        int j = (k + 1) % 4;
        double cr = (fp[j][0] - fp[k][0]) * (y - fp[k][1]) - (fp[j][1] - fp[k][1]) * (x - fp[k][0]);
        if (cr < 0.0)
            return 0;
    }
    return 1;
}

/* Each input triangle's pieces cover its area, lie in its plane and face
 * its way; uncut triangles come through unchanged. */
static void check_pieces(const soup *s, const rad_mesh_contacts *m)
{
    double *area = calloc((size_t)s->nt, sizeof *area);
    for (size_t p = 0; p < m->nt; p++) {
        int f = m->parent[p];
        CHECK(f >= 0 && f < s->nt);
        rad_vec3 np = normal_of(m->xyz, m->tri + 3 * p), nf = normal_of(s->xyz, s->tri + 3 * f);
        double a = 0.5 * rad_vec3_norm(np);
        area[f] += a;
        CHECK_MSG(rad_vec3_dot(np, nf) > (1.0 - 1e-12) * rad_vec3_norm(np) * rad_vec3_norm(nf),
                  "piece %zu turned against triangle %d", p, f);
        rad_vec3 o = at(s->xyz, s->tri[3 * f]);
        for (int k = 0; k < 3; k++) {
            double h = rad_vec3_dot(rad_vec3_sub(at(m->xyz, m->tri[3 * p + k]), o), nf) /
                       rad_vec3_norm(nf);
            CHECK_MSG(fabs(h) < 1e-14, "piece %zu leaves the plane of %d by %g", p, f, h);
        }
    }
    for (int f = 0; f < s->nt; f++) {
        double want = 0.5 * rad_vec3_norm(normal_of(s->xyz, s->tri + 3 * f));
        CHECK_NEAR(area[f], want, 1e-12, 0.0);
    }
    free(area);
}

/* The floor's pieces (the first n of m): none straddles the footprint's
 * edges (sample points inside each piece are all in or all out); returns
 * the area of those inside it. */
static double footprint_area(const rad_mesh_contacts *m, size_t n, double fp[4][2])
{
    double inside = 0.0;
    for (size_t p = 0; p < n; p++) {
        rad_vec3 v[3];
        for (int k = 0; k < 3; k++)
            v[k] = at(m->xyz, m->tri[3 * p + k]);
        rad_vec3 c = rad_vec3_scale(rad_vec3_add(rad_vec3_add(v[0], v[1]), v[2]), 1.0 / 3.0);
        int in = in_footprint(fp, c.x, c.y);
        for (int k = 0; k < 3; k++) {
            rad_vec3 q = rad_vec3_add(rad_vec3_scale(v[k], 0.9), rad_vec3_scale(c, 0.1));
            CHECK_MSG(in_footprint(fp, q.x, q.y) == in, "piece %zu straddles the footprint", p);
        }
        if (in)
            inside += 0.5 * rad_vec3_norm(normal_of(m->xyz, m->tri + 3 * p));
    }
    return inside;
}

/* The box standing on the floor, and hovering 5 mm above it (0.54% of its
 * sides' longest edge, within the 1% that counts as hovering), cuts the
 * floor along its footprint; with hovering off (0) the hovering box cuts
 * nothing. */
TEST(contact_box_on_or_just_above_the_floor_cuts_it_along_its_footprint)
{
    const double lift[2] = {0.0, 0.005};
    for (int h = 0; h < 2; h++) {
        soup s = {0};
        double fp[4][2];
        floor2(&s);
        box(&s, 0.3, lift[h], fp);
        rad_mesh_contacts m;
        CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 1e-2, 1e-2, 0, &m) ==
              RAD_OK);
        CHECK(m.faces_split == 2); /* the footprint straddles the floor's diagonal */
        /* the bottom edges of four side triangles: the two that cross the
           diagonal on both floor triangles, the other two on one each */
        CHECK(m.segments == 6);
        check_pieces(&s, &m); /* the pieces lie in the floor's plane */
        /* the box's ten triangles are copied unchanged, after the floor's pieces */
        size_t box_first = m.nt - 10;
        for (int t = 2; t < s.nt; t++) {
            size_t p = box_first + (size_t)(t - 2);
            CHECK(m.parent[p] == t);
            CHECK(memcmp(m.tri + 3 * p, s.tri + 3 * t, 3 * sizeof(int)) == 0);
        }
        /* no piece straddles the footprint's edges, and the pieces in cover it */
        CHECK_NEAR(footprint_area(&m, box_first, fp), 0.36, 1e-12, 0.0);
        rad_mesh_contacts_free(&m);
        if (h == 1) {
            CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 0.0,
                                          0.0, 0, &m) == RAD_OK);
            CHECK(m.faces_split == 0 && m.nt == (size_t)s.nt);
            rad_mesh_contacts_free(&m);
        }
    }
}

/* A box (half side 0.3, height 0.7: its side triangles' longest edge 0.92)
 * hovering 15 cm (0.16 of that) above a floor.  Over an 8 m floor, whose
 * triangles are more than RAD_MESH_HOVER_LARGE times larger, the reach over
 * a large triangle (a quarter) cuts the floor along the footprint, and the
 * reach over any (a tenth) alone cuts nothing; over the 2 m floor (3.1
 * times larger) a quarter over large triangles cuts nothing either. */
TEST(contact_hovering_reaches_further_over_a_large_triangle)
{
    for (int big = 0; big < 2; big++) {
        soup s = {0};
        double fp[4][2], L = big ? 8.0 : 2.0;
        floor_of(&s, L);
        box_at(&s, 0.5 * L, 0.5 * L, 30.0, 0.3, 0.15, fp);
        rad_mesh_contacts m;
        CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 0.1, 0.25, 0,
                                      &m) == RAD_OK);
        CHECK_MSG(m.faces_split == (big ? 2u : 0u), "floor %g m: %zu cut", L, m.faces_split);
        if (big) {
            check_pieces(&s, &m);
            CHECK_NEAR(footprint_area(&m, m.nt - 10, fp), 0.36, 1e-12, 0.0);
        }
        rad_mesh_contacts_free(&m);
        CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 0.1, 0.1, 0,
                                      &m) == RAD_OK);
        CHECK(m.faces_split == 0 && m.nt == (size_t)s.nt);
        rad_mesh_contacts_free(&m);
    }
}

/* A footprint with one corner across the floor's diagonal: that corner's
 * two edges cross the diagonal and, with it, close a triangle outside the
 * lower floor triangle (area 0.125).  The lower triangle's pieces must not
 * include it: each floor triangle's pieces cover its own area, and the
 * pieces inside the footprint its area. */
/* The floor with a box of half side h standing at (x, y), turned by deg,
 * cut (m): `split` floor triangles cut, the pieces checked (check_pieces),
 * and those inside the footprint covering its area 4 h^2 exactly. */
static void cut_floor_under_box(double x, double y, double deg, double h, size_t split,
                                rad_mesh_contacts *m)
{
    soup s = {0};
    double fp[4][2];
    floor2(&s);
    box_at(&s, x, y, deg, h, 0.0, fp);
    CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 1e-2, 1e-2, 0, m) ==
          RAD_OK);
    CHECK(m->faces_split == split);
    check_pieces(&s, m);
    CHECK_NEAR(footprint_area(m, m->nt - 10, fp), 4.0 * h * h, 1e-12, 0.0);
}

TEST(contact_cut_keeps_to_the_triangle_where_a_corner_crosses_its_edge)
{
    rad_mesh_contacts m;
    cut_floor_under_box(1.05, 0.95, 0.0, 0.3, 2, &m);
    rad_mesh_contacts_free(&m);
}

/* A small box (footprint 0.04 wide) near a corner of the floor: the plain
 * triangulation would join its footprint's corners to the floor's far
 * corners by slivers as long as the floor.  Every piece longer than the
 * refinement's span (a sixteenth of its triangle and four times the
 * longest segment: 0.177 here, the segments 0.04 long) has its smallest
 * angle above 20.7 degrees (squared sine at least 0.125), and the pieces
 * still cover the floor and the footprint exactly, a few dozen of them. */
TEST(contact_cut_leaves_no_long_slivers)
{
    rad_mesh_contacts m;
    cut_floor_under_box(1.7, 0.25, 10.0, 0.02, 1, &m);
    size_t floor_pieces = m.nt - 10;
    CHECK_MSG(floor_pieces > 10 && floor_pieces < 200, "%zu pieces", floor_pieces);
    double span = sqrt(8.0) / 16.0;
    for (size_t p = 0; p < floor_pieces; p++) {
        rad_vec3 v[3];
        double e2[3];
        for (int k = 0; k < 3; k++)
            v[k] = at(m.xyz, m.tri[3 * p + k]);
        for (int k = 0; k < 3; k++)
            e2[k] = rad_vec3_dot(rad_vec3_sub(v[(k + 1) % 3], v[k]),
                                 rad_vec3_sub(v[(k + 1) % 3], v[k]));
        int j = e2[0] >= e2[1] && e2[0] >= e2[2] ? 0 : e2[1] >= e2[2] ? 1 : 2;
        double a2 = rad_vec3_dot(normal_of(m.xyz, m.tri + 3 * p), normal_of(m.xyz, m.tri + 3 * p));
        double sine2 = a2 / (e2[j] * fmax(e2[(j + 1) % 3], e2[(j + 2) % 3]));
        if (e2[j] > span * span)
            CHECK_MSG(sine2 >= 0.125 * (1.0 - 1e-9), "piece %zu: longest edge %.3f, squared "
                      "sine %.3g", p, sqrt(e2[j]), sine2);
    }
    rad_mesh_contacts_free(&m);
}

TEST(contact_nothing_to_cut_when_lifted_along_an_edge_coplanar_or_behind)
{
    double fp[4][2];
    /* the box lifted 2 cm: its sides' bottom edges 2.2% of the sides' own
       size above the floor, beyond what counts as hovering (1%) */
    soup a = {0};
    floor2(&a);
    box(&a, 0.3, 0.02, fp);
    /* a wall standing on the floor's outer edge, one lying in the floor's
       plane, one below the floor touching it along a segment inside */
    soup b = {0};
    floor2(&b);
    int w0 = vert(&b, 0, 0, 0), w1 = vert(&b, 2, 0, 0), w2 = vert(&b, 1, 0, 1);
    face(&b, w0, w2, w1);
    int c0 = vert(&b, 0.5, 0.2, 0), c1 = vert(&b, 1.5, 0.2, 0), c2 = vert(&b, 1.0, 0.8, 0);
    face(&b, c0, c1, c2);
    int d0 = vert(&b, 0.5, 1.5, 0), d1 = vert(&b, 1.5, 1.5, 0), d2 = vert(&b, 1.0, 1.5, -0.5);
    face(&b, d0, d1, d2);
    soup *cases[2] = {&a, &b};
    for (int k = 0; k < 2; k++) {
        rad_mesh_contacts m;
        CHECK(rad_mesh_split_contacts(cases[k]->xyz, (size_t)cases[k]->nv, cases[k]->tri,
                                      (size_t)cases[k]->nt, 1e-6, 1e-2, 1e-2, 0, &m) == RAD_OK);
        CHECK_MSG(m.faces_split == 0 && m.nt == (size_t)cases[k]->nt, "case %d: %zu cut", k,
                  m.faces_split);
        CHECK(memcmp(m.tri, cases[k]->tri, 3 * (size_t)cases[k]->nt * sizeof(int)) == 0);
        rad_mesh_contacts_free(&m);
    }
}

TEST(contact_a_triangle_through_the_floor_cuts_nothing)
{
    /* a triangle passing through the floor: its crossing stays inside
       elements */
    soup s = {0};
    floor2(&s);
    int a = vert(&s, 0.5, 1.2, -0.5), b = vert(&s, 1.5, 1.2, -0.5), c = vert(&s, 1.0, 1.2, 0.5);
    face(&s, a, c, b);
    rad_mesh_contacts m;
    CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 1e-2, 1e-2, 0, &m) == RAD_OK);
    CHECK(m.faces_split == 0 && m.nt == 3);
    rad_mesh_contacts_free(&m);
}

TEST(contact_refuses_bad_input)
{
    soup s = {0};
    floor2(&s);
    rad_mesh_contacts m;
    CHECK(rad_mesh_split_contacts(NULL, 4, s.tri, 2, 1e-6, 1e-2, 1e-2, 0, &m) != RAD_OK);
    CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, -1.0, 1e-2, 1e-2, 0, &m) !=
          RAD_OK);
    /* the reach over a large triangle is at least the reach over any */
    CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 0.1, 0.05, 0, &m) ==
          RAD_EINVAL);
    /* tolerances must be finite, below 1 and not NaN (an infinite one would
       ask the candidate grid for no end of cells) */
    const double bad[3] = {INFINITY, NAN, 1.0};
    for (int k = 0; k < 3; k++) {
        CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, bad[k],
                                      bad[k], 0, &m) == RAD_EINVAL);
        CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 1e-2,
                                      bad[k], 0, &m) == RAD_EINVAL);
        CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, bad[k], 1e-2,
                                      1e-2, 0, &m) == RAD_EINVAL);
    }
    s.tri[1] = 17;
    CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 1e-2, 1e-2, 0, &m) ==
          RAD_EINPUT);
    CHECK(m.xyz == NULL && m.nt == 0);
    /* a degenerate triangle (0, 0, 2) neither cuts nor is cut */
    s.tri[1] = 0;
    CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 1e-2, 1e-2, 0, &m) == RAD_OK);
    CHECK(m.faces_split == 0 && m.nt == 2);
    rad_mesh_contacts_free(&m);
}

TEST(contact_survives_tiny_triangles_far_apart)
{
    /* a unit triangle and one of size 1e185 (the smallest that 1e200 can
       hold), 1e200 apart: cells of the mean size would number 1e15 a side;
       the grid is clamped and coarsened, and the call returns, cutting
       nothing */
    soup s = {0};
    int a = vert(&s, 0, 0, 0), b = vert(&s, 1, 0, 0), c = vert(&s, 0, 1, 0);
    face(&s, a, b, c);
    a = vert(&s, 1e200, 1e200, 1e200), b = vert(&s, 1e200 + 1e185, 1e200, 1e200);
    c = vert(&s, 1e200, 1e200 + 1e185, 1e200);
    face(&s, a, b, c);
    rad_mesh_contacts m;
    CHECK(rad_mesh_split_contacts(s.xyz, (size_t)s.nv, s.tri, (size_t)s.nt, 1e-6, 1e-2, 1e-2, 0, &m) == RAD_OK);
    CHECK(m.faces_split == 0 && m.nt == 2);
    rad_mesh_contacts_free(&m);
}

/* A floor of n x n unit squares with a box of half side 0.3 standing in
 * every third square of every third row: at n = 60 the grid has 625
 * occupied cells, enough that the candidate pairs are shared among
 * threads (from 64 cells). */
static void crowded_floor(int n, double **xyz, size_t *nv, int **tri, size_t *nt)
{
    int boxes = ((n + 2) / 3) * ((n + 2) / 3);
    *xyz = malloc(sizeof **xyz * 3 * (size_t)((n + 1) * (n + 1) + 8 * boxes));
    *tri = malloc(sizeof **tri * 3 * (size_t)(2 * n * n + 10 * boxes));
    CHECK(*xyz && *tri);
    size_t v = 0, t = 0;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++, v++) {
            (*xyz)[3 * v] = i;
            (*xyz)[3 * v + 1] = j;
            (*xyz)[3 * v + 2] = 0.0;
        }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
            int q[6] = {a, b, c, a, c, d};
            memcpy(*tri + 3 * t, q, sizeof q);
            t += 2;
        }
    for (int j = 0; j < n; j += 3)
        for (int i = 0; i < n; i += 3) {
            double fp[4][2] = {
                {i + 0.2, j + 0.2}, {i + 0.8, j + 0.2}, {i + 0.8, j + 0.8}, {i + 0.2, j + 0.8}};
            int lo[4], hi[4];
            for (int k = 0; k < 4; k++) {
                lo[k] = (int)v;
                double p[6] = {fp[k][0], fp[k][1], 0.0, fp[k][0], fp[k][1], 0.7};
                memcpy(*xyz + 3 * v, p, sizeof p);
                hi[k] = (int)v + 1;
                v += 2;
            }
            for (int k = 0; k < 4; k++) {
                int m = (k + 1) % 4, q[6] = {lo[k], lo[m], hi[m], lo[k], hi[m], hi[k]};
                memcpy(*tri + 3 * t, q, sizeof q);
                t += 2;
            }
            int top[6] = {hi[0], hi[1], hi[2], hi[0], hi[2], hi[3]};
            memcpy(*tri + 3 * t, top, sizeof top);
            t += 2;
        }
    *nv = v;
    *nt = t;
}

TEST(contact_cut_is_the_same_on_one_thread_or_two)
{
    double *xyz = NULL;
    int *tri = NULL;
    size_t nv, nt;
    crowded_floor(60, &xyz, &nv, &tri, &nt);
    rad_mesh_contacts one, two;
    CHECK(rad_mesh_split_contacts(xyz, nv, tri, nt, 1e-6, 0.1, 0.25, 1, &one) == RAD_OK);
    CHECK(rad_mesh_split_contacts(xyz, nv, tri, nt, 1e-6, 0.1, 0.25, 2, &two) == RAD_OK);
    /* every box cuts the floor triangles under its footprint */
    CHECK(one.faces_split >= 2 * 20 * 20);
    CHECK(one.nt == two.nt && one.nv == two.nv && one.faces_split == two.faces_split &&
          one.segments == two.segments);
    CHECK(one.nt == two.nt && memcmp(one.tri, two.tri, 3 * one.nt * sizeof *one.tri) == 0 &&
          memcmp(one.parent, two.parent, one.nt * sizeof *one.parent) == 0);
    CHECK(one.nv == two.nv && memcmp(one.xyz, two.xyz, 3 * one.nv * sizeof *one.xyz) == 0);
    rad_mesh_contacts_free(&one);
    rad_mesh_contacts_free(&two);
    free(xyz);
    free(tri);
}
