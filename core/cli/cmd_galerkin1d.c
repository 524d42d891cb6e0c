/* radkit galerkin1d: solve the 1D model problem and report its errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "rad_dense.h"
#include "rad_galerkin1d.h"
#include "rad_sys.h"
#include "rad_version.h"

static const char help[] =
    "usage: radkit galerkin1d --n N [--problem seed|exp] [--basis p0|p1]\n"
    "                         [--assembly exact|midpoint|gauss:K|gauss-split:K] [--no-check]\n"
    "\n"
    "Solve y = f + K y on (0,1), k(x,t) = min(x,t)(1 - max(x,t)), by Galerkin's\n"
    "method on N equal cells, and compare with the exact solution.\n"
    "\n"
    "  --n N          number of cells (>= 1); the dense system has N (p0) or N+1 (p1)\n"
    "                 unknowns and must fit in 3/4 of the machine's memory\n"
    "  --problem P    seed: the notes' f = x^3/6 + 5x/6, exact y = x (default)\n"
    "                 exp:  f = 2e^x - 1 - (e-1)x, exact y = e^x\n"
    "  --basis B      p0: piecewise constants, one value per cell (default)\n"
    "                 p1: continuous piecewise linears, one value per node\n"
    "  --assembly A   how the matrix and load entries are integrated:\n"
    "                 exact          closed forms (default)\n"
    "                 midpoint       one point per cell and direction (= gauss:1)\n"
    "                 gauss:K        K-point Gauss-Legendre per cell and direction\n"
    "                 gauss-split:K  as gauss:K, diagonal cells split along the kink\n"
    "  --no-check     skip the independent residual check (16 N^2 kernel evaluations)\n"
    "\n"
    "Output: '#' lines with the parameters, the errors (err_l2, err_linf against\n"
    "the exact solution; err_nodal at cell midpoints (p0) or nodes (p1); err_coef,\n"
    "the largest coefficient difference from the exact-assembly Galerkin solution,\n"
    "which isolates the quadrature error), the relative Galerkin residual computed\n"
    "from the definitions alone (galerkin_residual), LAPACK's condition estimate\n"
    "and the timings; then the columns i, x (cell midpoint for p0, node for p1),\n"
    "y (the coefficient) and y_exact (the exact solution at x).\n"
    "\n"
    "example: radkit galerkin1d --n 16 --problem exp --basis p1 --assembly gauss:2\n";

/* Assemble and solve once; A is scratch of dim*dim doubles. */
static rad_status solve_once(const rad_galerkin1d_problem *problem, rad_galerkin1d_basis basis,
                             rad_galerkin1d_assembly assembly, int n, double *A, double *b,
                             double *y, double *rcond, double *assemble_s, double *solve_s)
{
    double t0 = rad_sys_seconds();
    rad_status st = rad_galerkin1d_assemble(problem, basis, assembly, n, A, b);
    double t1 = rad_sys_seconds();
    if (st == RAD_OK)
        st = rad_galerkin1d_solve(basis, n, A, b, y, rcond);
    double t2 = rad_sys_seconds();
    if (assemble_s)
        *assemble_s = t1 - t0;
    if (solve_s)
        *solve_s = t2 - t1;
    return st;
}

