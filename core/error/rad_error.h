/* rad_error: status codes and the one error funnel of radkit.
 *
 * Every failure in the library is reported through RAD_ERROR(), which records a
 * message (with the C source file and line, and, for bad input, the input's
 * file:line:col in the message itself) in a thread-local slot and returns the
 * status.  The library never prints and never exits; only the command-line
 * program turns a status into an exit code (rad_status_exit_code).
 * A breakpoint on rad_error_raise catches every error. */
#ifndef RAD_ERROR_H
#define RAD_ERROR_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum rad_status {
    RAD_OK = 0,      /* success */
    RAD_CONTINUE,    /* an iterative step that has not converged yet: not an error */
    RAD_EINVAL,      /* a bad argument or option (usage error) */
    RAD_EINPUT,      /* bad input data: malformed file, NaN, degenerate geometry */
    RAD_EIO,         /* a file could not be opened, read or written */
    RAD_ETOOBIG,     /* the problem is too large for the chosen method */
    RAD_ENOMEM,      /* an allocation failed */
    RAD_ESINGULAR,   /* a matrix is singular to working precision */
    RAD_ENUMERIC,    /* a numerical failure: NaN/Inf produced, no convergence */
    RAD_EGEOM,       /* a geometry-kernel failure (CGAL shim) */
    RAD_EDEP,        /* a dependency (LAPACK, Embree, Assimp) reported an error */
    RAD_STATUS_COUNT
} rad_status;

/* One line naming the status, e.g. "invalid argument". Never NULL. */
const char *rad_strerror(rad_status status);

/* Record an error message for this thread and return `status`.
 * `src_file`/`src_line` are the C source location (kept for debugging). */
rad_status rad_error_raise(rad_status status, const char *src_file, int src_line,
                           const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

#define RAD_ERROR(status, ...) rad_error_raise((status), __FILE__, __LINE__, __VA_ARGS__)

/* The message of the last error raised on this thread ("" if none). */
const char *rad_error_message(void);
/* The C source location of the last error ("file:line"). */
const char *rad_error_where(void);
/* Forget the last error. */
void rad_error_clear(void);

/* The process exit status for a status: 0 ok, 2 bad usage or input, 1 otherwise. */
int rad_status_exit_code(rad_status status);

#ifdef __cplusplus
}
#endif
#endif
