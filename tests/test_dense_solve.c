/* The radiosity solvers against closed forms (furnace, tetrahedron) and
 * against each other on random symmetric couplings. */
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_dense_solve.h"

static double rnd(unsigned long long *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * 0x1.0p-53;
}

/* An open system: random symmetric G >= 0 with zero diagonal, scaled so the
 * largest row sum of F is `fmax_row` (< 1). */
static void open_system(int n, unsigned long long seed, double fmax_row, double *G, double *A)
{
    for (int i = 0; i < n; i++)
        A[i] = 0.5 + 1.885 * rnd(&seed);
    for (int j = 0; j < n; j++)
        for (int i = 0; i <= j; i++) {
            double w = i == j ? 0.0 : rnd(&seed) * rnd(&seed);
            G[i + j * n] = G[j + i * n] = w;
        }
    double worst = 0.0;
    for (int i = 0; i < n; i++) {
        double s = 0.0;
        for (int j = 0; j < n; j++)
            s += G[j + i * n];
        worst = fmax(worst, s / A[i]);
    }
    for (int k = 0; k < n * n; k++)
        G[k] *= fmax_row / worst;
}

/* A closed system: the interior of a sphere cut into faces of areas A_i has
 * F_ij = A_j / A_total exactly, so G_ij = A_i A_j / A_total (diagonal included)
 * and every row of F sums to 1.  Symmetric moves that keep row sums
 * (+d at ij, kl; -d at il, kj, mirrored) make it less regular. */
static void closed_system(int n, unsigned long long seed, double *G, double *A)
{
    double total = 0.0;
    for (int i = 0; i < n; i++) {
        A[i] = 0.5 + 1.885 * rnd(&seed);
        total += A[i];
    }
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            G[i + j * n] = A[i] * A[j] / total;
    for (int move = 0; move < 20 * n; move++) {
        int i = (int)(rnd(&seed) * n), j = (int)(rnd(&seed) * n);
        int k = (int)(rnd(&seed) * n), l = (int)(rnd(&seed) * n);
        if (i == k || j == l || i == j || k == l || i == l || k == j)
            continue;
        double d = 0.5 * fmin(G[i + l * n], G[k + j * n]) * rnd(&seed);
        G[i + j * n] += d; G[j + i * n] += d;
        G[k + l * n] += d; G[l + k * n] += d;
        G[i + l * n] -= d; G[l + i * n] -= d;
        G[k + j * n] -= d; G[j + k * n] -= d;
    }
}

static double max_rel_diff(int m, const double *x, const double *y)
{
    double d = 0.0, s = 0.0;
    for (int k = 0; k < m; k++) {
        d = fmax(d, fabs(x[k] - y[k]));
        s = fmax(s, fabs(y[k]));
    }
    return s > 0 ? d / s : d;
}

TEST(dense_closed_system_rows_sum_to_one)
{
    enum { N = 23 };
    double G[N * N], A[N];
    closed_system(N, 77, G, A);
    for (int i = 0; i < N; i++) {
        double s = 0.0;
        for (int j = 0; j < N; j++) {
            s += G[j + i * N];
            CHECK(G[j + i * N] >= 0.0);
            CHECK(G[j + i * N] == G[i + j * N]);
        }
        CHECK_NEAR(s / A[i], 1.0, 1e-14, 0.0);
    }
}

