/* radkit's OFF reader [geomview:off], in double precision with file:line
 * messages.
 *
 *  1. The whole file is read first (scene_read_file: a regular file within
 *     max_file_bytes); lines are
 *     then taken one at a time, '#' starts a comment, blank lines are skipped.
 *  2. Header keyword [ST][C][N]OFF (texture coordinates, colours, normals
 *     after each vertex's x y z, all ignored); the keyword may be absent.
 *     4OFF / nOFF (other dimensions) and binary OFF are refused by name.  The
 *     counts "vertices faces [edges]" follow, on the keyword's line or the
 *     next.
 *  3. One vertex a line: x y z parsed with strtod as doubles, NaN and inf
 *     refused naming file:line; the rest of the line is ignored.
 *  4. One face a line: n, then n indices, each checked against the vertex
 *     count (file:line names the index); a trailing colour is ignored.  Faces
 *     with n < 3 (points, lines) are skipped with a counted warning; the
 *     others go through scene_add_polygon (fan when convex, else ear
 *     clipping), numbered by their place in the file.
 *  5. Every count is checked against the lines present: a file that ends
 *     early names what the header promised and what is there.  A file with
 *     vertices and no faces is refused as a point cloud.
 * OFF carries no material radkit uses: every face gets one material from the
 * parameters (--rho, --emission; default grey 0.5, no emission). */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"

/* More corners than this in one face is not a polygon radkit can use. */
enum { OFF_MAX_CORNERS = 1 << 20 };

typedef struct off_reader {
    const char *path;
    const char *p, *end; /* unread text */
    int line;            /* line number of the last line returned */
    const char *ls, *le; /* that line, comment stripped */
} off_reader;

/* The next line with content; 0 at end of file. */
static int next_line(off_reader *r)
{
    while (r->p < r->end) {
        const char *s = r->p, *e = memchr(s, '\n', (size_t)(r->end - s));
        if (!e)
            e = r->end;
        r->p = e < r->end ? e + 1 : e;
        r->line++;
        const char *hash = memchr(s, '#', (size_t)(e - s));
        if (hash)
            e = hash;
        while (s < e && (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\0'))
            s++;
        while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' || e[-1] == '\0'))
            e--;
        if (s < e) {
            r->ls = s;
            r->le = e;
            return 1;
        }
    }
    return 0;
}

/* The next whitespace-separated token of the current line: [*tok, return). */
static const char *next_token(off_reader *r, const char **tok)
{
    const char *s = r->ls;
    while (s < r->le && (*s == ' ' || *s == '\t' || *s == '\r'))
        s++;
    const char *e = s;
    while (e < r->le && *e != ' ' && *e != '\t' && *e != '\r')
        e++;
    r->ls = e;
    *tok = s;
    return e;
}

static rad_status parse_long(off_reader *r, const char *what, long lo, long hi, long *out)
{
    const char *tok, *e = next_token(r, &tok);
    if (tok == e)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: missing %s", r->path, r->line, what);
    char *stop;
    errno = 0;
    long long v = strtoll(tok, &stop, 10);
    if (stop != e)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s '%.*s' is not an integer", r->path, r->line, what,
                         (int)(e - tok > 40 ? 40 : e - tok), tok);
    if (errno == ERANGE || v < lo || v > hi)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s %.*s is out of range [%ld, %ld]", r->path, r->line,
                         what, (int)(e - tok > 40 ? 40 : e - tok), tok, lo, hi);
    *out = (long)v;
    return RAD_OK;
}

static rad_status parse_coord(off_reader *r, double *out)
{
    const char *tok, *e = next_token(r, &tok);
    if (tok == e)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: a vertex needs 3 coordinates", r->path, r->line);
    char *stop;
    double v = strtod(tok, &stop);
    if (stop != e)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: vertex coordinate '%.*s' is not a number", r->path,
                         r->line, (int)(e - tok > 40 ? 40 : e - tok), tok);
    if (!isfinite(v))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: vertex coordinate is %s", r->path, r->line,
                         isnan(v) ? "NaN" : "infinite");
    *out = v;
    return RAD_OK;
}

/* The header keyword, if the line holds one: 1 and the flags, 0 when absent. */
static rad_status read_keyword(off_reader *r, int *has_keyword)
{
    const char *tok, *e = next_token(r, &tok), *k = tok;
    *has_keyword = 0;
    if (e - k >= 2 && k[0] == 'S' && k[1] == 'T')
        k += 2;
    if (k < e && *k == 'C')
        k++;
    if (k < e && *k == 'N')
        k++;
    int other_dim = 0;
    if (k < e && (*k == '4' || *k == 'n')) {
        other_dim = 1;
        k++;
    }
    if (e - k != 3 || memcmp(k, "OFF", 3) != 0) {
        r->ls = tok; /* not a keyword: the line holds the counts */
        return RAD_OK;
    }
    if (other_dim)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %.*s (points in other than 3 dimensions) is not supported",
                         r->path, r->line, (int)(e - tok), tok);
    const char *t2, *e2 = next_token(r, &t2);
    if (e2 - t2 == 6 && memcmp(t2, "BINARY", 6) == 0)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: binary OFF is not supported; write it as text OFF or PLY",
                         r->path, r->line);
    r->ls = t2;
    *has_keyword = 1;
    return RAD_OK;
}

