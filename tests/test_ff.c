/* rad_ff against independent references: Howell's closed forms (B-3, C-11,
 * C-14), coaxial disks as a polygon limit, closed-scene identities, reciprocity
 * and invariances, and the hard cases every scheme must survive. */
#include <math.h>
#include <pthread.h>
#include <string.h>

#include "ff_internal.h"
#include "harness.h"
#include "rad_ff.h"
#include "rad_quad.h"


static rad_vec3 V(double x, double y, double z) { return rad_vec3_make(x, y, z); }

static rad_ff_result ff(const rad_vec3 *a, const rad_vec3 *b, const char *rule)
{
    rad_ff_rule r;
    rad_ff_result o;
    memset(&o, 0, sizeof o);
    if (rad_ff_rule_parse(rule, &r) != RAD_OK) {
        harness_fail(__FILE__, __LINE__, "rule %s does not parse", rule);
        return o;
    }
    rad_status st = rad_ff_compute(a, b, r, NULL, &o);
    CHECK_MSG(st == RAD_OK, "%s: status %d (%s)", rule, (int)st, rad_error_message());
    return o;
}

/* Sum of G over the 2 x 2 triangle pairs of two rectangles. */
static double rect_G(rad_vec3 r1[2][3], rad_vec3 r2[2][3], const char *rule, double *worst_err)
{
    double G = 0.0;
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2; j++) {
            rad_ff_result o = ff(r1[i], r2[j], rule);
            G += o.G;
            if (worst_err && isfinite(o.rel_error))
                *worst_err = fmax(*worst_err, o.rel_error);
        }
    return G;
}

static void c11_rects(double a, double b, double c, rad_vec3 r1[2][3], rad_vec3 r2[2][3])
{
    rad_vec3 t1[2][3] = {{V(0, 0, 0), V(a, 0, 0), V(a, b, 0)}, {V(0, 0, 0), V(a, b, 0), V(0, b, 0)}};
    rad_vec3 t2[2][3] = {{V(0, 0, c), V(0, b, c), V(a, b, c)}, {V(0, 0, c), V(a, b, c), V(a, 0, c)}};
    memcpy(r1, t1, sizeof t1);
    memcpy(r2, t2, sizeof t2);
}

static void c14_rects(double l, double w, double h, rad_vec3 r1[2][3], rad_vec3 r2[2][3])
{
    rad_vec3 t1[2][3] = {{V(0, 0, 0), V(l, 0, 0), V(l, w, 0)}, {V(0, 0, 0), V(l, w, 0), V(0, w, 0)}};
    rad_vec3 t2[2][3] = {{V(0, 0, 0), V(0, 0, h), V(l, 0, h)}, {V(0, 0, 0), V(l, 0, h), V(l, 0, 0)}};
    memcpy(r1, t1, sizeof t1);
    memcpy(r2, t2, sizeof t2);
}

TEST(ff_kernel_clamps_each_cosine)
{
    rad_vec3 x = V(0.1, 0.2, 0.3), nx = V(0, 0, 1), y = V(0.4, -0.3, 1.7), ny = V(0, 0.6, -0.8);
    rad_vec3 d = rad_vec3_sub(y, x);
    double r2 = rad_vec3_dot(d, d);
    double want = rad_vec3_dot(nx, d) * -rad_vec3_dot(ny, d) / (RAD_PI * r2 * r2);
    CHECK_NEAR(rad_ff_kernel(x, nx, y, ny, NULL), want, 1e-15, 0.0);
    /* Both cosines negative: the product is positive, the kernel must be 0. */
    CHECK(rad_ff_kernel(x, rad_vec3_scale(nx, -1), y, rad_vec3_scale(ny, -1), NULL) == 0.0);
    CHECK(rad_ff_kernel(x, rad_vec3_scale(nx, -1), y, ny, NULL) == 0.0);
    long guarded = 0;
    CHECK(rad_ff_kernel(x, nx, x, ny, &guarded) == 0.0 && guarded == 1);
}

/* Nested adaptive quadrature of the point-to-triangle definition. */
typedef struct pt_ctx {
    rad_vec3 x, n, a, b, c, nt;
    double s;
} pt_ctx;

static double pt_inner(double t, void *v)
{
    pt_ctx *c = v;
    rad_vec3 y = rad_geom_triangle_point(c->a, c->b, c->c, c->s, t);
    return rad_ff_kernel(c->x, c->n, y, c->nt, NULL) * RAD_PI / RAD_PI;
}

static double pt_outer(double s, void *v)
{
    pt_ctx *c = v;
    c->s = s;
    rad_quad_adapt_params p;
    rad_quad_adapt_params_default(&p);
    p.rel_tol = 1e-12;
    p.abs_tol = 1e-15;
    rad_quad_result r;
    rad_quad_adapt(pt_inner, c, 0.0, 1.0 - s, NULL, 0, &p, &r);
    return r.value;
}

static double point_triangle_quadrature(rad_vec3 x, rad_vec3 n, const rad_vec3 t[3])
{
    pt_ctx c = {x, n, t[0], t[1], t[2], rad_geom_triangle_normal(t[0], t[1], t[2]), 0.0};
    rad_quad_adapt_params p;
    rad_quad_adapt_params_default(&p);
    p.rel_tol = 1e-11;
    p.abs_tol = 1e-14;
    rad_quad_result r;
    rad_quad_adapt(pt_outer, &c, 0.0, 1.0, NULL, 0, &p, &r);
    return 2.0 * rad_geom_triangle_area(t[0], t[1], t[2]) * r.value; /* dA = 2 A ds dt; kernel has 1/pi */
}

TEST(ff_point_polygon_matches_quadrature_of_its_definition)
{
    rad_vec3 t[3] = {V(-0.4, 0.3, 1.3), V(0.2, 1.1, 0.9), V(0.9, -0.2, 1.6)};
    /* Orient t to face the point below it. */
    rad_vec3 x = V(0.1, 0.2, -0.1);
    rad_vec3 nt = rad_geom_triangle_normal(t[0], t[1], t[2]);
    if (rad_vec3_dot(nt, rad_vec3_sub(x, t[0])) < 0) {
        rad_vec3 tmp = t[1];
        t[1] = t[2];
        t[2] = tmp;
    }
    rad_vec3 n = V(0.1, -0.2, 0.97);
    n = rad_vec3_scale(n, 1.0 / rad_vec3_norm(n));
    CHECK_NEAR(rad_ff_point_polygon(x, n, t, 3), point_triangle_quadrature(x, n, t), 1e-9, 0.0);
    /* Tilted so the triangle straddles x's plane: the clamp (clipping) acts. */
    rad_vec3 m = V(0.9, 0.1, 0.3);
    m = rad_vec3_scale(m, 1.0 / rad_vec3_norm(m));
    double got = rad_ff_point_polygon(x, m, t, 3), want = point_triangle_quadrature(x, m, t);
    CHECK(got > 0.0);
    CHECK_NEAR(got, want, 1e-7, 0.0);
    /* A point behind the polygon sees nothing. */
    CHECK(rad_ff_point_polygon(V(0.1, 0.2, 5.0), V(0, 0, -1), t, 3) == 0.0);
}

