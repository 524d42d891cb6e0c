/* The error funnel: one function through which every error passes. */
#include "rad_error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static _Thread_local char last_message[1024];
static _Thread_local char last_where[256];

static const char *const status_names[RAD_STATUS_COUNT] = {
    [RAD_OK] = "success",
    [RAD_CONTINUE] = "not converged yet",
    [RAD_EINVAL] = "invalid argument",
    [RAD_EINPUT] = "bad input data",
    [RAD_EIO] = "input/output error",
    [RAD_ETOOBIG] = "problem too large for the method",
    [RAD_ENOMEM] = "out of memory",
    [RAD_ESINGULAR] = "singular matrix",
    [RAD_ENUMERIC] = "numerical failure",
    [RAD_EGEOM] = "geometry kernel failure",
    [RAD_EDEP] = "dependency failure",
};

const char *rad_strerror(rad_status status)
{
    if ((int)status < 0 || status >= RAD_STATUS_COUNT || !status_names[status])
        return "unknown status";
    return status_names[status];
}

rad_status rad_error_raise(rad_status status, const char *src_file, int src_line,
                           const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(last_message, sizeof last_message, fmt, ap);
    va_end(ap);
    snprintf(last_where, sizeof last_where, "%s:%d", src_file ? src_file : "?", src_line);
    return status;
}

const char *rad_error_message(void) { return last_message; }
const char *rad_error_where(void) { return last_where; }

void rad_error_clear(void)
{
    last_message[0] = '\0';
    last_where[0] = '\0';
}

int rad_status_exit_code(rad_status status)
{
    switch (status) {
    case RAD_OK:
    case RAD_CONTINUE:
        return 0;
    case RAD_EINVAL:
    case RAD_EINPUT:
    case RAD_ETOOBIG:
        return 2;
    default:
        return 1;
    }
}
