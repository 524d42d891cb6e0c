/* rad_io: every writer's output is parsed back here, by parsers written for
 * the test (TSV, PLY ASCII and binary, JSON, .dat). */
#include <ctype.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "rad_io.h"

static char *tmp_path(const char *name)
{
    static char buf[4][256];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "/tmp/radkit_test_io_%d_%s", (int)getpid(), name);
    return buf[k];
}

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    size_t got = fread(s, 1, (size_t)n, f);
    s[got] = 0;
    fclose(f);
    if (len)
        *len = got;
    return s;
}

TEST(io_faces_tsv_round_trips)
{
    enum { N = 5 };
    double area[N] = {0.125, 2.385, 1e-7, 3.0, 1.0 / 3.0}, B[3 * N];
    for (int k = 0; k < 3 * N; k++)
        B[k] = 1.0 / (k + 0.7) + (k == 4 ? 1e300 : 0.0);
    rad_io_kv hdr[2] = {{"scene", "cornell box.obj"}, {"rule", "auto"}};
    const char *path = tmp_path("faces.tsv");
    CHECK(rad_io_write_faces_tsv(path, N, area, B, hdr, 2) == RAD_OK);
    char *s = slurp(path, NULL);
    CHECK(s != NULL);
    if (!s)
        return;
    CHECK(strstr(s, "# scene = cornell box.obj\n") != NULL);
    char *line = strtok(s, "\n");
    int comments = 0, header = 0, rows = 0;
    for (; line; line = strtok(NULL, "\n")) {
        if (line[0] == '#') {
            comments++;
            CHECK(!header); /* comments come first */
            continue;
        }
        if (!header) {
            CHECK(strcmp(line, "face\tarea\tB_r\tB_g\tB_b") == 0);
            header = 1;
            continue;
        }
        char *end;
        long face = strtol(line, &end, 10);
        CHECK(face == rows && *end == '\t');
        double a = strtod(end + 1, &end), v[3];
        for (int c = 0; c < 3; c++)
            v[c] = strtod(end + 1, &end);
        CHECK(*end == 0);
        CHECK(a == area[rows]);
        for (int c = 0; c < 3; c++)
            CHECK(v[c] == B[rows + c * N]); /* %.17g reads back exactly */
        rows++;
    }
    CHECK(comments == 3 && header && rows == N);
    free(s);
    remove(path);
    CHECK(rad_io_write_faces_tsv("/nonexistent-dir/x.tsv", N, area, B, NULL, 0) == RAD_EINVAL); /* a missing directory: a usage error */
    CHECK(strstr(rad_error_message(), "/nonexistent-dir/x.tsv") != NULL);
}

/* Two triangles sharing an edge: vertices 0..3, faces (0,1,2) area 0.5 and
 * (0,2,3) area 1.5 (vertex 3 is pulled out to triple the second's area). */
static const double quad_xyz[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, -2, 1, 0};
static const int quad_tri[6] = {0, 1, 2, 0, 2, 3};

TEST(io_vertex_values_are_area_weighted_and_tone_mapped)
{
    double B[6] = {0.2, 0.6, 0.4, 0.8, 0.1, 0.1}, vb[12];
    CHECK(rad_io_vertex_values(4, quad_xyz, 2, quad_tri, B, vb) == RAD_OK);
    /* Shared vertices 0 and 2: (0.5 * 0.2 + 1.5 * 0.6) / 2 = 0.5 in red. */
    CHECK_NEAR(vb[0], 0.5, 1e-15, 0.0);
    CHECK_NEAR(vb[3 * 2 + 1], (0.5 * 0.4 + 1.5 * 0.8) / 2.0, 1e-15, 0.0);
    CHECK_NEAR(vb[3 * 1 + 0], 0.2, 1e-15, 0.0);
    CHECK_NEAR(vb[3 * 3 + 2], 0.1, 1e-15, 0.0);
    rad_io_tonemap tm;
    rad_io_tonemap_default(&tm);
    CHECK(rad_io_tonemap_apply(&tm, 0.0) == 0);
    CHECK(rad_io_tonemap_apply(&tm, -3.0) == 0);
    CHECK(rad_io_tonemap_apply(&tm, NAN) == 0);
    CHECK(rad_io_tonemap_apply(&tm, 1.0) == 255);
    CHECK(rad_io_tonemap_apply(&tm, 7.0) == 255);
    /* 0.25^(1/2.2) = exp(ln 0.25 / 2.2) = 0.5325...: 255 * that = 135.79 -> 136. */
    CHECK(rad_io_tonemap_apply(&tm, 0.25) == 136);
    tm.exposure = 0.5;
    CHECK(rad_io_tonemap_apply(&tm, 0.5) == 136);
    double vals[5] = {0.0, 4.0, 1.0, 2.0, 3.0};
    CHECK_NEAR(rad_io_tonemap_auto_exposure(5, vals, 1.0), 0.25, 0, 0);
    CHECK_NEAR(rad_io_tonemap_auto_exposure(5, vals, 0.5), 1.0 / 2.0, 0, 0); /* of 1,2,3,4 */
    CHECK_NEAR(rad_io_tonemap_auto_exposure(1, vals, 0.9), 1.0, 0, 0);
}