TEST(ff_point_polygon_matches_howell_b3)
{
    /* Differential area to a parallel rectangle a x b at distance c, the
     * element facing one corner (Howell B-3). */
    double a = 1.7, b = 0.6, c = 0.85, A = a / c, B = b / c;
    double want = (A / sqrt(1 + A * A) * atan(B / sqrt(1 + A * A)) +
                   B / sqrt(1 + B * B) * atan(A / sqrt(1 + B * B))) / (2 * RAD_PI);
    rad_vec3 rect[4] = {V(0, 0, c), V(0, b, c), V(a, b, c), V(a, 0, c)};
    CHECK_NEAR(rad_ff_point_polygon(V(0, 0, 0), V(0, 0, 1), rect, 4), want, 1e-14, 0.0);
}

static double log_integrand(double z, void *v)
{
    double h = *(double *)v;
    return 0.5 * log(z * z + h * h);
}

TEST(ff_log_segment_matches_quadrature_of_its_definition)
{
    double cases[][3] = {{-0.7, 1.3, 0.4}, {0.2, 2.385, 1e-3}, {-1.1, 0.6, 0.0}, {0.3, 0.9, 0.0}, {-2.0, -0.5, 3.1}};
    for (int k = 0; k < 5; k++) {
        double z0 = cases[k][0], z1 = cases[k][1], h = cases[k][2], zero = 0.0;
        rad_quad_adapt_params p;
        rad_quad_adapt_params_default(&p);
        p.rel_tol = 1e-14;
        rad_quad_result r;
        rad_quad_adapt(log_integrand, &h, z0, z1, &zero, 1, &p, &r);
        CHECK_NEAR(ff_log_segment(z0, z1, h), r.value, 1e-12, 1e-14);
    }
}

TEST(ff_exact_matches_howell_c11)
{
    double g[][3] = {{1.3, 0.7, 0.9}, {2.385, 1.1, 0.31}, {0.5, 0.45, 3.7}};
    for (int k = 0; k < 3; k++) {
        rad_vec3 r1[2][3], r2[2][3];
        c11_rects(g[k][0], g[k][1], g[k][2], r1, r2);
        double want = harness_howell_c11(g[k][0], g[k][1], g[k][2]);
        CHECK_NEAR(rect_G(r1, r2, "exact", NULL) / (g[k][0] * g[k][1]), want, 1e-12, 0.0);
    }
}

TEST(ff_exact_matches_howell_c14)
{
    double g[][3] = {{1.1, 0.8, 1.7}, {0.6, 2.385, 0.3}, {2.0, 0.5, 0.5}};
    for (int k = 0; k < 3; k++) {
        rad_vec3 r1[2][3], r2[2][3];
        c14_rects(g[k][0], g[k][1], g[k][2], r1, r2);
        double want = harness_howell_c14(g[k][0], g[k][1], g[k][2]);
        CHECK_NEAR(rect_G(r1, r2, "exact", NULL) / (g[k][0] * g[k][1]), want, 1e-12, 0.0);
        double err = 0.0;
        CHECK_NEAR(rect_G(r1, r2, "auto", &err) / (g[k][0] * g[k][1]), want, 1e-6, 0.0);
    }
}

/* The link parameters of hier and hierp (rad_ff_params_link_exact) keep
 * `exact` within 1e-6 (relative) of Howell's C-14 on a wall standing on a
 * floor, cut so that most triangle pairs touch without sharing a vertex (the
 * contact links they are for) and the rest share one, and each pair's error
 * estimate covers its true error. */
TEST(ff_exact_with_link_params_matches_howell_c14)
{
    double l = 1.3, w = 0.9, h = 0.7;
    rad_vec3 A = V(0, 0, 0), B = V(l, 0, 0), C = V(l, 0, h), D = V(0, 0, h);
    rad_vec3 P = V(l / 3, 0, 0), Q = V(l / 2, 0, 0), E = V(l, w, 0), Fp = V(0, w, 0);
    rad_vec3 wall[3][3] = {{A, D, P}, {P, C, B}, {P, D, C}};  /* facing +y */
    rad_vec3 floor_[3][3] = {{A, Q, Fp}, {Q, B, E}, {Q, E, Fp}}; /* facing +z */
    rad_ff_params def, link;
    rad_ff_params_default(&def);
    link = rad_ff_params_link_exact(&def);
    CHECK(link.exact_rel_tol > def.exact_rel_tol);
    double G = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            rad_ff_result o, ref;
            CHECK(rad_ff_compute(floor_[i], wall[j], (rad_ff_rule){RAD_FF_EXACT, 0}, &link, &o) ==
                  RAD_OK);
            CHECK(rad_ff_compute(floor_[i], wall[j], (rad_ff_rule){RAD_FF_EXACT, 0}, &def, &ref) ==
                  RAD_OK);
            CHECK_NEAR(o.G, ref.G, 1e-6, 0.0); /* each pair, against the reference's tolerance */
            CHECK(fabs(o.G - ref.G) <= o.rel_error * o.G);
            G += o.G;
        }
    CHECK_NEAR(G / (l * w), harness_howell_c14(l, w, h), 1e-6, 0.0);
}

/* Two coaxial regular n-gons (radius r1 at z = 0 facing up, r2 at z = h facing
 * down), each fanned from its centre; returns F_12 by `rule`. */
static double coaxial_polygons(int n, double r1, double r2, double h, const char *rule)
{
    double G = 0.0, A1 = 0.0;
    for (int i = 0; i < n; i++) {
        double a0 = 2 * RAD_PI * i / n, a1 = 2 * RAD_PI * (i + 1) / n;
        rad_vec3 ti[3] = {V(0, 0, 0), V(r1 * cos(a0), r1 * sin(a0), 0), V(r1 * cos(a1), r1 * sin(a1), 0)};
        A1 += rad_geom_triangle_area(ti[0], ti[1], ti[2]);
        for (int j = 0; j < n; j++) {
            double b0 = 2 * RAD_PI * j / n, b1 = 2 * RAD_PI * (j + 1) / n;
            rad_vec3 tj[3] = {V(0, 0, h), V(r2 * cos(b1), r2 * sin(b1), h), V(r2 * cos(b0), r2 * sin(b0), h)};
            G += ff(ti, tj, rule).G;
        }
    }
    return G / A1;
}

