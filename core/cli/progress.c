/* The hierarchy's progress on a terminal (radkit solve and radkit-mpi): one
 * line rewritten in place, the program's name from the callbacks' ctx. */
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "rad_sys.h"

/* Padded so that a shorter line covers a longer one before it. */
static void show(const char *who, const char *line)
{
    fprintf(stderr, "\r%s: %-60s", who, line);
    fflush(stderr);
}

void cli_hier_progress(int round, size_t leaves, size_t links, void *ctx)
{
    char line[128];
    snprintf(line, sizeof line, "hier round %d: %zu leaves, %zu links", round, leaves, links);
    show(ctx ? (const char *)ctx : "radkit", line);
}

void cli_hier_working(int round, const char *what, size_t count, void *ctx)
{
    /* at most five lines a second: a small hierarchy's steps come faster
       than a terminal shows them, and each line is a write */
    static double last = -1.0;
    double now = rad_sys_seconds();
    if (last >= 0.0 && now - last < 0.2)
        return;
    last = now;
    char line[128];
    if (strcmp(what, "linking") == 0)
        snprintf(line, sizeof line, "hier round %d: linking, %zu links", round, count);
    else
        snprintf(line, sizeof line, "hier round %d: %s, step %zu", round, what, count);
    show(ctx ? (const char *)ctx : "radkit", line);
}
