/* OpenBLAS's worker threads, parked while radkit's own threads work.
 *
 * OpenBLAS (the pthread build Debian installs) starts its worker threads when
 * the library loads and again after each threaded call, and each one busy-
 * waits (sched_yield) for about 2^28 cycles before it sleeps.  On a 2-core
 * machine that is one core taken for the first ~0.1-0.2 s of every run and
 * after every LU solve, exactly when radkit's OpenMP loops (assembly, link
 * estimates) want both cores.  blas_thread_shutdown_ stops the workers; OpenBLAS starts them again on its
 * next threaded call, so LAPACK keeps its threads where it needs them.  The
 * symbol is weak because other BLAS builds (serial, OpenMP) need not have it. */
#include "rad_dense.h"

extern int blas_thread_shutdown_(void) __attribute__((weak));

void rad_dense_blas_idle(void)
{
    if (blas_thread_shutdown_)
        blas_thread_shutdown_();
}
