/* The radkit program: subcommands over the library.  This is the only place
 * that prints errors and decides exit codes (0 ok, 1 computation failed,
 * 2 bad usage or input). */
#ifndef RAD_CLI_H
#define RAD_CLI_H

#include "rad_error.h"

/* One option of a subcommand.  `value` receives the argument of an option that
 * takes one; `flag` is set to 1 for an option that does not. */
typedef struct cli_option {
    const char *name; /* "--n" */
    const char **value;
    int *flag;
} cli_option;

/* Parse argv[first..argc) against a NULL-name-terminated option table.
 * Accepts "--name value" and "--name=value".  Unknown options, missing
 * values and stray arguments are RAD_EINVAL with a message naming them. */
rad_status cli_parse(const char *command, int argc, char **argv, int first,
                     const cli_option *options);

/* Parse a whole positive integer in [1, max]; RAD_EINVAL names the option. */
rad_status cli_parse_positive_int(const char *option, const char *text, long max, int *out);

int cli_galerkin1d(int argc, char **argv);
int cli_info(int argc, char **argv);

#endif
