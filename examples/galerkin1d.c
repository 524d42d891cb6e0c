/* The 1D model problem's error at a few n, and the observed order.
 *
 *   cc galerkin1d.c -o galerkin1d $(pkg-config --cflags --libs radkit) -lm
 *   ./galerkin1d
 *
 * Solves y = f + K y on (0,1) (kernel min(x,t)(1 - max(x,t)), the manufactured
 * problem with exact solution e^x) by Galerkin's method with continuous
 * piecewise linears and exact assembly, and prints the L2 and max errors:
 * the L2 error falls like h^2, so each fourfold n divides it by about 16.
 * The figures are those of `radkit galerkin1d --n N --problem exp --basis p1`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include <rad_galerkin1d.h>

int main(void)
{
    const int ns[] = {4, 16, 64, 256};
    const rad_galerkin1d_problem *problem = rad_galerkin1d_problem_find("exp");
    rad_galerkin1d_assembly assembly;
    if (!problem || rad_galerkin1d_assembly_parse("exact", &assembly) != RAD_OK) {
        fprintf(stderr, "galerkin1d: the library has no problem 'exp' or no exact assembly\n");
        return 1;
    }
    printf("# problem = %s\n# basis = p1\n# assembly = exact\n", problem->name);
    printf("n\terr_l2\terr_linf\torder_l2\n");
    double previous = 0.0;
    for (size_t k = 0; k < sizeof ns / sizeof ns[0]; k++) {
        int n = ns[k];
        size_t dim = rad_galerkin1d_dim(RAD_GALERKIN1D_P1, n);
        double *A = malloc(dim * dim * sizeof *A), *b = malloc(dim * sizeof *b), *y = malloc(dim * sizeof *y);
        rad_galerkin1d_error_norms err;
        rad_status st = A && b && y ? RAD_OK : RAD_ENOMEM;
        if (st == RAD_OK)
            st = rad_galerkin1d_assemble(problem, RAD_GALERKIN1D_P1, assembly, n, A, b);
        if (st == RAD_OK)
            st = rad_galerkin1d_solve(RAD_GALERKIN1D_P1, n, A, b, y, NULL);
        if (st == RAD_OK)
            st = rad_galerkin1d_errors(problem, RAD_GALERKIN1D_P1, n, y, &err);
        free(A);
        free(b);
        free(y);
        if (st != RAD_OK) {
            fprintf(stderr, "galerkin1d: n = %d: %s: %s\n", n, rad_strerror(st),
                    st == RAD_ENOMEM ? "no memory" : rad_error_message());
            return 1;
        }
        /* n grows by 4 from row to row: order = log(e_prev / e) / log 4. */
        printf("%d\t%.6e\t%.6e\t", n, err.l2, err.linf);
        if (k == 0)
            printf("-\n");
        else
            printf("%.2f\n", log(previous / err.l2) / log(4.0));
        previous = err.l2;
    }
    return 0;
}