TEST(ff_coaxial_disks_as_polygon_limit)
{
    /* Disk to coaxial parallel disk (Howell C-41): R_i = r_i / h,
     * X = 1 + (1 + R2^2) / R1^2, F = (X - sqrt(X^2 - 4 (R2/R1)^2)) / 2.
     * The n-gon's F differs by c/n^2 + d/n^4 + O(1/n^6): two Richardson
     * steps on n = 12, 24, 48. */
    double r1 = 0.8, r2 = 1.3, h = 0.9, R1 = r1 / h, R2 = r2 / h;
    double X = 1 + (1 + R2 * R2) / (R1 * R1);
    double want = 0.5 * (X - sqrt(X * X - 4 * (R2 / R1) * (R2 / R1)));
    double f12 = coaxial_polygons(12, r1, r2, h, "exact"), f24 = coaxial_polygons(24, r1, r2, h, "exact");
    double f48 = coaxial_polygons(48, r1, r2, h, "exact");
    CHECK(fabs(f48 - want) < fabs(f24 - want) && fabs(f24 - want) < fabs(f12 - want)); /* converging */
    double q1 = (4 * f24 - f12) / 3, q2 = (4 * f48 - f24) / 3;
    CHECK_NEAR((16 * q2 - q1) / 15, want, 1e-7, 0.0);
}

/* The unit cube's 12 triangles, normals pointing inward. */
static void cube(rad_vec3 t[12][3], double s)
{
    /* Each face: 4 corners listed counter-clockwise seen from inside. */
    static const double f[6][4][3] = {
        {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, /* z = 0, normal +z */
        {{0, 0, 1}, {0, 1, 1}, {1, 1, 1}, {1, 0, 1}}, /* z = 1, normal -z */
        {{0, 0, 0}, {0, 1, 0}, {0, 1, 1}, {0, 0, 1}}, /* x = 0, normal +x */
        {{1, 0, 0}, {1, 0, 1}, {1, 1, 1}, {1, 1, 0}}, /* x = 1, normal -x */
        {{0, 0, 0}, {0, 0, 1}, {1, 0, 1}, {1, 0, 0}}, /* y = 0, normal +y */
        {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}}, /* y = 1, normal -y */
    };
    for (int k = 0; k < 6; k++) {
        int q[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int h = 0; h < 2; h++)
            for (int v = 0; v < 3; v++) {
                const double *p = f[k][q[h][v]];
                t[2 * k + h][v] = V(s * p[0], s * p[1], s * p[2]);
            }
    }
}

TEST(ff_closed_cube_rows_sum_to_one)
{
    rad_vec3 t[12][3];
    cube(t, 2.385);
    for (int i = 0; i < 12; i++) {
        rad_vec3 n = rad_geom_triangle_normal(t[i][0], t[i][1], t[i][2]);
        rad_vec3 c = rad_geom_triangle_centroid(t[i][0], t[i][1], t[i][2]);
        rad_vec3 mid = V(1.1925, 1.1925, 1.1925);
        CHECK(rad_vec3_dot(n, rad_vec3_sub(mid, c)) > 0); /* inward */
        double row_exact = 0.0, row_auto = 0.0, row_ss = 0.0;
        for (int j = 0; j < 12; j++) {
            row_exact += ff(t[i], t[j], "exact").F12;
            row_auto += ff(t[i], t[j], "auto").F12;
            row_ss += ff(t[i], t[j], "ss:10").F12;
        }
        CHECK_NEAR(row_exact, 1.0, 1e-12, 0.0);
        CHECK_NEAR(row_auto, 1.0, 1e-6, 0.0);
        CHECK_NEAR(row_ss, 1.0, 1e-5, 0.0);
    }
}

TEST(ff_regular_tetrahedron_face_to_face_is_one_third)
{
    /* Faces wound so the normals point inward. */
    rad_vec3 p[4] = {V(1, 1, 1), V(1, -1, -1), V(-1, 1, -1), V(-1, -1, 1)};
    int f[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    rad_vec3 t[4][3];
    for (int k = 0; k < 4; k++) {
        for (int v = 0; v < 3; v++)
            t[k][v] = p[f[k][v]];
        rad_vec3 n = rad_geom_triangle_normal(t[k][0], t[k][1], t[k][2]);
        rad_vec3 c = rad_geom_triangle_centroid(t[k][0], t[k][1], t[k][2]);
        if (rad_vec3_dot(n, c) > 0) { /* centroid of the solid is the origin */
            rad_vec3 tmp = t[k][1];
            t[k][1] = t[k][2];
            t[k][2] = tmp;
        }
    }
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            if (i == j)
                continue;
            rad_ff_result e = ff(t[i], t[j], "exact");
            CHECK(e.adjacency == RAD_FF_SHARE_EDGE);
            CHECK_NEAR(e.F12, 1.0 / 3.0, 1e-12, 0.0);
            CHECK_NEAR(ff(t[i], t[j], "ss:12").F12, 1.0 / 3.0, 1e-9, 0.0);
            CHECK_NEAR(ff(t[i], t[j], "auto").F12, 1.0 / 3.0, 1e-6, 0.0);
        }
}

/* A set of pairs with high-entropy coordinates covering every adjacency. */
enum { NPAIRS = 6 };
static void sample_pairs(rad_vec3 P[NPAIRS][2][3])
{
    rad_vec3 s[NPAIRS][2][3] = {
        /* disjoint, near */
        {{V(0, 0, 0), V(1.1, 0.1, 0), V(0.2, 0.9, 0.05)}, {V(0.1, 0.2, 0.7), V(0.3, 1.2, 0.9), V(1.3, 0.1, 0.6)}},
        /* disjoint, far */
        {{V(0, 0, 0), V(1.1, 0.1, 0), V(0.2, 0.9, 0.05)}, {V(0.4, 0.2, 6.7), V(0.6, 1.2, 6.9), V(1.6, 0.1, 6.6)}},
        /* edge-adjacent, 90 degrees */
        {{V(0, 0, 0), V(1, 0, 0), V(0.3, 0.8, 0)}, {V(0, 0, 0), V(0.4, 0, 0.9), V(1, 0, 0)}},
        /* edge-adjacent, obtuse (120 degrees) */
        {{V(0, 0, 0), V(1, 0, 0), V(0.35, 0.9, 0)}, {V(0, 0, 0), V(0.6, -0.5, 0.866), V(1, 0, 0)}},
        /* vertex-adjacent */
        {{V(0, 0, 0), V(1, 0.1, 0), V(0.2, 0.9, 0)}, {V(0, 0, 0), V(-0.3, 0.5, 0.8), V(0.6, -0.1, 1.1)}},
        /* straddling: t2 crosses t1's plane */
        {{V(0, 0, 0), V(1.1, 0.1, 0), V(0.2, 0.9, 0.05)}, {V(0.2, 0.3, -0.4), V(0.3, 1.2, 0.9), V(1.3, 0.1, 0.6)}},
    };
    memcpy(P, s, sizeof s);
    /* Orient the second triangle to face the first where needed. */
    for (int k = 0; k < NPAIRS; k++) {
        rad_vec3 n = rad_geom_triangle_normal(P[k][1][0], P[k][1][1], P[k][1][2]);
        rad_vec3 c = rad_geom_triangle_centroid(P[k][0][0], P[k][0][1], P[k][0][2]);
        if (rad_vec3_dot(n, rad_vec3_sub(c, P[k][1][0])) < 0) {
            rad_vec3 tmp = P[k][1][1];
            P[k][1][1] = P[k][1][2];
            P[k][1][2] = tmp;
        }
    }
}

