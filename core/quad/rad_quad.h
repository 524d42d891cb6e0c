/* rad_quad: quadrature rules.
 *
 * - Gauss-Legendre rules on [0,1] of any number of points, computed by Newton's
 *   method on the three-term recurrence (not tabled).
 * - A globally adaptive Gauss-Kronrod (7,15) integrator on an interval with
 *   optional breakpoints, used as the independent reference for every closed form
 *   in radkit (QUADPACK's QAG/QAGP strategy, Piessens et al. 1983).
 * - Triangle rules (tri.c): the fully symmetric Witherden-Vincent rules of
 *   degree 1-10 (tabled, source cited there) and collapsed (Duffy) Gauss
 *   product rules of any order (computed). */
#ifndef RAD_QUAD_H
#define RAD_QUAD_H

#include "rad_error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Gauss-Legendre rule with k >= 1 points on [0,1]: nodes x[k] ascending, weights
 * w[k] summing to 1.  Exact for polynomials of degree <= 2k-1.  k = 1 is the
 * midpoint rule.  Returns RAD_EINVAL for k < 1. */
rad_status rad_quad_gauss_legendre(int k, double *x, double *w);

/* A value together with its error estimate and the work spent (STYLE point 9). */
typedef struct rad_quad_result {
    double value;
    double error; /* estimated absolute error */
    long evals;   /* integrand evaluations */
} rad_quad_result;

typedef double (*rad_quad_fn)(double x, void *ctx);

/* Parameters of the adaptive integrator; fill with rad_quad_adapt_params_default. */
typedef struct rad_quad_adapt_params {
    double abs_tol;    /* absolute tolerance on the integral */
    double rel_tol;    /* relative tolerance on the integral */
    int max_intervals; /* cap on subintervals (<= RAD_QUAD_ADAPT_MAX_INTERVALS) */
} rad_quad_adapt_params;

#define RAD_QUAD_ADAPT_MAX_INTERVALS 4096

void rad_quad_adapt_params_default(rad_quad_adapt_params *params);

/* Integrate f over [a,b], splitting first at the `nbreaks` breakpoints (points
 * where f or a derivative jumps; those outside (a,b) are ignored).  Bisects the
 * subinterval with the largest error until the total estimated error is below
 * max(abs_tol, rel_tol*|value|).  The error estimate of one interval is
 * |K15 - G7|, which for smooth integrands overestimates the K15 error by orders
 * of magnitude: it is a bound one can trust, not a tight one.
 * Returns RAD_OK, or RAD_ENUMERIC (result still filled) if the interval cap is
 * reached first or f returned a non-finite value. */
rad_status rad_quad_adapt(rad_quad_fn f, void *ctx, double a, double b,
                          const double *breaks, int nbreaks,
                          const rad_quad_adapt_params *params, rad_quad_result *out);

/* ---- triangle rules ------------------------------------------------------
 * A triangle rule is n points (s[i], t[i]) of the unit triangle s, t >= 0,
 * s + t <= 1 (the point a + s (b - a) + t (c - a) of triangle abc) with weights
 * summing to 1: sum_i w[i] f(p_i) approximates the MEAN of f over the triangle. */

#define RAD_QUAD_TRI_MAX_DEGREE 10  /* highest tabled symmetric degree */
#define RAD_QUAD_TRI_MAX_POINTS 25  /* most points of a tabled symmetric rule */
#define RAD_QUAD_TRI_DUFFY_MAX 64   /* most Gauss points per direction of a collapsed rule */

/* Number of points of the smallest symmetric rule exact to degree >= `degree`
 * (0 if there is none, i.e. degree > RAD_QUAD_TRI_MAX_DEGREE or < 0); the
 * degree it actually reaches goes to *exact_degree when that is not NULL. */
int rad_quad_tri_symmetric_count(int degree, int *exact_degree);

/* The smallest symmetric rule exact to degree >= `degree` (Witherden-Vincent,
 * positive weights, interior points).  s, t, w need RAD_QUAD_TRI_MAX_POINTS
 * entries; *npoints receives the count.  RAD_EINVAL if no rule exists. */
rad_status rad_quad_tri_symmetric(int degree, double *s, double *t, double *w, int *npoints);

/* Collapsed Gauss product rule with k points per direction (k*k points,
 * 1 <= k <= RAD_QUAD_TRI_DUFFY_MAX), exact to total degree 2k - 2. */
rad_status rad_quad_tri_duffy(int k, double *s, double *t, double *w);

#ifdef __cplusplus
}
#endif
#endif
