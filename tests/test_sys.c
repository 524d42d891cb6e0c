/* rad_sys: the large-array allocator, binding threads to CPUs. */
#define _GNU_SOURCE /* sched_getaffinity, CPU_SET */
#include <errno.h>
#include <omp.h>
#include <sched.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "harness.h"
#include "rad_sys.h"

TEST(sys_alloc_huge_gives_aligned_usable_memory)
{
    CHECK(rad_sys_alloc_huge(0) == NULL);
    CHECK(rad_sys_alloc_huge(SIZE_MAX) == NULL);
    CHECK(rad_sys_alloc_huge(SIZE_MAX - RAD_SYS_HUGE_PAGE / 2) == NULL);
    /* small: plain malloc; large: whole huge pages, aligned to one */
    size_t sizes[3] = {100, RAD_SYS_HUGE_PAGE, 3 * RAD_SYS_HUGE_PAGE + 12345};
    for (int k = 0; k < 3; k++) {
        unsigned char *p = rad_sys_alloc_huge(sizes[k]);
        CHECK(p != NULL);
        if (!p)
            continue;
        if (sizes[k] >= RAD_SYS_HUGE_PAGE)
            CHECK((uintptr_t)p % RAD_SYS_HUGE_PAGE == 0);
        memset(p, 0xA5, sizes[k]); /* every byte writable (the sanitizers check) */
        CHECK(p[0] == 0xA5 && p[sizes[k] - 1] == 0xA5);
        free(p);
    }
}

/* calloc's contract on huge pages: zeroed, even where the block reuses
 * memory just freed with other bytes in it (the small sizes come from
 * malloc's free lists); a count times size that overflows is refused. */
TEST(sys_calloc_huge_gives_zeroed_memory)
{
    CHECK(rad_sys_calloc_huge(0, 8) == NULL);
    CHECK(rad_sys_calloc_huge(SIZE_MAX / 4, 8) == NULL);
    size_t sizes[3] = {96, 4000, 3 * RAD_SYS_HUGE_PAGE + 40};
    for (int k = 0; k < 3; k++) {
        unsigned char *dirty = malloc(sizes[k]);
        if (dirty) {
            memset(dirty, 0xA5, sizes[k]);
            free(dirty);
        }
        unsigned char *p = rad_sys_calloc_huge(sizes[k] / 8, 8);
        CHECK(p != NULL);
        if (!p)
            continue;
        size_t nonzero = 0;
        for (size_t i = 0; i < sizes[k]; i++)
            nonzero += p[i] != 0;
        CHECK(nonzero == 0);
        free(p);
    }
}

/* rad_sys_grow keeps the items in use through every doubling, small and
 * past RAD_SYS_HUGE_PAGE (where the items are copied into a new block on
 * a huge page's boundary),
 * leaves a large enough array alone, and with none in use gives a fresh
 * block of the capacity. */
TEST(sys_grow_keeps_what_is_used)
{
    double *a = NULL;
    size_t cap = 0, n = 0;
    const size_t total = 3 * RAD_SYS_HUGE_PAGE / sizeof *a + 7;
    int unaligned = 0;
    while (n < total) {
        size_t cap0 = cap;
        CHECK(rad_sys_grow((void **)&a, &cap, n, n + 1000, sizeof *a, 16));
        CHECK(cap >= n + 1000 && (cap == cap0 || cap >= 2 * cap0));
        /* a large block is a new one from rad_sys_alloc_huge */
        unaligned += cap * sizeof *a >= RAD_SYS_HUGE_PAGE && (uintptr_t)a % RAD_SYS_HUGE_PAGE != 0;
        for (size_t k = n; k < n + 1000; k++)
            a[k] = (double)k;
        n += 1000;
    }
    int same = 1;
    for (size_t k = 0; k < n; k++)
        same &= a[k] == (double)k;
    CHECK(same);
    CHECK_MSG(unaligned == 0, "%d large blocks not on a huge page's boundary", unaligned);
    size_t full = cap;
    CHECK(rad_sys_grow((void **)&a, &cap, n, cap, sizeof *a, 16) && cap == full);
    CHECK(rad_sys_grow((void **)&a, &cap, 0, 4 * full, sizeof *a, 16) && cap == 4 * full);
    a[4 * full - 1] = 1.0; /* the whole capacity is writable (the sanitizers check) */
    double *kept = a; /* a size past SIZE_MAX is refused before anything is freed */
    CHECK(!rad_sys_grow((void **)&a, &cap, 0, SIZE_MAX / 2, sizeof *a, 16));
    CHECK(a == kept && cap == 4 * full);
    free(a);
}

