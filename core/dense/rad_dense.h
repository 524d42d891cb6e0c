/* rad_dense: dense linear algebra over LAPACKE/OpenBLAS.
 *
 * Matrices are column-major (LAPACK's own order): entry (i,j) of an n x n
 * matrix A is A[i + (size_t)j * n].  This header holds the LU solve with a
 * condition estimate, the memory check used before any dense allocation and
 * the parking of OpenBLAS's threads; the radiosity system and its solvers are
 * in rad_dense_solve.h, the assembly of G in rad_radiosity.h. */
#ifndef RAD_DENSE_H
#define RAD_DENSE_H

#include <stddef.h>

#include "rad_error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Before allocating `count` dense n x n double matrices for `what`: RAD_ETOOBIG
 * with an estimate in GiB when they would take more than 3/4 of this machine's
 * memory (rad_sys_memory_bytes), or when n exceeds LAPACK's 32-bit index range. */
rad_status rad_dense_check_size(size_t n, int count, const char *what);

/* Bytes that `count` dense n x n double matrices take. */
double rad_dense_bytes(size_t n, int count);

/* Stop the BLAS library's idle worker threads, which otherwise spin for a
 * while after loading and after each threaded call, taking cores from
 * OpenMP; the library restarts them when it next needs them (blas_threads.c).
 * Called at program start and after each LAPACK solve. */
void rad_dense_blas_idle(void);

/* Solve A X = B by LU with partial pivoting (LAPACKE dgesv).  A (n x n) is
 * overwritten by its LU factors and B (n x nrhs) by X.  If rcond is not NULL it
 * receives LAPACK's estimate (dgecon) of 1 / cond_1(A).
 * RAD_ESINGULAR if a pivot is exactly zero; RAD_ENUMERIC if A holds NaN/Inf. */
rad_status rad_dense_lu_solve(int n, double *A, int nrhs, double *B, double *rcond);

#ifdef __cplusplus
}
#endif
#endif
