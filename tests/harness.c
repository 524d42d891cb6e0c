#include "harness.h"

#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define MAX_TESTS 1024

typedef struct test_case {
    const char *name, *file;
    harness_fn fn;
} test_case;

static test_case tests[MAX_TESTS];
static int test_count;
static int current_failures;

void harness_register(const char *name, const char *file, harness_fn fn)
{
    if (test_count < MAX_TESTS)
        tests[test_count++] = (test_case){name, file, fn};
}

void harness_fail(const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    fprintf(stdout, "    %s:%d: ", file, line);
    va_start(ap, fmt);
    vfprintf(stdout, fmt, ap);
    va_end(ap);
    fputc('\n', stdout);
    current_failures++;
}

const char *harness_radkit(void)
{
    const char *p = getenv("RADKIT_BIN");
    return p && *p ? p : "build/radkit";
}

const char *harness_root(void)
{
    const char *p = getenv("RADKIT_ROOT");
    return p && *p ? p : ".";
}

int harness_count_lines(const char *s)
{
    int lines = 0;
    for (const char *p = s; p && *p; p++)
        if (*p == '\n' || p[1] == '\0')
            lines++;
    return lines;
}

static char *slurp(int fd)
{
    size_t cap = 4096, len = 0;
    char *buf = malloc(cap);
    lseek(fd, 0, SEEK_SET);
    for (;;) {
        if (len + 1 >= cap) {
            cap *= 2;
            buf = realloc(buf, cap);
        }
        ssize_t got = read(fd, buf + len, cap - len - 1);
        if (got <= 0)
            break;
        len += (size_t)got;
    }
    buf[len] = '\0';
    return buf;
}

char *harness_read_file(const char *path)
{
    int fd = open(path, O_RDONLY);
    if (fd < 0)
        return NULL;
    char *text = slurp(fd);
    close(fd);
    return text;
}

