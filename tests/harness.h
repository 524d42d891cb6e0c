/* A small test harness: tests register themselves, CHECK records failures
 * without stopping the test, and the runner's last line reads
 * "N passed, N failed" (counting tests).  `unit NAME...` runs only the tests
 * whose name contains one of the given strings. */
#ifndef RAD_TEST_HARNESS_H
#define RAD_TEST_HARNESS_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "rad_geom.h"
#include "rad_scene.h"
#include "rad_solve.h"

typedef void (*harness_fn)(void);
void harness_register(const char *name, const char *file, harness_fn fn);
void harness_fail(const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#define TEST(name)                                                                  \
    static void name(void);                                                         \
    __attribute__((constructor)) static void harness_reg_##name(void)               \
    {                                                                               \
        harness_register(#name, __FILE__, name);                                    \
    }                                                                               \
    static void name(void)

#define CHECK(cond)                                                                 \
    do {                                                                            \
        if (!(cond))                                                                \
            harness_fail(__FILE__, __LINE__, "CHECK(%s)", #cond);                   \
    } while (0)

#define CHECK_MSG(cond, ...)                                                        \
    do {                                                                            \
        if (!(cond))                                                                \
            harness_fail(__FILE__, __LINE__, __VA_ARGS__);                          \
    } while (0)

/* |got - want| <= rel * |want| + abs */
#define CHECK_NEAR(got, want, rel, abs_)                                            \
    do {                                                                            \
        double g_ = (got), w_ = (want);                                             \
        if (!(fabs(g_ - w_) <= (rel) * fabs(w_) + (abs_)))                          \
            harness_fail(__FILE__, __LINE__, "%s = %.17g, want %s = %.17g (diff %.3g)", \
                         #got, g_, #want, w_, fabs(g_ - w_));                       \
    } while (0)

/* Run a program (argv[0] is a path), capturing stdout and stderr (malloc'd,
 * NUL-terminated; the caller frees).  Returns the exit status, or -1 if it did
 * not exit normally (a crash counts as a failure in every caller). */
int harness_run(const char *const argv[], char **out, char **err);

/* The radkit binary under test ($RADKIT_BIN) and the source tree ($RADKIT_ROOT). */
const char *harness_radkit(void);
const char *harness_root(void);

/* Run the radkit binary: `command` (e.g. "solve", or NULL) then args[]
 * (NULL-terminated).  Output as for harness_run. */
int harness_radkit_run(const char *command, const char *const args[], char **out, char **err);

/* RADKIT_ROOT/rel, in one of 8 rotating buffers (so a few can be alive at once);
 * an absolute path is returned as it is. */
const char *harness_path(const char *rel);

/* The tests' one scene loader: rad_scene_load of harness_path(rel) with
 * params (NULL: the defaults).  harness_scene_load records a check failure
 * (at the caller's line, with the library's message) and returns NULL when the
 * scene does not load; harness_scene_load_status returns the status, for
 * tests of refusals. */
#define harness_scene_load(rel, params) harness_scene_load_at(__FILE__, __LINE__, rel, params)
rad_scene *harness_scene_load_at(const char *file, int line, const char *rel,
                                 const rad_scene_params *params);
rad_status harness_scene_load_status(const char *rel, const rad_scene_params *params,
                                     rad_scene **out);
/* A furnace: the scene with every face's reflectance rho and emission 1 in
 * every channel (so B = 1 / (1 - rho) wherever every point sees only such
 * faces), loaded as harness_scene_load does. */
#define harness_furnace_load(rel, rho) harness_furnace_load_at(__FILE__, __LINE__, rel, rho)
rad_scene *harness_furnace_load_at(const char *file, int line, const char *rel, double rho);
/* The scene with every face's reflectance rho in every channel and its own
 * emission, loaded as harness_scene_load does. */
#define harness_grey_load(rel, rho) harness_grey_load_at(__FILE__, __LINE__, rel, rho)
rad_scene *harness_grey_load_at(const char *file, int line, const char *rel, double rho);

/* Per channel: every face's B finite and nonnegative, and the power the
 * emitters give out absorbed by the faces, sum A (1 - rho) (B - E) / rho
 * (the scene's materials' rho, every one > 0, and E), within tol of it
 * (relative); failures
 * at the caller's line, the figures printed with `what`. */
#define harness_check_power(scene, s, what, tol)                                    \
    harness_check_power_at(__FILE__, __LINE__, scene, s, what, tol)
void harness_check_power_at(const char *file, int line, const rad_scene *scene,
                            const rad_solution *s, const char *what, double tol);

/* The tests' one scene writer: `text` into a file of /tmp named after the
 * process id and `name` (e.g. "order.obj"), so parallel runs do not collide;
 * returns its path (harness_temp_path), after recording a check failure at the
 * caller's line if it could not be written.  The caller removes it. */
#define harness_write_file(name, text) harness_write_file_at(__FILE__, __LINE__, name, text)
const char *harness_write_file_at(const char *file, int line, const char *name, const char *text);
/* The path harness_write_file gives `name`, in one of 8 rotating buffers. */
const char *harness_temp_path(const char *name);

/* The value of a "# key = value" line of a program's output, copied to buf;
 * NULL when there is no such line. */
const char *harness_header(const char *out, const char *key, char *buf, size_t size);
/* The same line's value as a number; NAN when there is no such line. */
double harness_header_number(const char *out, const char *key);

/* Bad usage or input: exit status 2, nothing on stdout, exactly one line on
 * stderr that starts "radkit: " and contains `needle`.  Failures are reported
 * at the caller's line. */
void harness_expect_usage_error_at(const char *file, int line, const char *command,
                                   const char *const args[], const char *needle);
/* Variadic so that a compound literal's commas pass through: (command, args, needle). */
#define HARNESS_EXPECT_USAGE_ERROR(command, ...)                                      \
    harness_expect_usage_error_at(__FILE__, __LINE__, command, __VA_ARGS__)

/* The per-face table of `radkit solve` (face, area, B_r, B_g, B_b): B receives
 * 3 values a row; returns the row count, or -1 if the table is missing or
 * malformed. */
int harness_face_table(const char *out, double *B, int max);
/* The same for tables with standard errors (radkit solve --method mc): se
 * receives 3 values a row; -1 if the table has no se columns. */
int harness_face_table_se(const char *out, double *B, double *se, int max);

/* Howell's closed forms \cite{howell2010}: C-11, parallel directly opposed
 * rectangles a x b at distance c; C-14, perpendicular rectangles with a
 * common edge of length l, the emitter of width w, the receiver of height h. */
double harness_howell_c11(double a, double b, double c);
double harness_howell_c14(double l, double w, double h);

/* The independent reference for scenes/occluder: Monte Carlo estimate of the
 * blocked form factor between the unit plates (fixed seed; see harness.c). */
double harness_occluder_form_factor_mc(long samples);

/* The squares of side `side` on an n x n checkerboard from (origin, origin)
 * whose (i + j) is even (so they touch only at corners): their lower corners
 * into lo[0 .. n^2), in row order; returns their count. */
int harness_checkerboard(int n, double origin, double side, double (*lo)[2]);

/* The whole of a file, NUL-terminated (free it), or NULL. */
char *harness_read_file(const char *path);

/* An independent light tracer (harness_light.c, no code shared with core/):
 * per triangle and channel (n x 3 column-major, as rho and E) the
 * area-average B and its standard error over `batches` batches.  0, or -1
 * on bad arguments or no emission. */
int harness_light_trace(const double *xyz, const int *tri, int n, const double *rho,
                        const double *E, long photons, int batches, uint64_t seed, double *B,
                        double *se);

/* Number of lines in a string (a final line without '\n' counts). */
int harness_count_lines(const char *s);

#endif
