#define _GNU_SOURCE /* madvise's MADV_HUGEPAGE, mremap */
#include "rad_sys.h"

#include <stdint.h>
#include <stdio.h>
#include <malloc.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

double rad_sys_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double rad_sys_memory_bytes(void)
{
    const char *env = getenv("RADKIT_MEMORY_LIMIT");
    if (env && *env) {
        char *end = NULL;
        double v = strtod(env, &end);
        if (end && *end == '\0' && v > 0)
            return v;
    }
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    if (pages <= 0 || size <= 0)
        return 0.0;
    return (double)pages * (double)size;
}

double rad_sys_rss_bytes(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long long size = 0, resident = 0;
    int got = f ? fscanf(f, "%llu %llu", &size, &resident) : 0;
    if (f)
        fclose(f);
    long page = sysconf(_SC_PAGESIZE);
    if (got == 2 && page > 0)
        return (double)resident * (double)page;
    return rad_sys_peak_rss_bytes();
}

int rad_sys_memory_allows(double more, double *would, double *have)
{
    *have = rad_sys_memory_bytes();
    *would = rad_sys_rss_bytes() + more;
    return !(*have > 0.0) || *would <= RAD_SYS_MEMORY_SHARE * *have;
}

double rad_sys_peak_rss_bytes(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0)
        return 0.0;
    return 1024.0 * (double)ru.ru_maxrss; /* Linux reports kilobytes */
}

/* Ask for transparent huge pages over the whole huge pages inside
 * [p, p + bytes) (advice: failure only costs speed). */
