/* A deterministic mutation fuzzer over radkit's scene formats and options.
 *
 * Each case takes a seed scene from scenes/ (OBJ with its MTL, OFF, PLY ascii
 * and binary, STL, glTF, MGF with its include), applies one to four mutations to one of its files
 * (bit flips, hostile bytes, deleted, duplicated or swapped chunks and lines,
 * numbers replaced by hostile tokens, truncation, and for OBJ and MTL whole
 * statements real files carry: unused, unusual or borderline ones), sometimes adds a hostile
 * option value, and runs `radkit info` or `radkit solve` (dense, hier or mc)
 * on it with a time limit.  Every outcome is classified:
 *   clean    exit 0, and for solve a table whose every B is finite and >= 0;
 *   refused  exit 1 or 2 with a "radkit: " message on stderr;
 *   defect   anything else: a signal, the time limit, a sanitizer report,
 *            another exit status, a refusal without a message, or exit 0
 *            with a missing table or a negative or non-finite radiosity.
 * A defect fails the test; its input is kept (the path is printed) so that the
 * case can be rerun by hand.  The case sequence depends only on the seed:
 * FUZZ_CASES (default 200: the short run of make test), FUZZ_SEED (default 1)
 * and FUZZ_TIMEOUT (seconds per case, default 60) choose the run; `make fuzz`
 * runs 5000 cases. */
#include "harness.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

typedef struct fuzz_seed {
    const char *main;  /* the scene file, relative to the source tree */
    const char *extra; /* a file beside it (the MTL), or NULL */
} fuzz_seed;

static const fuzz_seed seeds[] = {
    {"scenes/cornell/cornell.obj", "scenes/cornell/cornell.mtl"},
    {"scenes/furnace_cube/cube.obj", "scenes/furnace_cube/cube.mtl"},
    {"scenes/occluder/occluder.obj", "scenes/occluder/occluder.mtl"},
    {"scenes/tetrahedron/tetrahedron.obj", "scenes/tetrahedron/tetrahedron.mtl"},
    {"scenes/furnace_room/room_box.obj", "scenes/furnace_room/room.mtl"},
    {"scenes/lenient/ignored.obj", "scenes/lenient/ignored.mtl"},
    {"scenes/lenient/nonconvex_polygon.obj", NULL},
    {"scenes/formats/cube_mixed.off", NULL},
    {"scenes/formats/l_shape.off", NULL},
    {"scenes/formats/tetra.off", NULL},
    {"scenes/formats/quad_tri.ply", NULL},
    {"scenes/formats/tristrips.ply", NULL},
    {"scenes/formats/rectangle.stl", NULL},
    {"scenes/formats/two_triangles.gltf", NULL},
    {"scenes/mgf/cornell.mgf", "scenes/mgf/cornell_blocks.mgf"},
};
enum { NSEEDS = sizeof seeds / sizeof seeds[0] };

/* Hostile replacements for a number. */
static const char *const tokens[] = {
    "nan", "inf", "-inf", "-1", "0", "1e308", "-1e308", "1e-320", "99999999999",
    "4294967296", "2147483647", "-2147483648", "0x10", "1.5", "1e999", "", "-0", "1e",
    "18446744073709551616", "3", "100000000"};
enum { NTOKENS = sizeof tokens / sizeof tokens[0] };

/* Hostile option values: each refused with a message or harmless. */
typedef struct fuzz_option {
    const char *name;
    const char *values[8];
} fuzz_option;