TEST(ff_reciprocity_swapping_the_pair)
{
    rad_vec3 P[NPAIRS][2][3];
    sample_pairs(P);
    /* Each scheme on the pairs it is meant for: exact and auto everywhere,
     * analytic and gauss on separated pairs (0, 1), ss on adjacent ones (2-4). */
    const char *rules[] = {"exact", "auto", "analytic:20", "gauss:20", "ss:14"};
    double tol[] = {1e-12, 2e-6, 1e-6, 1e-6, 1e-9};
    int first[] = {0, 0, 0, 0, 2}, last[] = {NPAIRS - 1, NPAIRS - 1, 1, 1, 4};
    for (int r = 0; r < 5; r++)
        for (int k = first[r]; k <= last[r]; k++) {
            rad_ff_result a = ff(P[k][0], P[k][1], rules[r]), b = ff(P[k][1], P[k][0], rules[r]);
            CHECK_MSG(a.G > 0, "pair %d rule %s: G = %g", k, rules[r], a.G);
            CHECK_MSG(fabs(a.G - b.G) <= tol[r] * a.G, "pair %d rule %s: G %.17g swapped %.17g", k,
                      rules[r], a.G, b.G);
            CHECK_NEAR(a.F12 * a.A1, a.F21 * a.A2, 1e-15, 0.0);
            CHECK_NEAR(a.F12, b.F21, tol[r], 0.0);
        }
}

static rad_vec3 transform(rad_vec3 p, const double R[3][3], double s, rad_vec3 t)
{
    return V(s * (R[0][0] * p.x + R[0][1] * p.y + R[0][2] * p.z) + t.x,
             s * (R[1][0] * p.x + R[1][1] * p.y + R[1][2] * p.z) + t.y,
             s * (R[2][0] * p.x + R[2][1] * p.y + R[2][2] * p.z) + t.z);
}

TEST(ff_invariance_rotation_scaling_translation)
{
    rad_vec3 P[NPAIRS][2][3];
    sample_pairs(P);
    /* A rotation: axis (1, 2, 2)/3 by 0.737 rad (Rodrigues). */
    double ux = 1 / 3.0, uy = 2 / 3.0, uz = 2 / 3.0, c = cos(0.737), s = sin(0.737), C = 1 - c;
    double R[3][3] = {{c + ux * ux * C, ux * uy * C - uz * s, ux * uz * C + uy * s},
                      {uy * ux * C + uz * s, c + uy * uy * C, uy * uz * C - ux * s},
                      {uz * ux * C - uy * s, uz * uy * C + ux * s, c + uz * uz * C}};
    double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    struct {
        const double (*R)[3];
        double s;
        rad_vec3 t;
        double tol;
    } cases[] = {
        {(const double (*)[3])R, 1.0, V(0, 0, 0), 1e-13},
        {(const double (*)[3])I, 1e-4, V(0, 0, 0), 1e-13},
        {(const double (*)[3])I, 1e4, V(0, 0, 0), 1e-13},
        /* 1e6 from the origin the input itself is rounded to ~1e-10 of the
         * size, which bounds what any scheme can reproduce. */
        {(const double (*)[3])R, 1.0, V(1.3e6, -2.1e6, 0.7e6), 1e-8},
    };
    const char *rules[] = {"exact", "ss:6", "gauss:8", "analytic:6", "vertex", "centroid", "auto"};
    for (int k = 0; k < NPAIRS; k++)
        for (int q = 0; q < 4; q++)
            for (int r = 0; r < 7; r++) {
                rad_vec3 a[3], b[3];
                for (int v = 0; v < 3; v++) {
                    a[v] = transform(P[k][0][v], cases[q].R, cases[q].s, cases[q].t);
                    b[v] = transform(P[k][1][v], cases[q].R, cases[q].s, cases[q].t);
                }
                rad_ff_result o = ff(P[k][0], P[k][1], rules[r]), m = ff(a, b, rules[r]);
                CHECK_MSG(fabs(o.F12 - m.F12) <= cases[q].tol * fabs(o.F12) + 1e-300,
                          "pair %d case %d rule %s: F12 %.17g -> %.17g", k, q, rules[r], o.F12, m.F12);
                CHECK_NEAR(m.G, o.G * cases[q].s * cases[q].s, cases[q].tol, 0.0);
            }
}

TEST(ff_facing_away_and_coplanar_are_exactly_zero)
{
    rad_vec3 a[3] = {V(0, 0, 0), V(1.2, 0.1, 0), V(0.3, 0.9, 0)};
    rad_vec3 above_up[3] = {V(0, 0, 1), V(1, 0, 1), V(0, 1, 1)};        /* faces away (normal +z) */
    rad_vec3 below[3] = {V(0, 0, -1), V(0, 1, -1), V(1, 0, -1)};        /* behind a */
    rad_vec3 coplanar[3] = {V(2, 0, 0), V(3, 0.2, 0), V(2.5, 1, 0)};    /* same plane */
    rad_vec3 coplanar_adj[3] = {V(0, 0, 0), V(0.3, 0.9, 0), V(-1, 0.5, 0)};
    rad_vec3 *others[] = {above_up, below, coplanar, coplanar_adj};
    const char *rules[] = {"vertex", "centroid", "gauss:10", "analytic:4", "ss:4", "exact", "auto"};
    for (int k = 0; k < 4; k++)
        for (int r = 0; r < 7; r++) {
            rad_ff_result o = ff(a, others[k], rules[r]);
            CHECK(o.G == 0.0 && o.F12 == 0.0 && o.F21 == 0.0 && o.evals == 0);
            CHECK(o.flags & RAD_FF_FLAG_NOT_FACING);
        }
}

/* rad_ff_facing is rad_ff_compute's facing test: 0 on the four cases above,
 * and equal to the absence of RAD_FF_FLAG_NOT_FACING on random pairs, many of
 * which face away (hier skips the integration of a pair with it). */
