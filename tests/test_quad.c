/* Gauss-Legendre rules and the adaptive Gauss-Kronrod integrator. */
#include <math.h>

#include "harness.h"
#include "rad_quad.h"

TEST(gauss_legendre_is_exact_to_degree_2k_minus_1)
{
    double x[64], w[64];
    for (int k = 1; k <= 64; k++) {
        CHECK(rad_quad_gauss_legendre(k, x, w) == RAD_OK);
        for (int i = 0; i < k; i++) {
            CHECK(x[i] > 0.0 && x[i] < 1.0 && w[i] > 0.0);
            if (i > 0)
                CHECK(x[i] > x[i - 1]);
        }
        for (int m = 0; m <= 2 * k - 1; m++) {
            double s = 0.0;
            for (int i = 0; i < k; i++)
                s += w[i] * pow(x[i], m);
            CHECK_NEAR(s, 1.0 / (m + 1), 2e-14, 0.0);
        }
        /* ... and not beyond: x^(2k) is integrated with an error. */
        double s = 0.0;
        for (int i = 0; i < k; i++)
            s += w[i] * pow(x[i], 2 * k);
        CHECK_MSG(fabs(s - 1.0 / (2 * k + 1)) > 1e-16 * 0.5 / (2 * k + 1) || k > 20,
                  "k = %d integrates x^%d exactly", k, 2 * k);
    }
}

TEST(gauss_legendre_known_nodes)
{
    double x[3], w[3];
    rad_quad_gauss_legendre(3, x, w);
    /* On [-1,1]: 0, +-sqrt(3/5); weights 8/9, 5/9. */
    CHECK_NEAR(x[0], 0.5 * (1.0 - sqrt(0.6)), 1e-15, 0.0);
    CHECK_NEAR(x[1], 0.5, 0.0, 0.0);
    CHECK_NEAR(w[1], 4.0 / 9.0, 1e-15, 0.0);
    CHECK_NEAR(w[2], 5.0 / 18.0, 1e-15, 0.0);
    CHECK(rad_quad_gauss_legendre(0, x, w) == RAD_EINVAL);
}

TEST(gauss_legendre_large_order)
{
    static double x[400], w[400];
    CHECK(rad_quad_gauss_legendre(400, x, w) == RAD_OK);
    double s = 0.0, c = 0.0;
    for (int i = 0; i < 400; i++) {
        s += w[i];
        c += w[i] * cos(50.0 * x[i]);
    }
    CHECK_NEAR(s, 1.0, 1e-13, 0.0);
    CHECK_NEAR(c, sin(50.0) / 50.0, 1e-12, 0.0);
}

static double f_exp(double x, void *ctx) { (void)ctx; return exp(x); }
static double f_sqrt(double x, void *ctx) { (void)ctx; return sqrt(x); }
static double f_kink(double x, void *ctx) { return fabs(x - *(double *)ctx); }
static double f_poly22(double x, void *ctx) { (void)ctx; return pow(x, 22) + pow(x, 21); }
static double f_nan(double x, void *ctx) { (void)ctx; return x > 0.5 ? NAN : x; }
static double f_wild(double x, void *ctx) { (void)ctx; return sin(1.0 / (x + 1e-12)); }

TEST(adapt_integrates_reference_integrals)
{
    rad_quad_result r;
    rad_quad_adapt_params p;
    rad_quad_adapt_params_default(&p);
    CHECK(rad_quad_adapt(f_exp, NULL, 0.0, 1.0, NULL, 0, &p, &r) == RAD_OK);
    CHECK_NEAR(r.value, exp(1.0) - 1.0, 1e-14, 0.0);
    CHECK(r.error >= 0.0 && r.evals >= 15);

    CHECK(rad_quad_adapt(f_sqrt, NULL, 0.0, 2.385, NULL, 0, &p, &r) == RAD_OK);
    CHECK_NEAR(r.value, 2.0 / 3.0 * pow(2.385, 1.5), 1e-12, 0.0);

    /* K15 is exact for degree 22: one panel suffices. */
    CHECK(rad_quad_adapt(f_poly22, NULL, 0.0, 1.0, NULL, 0, &p, &r) == RAD_OK);
    CHECK_NEAR(r.value, 1.0 / 23.0 + 1.0 / 22.0, 1e-15, 0.0);
}

TEST(adapt_breakpoints_capture_kinks)
{
    double kink = 0.3183, brk = 0.3183;
    rad_quad_result r;
    CHECK(rad_quad_adapt(f_kink, &kink, 0.0, 1.0, &brk, 1, NULL, &r) == RAD_OK);
    CHECK_NEAR(r.value, 0.5 * (kink * kink + (1 - kink) * (1 - kink)), 1e-15, 0.0);
    CHECK(r.evals == 30); /* two exact panels, no bisection */
    /* Without the breakpoint it still converges, with more work. */
    rad_quad_result r2;
    CHECK(rad_quad_adapt(f_kink, &kink, 0.0, 1.0, NULL, 0, NULL, &r2) == RAD_OK);
    CHECK_NEAR(r2.value, r.value, 1e-12, 0.0);
    CHECK(r2.evals > r.evals);
}

TEST(adapt_reports_failure)
{
    rad_quad_result r;
    CHECK(rad_quad_adapt(f_nan, NULL, 0.0, 1.0, NULL, 0, NULL, &r) == RAD_ENUMERIC);
    rad_quad_adapt_params p;
    rad_quad_adapt_params_default(&p);
    p.max_intervals = 5;
    CHECK(rad_quad_adapt(f_wild, NULL, 0.0, 1.0, NULL, 0, &p, &r) == RAD_ENUMERIC);
    CHECK(isfinite(r.value) && r.error > 0.0);
    CHECK(rad_quad_adapt(f_exp, NULL, 1.0, 0.0, NULL, 0, NULL, &r) == RAD_EINVAL);
    CHECK(rad_quad_adapt(f_exp, NULL, 0.0, INFINITY, NULL, 0, NULL, &r) == RAD_EINVAL);
}
