/* Output files that appear whole or not at all (rad_io.h, "output files").
 *
 * A regular file is written to a temporary file beside its target (same
 * directory, so the final rename never crosses a file system), every write
 * and the close are checked, and only then is the temporary renamed onto the
 * target: a reader never sees half a file, a failed run leaves the old file
 * as it was, and the only thing ever removed is the temporary this module
 * made.  A target that exists and is not a regular file (a device such as
 * /dev/null, a pipe) is written in place and never renamed or removed; so is
 * standard output ("-").  A symbolic link is followed: the file it names is
 * replaced, the link stays.
 *
 * Paths that cannot be written at all (empty, a directory, a missing
 * directory) are RAD_EINVAL, a usage error, found before any work by
 * rad_io_output_check; failures while writing (a full disk) are RAD_EIO. */
#define _DEFAULT_SOURCE /* realpath, mkstemp, fchmod */
#include "rad_io.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The process's umask without changing it (reading it through umask() would
 * set it, process-wide state a library must not touch). */
static mode_t current_umask(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    unsigned mask = 022;
    if (f) {
        char line[256];
        while (fgets(line, sizeof line, f))
            if (sscanf(line, "Umask: %o", &mask) == 1)
                break;
        fclose(f);
    }
    return (mode_t)mask;
}

/* The directory part of path ("." when there is none), in buf. */
static void directory_of(const char *path, char *buf, size_t size)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(buf, size, ".");
    else if (slash == path)
        snprintf(buf, size, "/");
    else
        snprintf(buf, size, "%.*s", (int)(slash - path), path);
}

/* The file a write to path would replace: path itself, or for a symbolic
 * link the file it names (a dangling link: the path, written in place). */
static void resolve_target(const char *path, char *buf, size_t size, int *dangling)
{
    struct stat ls;
    char real[PATH_MAX];
    *dangling = 0;
    if (lstat(path, &ls) == 0 && S_ISLNK(ls.st_mode)) {
        if (realpath(path, real)) {
            snprintf(buf, size, "%s", real);
            return;
        }
        *dangling = 1;
    }
    snprintf(buf, size, "%s", path);
}

rad_status rad_io_output_check(const char *path)
{
    if (!path)
        return RAD_ERROR(RAD_EINVAL, "output: NULL path");
    if (!*path)
        return RAD_ERROR(RAD_EINVAL, "the output path is empty");
    if (strcmp(path, "-") == 0)
        return RAD_OK;
    if (strlen(path) >= PATH_MAX - 16)
        return RAD_ERROR(RAD_EINVAL, "'%.64s...': the output path is too long", path);
    char target[PATH_MAX], dir[PATH_MAX];
    int dangling;
    resolve_target(path, target, sizeof target, &dangling);
    struct stat st;
    if (stat(target, &st) == 0) {
        if (S_ISDIR(st.st_mode))
            return RAD_ERROR(RAD_EINVAL, "'%s' is a directory, not a file to write", path);
        if (!S_ISREG(st.st_mode))
            return RAD_OK; /* a device or pipe: written in place */
        /* the rename would replace it anyway: honour the file's own mode */
        if (access(target, W_OK) != 0)
            return RAD_ERROR(RAD_EINVAL, "'%s': the file is not writable: %s", path,
                             strerror(errno));
    }
    directory_of(target, dir, sizeof dir);
    if (stat(dir, &st) != 0) {
        if (errno == ENOENT)
            return RAD_ERROR(RAD_EINVAL, "'%s': the directory '%s' does not exist", path, dir);
        return RAD_ERROR(RAD_EINVAL, "'%s': cannot use the directory '%s': %s", path, dir,
                         strerror(errno));
    }
    if (!S_ISDIR(st.st_mode))
        return RAD_ERROR(RAD_EINVAL, "'%s': '%s' is not a directory", path, dir);
    if (access(dir, W_OK | X_OK) != 0)
        return RAD_ERROR(RAD_EINVAL, "'%s': cannot create files in '%s': %s", path, dir,
                         strerror(errno));
    return RAD_OK;
}