TEST(ff_facing_predicate_matches_compute)
{
    rad_vec3 a[3] = {V(0, 0, 0), V(1.2, 0.1, 0), V(0.3, 0.9, 0)};
    rad_vec3 above_up[3] = {V(0, 0, 1), V(1, 0, 1), V(0, 1, 1)};
    rad_vec3 below[3] = {V(0, 0, -1), V(0, 1, -1), V(1, 0, -1)};
    rad_vec3 coplanar[3] = {V(2, 0, 0), V(3, 0.2, 0), V(2.5, 1, 0)};
    rad_vec3 coplanar_adj[3] = {V(0, 0, 0), V(0.3, 0.9, 0), V(-1, 0.5, 0)};
    rad_vec3 *others[] = {above_up, below, coplanar, coplanar_adj};
    for (int k = 0; k < 4; k++)
        CHECK(rad_ff_facing(a, others[k], NULL) == 0);
    rad_ff_params p;
    rad_ff_params_default(&p);
    unsigned seed = 12345u;
    int facing = 0, away = 0;
    for (int trial = 0; trial < 400; trial++) {
        rad_vec3 t[2][3];
        for (int k = 0; k < 2; k++)
            for (int v = 0; v < 3; v++) {
                double c[3];
                for (int j = 0; j < 3; j++) {
                    seed = seed * 1103515245u + 12345u;
                    c[j] = (double)(seed >> 8) / (double)(1u << 24) * 2.0 - 1.0;
                }
                t[k][v] = V(c[0], c[1], c[2]);
            }
        rad_ff_result o;
        if (rad_ff_compute(t[0], t[1], (rad_ff_rule){RAD_FF_CENTROID, 0}, &p, &o) != RAD_OK)
            continue; /* degenerate draw */
        int f = rad_ff_facing(t[0], t[1], &p);
        CHECK(f == !(o.flags & RAD_FF_FLAG_NOT_FACING));
        facing += f;
        away += !f;
    }
    CHECK(facing > 50 && away > 50); /* both branches were exercised */
}

TEST(ff_vertex_rule_is_the_notes_formula)
{
    /* The notes: int int H ~ (A_i A_j / 9) sum_k sum_l H(F_ik, F_jl), with
     * H = ((z - x) . n(x)) ((x - z) . n(z)) / |x - z|^4; F_ij = that / (pi A_i). */
    rad_vec3 P[NPAIRS][2][3];
    sample_pairs(P);
    for (int k = 0; k < 2; k++) { /* the two disjoint pairs: no clamping at vertices */
        rad_vec3 *a = P[k][0], *b = P[k][1];
        rad_vec3 na = rad_geom_triangle_normal(a[0], a[1], a[2]), nb = rad_geom_triangle_normal(b[0], b[1], b[2]);
        double Aa = rad_geom_triangle_area(a[0], a[1], a[2]), Ab = rad_geom_triangle_area(b[0], b[1], b[2]);
        double sum = 0.0;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                rad_vec3 d = rad_vec3_sub(b[j], a[i]);
                double r2 = rad_vec3_dot(d, d);
                double H = rad_vec3_dot(d, na) * rad_vec3_dot(rad_vec3_scale(d, -1), nb) / (r2 * r2);
                sum += fmax(H, 0.0);
            }
        double want = Aa * Ab / 9.0 * sum / (RAD_PI * Aa);
        rad_ff_result o = ff(a, b, "vertex");
        CHECK_NEAR(o.F12, want, 1e-13, 0.0);
        CHECK(o.evals == 9 && o.guarded == 0);
    }
    /* Edge-adjacent: two shared vertices give 0/0, guarded and counted. */
    rad_ff_result e = ff(P[2][0], P[2][1], "vertex");
    CHECK(e.guarded == 2 && (e.flags & RAD_FF_FLAG_GUARDED));
    CHECK(isfinite(e.F12) && e.F12 >= 0);
    rad_ff_result v = ff(P[4][0], P[4][1], "vertex");
    CHECK(v.guarded == 1);
}

/* Hard cases: every scheme returns finite, non-negative values. */
TEST(ff_hard_cases_no_nan_inf_or_negative)
{
    enum { MAXC = 40 };
    rad_vec3 c[MAXC][2][3];
    int n = 0;
    rad_vec3 base[3] = {V(0, 0, 0), V(1, 0, 0), V(0.35, 0.85, 0)};
    /* edge-adjacent at 30, 90 and 150 degrees between the faces' planes
     * (dihedral measured through the pair's common space) */
    double angles[] = {30, 60, 90, 120, 150, 175};
    for (int k = 0; k < 6; k++) {
        double th = angles[k] * RAD_PI / 180;
        memcpy(c[n][0], base, sizeof base);
        rad_vec3 t[3] = {V(0, 0, 0), V(0.55, 0.8 * cos(th), 0.8 * sin(th)), V(1, 0, 0)};
        memcpy(c[n++][1], t, sizeof t);
    }
    /* near-touching: a parallel facing triangle at gaps 1e-3 .. 1e-9 */
    for (double g = 1e-3; g >= 1e-9; g *= 0.01) {
        memcpy(c[n][0], base, sizeof base);
        rad_vec3 t[3] = {V(0.1, 0.05, g), V(0.4, 0.9, g), V(1.1, 0.1, g)};
        memcpy(c[n++][1], t, sizeof t);
        /* and an edge-adjacent pair opened by a gap */
        memcpy(c[n][0], base, sizeof base);
        rad_vec3 u[3] = {V(0, 0, g), V(0.4, -0.1, 0.9), V(1, 0, g)};
        memcpy(c[n++][1], u, sizeof u);
    }
    /* nearly coincident parallel triangles */
    for (double g = 1e-2; g >= 1e-8; g *= 1e-3) {
        memcpy(c[n][0], base, sizeof base);
        rad_vec3 t[3] = {V(0, 0, g), V(0.35, 0.85, g), V(1, 0, g)};
        memcpy(c[n++][1], t, sizeof t);
    }
    /* slivers of aspect 1e6 */
    {
        rad_vec3 s1[3] = {V(0, 0, 0), V(1, 0, 0), V(0.5, 1e-6, 0)};
        rad_vec3 s2[3] = {V(0, 0, 0.3), V(0.5, 1e-6, 0.3), V(1, 0, 0.3)};
        memcpy(c[n][0], s1, sizeof s1);
        memcpy(c[n++][1], s2, sizeof s2);
        rad_vec3 s3[3] = {V(0, 0, 0), V(0.5, -1e-6, 0.4), V(1, 0, 0)}; /* edge-adjacent sliver */
        memcpy(c[n][0], base, sizeof base);
        memcpy(c[n++][1], s3, sizeof s3);
    }
    /* vertex-adjacent, one facing pair and one straddling the other's plane */
    {
        rad_vec3 v1[3] = {V(0, 0, 0), V(-0.3, 0.5, 0.8), V(0.6, -0.1, 1.1)};
        memcpy(c[n][0], base, sizeof base);
        memcpy(c[n++][1], v1, sizeof v1);
        rad_vec3 v2[3] = {V(0.35, 0.85, 0), V(0.9, 1.2, 0.7), V(-0.2, 1.4, -0.3)};
        memcpy(c[n][0], base, sizeof base);
        memcpy(c[n++][1], v2, sizeof v2);
    }
    const char *rules[] = {"vertex", "centroid", "gauss:1", "gauss:7", "gauss:20", "analytic:2",
                           "analytic:10", "ss:3", "ss:8", "exact", "auto"};
    for (int k = 0; k < n; k++) {
        rad_ff_result ex = ff(c[k][0], c[k][1], "exact");
        CHECK_MSG(ex.G > 0, "case %d: exact G = %g (a hard case must couple)", k, ex.G);
        for (int r = 0; r < 11; r++) {
            rad_ff_result o = ff(c[k][0], c[k][1], rules[r]);
            CHECK_MSG(isfinite(o.F12) && isfinite(o.F21) && o.F12 >= 0 && o.F21 >= 0,
                      "case %d rule %s: F12 %g F21 %g", k, rules[r], o.F12, o.F21);
            int out = o.F12 > 1 || o.F21 > 1;
            CHECK_MSG(out == !!(o.flags & RAD_FF_FLAG_OUT_OF_RANGE), "case %d rule %s: flag", k, rules[r]);
        }
        CHECK_MSG(ex.F12 <= 1 + 1e-12 && ex.F21 <= 1 + 1e-12, "case %d: exact F12 %g", k, ex.F12);
        CHECK_MSG(ex.rel_error <= 1e-10 && !(ex.flags & RAD_FF_FLAG_NOT_CONVERGED),
                  "case %d: exact's own estimate %.3g", k, ex.rel_error);
        rad_ff_result au = ff(c[k][0], c[k][1], "auto");
        CHECK_MSG(fabs(au.G - ex.G) <= 1e-6 * ex.G, "case %d: auto %.17g exact %.17g (%s)", k, au.G, ex.G,
                  "auto misses its tolerance");
    }
    /* The notes' rule on nearly coincident triangles: far above 1, flagged. */
    rad_vec3 near[3] = {V(0, 0, 1e-4), V(0.35, 0.85, 1e-4), V(1, 0, 1e-4)};
    rad_ff_result v = ff(base, near, "vertex");
    CHECK(v.F12 > 1.0 && (v.flags & RAD_FF_FLAG_OUT_OF_RANGE));
    rad_ff_result e = ff(base, near, "exact");
    CHECK(e.F12 < 1.0 && e.F12 > 0.99);
}

