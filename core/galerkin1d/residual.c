/* The independent check: the Galerkin residual from the definitions alone.
 *
 *   r_i = (M y)_i - int phi_i(x) int k(x,t) y_h(t) dt dx - int phi_i f
 *
 * The double integral is computed by a G-point Gauss rule in x on every cell
 * and, for each outer point x, a G-point rule in t on every cell, the cell that
 * holds x split at t = x where the kernel kinks.  No closed form is used, so a
 * small residual confirms both the closed forms and the solve.  With G = 4 the
 * nested rule is exact for kernels polynomial of low degree on each side of the
 * diagonal (the seed kernel gives degree <= 5 integrands); the load uses 16
 * points per cell. */
#include "rad_galerkin1d.h"

#include <math.h>
#include <stdlib.h>

#include "rad_quad.h"

#define RES_POINTS 4
#define LOAD_POINTS 16

static double local_value(rad_galerkin1d_basis basis, const double *y, int c, double u)
{
    return basis == RAD_GALERKIN1D_P0 ? y[c] : y[c] * (1.0 - u) + y[c + 1] * u;
}

rad_status rad_galerkin1d_residual(const rad_galerkin1d_problem *problem,
                                   rad_galerkin1d_basis basis, int n, const double *y,
                                   double *relative_residual)
{
    size_t dim = rad_galerkin1d_dim(basis, n);
    if (!problem || !y || !relative_residual || dim == 0)
        return RAD_ERROR(RAD_EINVAL, "galerkin1d residual: bad arguments (n = %d)", n);
    double gu[RES_POINTS], gw[RES_POINTS], lu[LOAD_POINTS], lw[LOAD_POINTS];
    rad_quad_gauss_legendre(RES_POINTS, gu, gw);
    rad_quad_gauss_legendre(LOAD_POINTS, lu, lw);

    double *ky = calloc(3 * dim + (size_t)n * RES_POINTS, sizeof *ky);
    if (!ky)
        return RAD_ERROR(RAD_ENOMEM, "galerkin1d residual: no memory for n = %d", n);
    double *load = ky + dim, *mass = load + dim, *yq = mass + dim;
    double h = 1.0 / n;
    for (int c = 0; c < n; c++)
        for (int q = 0; q < RES_POINTS; q++)
            yq[c * RES_POINTS + q] = local_value(basis, y, c, gu[q]);

    for (int a = 0; a < n; a++) {
        for (int p = 0; p < RES_POINTS; p++) {
            double x = (a + gu[p]) * h, inner = 0.0;
            for (int c = 0; c < n; c++) {
                if (c == a)
                    continue;
                for (int q = 0; q < RES_POINTS; q++)
                    inner += h * gw[q] * problem->kernel(x, (c + gu[q]) * h) * yq[c * RES_POINTS + q];
            }
            double left = x - a * h, right = (a + 1) * h - x;
            for (int q = 0; q < RES_POINTS; q++) {
                double t1 = a * h + left * gu[q], t2 = x + right * gu[q];
                inner += left * gw[q] * problem->kernel(x, t1) * local_value(basis, y, a, t1 * n - a);
                inner += right * gw[q] * problem->kernel(x, t2) * local_value(basis, y, a, t2 * n - a);
            }
            double wt = h * gw[p] * inner;
            if (basis == RAD_GALERKIN1D_P0) {
                ky[a] += wt;
            } else {
                ky[a] += wt * (1.0 - gu[p]);
                ky[a + 1] += wt * gu[p];
            }
        }
        for (int q = 0; q < LOAD_POINTS; q++) {
            double fw = h * lw[q] * problem->f((a + lu[q]) * h);
            if (basis == RAD_GALERKIN1D_P0) {
                load[a] += fw;
            } else {
                load[a] += fw * (1.0 - lu[q]);
                load[a + 1] += fw * lu[q];
            }
        }
    }

    double *diag = mass; /* reuse: M y computed in place below */
    double *off = malloc(dim * sizeof *off);
    if (!off) {
        free(ky);
        return RAD_ERROR(RAD_ENOMEM, "galerkin1d residual: no memory for n = %d", n);
    }
    rad_galerkin1d_mass(basis, n, diag, off);
    double rmax = 0.0, bmax = 0.0;
    for (size_t i = 0; i < dim; i++) {
        double my = diag[i] * y[i];
        if (i > 0)
            my += off[i - 1] * y[i - 1];
        if (i + 1 < dim)
            my += off[i] * y[i + 1];
        rmax = fmax(rmax, fabs(my - ky[i] - load[i]));
        bmax = fmax(bmax, fabs(load[i]));
    }
    free(off);
    free(ky);
    *relative_residual = bmax > 0.0 ? rmax / bmax : rmax;
    if (!isfinite(*relative_residual))
        return RAD_ERROR(RAD_ENUMERIC, "galerkin1d residual: not finite");
    return RAD_OK;
}