static const fuzz_option options[] = {
    {"--rho", {"1", "0.99999999", "-0.1", "nan", "1e308", "0.5 0.5", "abc", ""}},
    {"--emission", {"-1", "inf", "1e308", "0 0 0", "1 2", "nan", "1e-320", "x"}},
    {"--scale", {"0", "-1", "1e308", "1e-308", "nan", "inf", "1e-3", "z"}},
    {"--eps", {"0", "-1", "nan", "abc", "inf", "", "1e300", "2"}},
    {"--refine", {"-1", "99", "1.5", "x", "", "40", "2147483648", "0"}},
    {"--samples", {"0", "1", "-5", "1e99", "x", "", "2", "18446744073709551617"}},
    {"--threads", {"0", "-1", "x", "", "1.5", "99999999999", "1", "2"}},
    {"--min-area", {"-1", "nan", "inf", "x", "", "1e300", "0", "-0"}},
    {"--tol", {"0", "-1", "nan", "2", "x", "", "1e-300", "inf"}},
    {"--max-iter", {"0", "-1", "x", "", "1.5", "99999999999", "1", "2"}},
    {"--basis", {"p3", "x", "", "p1", "P1", "p0", "-1", "p1 "}},
};
enum { NOPTIONS = sizeof options / sizeof options[0] };

typedef struct rng {
    unsigned long long s;
} rng;