TEST(ff_ss_reaches_1e10_on_edge_adjacent_90_degrees)
{
    /* Right isoceles faces at 90 degrees, and a less regular pair. */
    rad_vec3 a[3] = {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)}, b[3] = {V(0, 0, 0), V(0, 0, 1), V(1, 0, 0)};
    rad_ff_result ex = ff(a, b, "exact");
    /* Measured: N = 13 gives 2e-10, N = 14 gives 1e-11 (experiments/quadrature). */
    CHECK_NEAR(ff(a, b, "ss:14").G, ex.G, 1e-10, 0.0);
    CHECK(fabs(ff(a, b, "ss:10").G - ex.G) > 1e-10 * ex.G); /* the test can fail */
    rad_vec3 c[3] = {V(0, 0, 0), V(1, 0, 0), V(0.3, 0.8, 0)}, d[3] = {V(0, 0, 0), V(0.4, 0, 0.9), V(1, 0, 0)};
    ex = ff(c, d, "exact");
    CHECK_NEAR(ff(c, d, "ss:12").G, ex.G, 1e-10, 0.0);
}

TEST(ff_auto_meets_tolerance_and_reports_choice)
{
    rad_vec3 P[NPAIRS][2][3];
    sample_pairs(P);
    double tols[] = {1e-3, 1e-4, 1e-5, 1e-6, 1e-9};
    for (int t = 0; t < 5; t++)
        for (int k = 0; k < NPAIRS; k++) {
            rad_ff_params p;
            rad_ff_params_default(&p);
            p.tol = tols[t];
            rad_ff_rule r = {RAD_FF_AUTO, 0};
            rad_ff_result o, ex = ff(P[k][0], P[k][1], "exact");
            CHECK(rad_ff_compute(P[k][0], P[k][1], r, &p, &o) == RAD_OK);
            CHECK(o.used.scheme != RAD_FF_AUTO);
            CHECK_MSG(fabs(o.G - ex.G) <= tols[t] * ex.G, "pair %d tol %g: error %.3g", k, tols[t],
                      fabs(o.G - ex.G) / ex.G);
            CHECK(o.rel_error >= 0.0);
        }
    /* A far pair goes to a low-degree symmetric rule. */
    rad_ff_result far = ff(P[1][0], P[1][1], "auto");
    CHECK(far.used.scheme == RAD_FF_GAUSS && far.evals < 1000);
}

TEST(ff_bad_input_and_rules)
{
    rad_vec3 a[3] = {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)}, b[3] = {V(0, 0, 1), V(0, 1, 1), V(1, 0, 1)};
    rad_vec3 col[3] = {V(0, 0, 1), V(1, 1, 1), V(2, 2, 1)}, nan3[3] = {V(0, 0, 1), V(NAN, 1, 1), V(1, 0, 1)};
    rad_ff_rule r = {RAD_FF_EXACT, 0};
    rad_ff_result o;
    CHECK(rad_ff_compute(a, col, r, NULL, &o) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "degenerate") != NULL);
    CHECK(rad_ff_compute(nan3, a, r, NULL, &o) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "non-finite") != NULL);
    r.scheme = RAD_FF_GAUSS;
    r.order = RAD_FF_MAX_DEGREE + 1;
    CHECK(rad_ff_compute(a, b, r, NULL, &o) == RAD_EINVAL);
    rad_ff_params p;
    rad_ff_params_default(&p);
    p.tol = 0.0;
    r.scheme = RAD_FF_AUTO;
    CHECK(rad_ff_compute(a, b, r, &p, &o) == RAD_EINVAL);
    const char *bad[] = {"", "simpson", "gauss", "gauss:", "gauss:x", "gauss:41", "ss:0", "ss:33",
                         "exact:3", "analytic:-1", "gauss:4x"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        CHECK_MSG(rad_ff_rule_parse(bad[k], &r) == RAD_EINVAL, "'%s' parsed", bad[k]);
    const char *good[] = {"vertex", "centroid", "gauss:0", "gauss:40", "analytic:3", "ss:1", "ss:32", "exact", "auto"};
    for (size_t k = 0; k < sizeof good / sizeof good[0]; k++) {
        char buf[32];
        CHECK(rad_ff_rule_parse(good[k], &r) == RAD_OK);
        rad_ff_rule_format(r, buf, sizeof buf);
        CHECK(strcmp(buf, good[k]) == 0);
    }
}