TEST(dense_all_solvers_agree_with_lu)
{
    enum { N = 41 };
    static double G[N * N];
    double A[N], rho[3 * N], E[3 * N], ref[3 * N], B[3 * N];
    open_system(N, 2024, 0.93, G, A);
    unsigned long long s = 99;
    for (int k = 0; k < 3 * N; k++) {
        rho[k] = k % 7 == 3 ? 0.0 : 0.95 * rnd(&s); /* coloured, some faces black */
        E[k] = k % 5 == 0 ? 10.0 * rnd(&s) : 0.0;
    }
    rad_dense_params p;
    rad_dense_params_default(&p);
    p.tol = 1e-13;
    rad_dense_report rep;
    CHECK(rad_dense_radiosity_solve(N, G, A, rho, E, ref, &p, &rep) == RAD_OK);
    CHECK(rep.factorizations == 3);
    CHECK(rep.residual < 1e-13);
    /* Independent check of LU: the answer satisfies B_i = E_i + rho_i sum F_ij B_j. */
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < N; i++) {
            double sum = 0.0;
            for (int j = 0; j < N; j++)
                sum += G[i + j * N] / A[i] * ref[j + c * N];
            CHECK_NEAR(ref[i + c * N], E[i + c * N] + rho[i + c * N] * sum, 1e-12, 1e-12);
        }
    for (int m = RAD_DENSE_CHOLESKY; m < RAD_DENSE_METHOD_COUNT; m++) {
        p.method = (rad_dense_method)m;
        memset(B, 0, sizeof B);
        CHECK(rad_dense_radiosity_solve(N, G, A, rho, E, B, &p, &rep) == RAD_OK);
        double diff = max_rel_diff(3 * N, B, ref);
        CHECK_MSG(diff < 1e-11, "%s differs from LU by %.3g", rad_dense_method_name(p.method), diff);
        if (m != RAD_DENSE_CHOLESKY)
            CHECK(rep.iterations > 1 && rep.residual <= p.tol);
    }
}

TEST(dense_furnace_closed_system_all_solvers)
{
    enum { N = 31 };
    static double G[N * N];
    double A[N], rho[3 * N], E[3 * N], B[3 * N];
    closed_system(N, 4242, G, A);
    const double r = 0.7318, e = 2.385;
    for (int k = 0; k < 3 * N; k++) {
        rho[k] = r;
        E[k] = e;
    }
    for (int m = 0; m < RAD_DENSE_METHOD_COUNT; m++) {
        rad_dense_params p;
        rad_dense_params_default(&p);
        p.method = (rad_dense_method)m;
        p.tol = 1e-13;
        rad_dense_report rep;
        CHECK(rad_dense_radiosity_solve(N, G, A, rho, E, B, &p, &rep) == RAD_OK);
        for (int k = 0; k < 3 * N; k++)
            CHECK_NEAR(B[k], e / (1.0 - r), 1e-11, 0.0);
        if (m <= RAD_DENSE_CHOLESKY)
            CHECK(rep.factorizations == 1); /* grey: one factorization, three columns */
    }
}

TEST(dense_tetrahedron_closed_form)
{
    /* A regular tetrahedron: by symmetry F_ij is the same for all i != j and
     * F_ii = 0 (planar faces), and the rows sum to 1: F_ij = 1/3.  Light only
     * face 0: B_1 = B_2 = B_3 = rho B_0 / (3 - 2 rho) and
     * B_0 = E (3 - 2 rho) / ((3 + rho)(1 - rho)). */
    const double a = 0.4330127018922193 * 2.385 * 2.385; /* sqrt(3)/4 s^2 */
    double G[16], A[4] = {a, a, a, a}, rho[12], E[12] = {0}, B[12];
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            G[i + 4 * j] = i == j ? 0.0 : a / 3.0;
    const double r[3] = {0.5, 0.81, 0.137}, e = 7.25;
    for (int c = 0; c < 3; c++) {
        for (int i = 0; i < 4; i++)
            rho[i + 4 * c] = r[c];
        E[0 + 4 * c] = e;
    }
    for (int m = 0; m < RAD_DENSE_METHOD_COUNT; m++) {
        rad_dense_params p;
        rad_dense_params_default(&p);
        p.method = (rad_dense_method)m;
        p.tol = 1e-14;
        rad_dense_report rep;
        CHECK(rad_dense_radiosity_solve(4, G, A, rho, E, B, &p, &rep) == RAD_OK);
        for (int c = 0; c < 3; c++) {
            double b0 = e * (3 - 2 * r[c]) / ((3 + r[c]) * (1 - r[c]));
            CHECK_NEAR(B[0 + 4 * c], b0, 1e-13, 0.0);
            for (int i = 1; i < 4; i++)
                CHECK_NEAR(B[i + 4 * c], r[c] * b0 / (3 - 2 * r[c]), 1e-13, 0.0);
        }
        if (m <= RAD_DENSE_CHOLESKY)
            CHECK(rep.factorizations == 3); /* coloured */
    }
}