/* A PLY reader for what the writer produces: header lines, then vertices and faces. */
static int read_ply(const char *path, float *xyz, unsigned char *rgb, int *tri, int *nv, int *nt)
{
    size_t len;
    char *s = slurp(path, &len);
    if (!s)
        return 0;
    char *end = strstr(s, "end_header\n");
    if (!end) {
        free(s);
        return 0;
    }
    int binary = strstr(s, "format binary_little_endian 1.0\n") != NULL;
    char *p = strstr(s, "element vertex ");
    *nv = p ? atoi(p + 15) : -1;
    p = strstr(s, "element face ");
    *nt = p ? atoi(p + 13) : -1;
    const unsigned char *d = (const unsigned char *)end + 11;
    if (binary) {
        for (int v = 0; v < *nv; v++) {
            for (int c = 0; c < 3; c++) {
                uint32_t u = (uint32_t)d[0] | (uint32_t)d[1] << 8 | (uint32_t)d[2] << 16 | (uint32_t)d[3] << 24;
                memcpy(&xyz[3 * v + c], &u, 4);
                d += 4;
            }
            for (int c = 0; c < 3; c++)
                rgb[3 * v + c] = *d++;
        }
        for (int t = 0; t < *nt; t++) {
            if (*d++ != 3) {
                free(s);
                return 0;
            }
            for (int k = 0; k < 3; k++, d += 4)
                tri[3 * t + k] = (int)((uint32_t)d[0] | (uint32_t)d[1] << 8 | (uint32_t)d[2] << 16 | (uint32_t)d[3] << 24);
        }
        int ok = (size_t)((const char *)d - s) == len;
        free(s);
        return ok;
    }
    char *q = end + 11;
    for (int v = 0; v < *nv; v++) {
        unsigned r, g, b;
        int used = 0;
        if (sscanf(q, "%f %f %f %u %u %u\n%n", &xyz[3 * v], &xyz[3 * v + 1], &xyz[3 * v + 2], &r, &g, &b, &used) != 6) {
            free(s);
            return 0;
        }
        rgb[3 * v] = (unsigned char)r;
        rgb[3 * v + 1] = (unsigned char)g;
        rgb[3 * v + 2] = (unsigned char)b;
        q += used;
    }
    for (int t = 0; t < *nt; t++) {
        int three, used = 0;
        if (sscanf(q, "%d %d %d %d\n%n", &three, &tri[3 * t], &tri[3 * t + 1], &tri[3 * t + 2], &used) != 4 || three != 3) {
            free(s);
            return 0;
        }
        q += used;
    }
    int ok = *q == 0;
    free(s);
    return ok;
}

TEST(io_ply_ascii_and_binary_round_trip)
{
    double B[6] = {0.2, 0.6, 0.4, 0.8, 0.1, 0.1};
    rad_io_tonemap tm = {1.7, 2.2};
    for (int binary = 0; binary < 2; binary++) {
        const char *path = tmp_path(binary ? "b.ply" : "a.ply");
        CHECK(rad_io_write_ply(path, 4, quad_xyz, 2, quad_tri, B, &tm, binary) == RAD_OK);
        float xyz[12];
        unsigned char rgb[12];
        int tri[6], nv = 0, nt = 0;
        CHECK_MSG(read_ply(path, xyz, rgb, tri, &nv, &nt), "cannot parse %s", path);
        CHECK(nv == 4 && nt == 2);
        for (int k = 0; k < 12; k++)
            CHECK(xyz[k] == (float)quad_xyz[k]);
        for (int k = 0; k < 6; k++)
            CHECK(tri[k] == quad_tri[k]);
        /* vertex 0 red: 0.5 (area-weighted) -> (1.7 * 0.5)^(1/2.2) * 255 */
        CHECK(rgb[0] == (unsigned char)lround(255.0 * pow(0.85, 1.0 / 2.2)));
        CHECK(rgb[3 * 1 + 1] == (unsigned char)lround(255.0 * pow(1.7 * 0.4, 1.0 / 2.2)));
        remove(path);
    }
}

