/* rad_quad: quadrature rules.
 *
 * - Gauss-Legendre rules on [0,1] of any number of points, computed by Newton's
 *   method on the three-term recurrence (not tabled).
 * - A globally adaptive Gauss-Kronrod (7,15) integrator on an interval with
 *   optional breakpoints, used as the independent reference for every closed form
 *   in radkit (QUADPACK's QAG/QAGP strategy, Piessens et al. 1983).
 * Triangle rules arrive with the form-factor module. */
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

/* Parameters of the adaptive integrator; fill with rad_quad_adapt_defaults(). */
typedef struct rad_quad_adapt_params {
    double abs_tol;    /* absolute tolerance on the integral */
    double rel_tol;    /* relative tolerance on the integral */
    int max_intervals; /* cap on subintervals (<= RAD_QUAD_ADAPT_MAX_INTERVALS) */
} rad_quad_adapt_params;

#define RAD_QUAD_ADAPT_MAX_INTERVALS 4096

rad_quad_adapt_params rad_quad_adapt_defaults(void);

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

#ifdef __cplusplus
}
#endif
#endif