int harness_run(const char *const argv[], char **out, char **err)
{
    char out_name[] = "/tmp/radkit-test-out-XXXXXX", err_name[] = "/tmp/radkit-test-err-XXXXXX";
    int fo = mkstemp(out_name), fe = mkstemp(err_name);
    unlink(out_name);
    unlink(err_name);
    fflush(stdout);
    pid_t pid = fork();
    if (pid == 0) {
        int devnull = open("/dev/null", O_RDONLY);
        dup2(devnull, 0);
        dup2(fo, 1);
        dup2(fe, 2);
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    *out = slurp(fo);
    *err = slurp(fe);
    close(fo);
    close(fe);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

int harness_radkit_run(const char *command, const char *const args[], char **out, char **err)
{
    const char *argv[64] = {harness_radkit()};
    int k = 1;
    if (command)
        argv[k++] = command;
    for (int a = 0; args && args[a] && k < 63; a++)
        argv[k++] = args[a];
    argv[k] = NULL;
    return harness_run(argv, out, err);
}

const char *harness_path(const char *rel)
{
    static char buf[8][1024];
    static int next;
    char *p = buf[next++ % 8];
    if (rel[0] == '/')
        snprintf(p, sizeof buf[0], "%s", rel);
    else
        snprintf(p, sizeof buf[0], "%s/%s", harness_root(), rel);
    return p;
}

rad_status harness_scene_load_status(const char *rel, const rad_scene_params *params,
                                     rad_scene **out)
{
    return rad_scene_load(harness_path(rel), params, out);
}

const char *harness_temp_path(const char *name)
{
    static char buf[8][512];
    static int next;
    char *p = buf[next++ % 8];
    snprintf(p, sizeof buf[0], "/tmp/radkit-test-%ld-%s", (long)getpid(), name);
    return p;
}

const char *harness_write_file_at(const char *file, int line, const char *name, const char *text)
{
    const char *path = harness_temp_path(name);
    FILE *f = fopen(path, "w");
    int ok = f && fputs(text, f) >= 0;
    if (f && fclose(f) != 0)
        ok = 0;
    if (!ok)
        harness_fail(file, line, "cannot write %s", path);
    return path;
}

rad_scene *harness_scene_load_at(const char *file, int line, const char *rel,
                                 const rad_scene_params *params)
{
    rad_scene *s = NULL;
    if (harness_scene_load_status(rel, params, &s) != RAD_OK) {
        harness_fail(file, line, "loading %s: %s", rel, rad_error_message());
        rad_scene_destroy(s);
        return NULL;
    }
    return s;
}

void harness_check_power_at(const char *file, int line, const rad_scene *scene,
                            const rad_solution *s, const char *what, double tol)
{
    const int *mat = rad_scene_triangle_materials(scene);
    const rad_scene_material *m = rad_scene_materials(scene);
    if (s->faces != rad_scene_triangle_count(scene)) {
        harness_fail(file, line, "%s: %d rows for %d triangles", what, s->faces,
                     rad_scene_triangle_count(scene));
        return;
    }
    for (int c = 0; c < 3; c++) {
        double emitted = 0.0, absorbed = 0.0;
        int bad = 0;
        for (int f = 0; f < s->faces; f++) {
            double B = s->face_B[f + (size_t)c * (size_t)s->faces], A = s->face_area[f];
            double rho = m[mat[f]].rho[c], E = m[mat[f]].emission[c];
            bad += !isfinite(B) || B < 0.0 || !(rho > 0.0); /* H = (B - E) / rho */
            emitted += A * E;
            absorbed += A * (1.0 - rho) * (B - E) / rho;
        }
        printf("# %s, channel %d: emitted %.9g, absorbed %.9g\n", what, c, emitted, absorbed);
        if (bad)
            harness_fail(file, line, "%s, channel %d: %d rows not finite, negative or not reflecting", what, c,
                         bad);
        if (!(fabs(absorbed - emitted) <= tol * emitted))
            harness_fail(file, line, "%s, channel %d: absorbed %g of %g", what, c, absorbed,
                         emitted);
    }
}

rad_scene *harness_furnace_load_at(const char *file, int line, const char *rel, double rho)
{
    rad_scene_params sp;
    rad_scene_params_default(&sp);
    sp.has_rho = sp.has_emission = 1;
    for (int c = 0; c < 3; c++) {
        sp.rho[c] = rho;
        sp.emission[c] = 1.0;
    }
    return harness_scene_load_at(file, line, rel, &sp);
}

rad_scene *harness_grey_load_at(const char *file, int line, const char *rel, double rho)
{
    rad_scene_params sp;
    rad_scene_params_default(&sp);
    sp.has_rho = 1;
    sp.no_cross_check = 1;
    sp.rho[0] = sp.rho[1] = sp.rho[2] = rho;
    return harness_scene_load_at(file, line, rel, &sp);
}

const char *harness_header(const char *out, const char *key, char *buf, size_t size)
{
    char pattern[128];
    snprintf(pattern, sizeof pattern, "\n# %s = ", key);
    const char *p = out ? strstr(out, pattern) : NULL;
    if (!p || size == 0)
        return NULL;
    p += strlen(pattern);
    size_t len = strcspn(p, "\n");
    if (len >= size)
        len = size - 1;
    memcpy(buf, p, len);
    buf[len] = '\0';
    return buf;
}

double harness_header_number(const char *out, const char *key)
{
    char buf[64];
    return harness_header(out, key, buf, sizeof buf) ? atof(buf) : NAN;
}

void harness_expect_usage_error_at(const char *file, int line, const char *command,
                                   const char *const args[], const char *needle)
{
    char *out, *err;
    int code = harness_radkit_run(command, args, &out, &err);
    const char *first = args && args[0] ? args[0] : "(no arguments)";
    if (code != 2)
        harness_fail(file, line, "%s %s: exit %d, want 2", command ? command : "", first, code);
    if (strcmp(out, "") != 0)
        harness_fail(file, line, "%s %s: stdout not empty", command ? command : "", first);
    if (harness_count_lines(err) != 1 || strncmp(err, "radkit: ", 8) != 0)
        harness_fail(file, line, "%s %s: stderr is not one 'radkit: ' line: %s", command ? command : "",
                     first, err);
    if (!strstr(err, needle))
        harness_fail(file, line, "stderr '%s' does not name '%s'", err, needle);
    free(out);
    free(err);
}

/* Emitter z = 0 (up), receiver z = 1 (down), both [0,1]^2; the occluder is
 * [0.25,0.75]^2 at z = 0.5.  A segment between the plates crosses z = 0.5 at
 * its midpoint, so it is blocked exactly when the midpoint lies in the
 * occluder.  F = int int [unblocked] cos cos / (pi r^2) = int int 1/(pi r^4),
 * estimated with a fixed-seed generator. */
double harness_occluder_form_factor_mc(long samples)
{
    unsigned long long state = 0x9e3779b97f4a7c15ull;
    double sum = 0.0;
    for (long s = 0; s < samples; s++) {
        double u[4];
        for (int k = 0; k < 4; k++) {
            state = state * 6364136223846793005ull + 1442695040888963407ull;
            u[k] = (double)(state >> 11) * (1.0 / 9007199254740992.0);
        }
        double mx = 0.5 * (u[0] + u[2]), my = 0.5 * (u[1] + u[3]);
        if (mx > 0.25 && mx < 0.75 && my > 0.25 && my < 0.75)
            continue;
        double dx = u[2] - u[0], dy = u[3] - u[1], r2 = dx * dx + dy * dy + 1.0;
        sum += 1.0 / (RAD_PI * r2 * r2);
    }
    return sum / samples;
}

/* Rows of the table: face, area, B_r, B_g, B_b (and se_r, se_g, se_b when
 * se is not NULL).  Returns the row count. */
int harness_face_table_se(const char *out, double *B, double *se, int max)
{
    const char *p = strstr(out, "\nface\tarea\tB_r\tB_g\tB_b");
    if (!p)
        return -1;
    const char *header_end = strchr(p + 1, '\n');
    if (!header_end)
        return -1;
    static const char se_header[] = "face\tarea\tB_r\tB_g\tB_b\tse_r\tse_g\tse_b\n";
    int has_se = strncmp(p + 1, se_header, sizeof se_header - 1) == 0;
    if (se && !has_se)
        return -1;
    p = header_end + 1;
    int rows = 0;
    while (*p && rows < max) {
        int f, used = 0;
        double a, v[6];
        if (sscanf(p, "%d\t%lf\t%lf\t%lf\t%lf%n", &f, &a, &v[0], &v[1], &v[2], &used) != 5 ||
            f != rows)
            return -1;
        if (has_se && sscanf(p + used, "\t%lf\t%lf\t%lf", &v[3], &v[4], &v[5]) != 3)
            return -1;
        for (int c = 0; c < 3; c++) {
            B[3 * rows + c] = v[c];
            if (se)
                se[3 * rows + c] = v[3 + c];
        }
        rows++;
        p = strchr(p, '\n');
        if (!p)
            break;
        p++;
    }
    return rows;
}

int harness_face_table(const char *out, double *B, int max)
{
    return harness_face_table_se(out, B, NULL, max);
}

double harness_howell_c11(double a, double b, double c)
{
    double X = a / c, Y = b / c, sx = sqrt(1 + X * X), sy = sqrt(1 + Y * Y);
    return 2.0 / (RAD_PI * X * Y) *
           (log(sqrt((1 + X * X) * (1 + Y * Y) / (1 + X * X + Y * Y))) + X * sy * atan(X / sy) +
            Y * sx * atan(Y / sx) - X * atan(X) - Y * atan(Y));
}

double harness_howell_c14(double l, double w, double h)
{
    double H = h / l, W = w / l, H2 = H * H, W2 = W * W, S = sqrt(H2 + W2);
    double lg = log((1 + W2) * (1 + H2) / (1 + W2 + H2)) +
                W2 * log(W2 * (1 + W2 + H2) / ((1 + W2) * (W2 + H2))) +
                H2 * log(H2 * (1 + H2 + W2) / ((1 + H2) * (H2 + W2)));
    return (W * atan(1 / W) + H * atan(1 / H) - S * atan(1 / S) + 0.25 * lg) / (RAD_PI * W);
}

int main(int argc, char **argv)
{
    int passed = 0, failed = 0;
    /* a name selects its test: two tests of one name would run and report as one */
    for (int t = 0; t < test_count; t++)
        for (int u = t + 1; u < test_count; u++)
            if (strcmp(tests[t].name, tests[u].name) == 0) {
                printf("FAIL two tests named %s (%s, %s)\n", tests[t].name, tests[t].file,
                       tests[u].file);
                failed++;
            }
    for (int t = 0; t < test_count; t++) {
        int selected = argc < 2;
        for (int a = 1; a < argc; a++)
            selected |= strstr(tests[t].name, argv[a]) != NULL;
        if (!selected)
            continue;
        current_failures = 0;
        tests[t].fn();
        if (current_failures == 0) {
            passed++;
            printf("PASS %s\n", tests[t].name);
        } else {
            failed++;
            printf("FAIL %s (%s)\n", tests[t].name, tests[t].file);
        }
        fflush(stdout);
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 && passed > 0 ? 0 : 1;
}

int harness_checkerboard(int n, double origin, double side, double (*lo)[2])
{
    int count = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            if ((i + j) % 2 == 0) {
                lo[count][0] = origin + i * side;
                lo[count][1] = origin + j * side;
                count++;
            }
    return count;
}
