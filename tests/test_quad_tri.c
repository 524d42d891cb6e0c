/* Triangle rules: every rule integrates every monomial up to its degree. */
#include <math.h>

#include "harness.h"
#include "rad_quad.h"

/* Mean of s^a t^b over the unit triangle: 2 a! b! / (a + b + 2)!. */
static double monomial_mean(int a, int b)
{
    double v = 2.0;
    for (int i = 1; i <= a; i++)
        v *= i;
    for (int i = 1; i <= b; i++)
        v *= i;
    for (int i = 1; i <= a + b + 2; i++)
        v /= i;
    return v;
}

static double rule_error(int n, const double *s, const double *t, const double *w, int a, int b)
{
    double sum = 0.0;
    for (int i = 0; i < n; i++)
        sum += w[i] * pow(s[i], a) * pow(t[i], b);
    return fabs(sum - monomial_mean(a, b)) / monomial_mean(a, b);
}

TEST(tri_symmetric_rules_integrate_monomials)
{
    double s[RAD_QUAD_TRI_MAX_POINTS], t[RAD_QUAD_TRI_MAX_POINTS], w[RAD_QUAD_TRI_MAX_POINTS];
    int tabled[] = {1, 2, 4, 5, 6, 7, 8, 9, 10};
    for (int deg = 0; deg <= RAD_QUAD_TRI_MAX_DEGREE; deg++) {
        int n = 0, exact = -1;
        int count = rad_quad_tri_symmetric_count(deg, &exact);
        CHECK(rad_quad_tri_symmetric(deg, s, t, w, &n) == RAD_OK);
        CHECK(n == count && n <= RAD_QUAD_TRI_MAX_POINTS && exact >= deg);
        for (int i = 0; i < n; i++)
            CHECK_MSG(s[i] > 0 && t[i] > 0 && s[i] + t[i] < 1 && w[i] > 0,
                      "degree %d point %d outside the triangle or negative weight", deg, i);
        for (int a = 0; a <= exact; a++)
            for (int b = 0; a + b <= exact; b++)
                CHECK_MSG(rule_error(n, s, t, w, a, b) < 1e-14,
                          "degree-%d rule: s^%d t^%d off by %.3g", exact, a, b,
                          rule_error(n, s, t, w, a, b));
        /* ... and the rule is not exact one degree beyond (for the tabled degrees). */
        int is_tabled = 0;
        for (size_t k = 0; k < sizeof tabled / sizeof tabled[0]; k++)
            is_tabled |= tabled[k] == deg;
        if (is_tabled) {
            double worst = 0.0;
            for (int a = 0; a <= deg + 1; a++)
                worst = fmax(worst, rule_error(n, s, t, w, a, deg + 1 - a));
            CHECK_MSG(worst > 1e-12, "degree-%d rule is exact at degree %d", deg, deg + 1);
        }
    }
    int n;
    CHECK(rad_quad_tri_symmetric(RAD_QUAD_TRI_MAX_DEGREE + 1, s, t, w, &n) == RAD_EINVAL);
    CHECK(rad_quad_tri_symmetric_count(RAD_QUAD_TRI_MAX_DEGREE + 1, NULL) == 0);
    CHECK(rad_quad_tri_symmetric(-1, s, t, w, &n) == RAD_EINVAL);
}

TEST(tri_symmetric_rules_are_symmetric)
{
    /* The rule is invariant under the 6 permutations of the barycentrics: the
     * mean of the non-symmetric polynomial s^2 t + 3 s t^5 computed with the
     * points and with the mirrored points (s <-> t) agree. */
    double s[RAD_QUAD_TRI_MAX_POINTS], t[RAD_QUAD_TRI_MAX_POINTS], w[RAD_QUAD_TRI_MAX_POINTS];
    for (int deg = 1; deg <= RAD_QUAD_TRI_MAX_DEGREE; deg++) {
        int n;
        rad_quad_tri_symmetric(deg, s, t, w, &n);
        double q1 = 0.0, q2 = 0.0, q3 = 0.0;
        for (int i = 0; i < n; i++) {
            double u = 1.0 - s[i] - t[i];
            q1 += w[i] * (s[i] * s[i] * t[i] + 3 * s[i] * pow(t[i], 5));
            q2 += w[i] * (t[i] * t[i] * s[i] + 3 * t[i] * pow(s[i], 5));
            q3 += w[i] * (u * u * t[i] + 3 * u * pow(t[i], 5));
        }
        CHECK_NEAR(q1, q2, 1e-14, 0.0);
        CHECK_NEAR(q1, q3, 1e-14, 0.0);
    }
}

TEST(tri_duffy_rules_integrate_monomials)
{
    static double s[64 * 64], t[64 * 64], w[64 * 64];
    for (int k = 1; k <= 24; k++) {
        CHECK(rad_quad_tri_duffy(k, s, t, w) == RAD_OK);
        int deg = 2 * k - 2;
        for (int a = 0; a <= deg; a++)
            for (int b = 0; a + b <= deg; b++)
                CHECK_MSG(rule_error(k * k, s, t, w, a, b) < 1e-14, "k = %d: s^%d t^%d off by %.3g",
                          k, a, b, rule_error(k * k, s, t, w, a, b));
        for (int i = 0; i < k * k; i++)
            CHECK(s[i] > 0 && t[i] > 0 && s[i] + t[i] < 1 && w[i] > 0);
    }
    CHECK(rad_quad_tri_duffy(64, s, t, w) == RAD_OK);
    CHECK(rad_quad_tri_duffy(0, s, t, w) == RAD_EINVAL);
    CHECK(rad_quad_tri_duffy(65, s, t, w) == RAD_EINVAL);
}