static unsigned long long next(rng *r)
{
    /* splitmix64: every case seeds its own generator */
    unsigned long long z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static size_t below(rng *r, size_t n)
{
    return n ? (size_t)(next(r) % n) : 0;
}

typedef struct buffer {
    char *p;
    size_t n, cap;
} buffer;

static int reserve(buffer *b, size_t n)
{
    if (n <= b->cap)
        return 1;
    size_t cap = b->cap ? b->cap : 256;
    while (cap < n)
        cap *= 2;
    char *p = realloc(b->p, cap);
    if (!p)
        return 0;
    b->p = p;
    b->cap = cap;
    return 1;
}

/* Replace b[at, at + len) by s[0, slen). */
static int splice(buffer *b, size_t at, size_t len, const char *s, size_t slen)
{
    if (at > b->n)
        at = b->n;
    if (len > b->n - at)
        len = b->n - at;
    if (!reserve(b, b->n - len + slen + 1))
        return 0;
    memmove(b->p + at + slen, b->p + at + len, b->n - at - len);
    memcpy(b->p + at, s, slen);
    b->n = b->n - len + slen;
    return 1;
}

/* The start of the line holding position at, and the start of the next. */
static void line_around(const buffer *b, size_t at, size_t *start, size_t *end)
{
    size_t s = at < b->n ? at : b->n;
    while (s > 0 && b->p[s - 1] != '\n')
        s--;
    size_t e = at;
    while (e < b->n && b->p[e] != '\n')
        e++;
    *start = s;
    *end = e < b->n ? e + 1 : e;
}

/* Statements real OBJ and MTL files carry that change nothing or little:
 * inserted whole, they keep a file valid but unusual. */
static const char *const unusual_lines[] = {
    "t 1 2 3\n", "vp 0.5 0.5\n", "curv 0 1 1 2\n", "o part\n", "s off\n", "g\n",
    "# a comment\n", "usemtl not_defined\n", "mtllib missing.mtl\n", "f 1 2 3 4\n",
    "v 1e-300 0 0\n", "vt 0.5 0.5\n", "vn 0 0 1\n", "l 1 2\n", "p 1\n", "cstype bezier\n",
    "Kd 1 1 1\n", "Ke 1e30 0 0\n", "Ni 1.5\n", "map_Kd -bm 0.5 -o 1 1 1 tex.png\n",
    "illum 2\n", "newmtl extra\n", "Tf 1 1 1\n", "Kd 0.999999 0.5 0.5\n", "f 1 1 1\n",
    "f -1 -2 -3\n", "f 1/1/1 2/2/2 3/3/3\n", "\\\n", "\r\n", "\n\n\n"};
enum { NUNUSUAL = sizeof unusual_lines / sizeof unusual_lines[0] };

static const char hostile_bytes[] = {'\0', '\n', '-', '9', '.', 'e', ' ', '/', '#', '\xff', '\r', '\t'};

/* One mutation of b; text (OBJ, MTL) may also get an unusual line. */
static int mutate(rng *r, buffer *b, int text)
{
    if (b->n == 0)
        return splice(b, 0, 0, "f 1 2 3\n", 8);
    size_t at = below(r, b->n);
    if (text && below(r, 3) == 0) {
        size_t s, e;
        line_around(b, at, &s, &e);
        const char *l = unusual_lines[below(r, NUNUSUAL)];
        return splice(b, e, 0, l, strlen(l));
    }
    switch (below(r, 8)) {
    case 0: /* bit flips */
        for (size_t k = 1 + below(r, 4); k > 0; k--)
            b->p[below(r, b->n)] ^= (char)(1u << below(r, 8));
        return 1;
    case 1: /* a hostile byte */
        b->p[at] = hostile_bytes[below(r, sizeof hostile_bytes)];
        return 1;
    case 2: { /* delete a chunk */
        size_t len = 1 + below(r, 64);
        return splice(b, at, len, "", 0);
    }
    case 3: { /* duplicate a chunk */
        size_t len = 1 + below(r, 64);
        if (len > b->n - at)
            len = b->n - at;
        char tmp[64];
        memcpy(tmp, b->p + at, len);
        return splice(b, below(r, b->n + 1), 0, tmp, len);
    }
    case 4: { /* a number becomes a hostile token */
        size_t s = at;
        while (s < b->n && !(b->p[s] >= '0' && b->p[s] <= '9'))
            s++;
        if (s == b->n)
            return 1;
        while (s > 0 && (strchr("0123456789.eE+-", b->p[s - 1]) != NULL))
            s--;
        size_t e = s;
        while (e < b->n && strchr("0123456789.eE+-", b->p[e]) != NULL)
            e++;
        const char *t = tokens[below(r, NTOKENS)];
        return splice(b, s, e - s, t, strlen(t));
    }
    case 5: /* truncate */
        b->n = at;
        return 1;
    case 6: { /* repeat a line */
        size_t s, e;
        line_around(b, at, &s, &e);
        size_t len = e - s, times = 1 + below(r, 100);
        if (len == 0 || len > 4096)
            return 1;
        char *line = malloc(len);
        if (!line)
            return 0;
        memcpy(line, b->p + s, len);
        int ok = 1;
        for (size_t k = 0; k < times && ok; k++)
            ok = splice(b, e, 0, line, len);
        free(line);
        return ok;
    }
    default: { /* swap a line with another */
        size_t s1, e1, s2, e2;
        line_around(b, at, &s1, &e1);
        line_around(b, below(r, b->n), &s2, &e2);
        if (s2 < s1) {
            size_t t = s1;
            s1 = s2;
            s2 = t;
            t = e1;
            e1 = e2;
            e2 = t;
        }
        if (e1 > s2 || e1 - s1 > 4096 || e2 - s2 > 4096)
            return 1;
        char a[4096], c[4096];
        size_t la = e1 - s1, lc = e2 - s2;
        memcpy(a, b->p + s1, la);
        memcpy(c, b->p + s2, lc);
        return splice(b, s2, lc, a, la) && splice(b, s1, la, c, lc);
    }
    }
}

static int read_whole(const char *path, buffer *b)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return 0;
    b->n = 0;
    char chunk[65536];
    size_t got;
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0)
        if (!splice(b, b->n, 0, chunk, got)) {
            fclose(f);
            return 0;
        }
    int ok = !ferror(f);
    fclose(f);
    return ok;
}

static int write_whole(const char *path, const buffer *b)
{
    FILE *f = fopen(path, "wb");
    if (!f)
        return 0;
    int ok = fwrite(b->p ? b->p : "", 1, b->n, f) == b->n;
    return fclose(f) == 0 && ok;
}

static const char *base_name(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}

/* Run argv with stdin from /dev/null, stdout and stderr to files in dir, and
 * a time limit (an alarm survives exec: the child dies of SIGALRM).  Returns
 * the wait status; *out and *err receive the outputs (free them). */