TEST(ff_adjacency_detection_is_relative_to_size)
{
    double s = 1e-5;
    rad_vec3 a[3] = {V(0, 0, 0), V(s, 0, 0), V(0, s, 0)};
    rad_vec3 b[3] = {V(s * 1e-12, 0, 0), V(0, 0, s), V(s, 0, 0)};
    int map[3];
    CHECK(rad_ff_adjacency_detect(a, b, 1e-10, map) == RAD_FF_SHARE_EDGE);
    CHECK(map[0] == 0 && map[1] == 2 && map[2] == -1);
    b[0] = V(s * 1e-6, 0, 0);
    CHECK(rad_ff_adjacency_detect(a, b, 1e-10, map) == RAD_FF_SHARE_VERTEX);
    CHECK_NEAR(rad_ff_triangle_distance(a, b), 0.0, 0.0, 1e-20);
}

/* A wall triangle standing on a floor triangle touches it along part of an
 * edge without sharing a vertex (a contact): it touches at a gap of 1e-12 of
 * its size, not at 1e-6, nor when the two are set apart; the answer does not
 * depend on the order or the scale. */
TEST(ff_triangles_touch_within_a_relative_gap)
{
    for (int k = 0; k < 2; k++) {
        double s = k ? 1e-4 : 10.0;
        rad_vec3 floor_[3] = {V(0, 0, 0), V(s, 0, 0), V(0, s, 0)};
        double gaps[4] = {0.0, 1e-12, 1e-6, 0.5};
        int want[4] = {1, 1, 0, 0};
        for (int g = 0; g < 4; g++) {
            double z = gaps[g] * s;
            rad_vec3 wall[3] = {V(0.1 * s, 0.2 * s, z), V(0.4 * s, 0.2 * s, z),
                                V(0.2 * s, 0.2 * s, z + 0.5 * s)};
            rad_vec3 cf = rad_geom_triangle_centroid(floor_[0], floor_[1], floor_[2]);
            rad_vec3 cw = rad_geom_triangle_centroid(wall[0], wall[1], wall[2]);
            double sf = rad_geom_triangle_longest_edge(floor_), sw = rad_geom_triangle_longest_edge(wall);
            CHECK_MSG(rad_ff_triangles_touch(floor_, cf, sf, wall, cw, sw) == want[g] &&
                          rad_ff_triangles_touch(wall, cw, sw, floor_, cf, sf) == want[g],
                      "scale %g, gap %g: want %d", s, gaps[g], want[g]);
        }
    }
}

static double lcg(unsigned long *state)
{
    *state = *state * 6364136223846793005UL + 1442695040888963407UL;
    return (double)(*state >> 11) / 9007199254740992.0;
}

TEST(ff_auto_meets_tolerance_on_random_pairs)
{
    /* Random pairs of four kinds: edge-adjacent, vertex-adjacent, disjoint
     * near and far, each wound to face the other where possible. */
    unsigned long st = 2385;
    double tols[] = {1e-3, 1e-5, 1e-6};
    int checked = 0;
    for (int k = 0; k < 48; k++) {
        rad_vec3 a[3], b[3];
        for (int v = 0; v < 3; v++) {
            a[v] = V(lcg(&st), lcg(&st), 0.2 * lcg(&st));
            b[v] = V(lcg(&st), lcg(&st), 0.3 + 2.0 * lcg(&st) * (k % 4 == 3 ? 4.0 : 0.3));
        }
        if (k % 4 == 0) { /* share an edge */
            b[0] = a[0];
            b[1] = a[1];
        } else if (k % 4 == 1) { /* share a vertex */
            b[0] = a[2];
        }
        if (rad_geom_triangle_is_degenerate(a[0], a[1], a[2], 1e-3) ||
            rad_geom_triangle_is_degenerate(b[0], b[1], b[2], 1e-3))
            continue;
        /* Make a face up and b face a, when the geometry allows it. */
        rad_vec3 na = rad_geom_triangle_normal(a[0], a[1], a[2]);
        if (na.z < 0) {
            rad_vec3 tmp = a[1];
            a[1] = a[2];
            a[2] = tmp;
        }
        rad_vec3 nb = rad_geom_triangle_normal(b[0], b[1], b[2]);
        rad_vec3 ca = rad_geom_triangle_centroid(a[0], a[1], a[2]);
        if (rad_vec3_dot(nb, rad_vec3_sub(ca, b[0])) < 0) {
            rad_vec3 tmp = b[1];
            b[1] = b[2];
            b[2] = tmp;
        }
        rad_ff_result ex = ff(a, b, "exact");
        if (!(ex.G > 0))
            continue;
        for (int t = 0; t < 3; t++) {
            rad_ff_params p;
            rad_ff_params_default(&p);
            p.tol = tols[t];
            rad_ff_rule r = {RAD_FF_AUTO, 0};
            rad_ff_result o;
            CHECK(rad_ff_compute(a, b, r, &p, &o) == RAD_OK);
            char used[32];
            rad_ff_rule_format(o.used, used, sizeof used);
            CHECK_MSG(fabs(o.G - ex.G) <= tols[t] * ex.G, "pair %d (kind %d) tol %g: %s error %.3g", k, k % 4,
                      tols[t], used, fabs(o.G - ex.G) / ex.G);
            checked++;
        }
    }
    CHECK(checked > 60);
}

/* No hidden global state: two threads computing different pairs at once get
 * bit-identical results to a serial run. */
typedef struct thread_job {
    int first;
    double G[NPAIRS * 4];
} thread_job;

static void *thread_run(void *arg)
{
    thread_job *job = arg;
    rad_vec3 P[NPAIRS][2][3];
    sample_pairs(P);
    const char *rules[] = {"exact", "auto", "ss:6", "analytic:8"};
    for (int rep = 0; rep < 3; rep++)
        for (int k = 0; k < NPAIRS; k++)
            for (int r = 0; r < 4; r++) {
                int kk = (k + job->first) % NPAIRS;
                rad_ff_rule rule;
                rad_ff_result o;
                rad_ff_rule_parse(rules[r], &rule);
                rad_ff_compute(P[kk][0], P[kk][1], rule, NULL, &o);
                job->G[kk * 4 + r] = o.G;
            }
    return NULL;
}

TEST(ff_is_reentrant_across_threads)
{
    thread_job serial = {0, {0}}, a = {1, {0}}, b = {3, {0}};
    thread_run(&serial);
    pthread_t ta, tb;
    CHECK(pthread_create(&ta, NULL, thread_run, &a) == 0);
    CHECK(pthread_create(&tb, NULL, thread_run, &b) == 0);
    pthread_join(ta, NULL);
    pthread_join(tb, NULL);
    for (int k = 0; k < NPAIRS * 4; k++)
        CHECK(serial.G[k] == a.G[k] && serial.G[k] == b.G[k]);
}

/* auto on pairs where one triangle straddles the other's plane (a cosine clamp
 * is active inside the pair): the clipped pieces are integrated by the ladder
 * and must meet the tolerance against exact, at a fraction of exact's cost. */
