/* Solve the Galerkin system (M - A) y = b with LAPACK (rad_dense_lu_solve). */
#include "rad_galerkin1d.h"

#include <stdlib.h>
#include <string.h>

#include "rad_dense.h"

rad_status rad_galerkin1d_solve(rad_galerkin1d_basis basis, int n, double *A, const double *b,
                                double *y, double *rcond)
{
    size_t dim = rad_galerkin1d_dim(basis, n);
    if (dim == 0 || !A || !b || !y)
        return RAD_ERROR(RAD_EINVAL, "galerkin1d solve: bad arguments (n = %d)", n);
    double *diag = malloc(2 * dim * sizeof *diag);
    if (!diag)
        return RAD_ERROR(RAD_ENOMEM, "galerkin1d solve: no memory for the mass matrix");
    double *off = diag + dim;
    rad_galerkin1d_mass(basis, n, diag, off);

    for (size_t k = 0; k < dim * dim; k++)
        A[k] = -A[k];
    for (size_t i = 0; i < dim; i++) {
        A[i + i * dim] += diag[i];
        if (i + 1 < dim) {
            A[i + (i + 1) * dim] += off[i];
            A[(i + 1) + i * dim] += off[i];
        }
    }
    free(diag);
    memcpy(y, b, dim * sizeof *y);
    return rad_dense_lu_solve((int)dim, A, 1, y, rcond);
}
