/* rad_sys: the few facts about the machine that radkit needs: a monotonic clock
 * for phase timings, the physical memory for "too big for this method" checks,
 * and the peak resident memory for the stats. */
#ifndef RAD_SYS_H
#define RAD_SYS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Seconds on a monotonic clock (only differences are meaningful). */
double rad_sys_seconds(void);

/* Physical memory of the machine in bytes (0 if unknown).  The environment
 * variable RADKIT_MEMORY_LIMIT (bytes) overrides it, so tests can exercise the
 * "too big" path without a huge machine. */
double rad_sys_memory_bytes(void);

/* Peak resident set size of this process in bytes (0 if unknown). */
double rad_sys_peak_rss_bytes(void);

/* Memory for one large array (free it with free()): from RAD_SYS_HUGE_PAGE
 * bytes up it is aligned to RAD_SYS_HUGE_PAGE and the kernel is asked to back
 * it with transparent huge pages (Linux madvise; elsewhere, or when the kernel
 * declines, ordinary pages).  The first touch of each 4 KB page costs a fault,
 * several microseconds on a virtual machine: hier's link array, grown by
 * doubling, spent a tenth of a Cornell-box solve in them.  NULL when out of
 * memory or bytes is 0. */
#define RAD_SYS_HUGE_PAGE ((size_t)2 << 20)
void *rad_sys_alloc_huge(size_t bytes);

#ifdef __cplusplus
}
#endif
#endif
