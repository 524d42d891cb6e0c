/* The 1D model problem: every closed form against adaptive quadrature of its
 * definition, the exact solutions against the integral equation, the solver
 * against a fully independent assembly, and the convergence rates of theory. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "rad_dense.h"
#include "rad_galerkin1d.h"
#include "rad_quad.h"

/* ---- independent reference: nested adaptive Gauss-Kronrod ------------------ */

typedef struct entry_ctx {
    const rad_galerkin1d_problem *problem;
    int n, a, c;         /* test cell (x), trial cell (t) */
    int alpha, beta;     /* local shapes: -1 = constant 1, 0 = 1-u, 1 = u */
    double x;            /* current outer point */
} entry_ctx;

static double shape(int which, double u) { return which < 0 ? 1.0 : which == 0 ? 1.0 - u : u; }

static double inner_integrand(double t, void *vctx)
{
    entry_ctx *e = vctx;
    return e->problem->kernel(e->x, t) * shape(e->beta, t * e->n - e->c);
}

static double outer_integrand(double x, void *vctx)
{
    entry_ctx *e = vctx;
    e->x = x;
    rad_quad_result r;
    rad_quad_adapt_params p;
    rad_quad_adapt_params_default(&p);
    p.rel_tol = 1e-15;
    p.abs_tol = 1e-300;
    rad_quad_adapt(inner_integrand, e, (double)e->c / e->n, (double)(e->c + 1) / e->n, &x, 1, &p, &r);
    return shape(e->alpha, x * e->n - e->a) * r.value;
}

/* int_{cell a} int_{cell c} shape_alpha(x) k(x,t) shape_beta(t) dt dx */
static double entry_by_quadrature(const rad_galerkin1d_problem *pb, int n, int a, int c, int alpha, int beta)
{
    entry_ctx e = {pb, n, a, c, alpha, beta, 0.0};
    rad_quad_result r;
    rad_quad_adapt_params p;
    rad_quad_adapt_params_default(&p);
    p.rel_tol = 1e-14;
    CHECK(rad_quad_adapt(outer_integrand, &e, (double)a / n, (double)(a + 1) / n, NULL, 0, &p, &r) == RAD_OK);
    return r.value;
}

typedef struct load_ctx {
    const rad_galerkin1d_problem *problem;
    int n, c, alpha;
} load_ctx;

static double load_integrand(double x, void *vctx)
{
    load_ctx *l = vctx;
    return l->problem->f(x) * shape(l->alpha, x * l->n - l->c);
}

static double load_by_quadrature(const rad_galerkin1d_problem *pb, int n, int c, int alpha)
{
    load_ctx l = {pb, n, c, alpha};
    rad_quad_result r;
    rad_quad_adapt_params p;
    rad_quad_adapt_params_default(&p);
    p.rel_tol = 1e-14;
    p.abs_tol = 1e-300;
    CHECK(rad_quad_adapt(load_integrand, &l, (double)c / n, (double)(c + 1) / n, NULL, 0, &p, &r) == RAD_OK);
    return r.value;
}

static const int sizes[] = {1, 2, 3, 7, 64, 1000, 4096};
#define NSIZES ((int)(sizeof sizes / sizeof sizes[0]))

/* Cell pairs to test for size n: corners, diagonal, neighbours, interior. */
static int pick_pairs(int n, int pairs[][2])
{
    int cand[][2] = {{0, 0}, {n - 1, n - 1}, {n / 2, n / 2}, {0, n - 1}, {n - 1, 0},
                     {n / 3, n / 2}, {n / 2, n / 3}, {n / 2, n / 2 + 1}, {n - 2, n - 1}, {1, 0}};
    int count = 0;
    for (size_t k = 0; k < sizeof cand / sizeof cand[0]; k++)
        if (cand[k][0] >= 0 && cand[k][1] >= 0 && cand[k][0] < n && cand[k][1] < n) {
            pairs[count][0] = cand[k][0];
            pairs[count][1] = cand[k][1];
            count++;
        }
    return count;
}

/* ---- closed forms against their integrals ---------------------------------- */

