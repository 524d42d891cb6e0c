/* rad_basis: the closed-form q_k against quadrature of their definition
 * (orthonormal in the mean over the triangle, nested, spanning the
 * polynomials of their degree), and projections exact on polynomials. */
#include <math.h>

#include "harness.h"
#include "rad_basis.h"
#include "rad_quad.h"

TEST(basis_orthonormal_by_two_independent_rules)
{
    /* the symmetric degree-10 rule and a collapsed Gauss rule (exact to 2k-2) */
    double s[RAD_QUAD_TRI_MAX_POINTS], t[RAD_QUAD_TRI_MAX_POINTS], w[RAD_QUAD_TRI_MAX_POINTS];
    int np = 0;
    CHECK(rad_quad_tri_symmetric(10, s, t, w, &np) == RAD_OK);
    enum { K = 8 };
    double ds[K * K], dt[K * K], dw[K * K];
    CHECK(rad_quad_tri_duffy(K, ds, dt, dw) == RAD_OK);
    for (int rule = 0; rule < 2; rule++) {
        int n = rule ? K * K : np;
        const double *S = rule ? ds : s, *T = rule ? dt : t, *W = rule ? dw : w;
        double m[6][6] = {{0}};
        for (int i = 0; i < n; i++) {
            double q[RAD_BASIS_MAX_SIZE];
            rad_basis_eval(2, S[i], T[i], q);
            for (int k = 0; k < 6; k++)
                for (int l = 0; l < 6; l++)
                    m[k][l] += W[i] * q[k] * q[l];
        }
        for (int k = 0; k < 6; k++)
            for (int l = 0; l < 6; l++)
                CHECK_MSG(fabs(m[k][l] - (k == l)) < 1e-13, "rule %d: mean(q%d q%d) = %.3e", rule,
                          k, l, m[k][l]);
    }
}

TEST(basis_orders_are_nested_and_sized)
{
    CHECK(rad_basis_size(0) == 1 && rad_basis_size(1) == 3 && rad_basis_size(2) == 6);
    CHECK(rad_basis_size(3) == 0 && rad_basis_size(-1) == 0);
    double q1[RAD_BASIS_MAX_SIZE], q2[RAD_BASIS_MAX_SIZE];
    rad_basis_eval(1, 0.3, 0.2, q1);
    rad_basis_eval(2, 0.3, 0.2, q2);
    for (int k = 0; k < 3; k++)
        CHECK(q1[k] == q2[k]);
    int p = -1;
    CHECK(rad_basis_parse("p2", &p) == RAD_OK && p == 2);
    CHECK(rad_basis_parse("p3", &p) == RAD_EINVAL);
    CHECK(rad_basis_parse(NULL, &p) == RAD_EINVAL);
}

typedef struct poly {
    double c[6]; /* 1, x, y, x^2, xy, z */
} poly;

static double poly_at(rad_vec3 x, void *ctx)
{
    const poly *p = ctx;
    return p->c[0] + p->c[1] * x.x + p->c[2] * x.y + p->c[3] * x.x * x.x + p->c[4] * x.x * x.y +
           p->c[5] * x.z;
}

/* A polynomial of degree <= p on a triangle in space is reproduced exactly
 * by its order-p projection; a higher one is not (the test can fail). */
TEST(basis_projection_exact_on_polynomials)
{
    rad_vec3 tri[3] = {{0.3, -0.2, 1.0}, {2.1, 0.4, 1.5}, {0.7, 1.9, 0.2}};
    double area = rad_geom_triangle_area(tri[0], tri[1], tri[2]);
    const poly cases[3] = {{{2.5, 0, 0, 0, 0, 0}},
                           {{1.0, -0.7, 0.4, 0, 0, 0.9}},
                           {{0.5, 0.3, -1.1, 0.8, -0.6, 0.2}}};
    for (int p = 0; p <= 2; p++)
        for (int c = 0; c <= 2; c++) {
            double coef[RAD_BASIS_MAX_SIZE];
            CHECK(rad_basis_project(p, tri, poly_at, (void *)&cases[c], 2 * p + 2, coef) == RAD_OK);
            double worst = 0.0;
            for (int i = 0; i <= 4; i++)
                for (int j = 0; i + j <= 4; j++) {
                    double s = i / 4.0, t = j / 4.0;
                    double f = poly_at(rad_geom_triangle_point(tri[0], tri[1], tri[2], s, t),
                                       (void *)&cases[c]);
                    worst = fmax(worst, fabs(rad_basis_value(p, area, coef, s, t) - f));
                }
            if (c <= p)
                CHECK_MSG(worst < 1e-12, "order %d, degree-%d polynomial: %.3e", p, c, worst);
            else
                CHECK_MSG(worst > 1e-3, "order %d cannot hold a degree-%d polynomial: %.3e", p, c,
                          worst);
            /* the first coefficient is sqrt(A) times the mean */
            double mean = 0.0, s[RAD_QUAD_TRI_MAX_POINTS], t[RAD_QUAD_TRI_MAX_POINTS],
                   w[RAD_QUAD_TRI_MAX_POINTS];
            int np = 0;
            CHECK(rad_quad_tri_symmetric(8, s, t, w, &np) == RAD_OK);
            for (int k = 0; k < np; k++)
                mean += w[k] * poly_at(rad_geom_triangle_point(tri[0], tri[1], tri[2], s[k], t[k]),
                                       (void *)&cases[c]);
            CHECK_NEAR(coef[0], sqrt(area) * mean, 1e-13, 1e-13);
        }
    double coef[RAD_BASIS_MAX_SIZE];
    CHECK(rad_basis_project(3, tri, poly_at, (void *)&cases[0], 4, coef) == RAD_EINVAL);
}
