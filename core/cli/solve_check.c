/* The last check before any method's table is written: an answer is a
 * radiosity, finite and non-negative, or it is not printed.  The solvers
 * check their own arithmetic; this catches what reaches the table by other
 * ways (an emission near the largest double, overflow in a path's weight). */
#include <math.h>
#include <stddef.h>

#include "solve.h"

rad_status solve_check_answer(const char *method, size_t n, const double *B)
{
    static const char channel[3] = {'r', 'g', 'b'};
    for (int c = 0; c < 3; c++)
        for (size_t i = 0; i < n; i++) {
            double b = B[i + (size_t)c * n];
            if (!isfinite(b))
                return RAD_ERROR(RAD_ENUMERIC, "%s: face %zu has a non-finite radiosity (B_%c = %g): "
                                 "an emission or a scale beyond double precision's range?",
                                 method, i, channel[c], b);
            if (b < 0.0)
                return RAD_ERROR(RAD_ENUMERIC, "%s: face %zu has a negative radiosity (B_%c = %g)",
                                 method, i, channel[c], b);
        }
    return RAD_OK;
}
