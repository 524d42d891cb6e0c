/* Error norms of a discrete solution against the exact solution.
 *
 * L2: a 16-point Gauss rule per cell.  y_h is a polynomial of degree <= 1 on a
 * cell and y is analytic, so the rule's error is far below the errors measured.
 * L-infinity: 33 equally spaced samples per cell (the cell's own polynomial, so
 * the P0 jumps are seen from both sides), then golden-section search for the
 * maximum of |y_h - y| between the neighbours of the largest sample.  This
 * finds the maximum to ~1e-15 when |y_h - y| is unimodal near it, which holds
 * for smooth y once a cell resolves it. */
#include "rad_galerkin1d.h"

#include <math.h>

#include "rad_quad.h"

#define L2_POINTS 16
#define LINF_SAMPLES 32

typedef struct cell_error {
    const rad_galerkin1d_problem *problem;
    rad_galerkin1d_basis basis;
    int n, c;
    const double *y;
} cell_error;

static double local_value(rad_galerkin1d_basis basis, const double *y, int c, double u)
{
    return basis == RAD_GALERKIN1D_P0 ? y[c] : y[c] * (1.0 - u) + y[c + 1] * u;
}

static double abs_error(const cell_error *e, double u)
{
    double x = (e->c + u) / e->n;
    return fabs(local_value(e->basis, e->y, e->c, u) - e->problem->exact(x));
}

static double cell_linf(const cell_error *e)
{
    int best = 0;
    double best_value = -1.0;
    for (int s = 0; s <= LINF_SAMPLES; s++) {
        double v = abs_error(e, (double)s / LINF_SAMPLES);
        if (v > best_value) {
            best_value = v;
            best = s;
        }
    }
    /* Golden-section search for a maximum in the bracket around the best sample. */
    const double g = 0.61803398874989484820;
    double lo = (best > 0 ? best - 1 : 0) / (double)LINF_SAMPLES;
    double hi = (best < LINF_SAMPLES ? best + 1 : LINF_SAMPLES) / (double)LINF_SAMPLES;
    double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
    double f1 = abs_error(e, m1), f2 = abs_error(e, m2);
    for (int it = 0; it < 80 && hi - lo > 1e-15; it++) {
        if (f1 > f2) {
            hi = m2;
            m2 = m1;
            f2 = f1;
            m1 = hi - g * (hi - lo);
            f1 = abs_error(e, m1);
        } else {
            lo = m1;
            m1 = m2;
            f1 = f2;
            m2 = lo + g * (hi - lo);
            f2 = abs_error(e, m2);
        }
    }
    return fmax(best_value, fmax(f1, f2));
}

rad_status rad_galerkin1d_errors(const rad_galerkin1d_problem *problem,
                                 rad_galerkin1d_basis basis, int n, const double *y,
                                 rad_galerkin1d_error_norms *out)
{
    if (!problem || !problem->exact || !y || !out || n < 1)
        return RAD_ERROR(RAD_EINVAL, "galerkin1d errors: no exact solution to compare with");
    double u[L2_POINTS], w[L2_POINTS];
    rad_quad_gauss_legendre(L2_POINTS, u, w);
    double h = 1.0 / n, l2 = 0.0, linf = 0.0, nodal = 0.0;
    for (int c = 0; c < n; c++) {
        cell_error e = {problem, basis, n, c, y};
        for (int q = 0; q < L2_POINTS; q++) {
            double d = abs_error(&e, u[q]);
            l2 += h * w[q] * d * d;
        }
        linf = fmax(linf, cell_linf(&e));
        if (basis == RAD_GALERKIN1D_P0)
            nodal = fmax(nodal, abs_error(&e, 0.5));
    }
    if (basis == RAD_GALERKIN1D_P1)
        for (int i = 0; i <= n; i++)
            nodal = fmax(nodal, fabs(y[i] - problem->exact((double)i / n)));
    out->l2 = sqrt(l2);
    out->linf = linf;
    out->nodal = nodal;
    if (!isfinite(out->l2) || !isfinite(out->linf))
        return RAD_ERROR(RAD_ENUMERIC, "galerkin1d errors: the solution is not finite");
    return RAD_OK;
}