static void advise_huge(void *p, size_t bytes)
{
#ifdef MADV_HUGEPAGE
    uintptr_t lo = ((uintptr_t)p + RAD_SYS_HUGE_PAGE - 1) / RAD_SYS_HUGE_PAGE * RAD_SYS_HUGE_PAGE;
    uintptr_t hi = ((uintptr_t)p + bytes) / RAD_SYS_HUGE_PAGE * RAD_SYS_HUGE_PAGE;
    if (hi > lo)
        (void)madvise((void *)lo, hi - lo, MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

void *rad_sys_alloc_huge(size_t bytes)
{
    if (bytes == 0)
        return NULL;
    if (bytes < RAD_SYS_HUGE_PAGE)
        return malloc(bytes);
    if (bytes > SIZE_MAX - RAD_SYS_HUGE_PAGE)
        return NULL;
    /* whole huge pages, so the last one lies inside the block too */
    size_t size = (bytes + RAD_SYS_HUGE_PAGE - 1) / RAD_SYS_HUGE_PAGE * RAD_SYS_HUGE_PAGE;
    void *p = NULL;
    if (posix_memalign(&p, RAD_SYS_HUGE_PAGE, size) != 0)
        return NULL;
    advise_huge(p, size);
    return p;
}

void *rad_sys_calloc_huge(size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size)
        return NULL;
    void *p = rad_sys_alloc_huge(count * size);
    if (p)
        memset(p, 0, count * size);
    return p;
}

/* Free block p of `bytes`, a large one's pages handed back to the kernel
 * (malloc_trim): glibc keeps a freed heap block's pages resident, and
 * whether a block of some megabytes lies on its heap or in a mapping of its
 * own depends on the heap's state; handing the pages back makes a run's
 * resident memory independent of it, which the memory check (hier/memory.c)
 * counts on. */
static void release(void *p, size_t bytes)
{
    free(p);
    if (bytes >= RAD_SYS_HUGE_PAGE)
        malloc_trim(0);
}

/* The capacity that holds need items, doubling cap (or first, from 0);
 * 0 when it would overflow. */
static size_t doubled(size_t cap, size_t need, size_t first)
{
    size_t c = cap ? cap : (first ? first : 1);
    while (c < need) {
        if (c > SIZE_MAX / 2)
            return 0;
        c *= 2;
    }
    return c;
}

int rad_sys_grow(void **arr, size_t *cap, size_t used, size_t need, size_t item, size_t first)
{
    if (need <= *cap)
        return 1;
    size_t c = doubled(*cap, need, first);
    if (c == 0 || c > SIZE_MAX / item)
        return 0;
    if (used == 0) {
        /* nothing to keep: the old block goes before the new one comes */
        release(*arr, *cap * item);
        *arr = NULL;
        *cap = 0;
        void *n = rad_sys_alloc_huge(c * item);
        if (!n)
            return 0;
        *arr = n;
        *cap = c;
        return 1;
    }
    if (c * item >= RAD_SYS_HUGE_PAGE) {
        /* a large block: realloc would copy one on glibc's heap into 4 KB
           pages, each faulting on the copy's first touch, on one thread; a
           new block is advised onto huge pages before the copy touches it */
        void *n = rad_sys_alloc_huge(c * item);
        if (!n)
            return 0;
        memcpy(n, *arr, used * item);
        release(*arr, *cap * item);
        *arr = n;
        *cap = c;
        return 1;
    }
    void *n = realloc(*arr, c * item);
    if (!n)
        return 0;
    *arr = n;
    *cap = c;
    return 1;
}

/* ---- arrays on mappings of their own ------------------------------------ */

#ifdef __linux__
/* Whether an array of cap items of `item` bytes lies on a mapping (and the
 * mapping's length, whole huge pages). */
static int mapped(size_t cap, size_t item) { return cap * item >= RAD_SYS_HUGE_PAGE; }

static size_t mapped_length(size_t cap, size_t item)
{
    return (cap * item + RAD_SYS_HUGE_PAGE - 1) / RAD_SYS_HUGE_PAGE * RAD_SYS_HUGE_PAGE;
}

/* A fresh mapping of `bytes` (whole huge pages) aligned to a huge page, so
 * that the kernel may back it with them; NULL when out of memory. */
static void *map_aligned(size_t bytes)
{
    size_t span = bytes + RAD_SYS_HUGE_PAGE;
    char *p = mmap(NULL, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED)
        return NULL;
    uintptr_t a = ((uintptr_t)p + RAD_SYS_HUGE_PAGE - 1) / RAD_SYS_HUGE_PAGE * RAD_SYS_HUGE_PAGE;
    size_t head = a - (uintptr_t)p, tail = span - head - bytes;
    if (head)
        munmap(p, head);
    if (tail)
        munmap((char *)a + bytes, tail);
    (void)madvise((void *)a, bytes, MADV_HUGEPAGE);
    return (void *)a;
}

/* Mapping old (old_bytes) made `bytes` long: in place where the addresses
 * after it are free, else its pages moved onto a fresh aligned range (a
 * move to an address off the huge-page grid would split its huge pages). */
static void *remap_aligned(void *old, size_t old_bytes, size_t bytes)
{
    void *p = mremap(old, old_bytes, bytes, 0);
    if (p == MAP_FAILED) {
        void *dst = map_aligned(bytes);
        if (!dst)
            return NULL;
        p = mremap(old, old_bytes, bytes, MREMAP_MAYMOVE | MREMAP_FIXED, dst);
        if (p == MAP_FAILED) {
            munmap(dst, bytes);
            return NULL;
        }
    }
    (void)madvise(p, bytes, MADV_HUGEPAGE);
    return p;
}

int rad_sys_grow_mapped(void **arr, size_t *cap, size_t used, size_t need, size_t item,
                        size_t first)
{
    if (need <= *cap)
        return 1;
    size_t c = doubled(*cap, need, first);
    if (c == 0 || item == 0 || c > (SIZE_MAX - RAD_SYS_HUGE_PAGE) / item)
        return 0;
    if (!mapped(c, item)) {
        void *n = realloc(*arr, c * item);
        if (!n)
            return 0;
        *arr = n;
        *cap = c;
        return 1;
    }
    void *n;
    if (*arr && mapped(*cap, item)) {
        n = remap_aligned(*arr, mapped_length(*cap, item), mapped_length(c, item));
    } else {
        n = map_aligned(mapped_length(c, item));
        if (n && *arr)
            memcpy(n, *arr, used * item);
        if (n)
            free(*arr);
    }
    if (!n)
        return 0;
    *arr = n;
    *cap = c;
    return 1;
}

void rad_sys_free_mapped(void *arr, size_t cap, size_t item)
{
    if (arr && mapped(cap, item))
        munmap(arr, mapped_length(cap, item));
    else
        free(arr);
}
#else
int rad_sys_grow_mapped(void **arr, size_t *cap, size_t used, size_t need, size_t item,
                        size_t first)
{
    return rad_sys_grow(arr, cap, used, need, item, first);
}

void rad_sys_free_mapped(void *arr, size_t cap, size_t item)
{
    (void)cap;
    (void)item;
    free(arr);
}
#endif
