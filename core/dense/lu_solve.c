/* LU solve with a 1-norm condition estimate.
 * dlange gives ||A||_1 before the factorization overwrites A; dgesv factors and
 * solves; dgecon then estimates ||A^-1||_1 from the factors (Hager/Higham). */
#include "rad_dense.h"

#include <lapacke.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>

#include "rad_sys.h"

double rad_dense_bytes(size_t n, int count)
{
    return (double)n * (double)n * (double)sizeof(double) * (double)count;
}

rad_status rad_dense_check_size(size_t n, int count, const char *what)
{
    const double gib = 1024.0 * 1024.0 * 1024.0;
    double need = rad_dense_bytes(n, count), have = rad_sys_memory_bytes();
    if (n > (size_t)46340) /* n*n must stay below 2^31 for 32-bit LAPACK indices */
        return RAD_ERROR(RAD_ETOOBIG,
                         "%s: %zu unknowns is beyond the dense solver's limit of 46340 "
                         "(the matrix alone would take %.1f GiB)", what, n, need / gib);
    if (have > 0 && need > 0.75 * have)
        return RAD_ERROR(RAD_ETOOBIG,
                         "%s: %zu unknowns need %.2f GiB for the dense matrix, more than "
                         "3/4 of this machine's %.2f GiB", what, n, need / gib, have / gib);
    return RAD_OK;
}

rad_status rad_dense_lu_solve(int n, double *A, int nrhs, double *B, double *rcond)
{
    if (n < 1 || nrhs < 1 || !A || !B)
        return RAD_ERROR(RAD_EINVAL, "LU solve: bad arguments (n = %d, nrhs = %d)", n, nrhs);
    size_t nn = (size_t)n * (size_t)n;
    for (size_t k = 0; k < nn; k++)
        if (!isfinite(A[k]))
            return RAD_ERROR(RAD_ENUMERIC, "LU solve: matrix entry %zu is not finite", k);

    lapack_int *ipiv = malloc((size_t)n * sizeof *ipiv);
    if (!ipiv)
        return RAD_ERROR(RAD_ENOMEM, "LU solve: no memory for %d pivots", n);
    rad_status status = RAD_OK;
    double anorm = LAPACKE_dlange(LAPACK_COL_MAJOR, '1', n, n, A, n);
    lapack_int info = LAPACKE_dgesv(LAPACK_COL_MAJOR, n, nrhs, A, n, ipiv, B, n);
    if (info > 0) {
        status = RAD_ERROR(RAD_ESINGULAR, "LU solve: pivot %d is exactly zero", (int)info);
        goto done;
    }
    if (info < 0) {
        status = RAD_ERROR(RAD_EDEP, "LU solve: LAPACKE_dgesv rejected argument %d", (int)-info);
        goto done;
    }
    if (rcond) {
        *rcond = 0.0;
        info = LAPACKE_dgecon(LAPACK_COL_MAJOR, '1', n, A, n, anorm, rcond);
        if (info != 0) {
            status = RAD_ERROR(RAD_EDEP, "LU solve: LAPACKE_dgecon returned %d", (int)info);
            goto done;
        }
    }
done:
    free(ipiv);
    rad_dense_blas_idle();
    return status;
}