int cli_galerkin1d(int argc, char **argv)
{
    const char *n_text = NULL, *problem_text = "seed", *basis_text = "p0", *assembly_text = "exact";
    int want_help = 0, no_check = 0;
    cli_option options[] = {
        {"--n", &n_text, NULL, NULL},
        {"--problem", &problem_text, NULL, NULL},
        {"--basis", &basis_text, NULL, NULL},
        {"--assembly", &assembly_text, NULL, NULL},
        {"--no-check", NULL, &no_check, NULL},
        {"--help", NULL, &want_help, NULL},
        {"-h", NULL, &want_help, NULL},
        {NULL, NULL, NULL, NULL},
    };
    rad_status st = cli_parse("galerkin1d", argc, argv, 2, options);
    if (st != RAD_OK)
        return cli_fail(st);
    if (want_help) {
        fputs(help, stdout);
        return 0;
    }
    if (!n_text)
        return cli_fail(RAD_ERROR(RAD_EINVAL, "galerkin1d: --n N is required (see 'radkit galerkin1d --help')"));

    int n = 0;
    rad_galerkin1d_basis basis;
    rad_galerkin1d_assembly assembly;
    const rad_galerkin1d_problem *problem = rad_galerkin1d_problem_find(problem_text);
    if ((st = cli_parse_positive_int("galerkin1d: --n", n_text, 1L << 30, &n)) != RAD_OK)
        return cli_fail(st);
    if (!problem)
        return cli_fail(RAD_ERROR(RAD_EINVAL, "galerkin1d: unknown problem '%s' (expected seed or exp)",
                              problem_text));
    if ((st = rad_galerkin1d_basis_parse(basis_text, &basis)) != RAD_OK ||
        (st = rad_galerkin1d_assembly_parse(assembly_text, &assembly)) != RAD_OK) {
        fprintf(stderr, "radkit: galerkin1d: %s\n", rad_error_message());
        return rad_status_exit_code(st);
    }
    size_t dim = rad_galerkin1d_dim(basis, n);
    if ((st = rad_dense_check_size(dim, 1, "galerkin1d")) != RAD_OK)
        return cli_fail(st);

    double *A = malloc(dim * dim * sizeof *A);
    double *vec = malloc(3 * dim * sizeof *vec);
    if (!A || !vec) {
        free(A);
        free(vec);
        return cli_fail(RAD_ERROR(RAD_ENOMEM, "galerkin1d: no memory for %zu unknowns", dim));
    }
    double *b = vec, *y = vec + dim, *y_ref = vec + 2 * dim;
    double rcond = 0.0, assemble_s = 0.0, solve_s = 0.0, check_s = 0.0, residual = NAN;
    double err_coef = 0.0;
    rad_galerkin1d_error_norms err = {0};
    char assembly_name[64];
    rad_galerkin1d_assembly_format(assembly, assembly_name, sizeof assembly_name);

    /* The exact-assembly solution is the reference for the quadrature error. */
    if (assembly.kind != RAD_GALERKIN1D_EXACT) {
        rad_galerkin1d_assembly exact = {RAD_GALERKIN1D_EXACT, 0};
        st = solve_once(problem, basis, exact, n, A, b, y_ref, NULL, NULL, NULL);
        if (st != RAD_OK)
            goto out;
    }
    st = solve_once(problem, basis, assembly, n, A, b, y, &rcond, &assemble_s, &solve_s);
    if (st != RAD_OK)
        goto out;
    if (assembly.kind != RAD_GALERKIN1D_EXACT)
        for (size_t i = 0; i < dim; i++)
            err_coef = fmax(err_coef, fabs(y[i] - y_ref[i]));
    if ((st = rad_galerkin1d_errors(problem, basis, n, y, &err)) != RAD_OK)
        goto out;
    if (!no_check) {
        double t0 = rad_sys_seconds();
        if ((st = rad_galerkin1d_residual(problem, basis, n, y, &residual)) != RAD_OK)
            goto out;
        check_s = rad_sys_seconds() - t0;
    }

    printf("# radkit %s galerkin1d\n", RAD_VERSION);
    printf("# problem = %s (%s)\n", problem->name, problem->description);
    printf("# basis = %s\n# assembly = %s\n# n = %d\n# h = %.17g\n# unknowns = %zu\n",
           rad_galerkin1d_basis_name(basis), assembly_name, n, 1.0 / n, dim);
    printf("# err_l2 = %.6e\n# err_linf = %.6e\n# err_nodal = %.6e\n# err_coef = %.6e\n",
           err.l2, err.linf, err.nodal, err_coef);
    if (no_check)
        printf("# galerkin_residual = skipped\n");
    else
        printf("# galerkin_residual = %.6e\n", residual);
    printf("# rcond = %.6e\n# cond1_estimate = %.6e\n", rcond, rcond > 0 ? 1.0 / rcond : INFINITY);
    printf("# assemble_s = %.6f\n# solve_s = %.6f\n# check_s = %.6f\n", assemble_s, solve_s, check_s);
    printf("i\tx\ty\ty_exact\n");
    for (size_t i = 0; i < dim; i++) {
        double x = basis == RAD_GALERKIN1D_P0 ? (i + 0.5) / n : (double)i / n;
        printf("%zu\t%.17g\t%.17g\t%.17g\n", i, x, y[i], problem->exact(x));
    }
out:
    free(A);
    free(vec);
    return st == RAD_OK ? 0 : cli_fail(st);
}