TEST(g1d_p0_closed_forms_match_quadrature)
{
    const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find("seed");
    for (int s = 0; s < NSIZES; s++) {
        int n = sizes[s], pairs[16][2], np = pick_pairs(n, pairs);
        for (int k = 0; k < np; k++) {
            int a = pairs[k][0], c = pairs[k][1];
            double want = entry_by_quadrature(pb, n, a, c, -1, -1);
            CHECK_NEAR(rad_galerkin1d_green_p0(n, a, c), want, 1e-12, 0.0);
        }
    }
}

TEST(g1d_p1_closed_forms_match_quadrature)
{
    const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find("seed");
    for (int s = 0; s < NSIZES; s++) {
        int n = sizes[s], pairs[16][2], np = pick_pairs(n, pairs);
        for (int k = 0; k < np; k++) {
            int a = pairs[k][0], c = pairs[k][1];
            double local[2][2];
            rad_galerkin1d_green_p1_local(n, a, c, local);
            for (int al = 0; al < 2; al++)
                for (int be = 0; be < 2; be++)
                    CHECK_NEAR(local[al][be], entry_by_quadrature(pb, n, a, c, al, be), 1e-12, 0.0);
        }
    }
}

TEST(g1d_load_closed_forms_match_quadrature)
{
    const char *names[] = {"seed", "exp"};
    for (int p = 0; p < 2; p++) {
        const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find(names[p]);
        for (int s = 0; s < NSIZES; s++) {
            int n = sizes[s];
            int cells[] = {0, n / 3, n / 2, n - 1};
            for (int k = 0; k < 4; k++) {
                double mom[2];
                pb->f_moments((double)cells[k] / n, 1.0 / n, mom);
                CHECK_NEAR(mom[0], load_by_quadrature(pb, n, cells[k], 0), 1e-12, 0.0);
                CHECK_NEAR(mom[1], load_by_quadrature(pb, n, cells[k], 1), 1e-12, 0.0);
            }
        }
    }
}

/* The paper's P0 load for the seed problem, h^2 (i-1/2)(5 + (i^2-i+1/2) h^2)/6
 * (1-based i), and the notes' version, which lacks the /6 on the 5. */
static double seed_load_paper(int n, int i) { double h = 1.0 / n; return h * h * (i - 0.5) * (5.0 + (i * (double)i - i + 0.5) * h * h) / 6.0; }
static double seed_load_notes(int n, int i) { double h = 1.0 / n; return h * h * (i - 0.5) * (5.0 + (i * (double)i - i + 0.5) * h * h / 6.0); }
/* The notes' P0 matrix entries (1-based): right off the diagonal, wrong on it. */
static double notes_offdiag(int n, int i, int j) { double h = 1.0 / n; return -h * h * h * (2.0 * j * h - h - 2.0) * (2.0 * i - 1.0) / 4.0; }
static double notes_diag(int n, int j) { double h = 1.0 / n; return (4.0 * j - 2.0) * h * h * h / 4.0 - (2.0 * j - 1.0) * (2.0 * j - 1.0) * h * h * h * h / 4.0; }

TEST(g1d_notes_closed_forms_two_wrong_one_right)
{
    const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find("seed");
    int ns[] = {1, 4, 9};
    for (int s = 0; s < 3; s++) {
        int n = ns[s];
        for (int i = 1; i <= n; i++) {
            double load = load_by_quadrature(pb, n, i - 1, 0) + load_by_quadrature(pb, n, i - 1, 1);
            CHECK_NEAR(seed_load_paper(n, i), load, 1e-12, 0.0);
            CHECK_MSG(fabs(seed_load_notes(n, i) - load) > 0.5 * load, "notes' load agrees at n=%d i=%d", n, i);
            double diag = entry_by_quadrature(pb, n, i - 1, i - 1, -1, -1);
            CHECK_MSG(fabs(notes_diag(n, i) - diag) > 1e-3 * diag, "notes' diagonal agrees at n=%d j=%d", n, i);
            for (int j = i + 1; j <= n; j++)
                CHECK_NEAR(notes_offdiag(n, i, j), entry_by_quadrature(pb, n, i - 1, j - 1, -1, -1), 1e-12, 0.0);
        }
    }
    /* The smallest case by hand: n = 1, int int min(1-max) = 1/3 - 1/4 = 1/12. */
    CHECK_NEAR(rad_galerkin1d_green_p0(1, 0, 0), 1.0 / 12.0, 1e-15, 0.0);
    CHECK_NEAR(notes_diag(1, 1), 0.25, 1e-15, 0.0);
}