/* ---- a JSON parser for the test: flattens objects to "a.b.c" = text ------- */

typedef struct jitem {
    char key[128];
    char val[256];
    int is_string;
} jitem;

typedef struct jparse {
    const char *p;
    jitem items[64];
    int n;
    int ok;
} jparse;

static void ws(jparse *j)
{
    while (isspace((unsigned char)*j->p))
        j->p++;
}

static int parse_string(jparse *j, char *out, size_t cap)
{
    if (*j->p != '"')
        return 0;
    j->p++;
    size_t k = 0;
    while (*j->p && *j->p != '"') {
        char c = *j->p++;
        if (c == '\\') {
            char e = *j->p++;
            if (e == 'n') c = '\n';
            else if (e == 't') c = '\t';
            else if (e == 'r') c = '\r';
            else if (e == '"' || e == '\\' || e == '/') c = e;
            else if (e == 'u') {
                unsigned u = 0;
                if (sscanf(j->p, "%4x", &u) != 1 || u > 0x7f)
                    return 0;
                j->p += 4;
                c = (char)u;
            } else
                return 0;
        } else if ((unsigned char)c < 0x20) {
            return 0; /* raw control characters are not JSON */
        }
        if (k + 1 < cap)
            out[k++] = c;
    }
    out[k] = 0;
    if (*j->p != '"')
        return 0;
    j->p++;
    return 1;
}

static int parse_value(jparse *j, const char *path);

static int parse_object(jparse *j, const char *path)
{
    if (*j->p != '{')
        return 0;
    j->p++;
    ws(j);
    if (*j->p == '}') {
        j->p++;
        return 1;
    }
    for (;;) {
        char key[128], sub[128];
        ws(j);
        if (!parse_string(j, key, sizeof key))
            return 0;
        ws(j);
        if (*j->p++ != ':')
            return 0;
        ws(j);
        int w = snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "." : "", key);
        if (w < 0 || (size_t)w >= sizeof sub)
            return 0;
        if (!parse_value(j, sub))
            return 0;
        ws(j);
        if (*j->p == ',') {
            j->p++;
            continue;
        }
        if (*j->p == '}') {
            j->p++;
            return 1;
        }
        return 0;
    }
}

static int parse_value(jparse *j, const char *path)
{
    if (*j->p == '{')
        return parse_object(j, path);
    if (j->n >= 64)
        return 0;
    jitem *it = &j->items[j->n++];
    int w = snprintf(it->key, sizeof it->key, "%s", path);
    if (w < 0 || (size_t)w >= sizeof it->key)
        return 0;
    if (*j->p == '"') {
        it->is_string = 1;
        return parse_string(j, it->val, sizeof it->val);
    }
    /* a JSON number: -?digits(.digits)?([eE][+-]?digits)? */
    const char *s = j->p;
    if (*j->p == '-')
        j->p++;
    if (!isdigit((unsigned char)*j->p))
        return 0;
    while (isdigit((unsigned char)*j->p))
        j->p++;
    if (*j->p == '.') {
        j->p++;
        if (!isdigit((unsigned char)*j->p))
            return 0;
        while (isdigit((unsigned char)*j->p))
            j->p++;
    }
    if (*j->p == 'e' || *j->p == 'E') {
        j->p++;
        if (*j->p == '+' || *j->p == '-')
            j->p++;
        if (!isdigit((unsigned char)*j->p))
            return 0;
        while (isdigit((unsigned char)*j->p))
            j->p++;
    }
    snprintf(it->val, sizeof it->val, "%.*s", (int)(j->p - s), s);
    return 1;
}

static const jitem *jfind(const jparse *j, const char *key)
{
    for (int k = 0; k < j->n; k++)
        if (strcmp(j->items[k].key, key) == 0)
            return &j->items[k];
    return NULL;
}