TEST(ff_auto_straddling_pairs_meet_tolerance_by_clipping)
{
    unsigned long long state = 0x2385u;
    int cheap = 0, total = 0;
    for (int trial = 0; trial < 40; trial++) {
        double u[9];
        for (int k = 0; k < 9; k++) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            u[k] = (double)(state >> 11) * (1.0 / 9007199254740992.0);
        }
        /* A floor triangle (z = 0, facing up) and a wall triangle (x = 0.4 +
         * 0.3 u, facing -x) held above the floor: the wall's plane cuts the
         * floor triangle, so part of the floor lies behind the wall.  Even
         * trials hold the wall high (pieces well separated: the clipped
         * ladder must be taken), odd ones low (near pieces: exact is used).
         * Were the wall to dip through the floor, the clipped pieces would
         * touch along the intersection line, where the kernel is singular. */
        double lift = trial % 2 == 0 ? 1.2 : 0.05;
        rad_vec3 floor_t[3] = {{0, 0, 0}, {1.3 + u[0], 0.1, 0}, {0.2, 1.1 + u[1], 0}};
        double x = 0.4 + 0.3 * u[2];
        rad_vec3 wall[3] = {{x, 0.2 + u[3], lift + 0.3 * u[4]}, {x, 0.1, lift + 0.9 + u[5]},
                            {x, 1.4 + u[6], lift + 0.5}};
        /* Normal of the wall must be -x: orient by swapping if needed. */
        rad_vec3 nw = rad_vec3_cross(rad_vec3_sub(wall[1], wall[0]), rad_vec3_sub(wall[2], wall[0]));
        if (nw.x > 0) {
            rad_vec3 t = wall[1];
            wall[1] = wall[2];
            wall[2] = t;
        }
        rad_ff_rule ex = {RAD_FF_EXACT, 0}, au = {RAD_FF_AUTO, 0};
        rad_ff_params p;
        rad_ff_params_default(&p);
        double tols[2] = {1e-3, 1e-6};
        rad_ff_result re;
        CHECK(rad_ff_compute(floor_t, wall, ex, &p, &re) == RAD_OK);
        for (int k = 0; k < 2; k++) {
            p.tol = tols[k];
            rad_ff_result ra;
            CHECK(rad_ff_compute(floor_t, wall, au, &p, &ra) == RAD_OK);
            CHECK_MSG(fabs(ra.G - re.G) <= tols[k] * re.G, "trial %d tol %g: auto %.15g exact %.15g",
                      trial, tols[k], ra.G, re.G);
            if (trial % 2 == 0) {
                total++;
                /* (evals are not comparable: exact counts closed-form contour
                 * evaluations, the ladder kernel evaluations) */
                cheap += ra.used.scheme != RAD_FF_EXACT;
            }
        }
    }
    CHECK_MSG(cheap == total, "only %d of %d well-separated straddling pairs avoided exact", cheap, total);
}

/* hier's far rule: gauss:2 on pairs whose centroids lie 1.5-2 and 2-3 longest
 * edges apart, against exact, over random pairs that face each other whole
 * (every vertex of each in front of the other; straddling pairs are refined
 * as unknown links instead).  Measured: mean 0.15% and 0.06%, 95% of pairs
 * within 0.44% and 0.18% (rad_hier_params_default quotes these); the bounds
 * here are twice that. */
static double lcg_uniform(unsigned *seed)
{
    *seed = *seed * 1103515245u + 12345u;
    return (double)(*seed >> 8) / (double)(1u << 24);
}

TEST(ff_gauss2_far_pairs)
{
    static const double lo[2] = {1.5, 2.0}, hi[2] = {2.0, 3.0};
    static const double mean_max[2] = {0.003, 0.0012}, p95_max[2] = {0.009, 0.0036};
    rad_ff_params p;
    rad_ff_params_default(&p);
    unsigned seed = 2026u;
    for (int band = 0; band < 2; band++) {
        enum { N = 600 };
        double err[N], sum = 0.0;
        int n = 0;
        while (n < N) {
            rad_vec3 t[2][3];
            for (int k = 0; k < 2; k++)
                for (int v = 0; v < 3; v++)
                    t[k][v] = V(2 * lcg_uniform(&seed) - 1, 2 * lcg_uniform(&seed) - 1, 2 * lcg_uniform(&seed) - 1);
            double L[2];
            for (int k = 0; k < 2; k++) {
                L[k] = 0.0;
                for (int v = 0; v < 3; v++)
                    L[k] = fmax(L[k], rad_vec3_norm(rad_vec3_sub(t[k][(v + 1) % 3], t[k][v])));
                if (rad_geom_triangle_area(t[k][0], t[k][1], t[k][2]) < 0.05 * L[k] * L[k])
                    goto next; /* a sliver: not the elements hier makes */
            }
            rad_vec3 dir = V(2 * lcg_uniform(&seed) - 1, 2 * lcg_uniform(&seed) - 1, 2 * lcg_uniform(&seed) - 1);
            double dn = rad_vec3_norm(dir), ratio = lo[band] + (hi[band] - lo[band]) * lcg_uniform(&seed);
            if (dn < 1e-3)
                continue;
            rad_vec3 c0 = rad_geom_triangle_centroid(t[0][0], t[0][1], t[0][2]);
            rad_vec3 c1 = rad_geom_triangle_centroid(t[1][0], t[1][1], t[1][2]);
            rad_vec3 shift = rad_vec3_add(rad_vec3_sub(c0, c1),
                                          rad_vec3_scale(dir, ratio * fmax(L[0], L[1]) / dn));
            for (int v = 0; v < 3; v++)
                t[1][v] = rad_vec3_add(t[1][v], shift);
            for (int k = 0; k < 2; k++) {
                rad_vec3 nk = rad_geom_triangle_normal(t[k][0], t[k][1], t[k][2]);
                for (int v = 0; v < 3; v++)
                    if (!(rad_vec3_dot(nk, rad_vec3_sub(t[1 - k][v], t[k][0])) > 0.0))
                        goto next;
            }
            rad_ff_result ex, g2;
            CHECK(rad_ff_compute(t[0], t[1], (rad_ff_rule){RAD_FF_EXACT, 0}, &p, &ex) == RAD_OK);
            CHECK(rad_ff_compute(t[0], t[1], (rad_ff_rule){RAD_FF_GAUSS, 2}, &p, &g2) == RAD_OK);
            if (!(ex.F12 > 1e-9))
                continue;
            err[n] = fabs(g2.F12 / ex.F12 - 1.0);
            sum += err[n++];
        next:;
        }
        int below = 0;
        for (int k = 0; k < N; k++)
            below += err[k] <= p95_max[band];
        CHECK_MSG(sum / N <= mean_max[band], "band %g-%g edges: mean error %.3g%%", lo[band],
                  hi[band], 100.0 * sum / N);
        CHECK_MSG(below >= 0.95 * N, "band %g-%g edges: only %d of %d pairs within %.3g%%",
                  lo[band], hi[band], below, (int)N, 100.0 * p95_max[band]);
    }
}