/* ---- the problems' exact solutions solve the integral equation --------------- */

typedef struct sol_ctx {
    const rad_galerkin1d_problem *problem;
    double x;
} sol_ctx;

static double ky_integrand(double t, void *vctx)
{
    sol_ctx *s = vctx;
    return s->problem->kernel(s->x, t) * s->problem->exact(t);
}

TEST(g1d_exact_solutions_solve_the_equation)
{
    const char *names[] = {"seed", "exp"};
    double xs[] = {0.0, 0.137, 0.5, 0.862, 1.0};
    for (int p = 0; p < 2; p++) {
        const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find(names[p]);
        CHECK(pb && pb->exact && pb->f && pb->kernel);
        for (int k = 0; k < 5; k++) {
            sol_ctx s = {pb, xs[k]};
            rad_quad_result r;
            CHECK(rad_quad_adapt(ky_integrand, &s, 0.0, 1.0, &xs[k], 1, NULL, &r) == RAD_OK);
            double residual = pb->exact(xs[k]) - pb->f(xs[k]) - r.value;
            CHECK_MSG(fabs(residual) < 1e-14, "%s: y - f - Ky = %.3g at x = %g", names[p], residual, xs[k]);
        }
    }
    CHECK(rad_galerkin1d_problem_find("nope") == NULL);
    CHECK(strcmp(rad_galerkin1d_problem_names()[0], "seed") == 0);
}

/* ---- mass matrices ------------------------------------------------------------- */

TEST(g1d_mass_matrices_match_quadrature)
{
    int n = 5;
    double diag[6], off[6], u[4], w[4];
    rad_quad_gauss_legendre(4, u, w);
    for (int b = 0; b < 2; b++) {
        rad_galerkin1d_basis basis = b ? RAD_GALERKIN1D_P1 : RAD_GALERKIN1D_P0;
        int dim = (int)rad_galerkin1d_dim(basis, n);
        rad_galerkin1d_mass(basis, n, diag, off);
        for (int i = 0; i < dim; i++)
            for (int j = i; j < dim && j <= i + 1; j++) {
                double ei[6] = {0}, ej[6] = {0}, m = 0.0;
                ei[i] = 1.0;
                ej[j] = 1.0;
                for (int c = 0; c < n; c++)
                    for (int q = 0; q < 4; q++) {
                        double x = (c + u[q]) / n;
                        m += w[q] / n * rad_galerkin1d_eval(basis, n, ei, x) * rad_galerkin1d_eval(basis, n, ej, x);
                    }
                CHECK_NEAR(j == i ? diag[i] : off[i], m, 1e-14, 1e-16);
            }
    }
}

/* ---- solutions ------------------------------------------------------------------- */

static double *solve_exact(const char *name, rad_galerkin1d_basis basis, int n)
{
    size_t dim = rad_galerkin1d_dim(basis, n);
    double *A = malloc(dim * dim * sizeof *A), *b = malloc(dim * sizeof *b), *y = malloc(dim * sizeof *y);
    rad_galerkin1d_assembly exact = {RAD_GALERKIN1D_EXACT, 0};
    CHECK(rad_galerkin1d_assemble(rad_galerkin1d_problem_find(name), basis, exact, n, A, b) == RAD_OK);
    CHECK(rad_galerkin1d_solve(basis, n, A, b, y, NULL) == RAD_OK);
    free(A);
    free(b);
    return y;
}