static int run_limited(const char *const argv[], const char *dir, unsigned seconds, char **out,
                       char **err)
{
    char out_path[1024], err_path[1024];
    snprintf(out_path, sizeof out_path, "%s/stdout", dir);
    snprintf(err_path, sizeof err_path, "%s/stderr", dir);
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid == 0) {
        int in = open("/dev/null", O_RDONLY);
        int fo = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
        int fe = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
        if (in < 0 || fo < 0 || fe < 0)
            _exit(126);
        dup2(in, 0);
        dup2(fo, 1);
        dup2(fe, 2);
        if (chdir(dir) != 0)
            _exit(126);
        alarm(seconds);
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    int status = 0;
    if (pid < 0 || waitpid(pid, &status, 0) != pid)
        status = -1;
    *out = harness_read_file(out_path);
    *err = harness_read_file(err_path);
    return status;
}

typedef enum outcome { CLEAN, REFUSED, DEFECT } outcome;

/* Classify a finished run; why receives the reason of a defect. */
static outcome classify(int status, int is_solve, const char *out, const char *err, char *why,
                        size_t size)
{
    if (status == -1) {
        snprintf(why, size, "could not run");
        return DEFECT;
    }
    if (WIFSIGNALED(status)) {
        int sig = WTERMSIG(status);
        snprintf(why, size, sig == SIGALRM ? "time limit" : "signal %d", sig);
        return DEFECT;
    }
    int code = WEXITSTATUS(status);
    if (err && (strstr(err, "Sanitizer") || strstr(err, "runtime error:"))) {
        snprintf(why, size, "sanitizer report (exit %d)", code);
        return DEFECT;
    }
    if (code == 1 || code == 2) {
        /* warnings may precede it: the last line must be radkit's message */
        const char *last = err, *p = err;
        while (p && *p) {
            const char *nl = strchr(p, '\n');
            if (!nl)
                break;
            if (nl[1] != '\0')
                last = nl + 1;
            p = nl + 1;
        }
        if (!last || strncmp(last, "radkit: ", 8) != 0 || last[8] == '\n' || last[8] == '\0') {
            snprintf(why, size, "exit %d without a message", code);
            return DEFECT;
        }
        return REFUSED;
    }
    if (code != 0) {
        snprintf(why, size, "exit %d", code);
        return DEFECT;
    }
    if (!is_solve)
        return CLEAN;
    int cap = 1 << 20;
    double *B = malloc((size_t)cap * 3 * sizeof *B);
    int rows = B ? harness_face_table(out, B, cap) : -1;
    outcome o = CLEAN;
    if (rows <= 0) {
        snprintf(why, size, "exit 0 without a table");
        o = DEFECT;
    }
    for (int i = 0; o == CLEAN && i < rows * 3; i++)
        if (!(B[i] >= 0.0) || !isfinite(B[i])) {
            snprintf(why, size, "exit 0 with B = %g (face %d)", B[i], i / 3);
            o = DEFECT;
        }
    free(B);
    return o;
}

static unsigned env_unsigned(const char *name, unsigned fallback)
{
    const char *v = getenv(name);
    if (!v || !*v)
        return fallback;
    char *end;
    unsigned long x = strtoul(v, &end, 10);
    return *end == '\0' && x > 0 && x < 100000000ul ? (unsigned)x : fallback;
}

static void remove_dir(const char *dir, const char *const names[], int n)
{
    char path[1024];
    for (int k = 0; k < n; k++) {
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        unlink(path);
    }
    rmdir(dir);
}

