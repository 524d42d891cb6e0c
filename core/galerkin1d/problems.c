/* The built-in 1D model problems.
 *
 * The kernel k(x,t) = min(x,t) (1 - max(x,t)) is the Green's function of
 * -w'' = g with w(0) = w(1) = 0, so w = K g.  Hence y = f + K y is equivalent to
 * the boundary-value problem  -y'' = -f'' + y,  y(0) = f(0),  y(1) = f(1).
 *
 * seed: f = x^3/6 + 5x/6 gives y'' + y = x, y(0) = 0, y(1) = 1, whose solution
 *       is y = x (the homogeneous part A cos x + B sin x must vanish).
 * exp:  manufactured with y = e^x: K e^x = w solves -w'' = e^x, w(0)=w(1)=0,
 *       so w = 1 + (e-1) x - e^x and f = y - K y = 2 e^x - 1 - (e-1) x.
 * Both claims are checked numerically in tests/test_galerkin1d.c.
 * Reference for the Galerkin method on second-kind equations: [atkinson1997]. */
#include "rad_galerkin1d.h"

#include <math.h>
#include <string.h>

static const double euler_e = 2.71828182845904523536;

static double green_kernel(double x, double t)
{
    return t < x ? t * (1.0 - x) : x * (1.0 - t);
}

/* ---- seed ---------------------------------------------------------------- */

static double seed_f(double x) { return x * x * x / 6.0 + 5.0 * x / 6.0; }
static double seed_exact(double x) { return x; }

/* With x = p + h u every term below is a positive multiple of a power of p and
 * h, so there is no cancellation however small h is (expanding (p+h)^4 - p^4
 * instead would lose digits like (p/h)^2 eps). */
static void seed_moments(double p, double h, double out[2])
{
    double x1_0 = h * (p / 2.0 + h / 6.0);             /* int x (1-u) */
    double x1_1 = h * (p / 2.0 + h / 3.0);             /* int x u     */
    double x3_0 = h * (p * p * p / 2.0 + p * p * h / 2.0 + p * h * h / 4.0 + h * h * h / 20.0);
    double x3_1 = h * (p * p * p / 2.0 + p * p * h + 3.0 * p * h * h / 4.0 + h * h * h / 5.0);
    out[0] = (x3_0 + 5.0 * x1_0) / 6.0;
    out[1] = (x3_1 + 5.0 * x1_1) / 6.0;
}

/* ---- exp ----------------------------------------------------------------- */

static double exp_f(double x) { return 2.0 * exp(x) - 1.0 - (euler_e - 1.0) * x; }
static double exp_exact(double x) { return exp(x); }

/* int_0^1 e^{s u} (1-u) du = sum_k s^k/(k+2)!  and  int_0^1 e^{s u} u du =
 * sum_k s^k/(k! (k+2)), summed as series: the closed forms (e^s - 1 - s)/s^2 and
 * (e^s (s-1) + 1)/s^2 cancel catastrophically for small s = h.  0 < s <= 1
 * here, so 25 terms are far past convergence. */
static void exp_unit_moments(double s, double *e0, double *e1)
{
    double term = 1.0, sum0 = 0.0, sum1 = 0.0; /* term = s^k / k! */
    for (int k = 0; k < 25; k++) {
        sum0 += term / ((k + 1.0) * (k + 2.0));
        sum1 += term / (k + 2.0);
        term *= s / (k + 1.0);
    }
    *e0 = sum0;
    *e1 = sum1;
}

static void exp_moments(double p, double h, double out[2])
{
    double e0, e1, ep = exp(p);
    exp_unit_moments(h, &e0, &e1);
    out[0] = 2.0 * ep * h * e0 - h / 2.0 - (euler_e - 1.0) * h * (p / 2.0 + h / 6.0);
    out[1] = 2.0 * ep * h * e1 - h / 2.0 - (euler_e - 1.0) * h * (p / 2.0 + h / 3.0);
}

static const rad_galerkin1d_problem problems[] = {
    {"seed", "the notes' problem: f = x^3/6 + 5x/6, exact y = x", green_kernel, 1, 1,
     seed_f, seed_exact, seed_moments},
    {"exp", "manufactured: f = 2e^x - 1 - (e-1)x, exact y = e^x", green_kernel, 1, 1,
     exp_f, exp_exact, exp_moments},
};

static const char *const problem_names[] = {"seed", "exp", NULL};

const rad_galerkin1d_problem *rad_galerkin1d_problem_find(const char *name)
{
    if (!name)
        return NULL;
    for (size_t i = 0; i < sizeof problems / sizeof problems[0]; i++)
        if (strcmp(problems[i].name, name) == 0)
            return &problems[i];
    return NULL;
}

const char *const *rad_galerkin1d_problem_names(void) { return problem_names; }