TEST(g1d_seed_p1_reproduces_the_linear_solution)
{
    /* y = x lies in the P1 space, so the Galerkin solution is exact. */
    int ns[] = {1, 5, 64, 1000};
    for (int k = 0; k < 4; k++) {
        double *y = solve_exact("seed", RAD_GALERKIN1D_P1, ns[k]);
        for (int i = 0; i <= ns[k]; i++)
            CHECK_NEAR(y[i], (double)i / ns[k], 0.0, 1e-13);
        free(y);
    }
}

TEST(g1d_seed_p0_gives_exact_cell_means)
{
    /* For y = x, K (y - P0 y) has zero mean on every cell (papers/galerkin-1d.md),
     * so the P0 Galerkin solution is exactly the cell means of y. */
    int ns[] = {1, 6, 333};
    for (int k = 0; k < 3; k++) {
        double *y = solve_exact("seed", RAD_GALERKIN1D_P0, ns[k]);
        for (int c = 0; c < ns[k]; c++)
            CHECK_NEAR(y[c], (c + 0.5) / ns[k], 0.0, 1e-14);
        free(y);
    }
}

TEST(g1d_exact_assembly_matches_independent_assembly)
{
    /* Assemble M - A entry by entry with adaptive quadrature, solve, compare. */
    const char *names[] = {"seed", "exp"};
    int n = 6;
    for (int p = 0; p < 2; p++)
        for (int bs = 0; bs < 2; bs++) {
            const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find(names[p]);
            rad_galerkin1d_basis basis = bs ? RAD_GALERKIN1D_P1 : RAD_GALERKIN1D_P0;
            int dim = (int)rad_galerkin1d_dim(basis, n), ns = bs ? 2 : 1;
            double S[7 * 7] = {0}, b[7] = {0}, diag[7], off[7];
            rad_galerkin1d_mass(basis, n, diag, off);
            for (int a = 0; a < n; a++)
                for (int c = 0; c < n; c++)
                    for (int al = 0; al < ns; al++)
                        for (int be = 0; be < ns; be++)
                            S[(a + al) + (c + be) * dim] -= entry_by_quadrature(pb, n, a, c, bs ? al : -1, bs ? be : -1);
            for (int i = 0; i < dim; i++) {
                S[i + i * dim] += diag[i];
                if (i + 1 < dim) {
                    S[i + (i + 1) * dim] += off[i];
                    S[(i + 1) + i * dim] += off[i];
                }
            }
            for (int c = 0; c < n; c++)
                for (int al = 0; al < ns; al++)
                    b[c + al] += bs ? load_by_quadrature(pb, n, c, al)
                                    : load_by_quadrature(pb, n, c, 0) + load_by_quadrature(pb, n, c, 1);
            CHECK(rad_dense_lu_solve(dim, S, 1, b, NULL) == RAD_OK);
            double *y = solve_exact(names[p], basis, n);
            for (int i = 0; i < dim; i++)
                CHECK_NEAR(y[i], b[i], 1e-13, 1e-15);
            free(y);
        }
}

TEST(g1d_residual_check_confirms_exact_and_catches_quadrature)
{
    const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find("exp");
    for (int bs = 0; bs < 2; bs++) {
        rad_galerkin1d_basis basis = bs ? RAD_GALERKIN1D_P1 : RAD_GALERKIN1D_P0;
        int n = 50;
        size_t dim = rad_galerkin1d_dim(basis, n);
        double *A = malloc(dim * dim * sizeof *A), *b = malloc(dim * sizeof *b), *y = malloc(dim * sizeof *y);
        double res = 1.0;
        rad_galerkin1d_assembly exact = {RAD_GALERKIN1D_EXACT, 0}, mid = {RAD_GALERKIN1D_GAUSS, 1};
        rad_galerkin1d_assemble(pb, basis, exact, n, A, b);
        rad_galerkin1d_solve(basis, n, A, b, y, NULL);
        CHECK(rad_galerkin1d_residual(pb, basis, n, y, &res) == RAD_OK);
        CHECK_MSG(res < 1e-13, "exact assembly residual %.3g", res);
        rad_galerkin1d_assemble(pb, basis, mid, n, A, b);
        rad_galerkin1d_solve(basis, n, A, b, y, NULL);
        CHECK(rad_galerkin1d_residual(pb, basis, n, y, &res) == RAD_OK);
        CHECK_MSG(res > 1e-6, "midpoint assembly residual %.3g", res);
        free(A);
        free(b);
        free(y);
    }
}

