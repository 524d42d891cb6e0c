/* rad_sys: the large-array allocator. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

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