TEST(dense_high_reflectance_stays_accurate)
{
    enum { N = 29 };
    static double G[N * N];
    double A[N], rho[3 * N], E[3 * N], B[3 * N];
    closed_system(N, 31337, G, A);
    const double rs[2] = {0.99, 0.999};
    for (int t = 0; t < 2; t++) {
        for (int k = 0; k < 3 * N; k++) {
            rho[k] = rs[t];
            E[k] = 1.25;
        }
        for (int m = 0; m < RAD_DENSE_METHOD_COUNT; m++) {
            rad_dense_params p;
            rad_dense_params_default(&p);
            p.method = (rad_dense_method)m;
            p.tol = 1e-12;
            p.max_iter = 100000;
            rad_dense_report rep;
            CHECK(rad_dense_radiosity_solve(N, G, A, rho, E, B, &p, &rep) == RAD_OK);
            double want = 1.25 / (1.0 - rs[t]);
            /* Error bound: residual tolerance times 1/(1 - rho) for the iterative
             * solvers; for the direct ones about cond * eps, with cond ~ 1/rcond. */
            double bound = m <= RAD_DENSE_CHOLESKY ? 50 * 2.2e-16 / rep.rcond : 2 * p.tol / (1 - rs[t]);
            for (int k = 0; k < 3 * N; k++)
                CHECK_NEAR(B[k], want, bound, 0.0);
            if (m <= RAD_DENSE_CHOLESKY) {
                CHECK_MSG(rep.rcond > 0.0 && rep.rcond < 20 * (1 - rs[t]),
                          "%s rho %g: rcond %.3g", rad_dense_method_name(p.method), rs[t], rep.rcond);
            }
        }
    }
}

TEST(dense_jacobi_residual_decreases_monotonically)
{
    enum { N = 33 };
    static double G[N * N], H[N * N];
    double A[N], A2[N], rho[N], E[N];
    open_system(N, 5, 0.97, G, A);
    closed_system(N, 6, H, A2);
    unsigned long long s = 1;
    for (int i = 0; i < N; i++) {
        rho[i] = 0.3 + 0.69 * rnd(&s);
        E[i] = i % 4 == 1 ? 3.7 * rnd(&s) : 0.0;
    }
    for (int sys = 0; sys < 2; sys++) {
        rad_dense_iter *it = NULL;
        rad_dense_params p;
        rad_dense_params_default(&p);
        p.tol = 1e-12;
        CHECK(rad_dense_iter_create(N, sys ? H : G, sys ? A2 : A, rho, E, RAD_DENSE_JACOBI, &p, &it) == RAD_OK);
        if (!it)
            return;
        rad_status st;
        while ((st = rad_dense_iter_test(it)) == RAD_CONTINUE)
            CHECK(rad_dense_iter_step(it) == RAD_OK);
        CHECK(st == RAD_OK);
        int len = 0;
        const double *h = rad_dense_iter_history(it, &len);
        CHECK(len == rad_dense_iter_count(it) + 1 && len > 10);
        for (int k = 1; k < len; k++)
            CHECK_MSG(h[k] <= h[k - 1], "sweep %d: residual %.3g after %.3g", k, h[k], h[k - 1]);
        rad_dense_iter_destroy(it);
    }
}

TEST(dense_iteration_cap_is_reported)
{
    enum { N = 9 };
    double G[N * N], A[N], rho[N], E[N];
    closed_system(N, 8, G, A);
    for (int i = 0; i < N; i++) {
        rho[i] = 0.95;
        E[i] = 1.0 + i;
    }
    rad_dense_params p;
    rad_dense_params_default(&p);
    p.max_iter = 3;
    rad_dense_iter *it = NULL;
    CHECK(rad_dense_iter_create(N, G, A, rho, E, RAD_DENSE_JACOBI, &p, &it) == RAD_OK);
    for (int k = 0; k < 3; k++)
        CHECK(rad_dense_iter_step(it) == RAD_OK);
    CHECK(rad_dense_iter_test(it) == RAD_CONTINUE);
    CHECK(rad_dense_iter_step(it) == RAD_ENUMERIC);
    CHECK(strstr(rad_error_message(), "no convergence in 3 sweeps") != NULL);
    rad_dense_iter_destroy(it);
    CHECK(rad_dense_iter_create(N, G, A, rho, E, RAD_DENSE_LU, &p, &it) == RAD_EINVAL);
}