TEST(g1d_gauss_is_exact_off_the_diagonal)
{
    /* Off the diagonal the seed kernel is bilinear on each cell pair, so K >= 2
     * Gauss points integrate it (times P1 shapes) exactly; on the diagonal the
     * kink leaves an O(h^3) error whatever K is. */
    const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find("seed");
    int n = 9;
    for (int bs = 0; bs < 2; bs++) {
        rad_galerkin1d_basis basis = bs ? RAD_GALERKIN1D_P1 : RAD_GALERKIN1D_P0;
        size_t dim = rad_galerkin1d_dim(basis, n);
        double *E = malloc(dim * dim * sizeof *E), *G = malloc(dim * dim * sizeof *G), b[10];
        rad_galerkin1d_assembly exact = {RAD_GALERKIN1D_EXACT, 0}, g2 = {RAD_GALERKIN1D_GAUSS, 2}, split = {RAD_GALERKIN1D_GAUSS_SPLIT, 6};
        rad_galerkin1d_assemble(pb, basis, exact, n, E, b);
        rad_galerkin1d_assemble(pb, basis, g2, n, G, b);
        for (size_t j = 0; j < dim; j++)
            for (size_t i = 0; i < dim; i++) {
                size_t k = i + j * dim;
                int touches_diagonal = bs ? (i <= j + 1 && j <= i + 1) : i == j;
                if (!touches_diagonal)
                    CHECK_NEAR(G[k], E[k], 1e-13, 1e-18);
                else if (i == j)
                    CHECK_MSG(fabs(G[k] - E[k]) > 1e-4 * fabs(E[k]), "gauss:2 diagonal exact at %zu", i);
            }
        rad_galerkin1d_assemble(pb, basis, split, n, G, b);
        for (size_t k = 0; k < dim * dim; k++)
            CHECK_NEAR(G[k], E[k], 1e-13, 1e-18);
        free(E);
        free(G);
    }
}

/* Observed order between n and 2n for one error kind (0 l2, 1 coef vs exact assembly). */
static double observed_order(const char *name, rad_galerkin1d_basis basis, rad_galerkin1d_assembly assembly, int n, int kind)
{
    const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find(name);
    double err[2];
    for (int level = 0; level < 2; level++) {
        int m = n << level;
        size_t dim = rad_galerkin1d_dim(basis, m);
        double *A = malloc(dim * dim * sizeof *A), *b = malloc(dim * sizeof *b), *y = malloc(dim * sizeof *y);
        rad_galerkin1d_assemble(pb, basis, assembly, m, A, b);
        rad_galerkin1d_solve(basis, m, A, b, y, NULL);
        if (kind == 0) {
            rad_galerkin1d_error_norms e;
            rad_galerkin1d_errors(pb, basis, m, y, &e);
            err[level] = e.l2;
        } else {
            double *ye = solve_exact(name, basis, m);
            err[level] = 0.0;
            for (size_t i = 0; i < dim; i++)
                err[level] = fmax(err[level], fabs(y[i] - ye[i]));
            free(ye);
        }
        free(A);
        free(b);
        free(y);
    }
    return log2(err[0] / err[1]);
}

TEST(g1d_convergence_orders_match_theory)
{
    rad_galerkin1d_assembly exact = {RAD_GALERKIN1D_EXACT, 0}, mid = {RAD_GALERKIN1D_GAUSS, 1}, g2 = {RAD_GALERKIN1D_GAUSS, 2},
                     g4 = {RAD_GALERKIN1D_GAUSS, 4}, s2 = {RAD_GALERKIN1D_GAUSS_SPLIT, 2};
    struct { rad_galerkin1d_basis basis; rad_galerkin1d_assembly a; int kind; double order; } cases[] = {
        {RAD_GALERKIN1D_P0, exact, 0, 1.0}, {RAD_GALERKIN1D_P1, exact, 0, 2.0},
        {RAD_GALERKIN1D_P0, mid, 1, 2.0},   {RAD_GALERKIN1D_P0, g2, 1, 2.0}, {RAD_GALERKIN1D_P0, g4, 1, 2.0},
        {RAD_GALERKIN1D_P1, mid, 1, 1.0},   {RAD_GALERKIN1D_P1, g2, 1, 2.0}, {RAD_GALERKIN1D_P0, s2, 1, 4.0},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        double order = observed_order("exp", cases[k].basis, cases[k].a, 64, cases[k].kind);
        CHECK_MSG(fabs(order - cases[k].order) < 0.1, "case %zu: order %.3f, theory %.1f", k, order,
                  cases[k].order);
    }
}

