/* Internal to rad_scene: opening scene files safely and reading text files
 * (OBJ, MTL) line by line with bounded memory (text_file.c). */
#ifndef RAD_SCENE_TEXT_FILE_H
#define RAD_SCENE_TEXT_FILE_H

#include <stddef.h>
#include <stdio.h>

#include "rad_error.h"

/* Open `path` for reading if it is a regular file of at most max_bytes
 * bytes.  Directories, devices, FIFOs and sockets are refused without
 * blocking or reading a byte.  RAD_EINPUT names the path; *open_errno is the
 * errno of a failed open (e.g. ENOENT), 0 for every other failure.  *size
 * receives the file's size. */
rad_status scene_open_regular(const char *path, size_t max_bytes, FILE **out, long long *size,
                              int *open_errno);

typedef struct scene_text {
    FILE *f;
    const char *path; /* borrowed, for messages */
    char *buf;        /* max_line + 1 bytes */
    size_t max_line, max_bytes, total;
    int line;         /* number of the line last returned (1-based) */
} scene_text;

/* scene_open_regular, then a buffer for one line of up to max_line bytes.
 * On failure nothing needs closing. */
rad_status scene_text_open(scene_text *t, const char *path, size_t max_line, size_t max_bytes,
                           int *open_errno);

/* The next line, without its line break and cut at the first carriage return,
 * in t->buf (valid until the next call); *line = NULL at the end of the file.
 * RAD_EINPUT at a line longer than max_line, a NUL byte, more than max_bytes
 * in all (a file that grows) or a read error: never taken as the end. */
rad_status scene_text_next(scene_text *t, char **line);

void scene_text_close(scene_text *t);

#endif
