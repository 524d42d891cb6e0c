/* Gauss-Legendre nodes and weights by Newton's method.
 *
 * 1. Start from Tricomi's asymptotic guess x_i ~ cos(pi (i + 3/4) / (k + 1/2)).
 * 2. Evaluate P_k and P_k' by the recurrence (j+1) P_{j+1} = (2j+1) x P_j - j P_{j-1}
 *    and iterate x <- x - P_k/P_k' until the step is below a few ulps.
 * 3. Weight w_i = 2 / ((1 - x_i^2) P_k'(x_i)^2) on [-1,1]; map to [0,1].
 * The guess lies in the basin of the right root for every k, so the nodes come out
 * distinct and ordered; accuracy is a few ulps for k up to several hundred.
 * (Golub-Welsch [golub1969] would give the same rule from an eigenproblem;
 * Newton is O(k^2) and needs no LAPACK call.) */
#include "rad_quad.h"

#include <math.h>

#include "rad_geom.h"

static void legendre_eval(int k, double x, double *p, double *dp)
{
    double p0 = 1.0, p1 = x;
    if (k == 0) {
        *p = 1.0;
        *dp = 0.0;
        return;
    }
    for (int j = 1; j < k; j++) {
        double p2 = ((2.0 * j + 1.0) * x * p1 - j * p0) / (j + 1.0);
        p0 = p1;
        p1 = p2;
    }
    *p = p1;
    /* (1 - x^2) P_k' = k (P_{k-1} - x P_k); |x| < 1 strictly at every iterate. */
    *dp = k * (p0 - x * p1) / (1.0 - x * x);
}

rad_status rad_quad_gauss_legendre(int k, double *x, double *w)
{
    if (k < 1)
        return RAD_ERROR(RAD_EINVAL, "Gauss-Legendre rule needs at least 1 point, got %d", k);
    int half = (k + 1) / 2;
    for (int i = 0; i < half; i++) {
        double z = cos(RAD_PI * (i + 0.75) / (k + 0.5)), p = 0.0, dp = 1.0;
        for (int it = 0; it < 100; it++) {
            legendre_eval(k, z, &p, &dp);
            double step = p / dp;
            z -= step;
            if (fabs(step) <= 4e-16 * fabs(z) + 1e-300)
                break;
        }
        legendre_eval(k, z, &p, &dp);
        double wt = 2.0 / ((1.0 - z * z) * dp * dp);
        /* z is the i-th largest root: it maps to the node k-1-i; its mirror to i. */
        x[k - 1 - i] = 0.5 * (1.0 + z);
        x[i] = 0.5 * (1.0 - z);
        w[k - 1 - i] = 0.5 * wt;
        w[i] = 0.5 * wt;
    }
    if (k % 2 == 1)
        x[k / 2] = 0.5; /* the middle root is exactly 0 on [-1,1] */
    return RAD_OK;
}