/* rad_sys_grow_mapped keeps the items in use through every doubling, small
 * and on mappings of their own past RAD_SYS_HUGE_PAGE (two arrays grown in
 * turn, and a page mapped right after the first's mapping once it has one,
 * so that it cannot grow in place and its pages must move), each large one
 * on a huge page's boundary; with none in use the whole new capacity is
 * writable; a size past SIZE_MAX is refused and the array kept unchanged. */
TEST(sys_grow_mapped_keeps_what_is_used)
{
    double *a[2] = {NULL, NULL};
    size_t cap[2] = {0, 0}, n = 0;
    const size_t total = 5 * RAD_SYS_HUGE_PAGE / sizeof(double) + 7;
    int unaligned = 0, moved = 0;
    void *guard = NULL;
    while (n < total) {
        if (!guard && cap[0] * sizeof(double) >= RAD_SYS_HUGE_PAGE) {
            size_t len = (cap[0] * sizeof(double) + RAD_SYS_HUGE_PAGE - 1) / RAD_SYS_HUGE_PAGE *
                         RAD_SYS_HUGE_PAGE;
            /* taken already (EEXIST) stands in the way as well */
            guard = mmap((char *)a[0] + len, 4096, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS |
                         MAP_FIXED_NOREPLACE, -1, 0);
            CHECK(guard == (char *)a[0] + len || (guard == MAP_FAILED && errno == EEXIST));
        }
        for (int i = 0; i < 2; i++) {
            size_t cap0 = cap[i];
            double *at = a[i];
            CHECK(rad_sys_grow_mapped((void **)&a[i], &cap[i], n, n + 1000, sizeof(double), 16));
            CHECK(cap[i] >= n + 1000 && (cap[i] == cap0 || cap[i] >= 2 * cap0));
            unaligned += cap[i] * sizeof(double) >= RAD_SYS_HUGE_PAGE &&
                         (uintptr_t)a[i] % RAD_SYS_HUGE_PAGE != 0;
            moved += cap0 * sizeof(double) >= RAD_SYS_HUGE_PAGE && a[i] != at;
            for (size_t k = n; k < n + 1000; k++)
                a[i][k] = (double)(k + (size_t)i);
        }
        n += 1000;
    }
    int same = 1;
    for (int i = 0; i < 2; i++)
        for (size_t k = 0; k < n; k++)
            same &= a[i][k] == (double)(k + (size_t)i);
    CHECK(same);
    CHECK_MSG(unaligned == 0, "%d large blocks not on a huge page's boundary", unaligned);
    CHECK_MSG(moved > 0, "no mapping had to move: the test did not exercise the move");
    size_t full = cap[0];
    CHECK(rad_sys_grow_mapped((void **)&a[0], &cap[0], 0, 4 * full, sizeof(double), 16) &&
          cap[0] == 4 * full);
    a[0][4 * full - 1] = 1.0;
    double *kept = a[0];
    CHECK(!rad_sys_grow_mapped((void **)&a[0], &cap[0], 0, SIZE_MAX / 2, sizeof(double), 16));
    CHECK(a[0] == kept && cap[0] == 4 * full);
    for (int i = 0; i < 2; i++)
        rad_sys_free_mapped(a[i], cap[i], sizeof(double));
    if (guard && guard != MAP_FAILED)
        munmap(guard, 4096);
    /* a small array stays a malloc'd block, which rad_sys_free_mapped frees */
    double *s = NULL;
    size_t cs = 0;
    CHECK(rad_sys_grow_mapped((void **)&s, &cs, 0, 10, sizeof *s, 4) && cs == 16);
    s[15] = 1.0;
    rad_sys_free_mapped(s, cs, sizeof *s);
}

