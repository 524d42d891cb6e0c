/* Safe opening of scene files and bounded line reading for OBJ and MTL.
 *
 * A scene path may name anything: /dev/zero (endless bytes, no line break),
 * a FIFO (open blocks until a writer comes), a directory, a file of many
 * gigabytes.  So:
 *  1. open with O_NONBLOCK (a FIFO opens at once), fstat the descriptor (the
 *     object actually opened, not the name) and refuse anything that is not a
 *     regular file, or is larger than the caller's limit, before reading;
 *  2. lines are read into one buffer of max_line + 1 bytes allocated at open:
 *     a longer line is an error at its number, so memory never grows with the
 *     input and an allocation failure cannot pass for the end of the file;
 *  3. a NUL byte is an error (binary data is not an OBJ/MTL, and C strings
 *     would silently cut the line there); a read error (ferror) is an error
 *     with errno's text; the bytes read are counted against the size limit
 *     again, for files that grow while being read. */
#include "text_file.h"

#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static const char *kind_of(mode_t m)
{
    if (S_ISDIR(m))
        return "a directory";
    if (S_ISCHR(m))
        return "a character device";
    if (S_ISBLK(m))
        return "a block device";
    if (S_ISFIFO(m))
        return "a FIFO";
    if (S_ISSOCK(m))
        return "a socket";
    return "not a file";
}

rad_status scene_open_regular(const char *path, size_t max_bytes, FILE **out, long long *size,
                              int *open_errno)
{
    *out = NULL;
    if (open_errno)
        *open_errno = 0;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        if (open_errno)
            *open_errno = e;
        return RAD_ERROR(RAD_EINPUT, "%s: cannot open: %s", path, strerror(e));
    }
    struct stat sb;
    if (fstat(fd, &sb) != 0) {
        int e = errno;
        close(fd);
        return RAD_ERROR(RAD_EINPUT, "%s: cannot read: %s", path, strerror(e));
    }
    if (!S_ISREG(sb.st_mode)) {
        close(fd);
        return RAD_ERROR(RAD_EINPUT, "%s: not a regular file (%s)", path, kind_of(sb.st_mode));
    }
    if ((unsigned long long)sb.st_size > (unsigned long long)max_bytes) {
        close(fd);
        return RAD_ERROR(RAD_EINPUT, "%s: the file has %lld bytes, more than the limit of %zu",
                         path, (long long)sb.st_size, max_bytes);
    }
    int flags = fcntl(fd, F_GETFL);
    if (flags >= 0)
        (void)fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    FILE *f = fdopen(fd, "rb");
    if (!f) {
        int e = errno;
        close(fd);
        return RAD_ERROR(e == ENOMEM ? RAD_ENOMEM : RAD_EINPUT, "%s: cannot open: %s", path,
                         strerror(e));
    }
    if (size)
        *size = (long long)sb.st_size;
    *out = f;
    return RAD_OK;
}

rad_status scene_text_open(scene_text *t, const char *path, size_t max_line, size_t max_bytes,
                           int *open_errno)
{
    memset(t, 0, sizeof *t);
    t->path = path;
    t->max_line = max_line;
    t->max_bytes = max_bytes;
    rad_status st = scene_open_regular(path, max_bytes, &t->f, NULL, open_errno);
    if (st != RAD_OK)
        return st;
    t->buf = malloc(max_line + 1);
    if (!t->buf) {
        fclose(t->f);
        t->f = NULL;
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory for a line of %zu bytes", path, max_line);
    }
    return RAD_OK;
}

rad_status scene_text_next(scene_text *t, char **line)
{
    *line = NULL;
    size_t n = 0, cr = (size_t)-1; /* cr: where the first carriage return is */
    int c;
    while ((c = getc_unlocked(t->f)) != EOF && c != '\n') {
        if (c == '\0')
            return RAD_ERROR(RAD_EINPUT, "%s:%d: a NUL byte: not a text file", t->path, t->line + 1);
        if (n >= t->max_line)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: the line is longer than %zu bytes", t->path,
                             t->line + 1, t->max_line);
        if (c == '\r' && cr > n)
            cr = n;
        t->buf[n++] = (char)c;
    }
    if (c == EOF && ferror(t->f))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: read error: %s", t->path, t->line + 1, strerror(errno));
    t->total += n + (c == '\n');
    if (t->total > t->max_bytes)
        return RAD_ERROR(RAD_EINPUT, "%s: more than %zu bytes (the file grew while read)", t->path,
                         t->max_bytes);
    if (c == EOF && n == 0)
        return RAD_OK; /* the end */
    t->buf[cr < n ? cr : n] = '\0';
    t->line++;
    *line = t->buf;
    return RAD_OK;
}

void scene_text_close(scene_text *t)
{
    if (t->f)
        fclose(t->f);
    free(t->buf);
    t->f = NULL;
    t->buf = NULL;
}