TEST(g1d_errors_of_a_known_function)
{
    /* y_h = 0 against y = x: L2 = 1/sqrt(3), L-inf = 1 (at x = 1), nodal = 1 - h/2. */
    const rad_galerkin1d_problem *pb = rad_galerkin1d_problem_find("seed");
    double zero[8] = {0};
    rad_galerkin1d_error_norms e;
    CHECK(rad_galerkin1d_errors(pb, RAD_GALERKIN1D_P0, 7, zero, &e) == RAD_OK);
    CHECK_NEAR(e.l2, 1.0 / sqrt(3.0), 1e-14, 0.0);
    CHECK_NEAR(e.linf, 1.0, 1e-15, 0.0);
    CHECK_NEAR(e.nodal, 1.0 - 0.5 / 7.0, 1e-15, 0.0);
    /* An interior maximum: y_h = 1 + (e-1) x (the P1 interpolant with n = 1) against
     * e^x; the error peaks where e^x = e - 1, at x = ln(e-1). */
    const rad_galerkin1d_problem *ex = rad_galerkin1d_problem_find("exp");
    double interp[2] = {1.0, exp(1.0)};
    CHECK(rad_galerkin1d_errors(ex, RAD_GALERKIN1D_P1, 1, interp, &e) == RAD_OK);
    double xm = log(exp(1.0) - 1.0);
    CHECK_NEAR(e.linf, 1.0 + (exp(1.0) - 1.0) * xm - exp(xm), 1e-13, 0.0);
    CHECK_NEAR(e.nodal, 0.0, 0.0, 1e-15);
}

TEST(g1d_option_parsing)
{
    rad_galerkin1d_assembly a;
    rad_galerkin1d_basis b;
    char buf[32];
    CHECK(rad_galerkin1d_assembly_parse("exact", &a) == RAD_OK && a.kind == RAD_GALERKIN1D_EXACT);
    CHECK(rad_galerkin1d_assembly_parse("midpoint", &a) == RAD_OK && a.kind == RAD_GALERKIN1D_GAUSS && a.points == 1);
    CHECK(rad_galerkin1d_assembly_parse("gauss:7", &a) == RAD_OK && a.points == 7);
    rad_galerkin1d_assembly_format(a, buf, sizeof buf);
    CHECK(strcmp(buf, "gauss:7") == 0);
    CHECK(rad_galerkin1d_assembly_parse("gauss-split:3", &a) == RAD_OK && a.kind == RAD_GALERKIN1D_GAUSS_SPLIT);
    const char *bad[] = {"gauss:0", "gauss:", "gauss:-2", "gauss:2x", "gauss:1e3", "gauss:99999",
                         "simpson", "", "Exact", "gauss-split:0"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        CHECK_MSG(rad_galerkin1d_assembly_parse(bad[k], &a) == RAD_EINVAL, "accepted '%s'", bad[k]);
    CHECK(rad_galerkin1d_assembly_parse(NULL, &a) == RAD_EINVAL);
    CHECK(rad_galerkin1d_basis_parse("p1", &b) == RAD_OK && b == RAD_GALERKIN1D_P1);
    CHECK(rad_galerkin1d_basis_parse("p2", &b) == RAD_EINVAL);
    CHECK(rad_galerkin1d_dim(RAD_GALERKIN1D_P1, 10) == 11 && rad_galerkin1d_dim(RAD_GALERKIN1D_P0, 0) == 0);
}