/* Each thread's CPUs after rad_sys_bind_threads with as many threads as
 * the process may use CPUs: one each, all different, the calling thread on
 * the first allowed; fewer threads, or the environment's OMP_PROC_BIND,
 * leave them alone.  The test process's threads get their CPUs back at the
 * end. */
TEST(sys_bind_threads_gives_each_thread_one_cpu)
{
    cpu_set_t allowed;
    CHECK(sched_getaffinity(0, sizeof allowed, &allowed) == 0);
    int ncpu = CPU_COUNT(&allowed), first = -1;
    for (int c = 0; c < CPU_SETSIZE && first < 0; c++)
        if (CPU_ISSET(c, &allowed))
            first = c;
    if (ncpu > 64)
        return; /* the checks below keep one slot per thread */
    setenv("OMP_PROC_BIND", "false", 1);
    CHECK(rad_sys_bind_threads(ncpu) == 0);
    unsetenv("OMP_PROC_BIND");
    CHECK(rad_sys_bind_threads(1) == 0); /* fewer threads than CPUs (or one CPU) */
    CHECK(rad_sys_bind_threads(ncpu + 1) == 0);
    int bound = rad_sys_bind_threads(ncpu);
    CHECK(bound == (ncpu >= 2 ? ncpu : 0));
    int count[64], cpu[64];
    for (int t = 0; t < 64; t++)
        count[t] = 0, cpu[t] = -1;
#pragma omp parallel num_threads(ncpu)
    {
        int t = omp_get_thread_num();
        cpu_set_t mine;
        if (t < 64 && sched_getaffinity(0, sizeof mine, &mine) == 0) {
            count[t] = CPU_COUNT(&mine);
            for (int c = 0; c < CPU_SETSIZE; c++)
                if (CPU_ISSET(c, &mine))
                    cpu[t] = c;
        }
    }
    if (bound == ncpu && ncpu >= 2) {
        CHECK(cpu[0] == first);
        for (int t = 0; t < ncpu; t++) {
            CHECK(count[t] == 1 && cpu[t] >= 0 && CPU_ISSET(cpu[t], &allowed));
            for (int u = 0; u < t; u++)
                CHECK(cpu[u] != cpu[t]);
        }
    }
#pragma omp parallel num_threads(ncpu)
    sched_setaffinity(0, sizeof allowed, &allowed);
}

static unsigned char *volatile escaped;

/* The resident memory rises by what the process touches (64 MB written:
 * at least 60 MB more), and rad_sys_memory_allows holds it and the growth
 * asked for against RAD_SYS_MEMORY_SHARE of RADKIT_MEMORY_LIMIT: half as much
 * again fits under 0.9 of twice it, 0.9 as much again does not. */
TEST(sys_resident_memory_follows_what_is_touched)
{
    double before = rad_sys_rss_bytes();
    CHECK(before > 0.0);
    size_t n = 64u << 20;
    unsigned char *p = malloc(n);
    CHECK(p != NULL);
    if (!p)
        return;
    memset(p, 1, n);
    escaped = p; /* the stores must happen before the call that could read them */
    double after = rad_sys_rss_bytes();
    CHECK_MSG(after - before >= 60e6, "resident %.0f then %.0f bytes", before, after);
    char limit[64];
    snprintf(limit, sizeof limit, "%.0f", 2.0 * after);
    setenv("RADKIT_MEMORY_LIMIT", limit, 1);
    double would, have;
    CHECK(rad_sys_memory_allows(0.5 * after, &would, &have));
    CHECK_MSG(have == 2.0 * after && would >= 1.5 * after, "would %.0f, have %.0f", would, have);
    CHECK(!rad_sys_memory_allows(0.9 * after, &would, &have));
    unsetenv("RADKIT_MEMORY_LIMIT");
    CHECK(rad_sys_memory_allows(0.0, &would, &have) && have > 0.0);
    escaped = NULL;
    free(p);
}