TEST(io_stats_json_has_the_design_keys_and_parses)
{
    rad_io_phase phases[2] = {{"assembly", 1.25}, {"solve", 0.0625}};
    rad_io_effect effects[2] = {{"occlusion", "off", "convex \"closed\" enclosure\n\tno blockers"},
                                {"colour", "grey", "all reflectances grey \x01"}};
    rad_io_figure details[2] = {{"links_partial", 17}, {"max_depth", 4}};
    rad_io_stats st = {"dense", 12, 48, 1128, 123456789012LL, 99, phases, 2, 1.3125,
                       1.5e8, effects, 2, "lu", 0, 3.5e-16, details, 2, 0, 0.0};
    const char *path = tmp_path("stats.json");
    CHECK(rad_io_write_stats_json(path, &st) == RAD_OK);
    char *s = slurp(path, NULL);
    CHECK(s != NULL);
    if (!s)
        return;
    static jparse j;
    memset(&j, 0, sizeof j);
    j.p = s;
    ws(&j);
    j.ok = parse_object(&j, "");
    ws(&j);
    CHECK_MSG(j.ok && *j.p == 0, "JSON does not parse near: %.40s", j.p);
    const char *keys[] = {"method", "faces", "elements", "links", "rays", "kernel_evals",
                          "time_s.assembly", "time_s.solve", "time_s.total", "memory_peak_bytes",
                          "effects.occlusion.value", "effects.occlusion.reason",
                          "effects.colour.value", "solver.name", "solver.iterations",
                          "solver.residual", "details.links_partial", "details.max_depth"};
    for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
        CHECK_MSG(jfind(&j, keys[k]) != NULL, "key %s missing", keys[k]);
    const jitem *it;
    if ((it = jfind(&j, "method")))
        CHECK(it->is_string && strcmp(it->val, "dense") == 0);
    if ((it = jfind(&j, "rays")))
        CHECK(strcmp(it->val, "123456789012") == 0);
    if ((it = jfind(&j, "time_s.total")))
        CHECK(strtod(it->val, NULL) == 1.3125);
    if ((it = jfind(&j, "solver.residual")))
        CHECK(strtod(it->val, NULL) == 3.5e-16);
    if ((it = jfind(&j, "effects.occlusion.reason")))
        CHECK(strcmp(it->val, "convex \"closed\" enclosure\n\tno blockers") == 0);
    if ((it = jfind(&j, "effects.colour.reason")))
        CHECK(strcmp(it->val, "all reflectances grey \x01") == 0);
    free(s);

    /* A non-finite number is refused, naming its key. */
    st.solver_residual = NAN;
    CHECK(rad_io_write_stats_json(path, &st) == RAD_ENUMERIC);
    CHECK(strstr(rad_error_message(), "residual") != NULL);
    remove(path);
}

TEST(io_json_emitter_checks_nesting)
{
    const char *path = tmp_path("nest.json");
    FILE *f = fopen(path, "w");
    rad_io_json j;
    rad_io_json_start(&j, f);
    rad_io_json_object(&j, "a");
    CHECK(rad_io_json_finish(&j) == RAD_EINVAL); /* "a" left open */
    fclose(f);
    f = fopen(path, "w");
    rad_io_json_start(&j, f);
    rad_io_json_object(&j, "a");
    rad_io_json_number(&j, "x", INFINITY);
    rad_io_json_end(&j);
    CHECK(rad_io_json_finish(&j) == RAD_ENUMERIC);
    CHECK(strstr(rad_error_message(), "'x'") != NULL);
    fclose(f);
    remove(path);
}

TEST(io_dat_header_and_rows)
{
    const char *cols[3] = {"n", "error", "seconds"};
    double data[6] = {16, 0.0123, 0.5, 64, 7.5e-4, 2.25};
    rad_io_kv hdr[1] = {{"rule", "gauss:4"}};
    const char *path = tmp_path("x.dat");
    CHECK(rad_io_write_dat(path, "accuracy vs time", hdr, 1, 3, cols, 2, data) == RAD_OK);
    char *s = slurp(path, NULL);
    if (!s)
        return;
    CHECK(strncmp(s, "# accuracy vs time\n# version = radkit ", 38) == 0);
    CHECK(strstr(s, "# rule = gauss:4\n# n\terror\tseconds\n") != NULL);
    const char *body = strstr(s, "seconds\n") + 8;
    double got[6];
    int k = 0;
    char *end = (char *)body;
    while (k < 6) {
        got[k] = strtod(end, &end);
        k++;
    }
    for (k = 0; k < 6; k++)
        CHECK(got[k] == data[k]);
    while (isspace((unsigned char)*end))
        end++;
    CHECK(*end == 0);
    free(s);
    remove(path);
}

