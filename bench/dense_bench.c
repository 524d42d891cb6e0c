/* bench/dense_bench N...: LU solve GFLOP/s through rad_dense_lu_solve against
 * LAPACKE_dgesv called directly on the same matrix (compiled by bench/dense.sh;
 * the thread count comes from OPENBLAS_NUM_THREADS, set by the script).
 * The matrix is a radiosity system K = I - R F from a random symmetric coupling
 * (row sums of F 0.9, rho 0.8): the matrices radkit actually factors.
 * Flops counted: 2/3 n^3 (factorization) + 2 n^2 (one right-hand side).
 * rad_dense_lu_solve also scans for non-finite entries, takes ||A||_1 (dlange)
 * and estimates the condition (dgecon): O(n^2) extras included in its time.
 * Best of 3 runs each. */
#include <lapacke.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_dense.h"
#include "rad_dense_solve.h"
#include "rad_sys.h"

static double rnd(unsigned long long *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * 0x1.0p-53;
}

int main(int argc, char **argv)
{
    const char *threads = getenv("OPENBLAS_NUM_THREADS");
    /* Repetitions (the best is kept): DENSE_BENCH_REPS, default 3; one is
     * enough where a single solve takes minutes. */
    const char *reps_env = getenv("DENSE_BENCH_REPS");
    int reps = reps_env && atoi(reps_env) > 0 ? atoi(reps_env) : 3;
    printf("method\tthreads\tn\tseconds\tGFLOP_per_s\trelative_to_dgesv\n");
    for (int a = 1; a < argc; a++) {
        int n = atoi(argv[a]);
        size_t nn = (size_t)n * (size_t)n;
        double *G = malloc(nn * sizeof *G), *K = malloc(nn * sizeof *K), *W = malloc(nn * sizeof *W);
        double *area = malloc((size_t)n * sizeof *area), *rho = malloc((size_t)n * sizeof *rho);
        double *b = malloc((size_t)n * sizeof *b), *x = malloc((size_t)n * sizeof *x);
        lapack_int *ipiv = malloc((size_t)n * sizeof *ipiv);
        unsigned long long s = 7 + (unsigned long long)n;
        for (int i = 0; i < n; i++) {
            area[i] = 0.5 + rnd(&s);
            rho[i] = 0.8;
            b[i] = rnd(&s);
        }
        for (int j = 0; j < n; j++)
            for (int i = 0; i <= j; i++)
                G[i + (size_t)j * n] = G[j + (size_t)i * n] = i == j ? 0.0 : rnd(&s);
        double worst = 0;
        for (int i = 0; i < n; i++) {
            double sum = 0;
            for (int j = 0; j < n; j++)
                sum += G[j + (size_t)i * n];
            if (sum / area[i] > worst)
                worst = sum / area[i];
        }
        for (size_t k = 0; k < nn; k++)
            G[k] *= 0.9 / worst;
        rad_dense_system_matrix(n, G, area, rho, K);
        double flops = 2.0 / 3.0 * n * (double)n * n + 2.0 * n * (double)n;
        double best[2] = {1e300, 1e300};
        for (int rep = 0; rep < reps; rep++)
            for (int method = 0; method < 2; method++) {
                memcpy(W, K, nn * sizeof *W);
                memcpy(x, b, (size_t)n * sizeof *x);
                double t0 = rad_sys_seconds(), rcond;
                if (method == 0)
                    LAPACKE_dgesv(LAPACK_COL_MAJOR, n, 1, W, n, ipiv, x, n);
                else if (rad_dense_lu_solve(n, W, 1, x, &rcond) != RAD_OK)
                    fprintf(stderr, "dense_bench: %s\n", rad_error_message());
                double t = rad_sys_seconds() - t0;
                if (t < best[method])
                    best[method] = t;
            }
        printf("dgesv\t%s\t%d\t%.4f\t%.2f\t1.000\n", threads ? threads : "?", n, best[0],
               flops / best[0] / 1e9);
        printf("rad_dense_lu_solve\t%s\t%d\t%.4f\t%.2f\t%.3f\n", threads ? threads : "?", n,
               best[1], flops / best[1] / 1e9, best[0] / best[1]);
        fflush(stdout);
        free(G); free(K); free(W); free(area); free(rho); free(b); free(x); free(ipiv);
    }
    return 0;
}