rad_status rad_io_output_open(const char *path, int binary, rad_io_output *out)
{
    memset(out, 0, sizeof *out);
    rad_status st = rad_io_output_check(path);
    if (st != RAD_OK)
        return st;
    out->path = path;
    if (strcmp(path, "-") == 0) {
        out->f = stdout;
        out->in_place = 1;
        return RAD_OK;
    }
    char target[PATH_MAX];
    int dangling;
    resolve_target(path, target, sizeof target, &dangling);
    struct stat st_target;
    int exists = stat(target, &st_target) == 0;
    if (dangling || (exists && !S_ISREG(st_target.st_mode))) {
        out->f = fopen(target, binary ? "wb" : "w");
        if (!out->f)
            return RAD_ERROR(RAD_EIO, "%s: cannot open for writing: %s", path, strerror(errno));
        out->in_place = 1;
        errno = 0;
        return RAD_OK;
    }
    size_t len = strlen(target);
    out->target = malloc(2 * len + 16);
    if (!out->target)
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory for the file name", path);
    memcpy(out->target, target, len + 1);
    out->tmp = out->target + len + 1;
    snprintf(out->tmp, len + 15, "%s.tmp.XXXXXX", target);
    int fd = mkstemp(out->tmp);
    if (fd < 0) {
        int err = errno;
        free(out->target);
        memset(out, 0, sizeof *out);
        return RAD_ERROR(RAD_EIO, "%s: cannot create a file beside it: %s", path, strerror(err));
    }
    /* mkstemp makes the file private (0600); the target gets the mode the
       old file had, or what creating it would have given */
    mode_t mode = exists ? (st_target.st_mode & 07777) : (0666 & ~current_umask());
    if (fchmod(fd, mode) != 0 || !(out->f = fdopen(fd, binary ? "wb" : "w"))) {
        int err = errno;
        close(fd);
        unlink(out->tmp);
        free(out->target);
        memset(out, 0, sizeof *out);
        return RAD_ERROR(RAD_EIO, "%s: cannot set up the file: %s", path, strerror(err));
    }
    errno = 0;
    return RAD_OK;
}

rad_status rad_io_output_commit(rad_io_output *out)
{
    if (!out->f)
        return RAD_ERROR(RAD_EINVAL, "output: commit without an open file");
    /* The reason of an earlier failed write is the errno it left, unless a
       failing flush now gives a fresher one. */
    int err = errno, bad = 0;
    if (fflush(out->f) != 0) {
        bad = 1;
        err = errno;
    } else if (ferror(out->f)) {
        bad = 1;
    }
    if (out->f == stdout) {
        out->f = NULL;
        if (bad)
            return RAD_ERROR(RAD_EIO, "error writing standard output: %s", strerror(err ? err : EIO));
        return RAD_OK;
    }
    if (fclose(out->f) != 0 && !bad) {
        bad = 1;
        err = errno;
    }
    out->f = NULL;
    rad_status st = RAD_OK;
    if (bad)
        st = RAD_ERROR(RAD_EIO, "%s: write failed: %s", out->path, strerror(err ? err : EIO));
    else if (out->tmp && rename(out->tmp, out->target) != 0)
        st = RAD_ERROR(RAD_EIO, "%s: cannot replace it with the new file: %s", out->path,
                       strerror(errno));
    if (st != RAD_OK && out->tmp)
        unlink(out->tmp);
    free(out->target);
    out->target = out->tmp = NULL;
    return st;
}

void rad_io_output_discard(rad_io_output *out)
{
    if (out->f && out->f != stdout)
        fclose(out->f);
    else if (out->f)
        fflush(out->f);
    if (out->tmp)
        unlink(out->tmp);
    free(out->target);
    memset(out, 0, sizeof *out);
}

/* path with its directory resolved (the file itself need not exist). */
static int canonical(const char *path, char *buf, size_t size)
{
    char dir[PATH_MAX], real[PATH_MAX];
    directory_of(path, dir, sizeof dir);
    if (!realpath(dir, real))
        return 0;
    const char *slash = strrchr(path, '/');
    return snprintf(buf, size, "%s/%s", real, slash ? slash + 1 : path) < (int)size;
}

int rad_io_output_same(const char *a, const char *b)
{
    if (!a || !b)
        return 0;
    if (strcmp(a, b) == 0)
        return 1;
    if (strcmp(a, "-") == 0 || strcmp(b, "-") == 0)
        return 0;
    struct stat sa, sb;
    int ea = stat(a, &sa) == 0, eb = stat(b, &sb) == 0;
    if (ea && eb)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    if (ea != eb)
        return 0;
    char ca[PATH_MAX + 8], cb[PATH_MAX + 8];
    return canonical(a, ca, sizeof ca) && canonical(b, cb, sizeof cb) && strcmp(ca, cb) == 0;
}