TEST(dense_rejects_bad_input_and_too_big)
{
    double G[4] = {0, 0.3, 0.3, 0}, A[2] = {1, 1}, rho[6] = {0.5, 1.0, 0.5, 0.5, 0.5, 0.5};
    double E[6] = {1, 0, 1, 0, 1, 0}, B[6];
    CHECK(rad_dense_radiosity_solve(2, G, A, rho, E, B, NULL, NULL) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "face 1") != NULL);
    rho[1] = 0.5;
    E[2] = -1;
    CHECK(rad_dense_radiosity_solve(2, G, A, rho, E, B, NULL, NULL) == RAD_EINPUT);
    E[2] = 1;
    G[1] = NAN;
    CHECK(rad_dense_radiosity_solve(2, G, A, rho, E, B, NULL, NULL) == RAD_EINPUT);
    G[1] = 0.3;
    /* Row sums of F far above 1: Cholesky's form is indefinite and says so. */
    double H[4] = {0, 3.0, 3.0, 0};
    rad_dense_params p;
    rad_dense_params_default(&p);
    p.method = RAD_DENSE_CHOLESKY;
    CHECK(rad_dense_radiosity_solve(2, H, A, rho, E, B, &p, NULL) == RAD_ESINGULAR);
    CHECK(strstr(rad_error_message(), "LU") != NULL);

    setenv("RADKIT_MEMORY_LIMIT", "1000000", 1);
    CHECK(rad_dense_radiosity_check_size(300, RAD_DENSE_LU) == RAD_ETOOBIG);
    CHECK(strstr(rad_error_message(), "--method hier") != NULL);
    CHECK(rad_dense_radiosity_check_size(300, RAD_DENSE_JACOBI) == RAD_OK); /* 0.72 MB */
    unsetenv("RADKIT_MEMORY_LIMIT");
    CHECK(rad_dense_radiosity_check_size(60000, RAD_DENSE_JACOBI) == RAD_ETOOBIG);
    CHECK(strstr(rad_error_message(), "--method hier") != NULL);

    rad_dense_method m;
    CHECK(rad_dense_method_parse("gauss-seidel", &m) == RAD_OK && m == RAD_DENSE_GAUSS_SEIDEL);
    CHECK(rad_dense_method_parse("gs", &m) == RAD_EINVAL);
}

TEST(dense_results_do_not_depend_on_thread_count)
{
    enum { N = 300 }; /* above the size at which the loops go parallel */
    static double G[N * N], A[N], rho[3 * N], E[3 * N], B1[3 * N], B2[3 * N];
    open_system(N, 11, 0.9, G, A);
    unsigned long long s = 3;
    for (int k = 0; k < 3 * N; k++) {
        rho[k] = 0.8 * rnd(&s);
        E[k] = rnd(&s);
    }
    for (int m = RAD_DENSE_JACOBI; m < RAD_DENSE_METHOD_COUNT; m++) {
        rad_dense_params p;
        rad_dense_params_default(&p);
        p.method = (rad_dense_method)m;
        omp_set_num_threads(1);
        CHECK(rad_dense_radiosity_solve(N, G, A, rho, E, B1, &p, NULL) == RAD_OK);
        omp_set_num_threads(2);
        CHECK(rad_dense_radiosity_solve(N, G, A, rho, E, B2, &p, NULL) == RAD_OK);
        CHECK_MSG(memcmp(B1, B2, sizeof B1) == 0, "%s: 1 and 2 threads differ",
                  rad_dense_method_name(p.method));
    }
}
