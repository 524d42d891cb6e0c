/* The radkit program: subcommands over the library.  This is the only place
 * that prints errors and decides exit codes (0 ok, 1 computation failed,
 * 2 bad usage or input). */
#ifndef RAD_CLI_H
#define RAD_CLI_H

#include <stddef.h>

#include "rad_error.h"

/* One option of a subcommand.  `value` receives the argument of an option that
 * takes one; `flag` is set to 1 for an option that does not. */
typedef struct cli_option {
    const char *name; /* "--n" */
    const char **value;
    int *flag;
    const char *what; /* the positional entry only: what it holds ("scene") */
} cli_option;

/* Parse argv[first..argc) against a NULL-name-terminated option table.
 * Accepts "--name value" and "--name=value".  Entries with the empty name ""
 * take the positional arguments (words not starting with '-'), in table
 * order; their values must start NULL.  Unknown options, missing values, a
 * positional beyond the last entry and stray arguments are RAD_EINVAL with a
 * message naming them. */
rad_status cli_parse(const char *command, int argc, char **argv, int first,
                     const cli_option *options);

/* Print the last error as "radkit: <message>" on stderr and return the exit
 * status for st (rad_status_exit_code). */
int cli_fail(rad_status st);
/* rad_hier_params' progress and working callbacks on a terminal (progress.c);
 * ctx: the program's name, or NULL for "radkit". */
void cli_hier_progress(int round, size_t leaves, size_t links, void *ctx);
void cli_hier_working(int round, const char *what, size_t count, void *ctx);

/* Parse a whole positive integer in [1, max]; RAD_EINVAL names the option. */
rad_status cli_parse_positive_int(const char *option, const char *text, long max, int *out);

/* The options every scene-reading command shares: --scale, --strict,
 * --drop-degenerate, --rho, --emission, --curve-tol and the effect overrides.
 * cli_scene_options_add appends their entries to a table (room for
 * CLI_SCENE_OPTION_COUNT); cli_scene_options_apply turns the parsed text into
 * parameters. */
#define CLI_SCENE_OPTION_COUNT 13
typedef struct cli_scene_options {
    const char *scale, *rho, *emission, *curve_tol;
    const char *mode[7]; /* occlusion, colour, facing-away, singular, reflectance, clustering,
                            contact */
    int strict, drop_degenerate;
} cli_scene_options;

struct rad_scene_params;
struct rad_effects_params;
void cli_scene_options_init(cli_scene_options *o);
int cli_scene_options_add(cli_scene_options *o, cli_option *table);
rad_status cli_scene_options_apply(const char *command, const cli_scene_options *o,
                                   struct rad_scene_params *scene, struct rad_effects_params *effects);
/* Help text lines for the shared options. */
extern const char cli_scene_options_help[];

int cli_galerkin1d(int argc, char **argv);
int cli_ff(int argc, char **argv);
int cli_info(int argc, char **argv);
int cli_solve(int argc, char **argv);
int cli_compare(int argc, char **argv);

#endif
