/* radkit: the command-line program.  Dispatches to one subcommand, then
 * checks that its standard output was written (exit 1 if not). */
#include <errno.h>
#include <malloc.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "rad_dense.h"
#include "rad_version.h"

static const char usage[] =
    "usage: radkit <command> [options]\n"
    "\n"
    "radkit is a research toolkit for Galerkin radiosity.\n"
    "\n"
    "commands:\n"
    "  galerkin1d   solve the 1D model problem of the notes and report its errors\n"
    "  info         load and validate a scene; its figures, adjacency and effects plan\n"
    "  solve        radiosity per triangle of a scene: dense or hierarchical Galerkin\n"
    "               radiosity, or Monte Carlo path tracing (the independent reference)\n"
    "  compare      the error of a per-face table against a reference table\n"
    "  ff           the form factor between two triangles by a chosen quadrature rule\n"
    "\n"
    "options:\n"
    "  -h, --help      this text; 'radkit <command> --help' explains a command\n"
    "  --version       print the version\n"
    "\n"
    "Output is TSV: '#' lines (parameters, figures), a header row, data rows.\n"
    "Exit status: 0 success, 1 the computation or writing an output failed (a\n"
    "full disk), 2 bad usage or input (including an output path that cannot be\n"
    "written).  Output files appear whole or not at all: each is written beside\n"
    "its target and renamed onto it once complete.\n";

/* Standard output is buffered: a full disk or a closed pipe shows up only
 * when it is flushed, after the command has returned.  A command that
 * succeeded but whose output was lost has failed (exit 1); one that failed
 * has already said why. */
static int finish_stdout(int code)
{
    int err = errno, bad = 0;
    if (fflush(stdout) != 0) {
        bad = 1;
        err = errno;
    } else if (ferror(stdout)) {
        bad = 1;
    }
    if (fclose(stdout) != 0 && !bad) {
        bad = 1;
        err = errno;
    }
    if (bad && code == 0) {
        fprintf(stderr, "radkit: error writing standard output: %s\n", strerror(err ? err : EIO));
        return 1;
    }
    return code;
}

static int run(int argc, char **argv)
{
    rad_dense_blas_idle(); /* OpenBLAS's workers would spin beside our OpenMP threads */
    /* Keep freed memory for reuse instead of handing it back to the kernel:
     * hier allocates and frees a batch of link estimates per refinement
     * generation, and each fresh mapping costs a page fault per 4 KiB (6% of
     * a hierarchical solve's samples under perf; 2-9% less CPU time with this). */
    mallopt(M_MMAP_THRESHOLD, 1 << 30);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    if (argc < 2) {
        fputs(usage, stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "-h") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "help") == 0) {
        fputs(usage, stdout);
        return 0;
    }
    if (strcmp(cmd, "--version") == 0) {
        printf("radkit %s\n", RAD_VERSION);
        return 0;
    }
    if (strcmp(cmd, "galerkin1d") == 0)
        return cli_galerkin1d(argc, argv);
    if (strcmp(cmd, "info") == 0)
        return cli_info(argc, argv);
    if (strcmp(cmd, "solve") == 0)
        return cli_solve(argc, argv);
    if (strcmp(cmd, "ff") == 0)
        return cli_ff(argc, argv);
    if (strcmp(cmd, "compare") == 0)
        return cli_compare(argc, argv);
    fprintf(stderr, "radkit: unknown command '%s' (see 'radkit --help')\n", cmd);
    return 2;
}

int main(int argc, char **argv)
{
    errno = 0;
    return finish_stdout(run(argc, argv));
}
