/* The whole of a scene file in memory, for the OFF and PLY readers.
 *
 * Reading everything first bounds every later read by the bytes actually
 * present (a header's counts are checked against them, never trusted), and
 * the buffer is NUL-terminated so strtod/strtol stop inside it.  Only regular
 * files of at most max_bytes are read (scene_open_regular), and only the size
 * they had when opened: a file that grows while it is read is refused, not
 * followed. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"
#include "text_file.h"

rad_status scene_read_file(const char *path, size_t max_bytes, char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    FILE *f = NULL;
    long long bytes = 0;
    rad_status st = scene_open_regular(path, max_bytes, &f, &bytes, NULL);
    if (st != RAD_OK)
        return st;
    size_t n = (size_t)bytes;
    char *buf = malloc(n + 1);
    if (!buf) {
        fclose(f);
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory to read %zu bytes", path, n);
    }
    size_t got = fread(buf, 1, n, f);
    int more = got == n && getc(f) != EOF;
    if (got != n || more || ferror(f))
        st = ferror(f) ? RAD_ERROR(RAD_EINPUT, "%s: cannot read: %s", path, strerror(errno))
                       : RAD_ERROR(RAD_EINPUT, "%s: the file changed size while being read", path);
    fclose(f);
    if (st != RAD_OK) {
        free(buf);
        return st;
    }
    buf[n] = '\0';
    *data = buf;
    *size = n;
    return RAD_OK;
}