TEST(fuzz_scenes_and_options)
{
    unsigned cases = env_unsigned("FUZZ_CASES", 200), seed = env_unsigned("FUZZ_SEED", 1);
    unsigned limit = env_unsigned("FUZZ_TIMEOUT", 60);
    static const char *const commands[][4] = {
        {"info", NULL, NULL, NULL},
        {"solve", "--quiet", NULL, NULL},
        {"solve", "--quiet", "--method", "hier"},
        {"solve", "--quiet", "--method", "mc"},
    };
    unsigned counts[3] = {0, 0, 0};
    buffer main_buf = {0}, extra_buf = {0};
    for (unsigned c = 0; c < cases; c++) {
        rng r = {((unsigned long long)seed << 32) ^ (c * 0x2545f4914f6cdd1dull)};
        const fuzz_seed *sd = &seeds[below(&r, NSEEDS)];
        if (!read_whole(harness_path(sd->main), &main_buf) ||
            (sd->extra && !read_whole(harness_path(sd->extra), &extra_buf))) {
            harness_fail(__FILE__, __LINE__, "fuzz: cannot read seed %s", sd->main);
            break;
        }
        int on_extra = sd->extra && below(&r, 3) == 0;
        buffer *target = on_extra ? &extra_buf : &main_buf;
        const char *name = on_extra ? sd->extra : sd->main;
        size_t nlen = strlen(name);
        int text = nlen > 4 &&
                   (strcmp(name + nlen - 4, ".obj") == 0 || strcmp(name + nlen - 4, ".mtl") == 0);
        int ok = 1;
        for (size_t k = 1 + below(&r, 4); k > 0 && ok; k--)
            ok = mutate(&r, target, text);
        char dir[] = "/tmp/radkit-fuzz-XXXXXX";
        if (!ok || !mkdtemp(dir)) {
            harness_fail(__FILE__, __LINE__, "fuzz: out of memory or no temporary directory");
            break;
        }
        char main_path[1024], extra_path[1024];
        snprintf(main_path, sizeof main_path, "%s/%s", dir, base_name(sd->main));
        snprintf(extra_path, sizeof extra_path, "%s/%s", dir, sd->extra ? base_name(sd->extra) : "-");
        if (!write_whole(main_path, &main_buf) || (sd->extra && !write_whole(extra_path, &extra_buf))) {
            harness_fail(__FILE__, __LINE__, "fuzz: cannot write into %s", dir);
            break;
        }
        const char *const *cmd = commands[below(&r, 4)];
        const char *argv[16];
        int a = 0;
        argv[a++] = harness_radkit();
        for (int k = 0; k < 4 && cmd[k]; k++)
            argv[a++] = cmd[k];
        argv[a++] = main_path;
        int is_solve = strcmp(cmd[0], "solve") == 0;
        if (is_solve && cmd[2] && strcmp(cmd[3], "mc") == 0) {
            argv[a++] = "--samples";
            argv[a++] = "64";
        }
        if (below(&r, 4) == 0) {
            const fuzz_option *o = &options[below(&r, NOPTIONS)];
            argv[a++] = o->name;
            argv[a++] = o->values[below(&r, 8)];
        }
        argv[a] = NULL;
        char *out = NULL, *err = NULL, why[128] = "";
        int status = run_limited(argv, dir, limit, &out, &err);
        outcome o = classify(status, is_solve, out, err, why, sizeof why);
        counts[o]++;
        const char *const names[] = {base_name(sd->main), sd->extra ? base_name(sd->extra) : "-",
                                     "stdout", "stderr"};
        if (o == DEFECT) {
            char line[1024];
            int len = snprintf(line, sizeof line, "%s", argv[1]);
            for (int k = 2; k < a && len < (int)sizeof line; k++)
                len += snprintf(line + len, sizeof line - (size_t)len, " '%s'", argv[k]);
            harness_fail(__FILE__, __LINE__, "fuzz case %u (seed %u, %s): %s: radkit %s (kept in %s)%s%.300s",
                         c, seed, sd->main, why, line, dir, err && *err ? "; stderr: " : "",
                         err ? err : "");
        } else {
            remove_dir(dir, names, 4);
        }
        free(out);
        free(err);
    }
    free(main_buf.p);
    free(extra_buf.p);
    printf("fuzz: %u cases (seed %u): %u clean, %u refused with a message, %u defects\n", cases, seed,
           counts[CLEAN], counts[REFUSED], counts[DEFECT]);
}
