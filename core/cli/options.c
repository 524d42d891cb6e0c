#include "cli.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

rad_status cli_parse(const char *command, int argc, char **argv, int first,
                     const cli_option *options)
{
    const cli_option *last_positional = NULL;
    for (const cli_option *o = options; o->name; o++)
        if (o->name[0] == '\0')
            last_positional = o;
    for (int i = first; i < argc; i++) {
        const char *arg = argv[i];
        if (last_positional && arg[0] != '-') {
            const cli_option *slot = NULL; /* the first positional entry still empty */
            for (const cli_option *o = options; o->name && !slot; o++)
                if (o->name[0] == '\0' && !*o->value)
                    slot = o;
            if (!slot)
                return RAD_ERROR(RAD_EINVAL, "%s: more than one %s given ('%s' and '%s')", command,
                                 last_positional->what ? last_positional->what : "argument",
                                 *last_positional->value, arg);
            *slot->value = arg;
            continue;
        }
        const char *eq = strchr(arg, '=');
        size_t len = eq ? (size_t)(eq - arg) : strlen(arg);
        const cli_option *match = NULL;
        for (const cli_option *o = options; o->name; o++)
            if (o->name[0] && strlen(o->name) == len && strncmp(o->name, arg, len) == 0)
                match = o;
        if (!match)
            return RAD_ERROR(RAD_EINVAL, "%s: unknown %s '%s' (see 'radkit %s --help')", command,
                             arg[0] == '-' ? "option" : "argument", arg, command);
        if (match->flag) {
            if (eq)
                return RAD_ERROR(RAD_EINVAL, "%s: option %s takes no value", command, match->name);
            *match->flag = 1;
            continue;
        }
        if (eq) {
            *match->value = eq + 1;
        } else {
            if (i + 1 >= argc)
                return RAD_ERROR(RAD_EINVAL, "%s: option %s needs a value", command, match->name);
            *match->value = argv[++i];
        }
    }
    return RAD_OK;
}

rad_status cli_parse_positive_int(const char *option, const char *text, long max, int *out)
{
    char *end = NULL;
    errno = 0;
    long v = text ? strtol(text, &end, 10) : 0;
    if (!text || *text == '\0' || *end != '\0' || errno == ERANGE)
        return RAD_ERROR(RAD_EINVAL, "%s must be a whole number, got '%s'", option,
                         text ? text : "");
    if (v < 1)
        return RAD_ERROR(RAD_EINVAL, "%s must be at least 1, got %ld", option, v);
    if (v > max)
        return RAD_ERROR(RAD_ETOOBIG, "%s = %ld is too large (at most %ld)", option, v, max);
    *out = (int)v;
    return RAD_OK;
}

int cli_fail(rad_status st)
{
    fprintf(stderr, "radkit: %s\n", rad_error_message());
    return rad_status_exit_code(st);
}