static rad_status read_off(rad_scene *s, off_reader *r, const rad_scene_params *p)
{
    rad_status st;
    if (!next_line(r))
        return RAD_ERROR(RAD_EINPUT, "%s: no OFF header (the file holds only comments or blanks)", r->path);
    int has_keyword;
    if ((st = read_keyword(r, &has_keyword)) != RAD_OK)
        return st;
    if (r->ls == r->le && !next_line(r))
        return RAD_ERROR(RAD_EINPUT, "%s: the file ends before the vertex and face counts", r->path);
    long nv, nf, ne;
    if ((st = parse_long(r, "vertex count", 0, 1L << 30, &nv)) != RAD_OK ||
        (st = parse_long(r, "face count", 0, 1L << 30, &nf)) != RAD_OK)
        return st;
    if (r->ls < r->le && (st = parse_long(r, "edge count", 0, LONG_MAX, &ne)) != RAD_OK)
        return st;
    if (nf == 0)
        return RAD_ERROR(RAD_EINPUT, "%s: no faces (a point cloud?)", r->path);
    double zero[3] = {0, 0, 0};
    if ((st = scene_add_material(s, "default", p->default_rho, zero)) != RAD_OK)
        return st;
    for (long v = 0; v < nv; v++) {
        if (!next_line(r))
            return RAD_ERROR(RAD_EINPUT, "%s:%d: the file ends after %ld of the %ld vertices its header "
                             "promises", r->path, r->line, v, nv);
        double c[3];
        for (int k = 0; k < 3; k++)
            if ((st = parse_coord(r, &c[k])) != RAD_OK ||
                (st = scene_check_coordinate(r->path, r->line, v, c[k], p->scale)) != RAD_OK)
                return st;
        if ((st = scene_add_vertex(s, c[0], c[1], c[2])) != RAD_OK)
            return st;
    }
    int *idx = NULL, cap = 0, skipped = 0;
    for (long f = 0; f < nf && st == RAD_OK; f++) {
        if (!next_line(r)) {
            st = RAD_ERROR(RAD_EINPUT, "%s:%d: the file ends after %ld of the %ld faces its header "
                           "promises", r->path, r->line, f, nf);
            break;
        }
        long n;
        if ((st = parse_long(r, "face corner count", 1, OFF_MAX_CORNERS, &n)) != RAD_OK)
            break;
        /* Each index takes at least two characters: bound n before allocating. */
        if (n > (r->le - r->ls + 1) / 2) {
            st = RAD_ERROR(RAD_EINPUT, "%s:%d: a face of %ld corners, but the line holds fewer indices",
                           r->path, r->line, n);
            break;
        }
        if (n > cap) {
            int *q = realloc(idx, (size_t)n * sizeof *idx);
            if (!q) {
                st = RAD_ERROR(RAD_ENOMEM, "%s:%d: no memory for a face of %ld corners", r->path,
                               r->line, n);
                break;
            }
            idx = q;
            cap = (int)n;
        }
        for (long k = 0; k < n && st == RAD_OK; k++) {
            long v;
            const char *save = r->ls;
            if ((st = parse_long(r, "face index", LONG_MIN, LONG_MAX, &v)) != RAD_OK)
                break;
            if (v < 0 || v >= nv) {
                r->ls = save;
                const char *tok, *e = next_token(r, &tok);
                st = RAD_ERROR(RAD_EINPUT, "%s:%d: face index %.*s is out of range (the file has %ld "
                               "vertices, numbered from 0)", r->path, r->line,
                               (int)(e - tok > 40 ? 40 : e - tok), tok, nv);
                break;
            }
            idx[k] = (int)v;
        }
        if (st != RAD_OK)
            break;
        if (n < 3) {
            skipped++;
            continue;
        }
        st = scene_add_polygon(s, idx, (int)n, 0, (int)f, r->line);
    }
    free(idx);
    if (st == RAD_OK && skipped > 0)
        st = scene_warn(s, "skipped %d point or line primitive(s) (faces of fewer than 3 corners)",
                        skipped);
    return st;
}

rad_status scene_import_off(rad_scene *s, const char *path, const rad_scene_params *p)
{
    char *data;
    size_t size;
    rad_status st = scene_read_file(path, p->max_file_bytes, &data, &size);
    if (st != RAD_OK)
        return st;
    off_reader r = {path, data, data + size, 0, NULL, NULL};
    st = read_off(s, &r, p);
    free(data);
    return st;
}
