/* LU solve with condition estimate, and the memory check. */
#include <math.h>
#include <stdlib.h>

#include "harness.h"
#include "rad_dense.h"

TEST(dense_lu_solves_and_estimates_condition)
{
    /* Column-major A = [[4,1,0],[2,5,1],[0,1,3]] (rows), x = (1.5, -2.25, 0.75). */
    double A[9] = {4, 2, 0, 1, 5, 1, 0, 1, 3};
    double x[3] = {1.5, -2.25, 0.75}, b[3];
    for (int i = 0; i < 3; i++)
        b[i] = A[i] * x[0] + A[i + 3] * x[1] + A[i + 6] * x[2];
    double rcond = 0.0;
    CHECK(rad_dense_lu_solve(3, A, 1, b, &rcond) == RAD_OK);
    for (int i = 0; i < 3; i++)
        CHECK_NEAR(b[i], x[i], 1e-14, 1e-15);
    /* ||A||_1 = 7; by cofactors det A = 50 and the columns of A^-1 are
     * (14,-6,2)/50, (-3,12,-4)/50, (1,-4,18)/50, so ||A^-1||_1 = 23/50.
     * dgecon's estimate is a lower bound on ||A^-1||_1, exact on this matrix. */
    CHECK_NEAR(rcond, 50.0 / (7.0 * 23.0), 1e-12, 0.0);
    CHECK(rcond > 0.0 && rcond <= 1.0);
}

/* After rad_dense_blas_idle has stopped OpenBLAS's worker threads, LAPACK
 * still solves (OpenBLAS starts them again), also a system big enough for
 * threaded dgesv, and idling twice is harmless.  A = n I + (i + 2j) mod 7 - 3
 * (diagonally dominant), x_i = sin(i). */
TEST(dense_lu_after_blas_idle)
{
    int n = 400;
    double *A = malloc((size_t)n * n * sizeof *A), *b = malloc((size_t)n * sizeof *b);
    for (int round = 0; round < 2; round++) {
        rad_dense_blas_idle();
        rad_dense_blas_idle();
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++)
                A[i + (size_t)j * n] = (i == j ? n : 0) + (double)((i + 2 * j) % 7) - 3.0;
        for (int i = 0; i < n; i++) {
            b[i] = 0.0;
            for (int j = 0; j < n; j++)
                b[i] += A[i + (size_t)j * n] * sin((double)j);
        }
        CHECK(rad_dense_lu_solve(n, A, 1, b, NULL) == RAD_OK);
        double worst = 0.0;
        for (int i = 0; i < n; i++)
            worst = fmax(worst, fabs(b[i] - sin((double)i)));
        CHECK_MSG(worst < 1e-12, "round %d: largest error %.3g", round, worst);
    }
    free(A);
    free(b);
}

TEST(dense_lu_rejects_singular_and_nan)
{
    double S[4] = {1, 2, 2, 4}, b[2] = {1, 1};
    CHECK(rad_dense_lu_solve(2, S, 1, b, NULL) == RAD_ESINGULAR);
    double N[4] = {1, NAN, 0, 1}, c[2] = {1, 1};
    CHECK(rad_dense_lu_solve(2, N, 1, c, NULL) == RAD_ENUMERIC);
    CHECK(rad_dense_lu_solve(0, N, 1, c, NULL) == RAD_EINVAL);
}

TEST(dense_size_check_refuses_with_an_estimate)
{
    CHECK(rad_dense_check_size(100, 1, "test") == RAD_OK);
    CHECK(rad_dense_check_size(50000, 1, "test") == RAD_ETOOBIG);
    setenv("RADKIT_MEMORY_LIMIT", "1000000", 1); /* 1 MB: 400 x 400 doubles is 1.28 MB */
    CHECK(rad_dense_check_size(400, 1, "test") == RAD_ETOOBIG);
    CHECK(rad_dense_check_size(200, 1, "test") == RAD_OK);
    unsetenv("RADKIT_MEMORY_LIMIT");
    CHECK_NEAR(rad_dense_bytes(1000, 2), 16e6, 0.0, 0.0);
}
