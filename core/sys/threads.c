/* Binding the OpenMP threads to CPUs (rad_sys_bind_threads).
 *
 * A hierarchical solve is a long run of short parallel loops (one per
 * refinement generation and per gather step), each ending at a barrier.
 * Left free, the scheduler moves the threads between CPUs and at times
 * puts two on one, and every such loop then waits for the late one.  The
 * main thread is bound too: binding the workers alone leaves most of the
 * waiting.  Only a pool that fills the CPUs the process may use is bound:
 * with fewer threads, several runs may be sharing the machine (a study that
 * starts one per core with --threads 1, or four with --threads 4 on sixteen
 * cores), and each would bind its threads to the same first CPUs.  What the
 * environment says of binding (OMP_PROC_BIND, OMP_PLACES) is left to the
 * OpenMP runtime. */
#define _GNU_SOURCE /* sched_setaffinity, CPU_SET */
#include "rad_sys.h"

#include <omp.h>
#include <sched.h>
#include <stdlib.h>

int rad_sys_bind_threads(int threads)
{
    if (getenv("OMP_PROC_BIND") || getenv("OMP_PLACES"))
        return 0;
    cpu_set_t allowed;
    if (sched_getaffinity(0, sizeof allowed, &allowed) != 0)
        return 0;
    int cpus[CPU_SETSIZE], ncpu = 0;
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET(c, &allowed))
            cpus[ncpu++] = c;
    int n = threads > 0 ? threads : omp_get_max_threads();
    if (ncpu < 2 || n != ncpu)
        return 0; /* not one thread per CPU: several runs may share the machine */
    int bound = 0;
#pragma omp parallel num_threads(n) reduction(+ : bound)
    {
        cpu_set_t one;
        CPU_ZERO(&one);
        CPU_SET(cpus[omp_get_thread_num() % ncpu], &one);
        bound += sched_setaffinity(0, sizeof one, &one) == 0;
    }
    return bound;
}