/* Face averages by hand: face 0 has elements of area 0.5 and 1.5 with values
 * 2 and 6 (red): (0.5*2 + 1.5*6)/2 = 5; face 1 has one element (value 3.25);
 * face 2 has none and stays 0. */
TEST(io_face_averages_by_hand)
{
    int face_of[3] = {0, 1, 0};
    double area[3] = {0.5, 0.7, 1.5};
    double B[9] = {2, 3.25, 6, /* green */ 1, 0, 1, /* blue */ 0, 4, 8};
    double fa[3], fb[9];
    CHECK(rad_io_face_averages(3, face_of, area, B, 3, fa, fb) == RAD_OK);
    CHECK_NEAR(fa[0], 2.0, 1e-15, 0.0);
    CHECK_NEAR(fa[1], 0.7, 1e-15, 0.0);
    CHECK(fa[2] == 0.0);
    CHECK_NEAR(fb[0], 5.0, 1e-15, 0.0);
    CHECK_NEAR(fb[1], 3.25, 1e-15, 0.0);
    CHECK(fb[2] == 0.0 && fb[5] == 0.0 && fb[8] == 0.0);
    CHECK_NEAR(fb[3], 1.0, 1e-15, 0.0);  /* green, face 0 */
    CHECK_NEAR(fb[6], 6.0, 1e-15, 0.0);  /* blue, face 0: (0.5*0 + 1.5*8)/2 */
    int bad[3] = {0, 3, 0};
    CHECK(rad_io_face_averages(3, bad, area, B, 3, fa, fb) == RAD_EINPUT);
}

/* Write text to a fresh temporary file; its path in buf. */
static void temp_text(char *buf, size_t size, const char *text)
{
    snprintf(buf, size, "/tmp/radkit-io-XXXXXX");
    int fd = mkstemp(buf);
    CHECK(fd >= 0);
    if (fd < 0)
        return;
    FILE *f = fdopen(fd, "w");
    fputs(text, f);
    fclose(f);
}

TEST(io_read_faces_reads_what_solve_writes)
{
    char path[64];
    temp_text(path, sizeof path,
              "# radkit solve\n# method = mc\nface\tarea\tB_r\tB_g\tB_b\tse_r\tse_g\tse_b\n"
              "0\t0.5\t1.25\t2.5\t3.75\t0.01\t0.02\t0.03\n"
              "1\t1.5\t-0\t1e-300\t7\t0\t0\t0.5\n");
    rad_io_faces t;
    CHECK(rad_io_read_faces_tsv(path, &t) == RAD_OK);
    CHECK(t.n == 2 && t.se != NULL);
    if (t.n == 2 && t.se) {
        CHECK(t.area[0] == 0.5 && t.area[1] == 1.5);
        CHECK(t.B[0] == 1.25 && t.B[2] == 2.5 && t.B[4] == 3.75 && t.B[3] == 1e-300 && t.B[5] == 7);
        CHECK(t.se[0] == 0.01 && t.se[2] == 0.02 && t.se[4] == 0.03 && t.se[5] == 0.5);
    }
    rad_io_faces_free(&t);
    remove(path);
    /* a table without se, as dense and hier write it */
    temp_text(path, sizeof path, "face\tarea\tB_r\tB_g\tB_b\n0\t2\t1\t2\t3\n");
    CHECK(rad_io_read_faces_tsv(path, &t) == RAD_OK && t.n == 1 && t.se == NULL && t.B[2] == 3);
    rad_io_faces_free(&t);
    remove(path);
}

