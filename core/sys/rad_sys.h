/* rad_sys: the few facts about the machine that radkit needs: a monotonic clock
 * for phase timings, the physical memory for "too big for this method" checks,
 * and the peak resident memory for the stats. */
#ifndef RAD_SYS_H
#define RAD_SYS_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Hashed sampling, the one generator of the library: splitmix64
 * \cite{steele2014splitmix}.  rad_sys_mix64 is its finalizer (a bijection of
 * 64-bit words); rad_sys_hash64(x) is splitmix64's output for the state x,
 * so that a key (a triangle, a cell, a sample) gives the same number on every
 * thread and every run, and a stream is hash64(x), hash64(x + RAD_SYS_GOLDEN),
 * ...; rad_sys_unit maps a word's top 53 bits to a uniform double in [0, 1). */
#define RAD_SYS_GOLDEN 0x9e3779b97f4a7c15ull
static inline uint64_t rad_sys_mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}
static inline uint64_t rad_sys_hash64(uint64_t x) { return rad_sys_mix64(x + RAD_SYS_GOLDEN); }
static inline double rad_sys_unit(uint64_t bits) { return (double)(bits >> 11) * 0x1.0p-53; }
static inline double rad_sys_hash_unit(uint64_t x) { return rad_sys_unit(rad_sys_hash64(x)); }

/* Seconds on a monotonic clock (only differences are meaningful). */
double rad_sys_seconds(void);

/* Bind each of the threads OpenMP runs a loop of `threads` (0: its default)
 * on to one of the CPUs this process may use, the calling thread to the
 * first, in turn (as OMP_PROC_BIND=true does), when they are as many as
 * those CPUs (more than one); nothing when the environment sets
 * OMP_PROC_BIND or OMP_PLACES, or when the threads are fewer or more.  Threads
 * the bound calling thread starts later inherit its one CPU, so a program
 * whose other thread pools start later (OpenBLAS's, at each threaded call)
 * should not bind.  Returns the number of threads bound. */
int rad_sys_bind_threads(int threads);

/* Physical memory of the machine in bytes (0 if unknown).  The environment
 * variable RADKIT_MEMORY_LIMIT (bytes) overrides it, so tests can exercise the
 * "too big" path without a huge machine. */
double rad_sys_memory_bytes(void);

/* Resident set size of this process now, in bytes (Linux /proc/self/statm;
 * elsewhere the peak, rad_sys_peak_rss_bytes). */
double rad_sys_rss_bytes(void);

/* Whether the process may take more bytes on top of what it holds now
 * (rad_sys_rss_bytes) and stay within RAD_SYS_MEMORY_SHARE of the machine's
 * memory (rad_sys_memory_bytes): 1, or 0; either way *would is what it
 * would hold and *have the machine's memory (0 when unknown: then always
 * 1).  Linux lends memory it does not have, so a large structure that grows
 * past the machine is not refused by malloc but killed by the kernel: the
 * hierarchical solvers ask this before they grow one. */
#define RAD_SYS_MEMORY_SHARE 0.9
int rad_sys_memory_allows(double more, double *would, double *have);

/* Peak resident set size of this process in bytes (0 if unknown). */
double rad_sys_peak_rss_bytes(void);

/* Memory for one large array (free it with free()): from RAD_SYS_HUGE_PAGE
 * bytes up it is aligned to RAD_SYS_HUGE_PAGE and the kernel is asked to back
 * it with transparent huge pages (Linux madvise; elsewhere, or when the kernel
 * declines, ordinary pages).  The first touch of each 4 KB page costs a fault,
 * several microseconds on a virtual machine, and an array grown by doubling
 * (hier's links) touches every page of every copy.  NULL when out of memory or
 * bytes is 0. */
#define RAD_SYS_HUGE_PAGE ((size_t)2 << 20)
void *rad_sys_alloc_huge(size_t bytes);

/* rad_sys_alloc_huge for count items of size bytes, zeroed (calloc's
 * contract; glibc's calloc maps a large block on 4 KB pages).  NULL when
 * the size overflows, memory runs out or count is 0. */
void *rad_sys_calloc_huge(size_t count, size_t size);

/* Make *arr (`used` items of `item` bytes, capacity *cap) hold at least
 * `need` items: the capacity doubles (from `first`), so appends cost O(1)
 * on average.  The first `used` items are kept: a small block by realloc; a
 * large one (RAD_SYS_HUGE_PAGE bytes and up) is copied into a new block from
 * rad_sys_alloc_huge, the old one freed and its pages handed back to the
 * kernel (realloc would copy a block glibc placed on its heap into 4 KB
 * pages, each faulting on the copy's first touch).  With `used` 0 the old
 * block is freed first, a large one's pages handed back, before a new one
 * comes from rad_sys_alloc_huge.  Free the array with free().  0 when the
 * size overflows (*arr unchanged) or memory runs out (*arr unchanged, but
 * with `used` 0 NULL and *cap 0), 1 otherwise. */
int rad_sys_grow(void **arr, size_t *cap, size_t used, size_t need, size_t item, size_t first);

/* rad_sys_grow for an array that grows large and is kept (hier's elements,
 * links and incidence): past RAD_SYS_HUGE_PAGE bytes it lies on a mapping
 * of its own, on huge pages where the kernel grants them, which grows by
 * remapping its pages (Linux mremap) instead of copying them into a fresh
 * block: no copy, and no page of the old block zeroed again by the kernel
 * for the new one.  Below that, a small block by realloc.  The capacity
 * doubles as rad_sys_grow's and the first `used` items are kept (with
 * `used` 0 whatever the pages held is left: the caller writes them anew).
 * 0 when the size overflows or memory runs out (*arr and *cap unchanged),
 * 1 otherwise.  Free the array with rad_sys_free_mapped and the capacity
 * this left in *cap. */
int rad_sys_grow_mapped(void **arr, size_t *cap, size_t used, size_t need, size_t item,
                        size_t first);
void rad_sys_free_mapped(void *arr, size_t cap, size_t item);

#ifdef __cplusplus
}
#endif
#endif