TEST(io_read_faces_names_the_bad_line)
{
    struct { const char *text, *needle; } bad[] = {
        {"face\tarea\tB_r\tB_g\tB_b\n0\t1\t2\t3\n", ":2: 4 columns"},
        {"face\tarea\tB_r\tB_g\tB_b\n0\t1\t2\tx\t4\n", ":2: column 4: 'x'"},
        {"face\tarea\tB_r\tB_g\tB_b\n0\t1\t2\tnan\t4\n", ":2: column 4"},
        {"face\tarea\tB_r\tB_g\tB_b\n1\t1\t2\t3\t4\n", ":2: face 1 out of order"},
        {"# only comments\n", "no per-face table"},
        {"a\tb\n", ":1: expected the header row"},
        {"face\tarea\tB_r\tB_g\tB_b\tse_r\n", ":1: unexpected columns"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char path[64];
        temp_text(path, sizeof path, bad[k].text);
        rad_io_faces t;
        CHECK(rad_io_read_faces_tsv(path, &t) == RAD_EINPUT);
        CHECK_MSG(strstr(rad_error_message(), bad[k].needle) && strstr(rad_error_message(), path),
                  "case %zu: '%s'", k, rad_error_message());
        CHECK(t.n == 0 && t.area == NULL);
        remove(path);
    }
    rad_io_faces t;
    CHECK(rad_io_read_faces_tsv("/nonexistent/x.tsv", &t) == RAD_EINPUT);
}

TEST(io_face_error_by_hand)
{
    /* Two faces, areas 1 and 3; face 0 emits 10 in every channel.  Reference
     * reflected parts: face 0 (2, 4, 6), face 1 (1, 1, 1): R = (1 * 12 + 3 * 3)
     * / (3 * 4) = 1.75.  Differences: face 0 (0.35, 0, 0), face 1 (0, -0.7, 0.175):
     * l1 = (0.35 + 3 * 0.875) / (12 * 1.75) = 0.1416..., worst = 0.7 / 1.75 = 0.4
     * at face 1, l2 = sqrt((0.1225 + 3 * 0.520625) / 12) / 1.75. */
    double area[2] = {1, 3}, E[6] = {10, 0, 10, 0, 10, 0};
    double ref[6] = {12, 1, 14, 1, 16, 1}, B[6] = {12.35, 1, 14, 0.3, 16, 1.175};
    double se[6] = {0.1, 0.01, 0.2, 0.02, 0.3, 0.03};
    rad_io_face_errors e;
    CHECK(rad_io_face_error(2, area, E, B, ref, se, &e) == RAD_OK);
    CHECK_NEAR(e.mean_reflected, 1.75, 1e-15, 0);
    CHECK_NEAR(e.l1, (0.35 + 3 * 0.875) / (12 * 1.75), 1e-14, 0);
    CHECK_NEAR(e.l2, sqrt((0.1225 + 3 * 0.520625) / 12) / 1.75, 1e-14, 0);
    CHECK_NEAR(e.worst, 0.4, 1e-14, 0);
    CHECK(e.worst_face == 1);
    CHECK_NEAR(e.ref_worst, 0.02 / 1.75, 1e-14, 0);
    CHECK_NEAR(e.ref_l1, (0.6 + 3 * 0.06) / (12 * 1.75), 1e-14, 0);
    /* power: reference 1 (12 + 14 + 16) + 3 (1 + 1 + 1) = 51, B 42.35 + 3 (2.475) = 49.775 */
    CHECK_NEAR(e.power, (49.775 - 51.0) / 51.0, 1e-14, 0);
    CHECK(rad_io_face_error(2, area, E, B, ref, NULL, &e) == RAD_OK && e.ref_l1 == 0.0);
    /* nothing reflected: no relative error */
    double dark[6] = {10, 0, 10, 0, 10, 0};
    CHECK(rad_io_face_error(2, area, E, B, dark, NULL, &e) == RAD_EINPUT);
    B[3] = NAN;
    CHECK(rad_io_face_error(2, area, E, B, ref, NULL, &e) == RAD_EINPUT);
}

/* Runs over MPI ranks add two top-level keys; other runs do not have them. */
TEST(io_stats_json_ranks_only_when_given)
{
    rad_io_phase phases[1] = {{"solve", 0.5}};
    rad_io_stats st = {"dense", 4, 4, 6, 0, 9, phases, 1, 0.5, 1e6, NULL, 0, "lu", 0, 1e-16,
                       NULL, 0, 0, 0.0};
    const char *path = tmp_path("ranks.json");
    CHECK(rad_io_write_stats_json(path, &st) == RAD_OK);
    char *text = harness_read_file(path);
    CHECK(text && !strstr(text, "\"ranks\"") && !strstr(text, "per_rank"));
    free(text);
    st.ranks = 4;
    st.memory_peak_bytes_per_rank = 2.5e7;
    CHECK(rad_io_write_stats_json(path, &st) == RAD_OK);
    text = harness_read_file(path);
    CHECK(text && strstr(text, "\"ranks\": 4") && strstr(text, "\"memory_peak_bytes_per_rank\": 25000000"));
    free(text);
    remove(path);
}
