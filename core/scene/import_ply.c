/* radkit's PLY reader [turk1994ply]: ascii, binary_little_endian and
 * binary_big_endian, in double precision.
 *
 *  1. The whole file is read first (scene_read_file: a regular file within
 *     max_file_bytes).
 *  2. Header: "ply", a format line, then element / property / comment /
 *     obj_info lines, ending with end_header, all within the first
 *     PLY_MAX_HEADER bytes (a truncated header or one without end_header is
 *     refused, never searched for beyond that).  Property types: char/int8,
 *     uchar/uint8, short/int16, ushort/uint16, int/int32, uint/uint32,
 *     float/float32, double/float64; lists of any count and item type.
 *  3. Elements in file order: `vertex` (x, y, z of any scalar type; other
 *     properties skipped by type), `face` (the list vertex_indices or
 *     vertex_index, polygons through scene_add_polygon; other properties
 *     skipped), `tristrips` (the list vertex_indices: strips separated by -1,
 *     orientation alternating along a strip, triangles with a repeated corner
 *     being the strips' stitches and skipped); any other element is skipped by
 *     its declared properties.  Faces are numbered in file order (points and
 *     lines skipped with a counted warning keep their number), each strip
 *     triangle being a face of its own.
 *  4. Every read is checked against the bytes present (binary) or tokens
 *     present (ascii): a file shorter than its header promises names the
 *     element and how far it got.  List counts are checked against the data
 *     that follows before anything is allocated; indices against the vertex
 *     count; coordinates must be finite.
 *  5. Vertices with no face or strip are refused as a point cloud.
 * PLY carries no material radkit uses: every face gets one material from the
 * parameters (--rho, --emission; default grey 0.5, no emission). */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"

enum {
    PLY_MAX_HEADER = 1 << 16,   /* bytes */
    PLY_MAX_ELEMENTS = 64,
    PLY_MAX_PROPERTIES = 256,   /* per element */
    PLY_MAX_LIST = 1 << 24,     /* items in one list */
    PLY_MAX_NAME = 64
};

typedef enum { T_NONE, T_I8, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 } ply_type;

static const struct {
    const char *name;
    ply_type type;
} type_names[] = {
    {"char", T_I8},   {"int8", T_I8},     {"uchar", T_U8},    {"uint8", T_U8},
    {"short", T_I16}, {"int16", T_I16},   {"ushort", T_U16},  {"uint16", T_U16},
    {"int", T_I32},   {"int32", T_I32},   {"uint", T_U32},    {"uint32", T_U32},
    {"float", T_F32}, {"float32", T_F32}, {"double", T_F64},  {"float64", T_F64},
};

static size_t type_size(ply_type t)
{
    switch (t) {
    case T_I8: case T_U8: return 1;
    case T_I16: case T_U16: return 2;
    case T_I32: case T_U32: case T_F32: return 4;
    case T_F64: return 8;
    default: return 0;
    }
}

typedef struct ply_property {
    char name[PLY_MAX_NAME];
    ply_type type;       /* item type of a list */
    ply_type count_type; /* T_NONE for a scalar */
} ply_property;

typedef struct ply_element {
    char name[PLY_MAX_NAME];
    long count;
    int header_line;
    ply_property prop[PLY_MAX_PROPERTIES];
    int np;
} ply_element;

typedef enum { F_ASCII, F_LE, F_BE } ply_format;

typedef struct ply_reader {
    const char *path;
    ply_format format;
    int swap;                 /* binary byte order differs from the machine's */
    const unsigned char *p, *end;
    int line;                 /* ascii: line of the next token */
    ply_element el[PLY_MAX_ELEMENTS];
    int ne;
    const char *what;         /* for messages: the element being read */
    long item, count;
} ply_reader;

/* ---- header ---------------------------------------------------------------- */

static ply_type type_of(const char *name)
{
    for (size_t i = 0; i < sizeof type_names / sizeof type_names[0]; i++)
        if (strcmp(name, type_names[i].name) == 0)
            return type_names[i].type;
    return T_NONE;
}

static rad_status header_line(ply_reader *r, char *line, int lineno)
{
    char *save = NULL, *key = strtok_r(line, " \t\r", &save);
    if (!key || strcmp(key, "comment") == 0 || strcmp(key, "obj_info") == 0)
        return RAD_OK;
    if (strcmp(key, "format") == 0) {
        char *f = strtok_r(NULL, " \t\r", &save), *v = strtok_r(NULL, " \t\r", &save);
        if (f && strcmp(f, "ascii") == 0)
            r->format = F_ASCII;
        else if (f && strcmp(f, "binary_little_endian") == 0)
            r->format = F_LE;
        else if (f && strcmp(f, "binary_big_endian") == 0)
            r->format = F_BE;
        else
            return RAD_ERROR(RAD_EINPUT, "%s:%d: unknown PLY format '%s'", r->path, lineno, f ? f : "");
        if (!v || strcmp(v, "1.0") != 0)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: PLY version '%s' is not 1.0", r->path, lineno, v ? v : "");
        return RAD_OK;
    }
    if (strcmp(key, "element") == 0) {
        char *name = strtok_r(NULL, " \t\r", &save), *count = strtok_r(NULL, " \t\r", &save);
        if (!name || !count || strlen(name) >= PLY_MAX_NAME)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: an element needs a name and a count", r->path, lineno);
        if (r->ne == PLY_MAX_ELEMENTS)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: more than %d elements", r->path, lineno, PLY_MAX_ELEMENTS);
        char *stop;
        errno = 0;
        long long n = strtoll(count, &stop, 10);
        if (*stop || errno == ERANGE || n < 0 || n > (1LL << 31) - 1)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: element %s has count '%s', not a count below 2^31",
                             r->path, lineno, name, count);
        ply_element *e = &r->el[r->ne++];
        memset(e, 0, sizeof *e);
        strcpy(e->name, name);
        e->count = (long)n;
        e->header_line = lineno;
        return RAD_OK;
    }
    if (strcmp(key, "property") == 0) {
        if (r->ne == 0)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: a property before any element", r->path, lineno);
        ply_element *e = &r->el[r->ne - 1];
        if (e->np == PLY_MAX_PROPERTIES)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: more than %d properties", r->path, lineno,
                             PLY_MAX_PROPERTIES);
        ply_property *q = &e->prop[e->np];
        char *t = strtok_r(NULL, " \t\r", &save);
        if (t && strcmp(t, "list") == 0) {
            char *ct = strtok_r(NULL, " \t\r", &save);
            q->count_type = ct ? type_of(ct) : T_NONE;
            if (q->count_type == T_NONE || q->count_type == T_F32 || q->count_type == T_F64)
                return RAD_ERROR(RAD_EINPUT, "%s:%d: a list's count type must be an integer type, got '%s'",
                                 r->path, lineno, ct ? ct : "");
            t = strtok_r(NULL, " \t\r", &save);
        }
        q->type = t ? type_of(t) : T_NONE;
        if (q->type == T_NONE)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: unknown property type '%s'", r->path, lineno, t ? t : "");
        char *name = strtok_r(NULL, " \t\r", &save);
        if (!name || strlen(name) >= PLY_MAX_NAME)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: a property needs a name", r->path, lineno);
        strcpy(q->name, name);
        e->np++;
        return RAD_OK;
    }
    return RAD_ERROR(RAD_EINPUT, "%s:%d: '%.40s' is not a PLY header line (is end_header missing?)",
                     r->path, lineno, key);
}

/* Parse the header; r->p is left on the first byte of data. */
static rad_status read_header(ply_reader *r, const char *data, size_t size)
{
    if (size < 4 || memcmp(data, "ply", 3) != 0 || (data[3] != '\n' && data[3] != '\r'))
        return RAD_ERROR(RAD_EINPUT, "%s: not a PLY file (it does not start with \"ply\")", r->path);
    size_t limit = size < PLY_MAX_HEADER ? size : PLY_MAX_HEADER;
    const char *s = memchr(data, '\n', limit);
    int lineno = 1, format_seen = 0;
    char line[1024];
    while (s) {
        s++;
        lineno++;
        const char *e = memchr(s, '\n', limit - (size_t)(s - data));
        if (!e)
            break;
        size_t n = (size_t)(e - s);
        if (n >= sizeof line)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: a header line longer than %zu bytes", r->path, lineno,
                             sizeof line - 1);
        memcpy(line, s, n);
        line[n] = '\0';
        if (n > 0 && line[n - 1] == '\r')
            line[--n] = '\0';
        if (strcmp(line, "end_header") == 0) {
            if (!format_seen)
                return RAD_ERROR(RAD_EINPUT, "%s: the PLY header has no format line", r->path);
            r->p = (const unsigned char *)e + 1;
            r->end = (const unsigned char *)data + size;
            r->line = lineno + 1;
            return RAD_OK;
        }
        if (strncmp(line, "format", 6) == 0)
            format_seen = 1;
        rad_status st = header_line(r, line, lineno);
        if (st != RAD_OK)
            return st;
        s = e;
    }
    if (size <= PLY_MAX_HEADER)
        return RAD_ERROR(RAD_EINPUT, "%s: the file ends inside the PLY header (no end_header line)",
                         r->path);
    return RAD_ERROR(RAD_EINPUT, "%s: no end_header line in the first %d bytes (a truncated or "
                     "damaged PLY header)", r->path, PLY_MAX_HEADER);
}

/* ---- data ------------------------------------------------------------------ */

static rad_status short_data(const ply_reader *r)
{
    if (r->format == F_ASCII)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: the file ends in %s %ld of the %ld its header promises",
                         r->path, r->line, r->what, r->item, r->count);
    return RAD_ERROR(RAD_EINPUT, "%s: the file ends in %s %ld of the %ld its header promises",
                     r->path, r->what, r->item, r->count);
}

/* One ascii token: [*tok, return); skips whitespace, counting lines. */
static const char *ascii_token(ply_reader *r, const char **tok)
{
    const unsigned char *s = r->p;
    while (s < r->end && (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')) {
        if (*s == '\n')
            r->line++;
        s++;
    }
    const unsigned char *e = s;
    while (e < r->end && !(*e == ' ' || *e == '\t' || *e == '\r' || *e == '\n'))
        e++;
    r->p = e;
    *tok = (const char *)s;
    return (const char *)e;
}

/* Read one scalar of type t as a double (integers exactly). */
static rad_status read_value(ply_reader *r, ply_type t, double *out)
{
    if (r->format == F_ASCII) {
        const char *tok, *e = ascii_token(r, &tok);
        if (tok == e)
            return short_data(r);
        char *stop;
        double v = (t == T_F32 || t == T_F64) ? strtod(tok, &stop) : (double)strtoll(tok, &stop, 10);
        if (stop != e)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: '%.*s' is not a number of the declared type (%s %ld)",
                             r->path, r->line, (int)(e - tok > 40 ? 40 : e - tok), tok, r->what, r->item);
        *out = v;
        return RAD_OK;
    }
    size_t n = type_size(t);
    if ((size_t)(r->end - r->p) < n)
        return short_data(r);
    unsigned char b[8];
    for (size_t i = 0; i < n; i++)
        b[i] = r->swap ? r->p[n - 1 - i] : r->p[i];
    r->p += n;
    switch (t) {
    case T_I8: { int8_t v; memcpy(&v, b, 1); *out = v; break; }
    case T_U8: { uint8_t v; memcpy(&v, b, 1); *out = v; break; }
    case T_I16: { int16_t v; memcpy(&v, b, 2); *out = v; break; }
    case T_U16: { uint16_t v; memcpy(&v, b, 2); *out = v; break; }
    case T_I32: { int32_t v; memcpy(&v, b, 4); *out = v; break; }
    case T_U32: { uint32_t v; memcpy(&v, b, 4); *out = v; break; }
    case T_F32: { float v; memcpy(&v, b, 4); *out = v; break; }
    case T_F64: { double v; memcpy(&v, b, 8); *out = v; break; }
    default: *out = 0; break;
    }
    return RAD_OK;
}

/* A list's item count, checked against the data that follows. */
static rad_status read_count(ply_reader *r, const ply_property *q, long *out)
{
    double c;
    rad_status st = read_value(r, q->count_type, &c);
    if (st != RAD_OK)
        return st;
    if (c < 0 || c > PLY_MAX_LIST)
        return RAD_ERROR(RAD_EINPUT, "%s%s%.0d: %s %ld: list %s has %.0f items (at most %d)", r->path,
                         r->format == F_ASCII ? ":" : "", r->format == F_ASCII ? r->line : 0, r->what,
                         r->item, q->name, c, PLY_MAX_LIST);
    /* Binary: the items must fit in what is left; ascii: each takes two bytes or more. */
    size_t need = r->format == F_ASCII ? 2 * (size_t)c - (c > 0) : (size_t)c * type_size(q->type);
    if ((size_t)(r->end - r->p) < need)
        return short_data(r);
    *out = (long)c;
    return RAD_OK;
}

static rad_status skip_property(ply_reader *r, const ply_property *q)
{
    double v;
    rad_status st = RAD_OK;
    if (q->count_type == T_NONE)
        return read_value(r, q->type, &v);
    long n;
    if ((st = read_count(r, q, &n)) != RAD_OK)
        return st;
    for (long k = 0; k < n && st == RAD_OK; k++)
        st = read_value(r, q->type, &v);
    return st;
}

static int find_property(const ply_element *e, const char *name, int list)
{
    for (int i = 0; i < e->np; i++)
        if (strcmp(e->prop[i].name, name) == 0 && (e->prop[i].count_type != T_NONE) == list)
            return i;
    return -1;
}

static void begin(ply_reader *r, const char *what, const ply_element *e)
{
    r->what = what;
    r->count = e->count;
    r->item = 0;
}

static rad_status read_vertices(rad_scene *s, ply_reader *r, const ply_element *e, double scale)
{
    int ix = find_property(e, "x", 0), iy = find_property(e, "y", 0), iz = find_property(e, "z", 0);
    if (s->nv > 0)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: a second vertex element", r->path, e->header_line);
    begin(r, "vertex", e);
    rad_status st = RAD_OK;
    for (r->item = 0; r->item < e->count && st == RAD_OK; r->item++) {
        double c[3] = {0, 0, 0};
        for (int i = 0; i < e->np && st == RAD_OK; i++) {
            int k = i == ix ? 0 : i == iy ? 1 : i == iz ? 2 : -1;
            if (k < 0) {
                st = skip_property(r, &e->prop[i]);
                continue;
            }
            st = read_value(r, e->prop[i].type, &c[k]);
            if (st == RAD_OK && !isfinite(c[k]))
                st = r->format == F_ASCII
                         ? RAD_ERROR(RAD_EINPUT, "%s:%d: vertex %ld has a %s coordinate", r->path,
                                     r->line, r->item, isnan(c[k]) ? "NaN" : "infinite")
                         : RAD_ERROR(RAD_EINPUT, "%s: vertex %ld has a %s coordinate", r->path,
                                     r->item, isnan(c[k]) ? "NaN" : "infinite");
            if (st == RAD_OK)
                st = scene_check_coordinate(r->path, r->format == F_ASCII ? r->line : 0, r->item,
                                            c[k], scale);
        }
        if (st == RAD_OK)
            st = scene_add_vertex(s, c[0], c[1], c[2]);
    }
    return st;
}

/* The corner list of one face or strip into r's buffer; indices checked. */
static rad_status read_indices(rad_scene *s, ply_reader *r, const ply_property *q, int allow_restart,
                               int **idx, long *cap, long *n)
{
    rad_status st = read_count(r, q, n);
    if (st != RAD_OK)
        return st;
    if (*n > *cap) {
        int *b = realloc(*idx, (size_t)*n * sizeof **idx);
        if (!b)
            return RAD_ERROR(RAD_ENOMEM, "%s: no memory for a list of %ld indices", r->path, *n);
        *idx = b;
        *cap = *n;
    }
    for (long k = 0; k < *n; k++) {
        double v;
        if ((st = read_value(r, q->type, &v)) != RAD_OK)
            return st;
        if (!(v >= 0 && v < s->nv && v == floor(v)) && !(allow_restart && v == -1)) {
            if (s->nv == 0)
                return RAD_ERROR(RAD_EINPUT, "%s: %s before any vertex (the vertex element must come first)",
                                 r->path, r->what);
            if (r->format == F_ASCII)
                return RAD_ERROR(RAD_EINPUT, "%s:%d: %s %ld: index %.0f is out of range (%d vertices, "
                                 "numbered from 0)", r->path, r->line, r->what, r->item, v, s->nv);
            return RAD_ERROR(RAD_EINPUT, "%s: %s %ld: index %.0f is out of range (%d vertices, "
                             "numbered from 0)", r->path, r->what, r->item, v, s->nv);
        }
        (*idx)[k] = (int)v;
    }
    return RAD_OK;
}

static rad_status read_faces(rad_scene *s, ply_reader *r, const ply_element *e, int strips,
                             int *faces, int *skipped)
{
    int li = find_property(e, "vertex_indices", 1);
    if (li < 0 && !strips)
        li = find_property(e, "vertex_index", 1);
    if (li < 0)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: element %s has no list vertex_indices", r->path,
                         e->header_line, e->name);
    begin(r, strips ? "strip" : "face", e);
    int *idx = NULL;
    long cap = 0, n = 0;
    rad_status st = RAD_OK;
    for (r->item = 0; r->item < e->count && st == RAD_OK; r->item++) {
        for (int i = 0; i < e->np && st == RAD_OK; i++)
            st = i == li ? read_indices(s, r, &e->prop[i], strips, &idx, &cap, &n)
                         : skip_property(r, &e->prop[i]);
        if (st != RAD_OK)
            break;
        int line = r->format == F_ASCII ? r->line : 0;
        if (!strips) {
            if (n < 3)
                (*skipped)++;
            else
                st = scene_add_polygon(s, idx, (int)n, 0, *faces, line);
            (*faces)++;
            continue;
        }
        /* Strip: triangle k of a run is (k, k+1, k+2), every other one reversed. */
        long start = 0;
        for (long k = 0; k <= n && st == RAD_OK; k++) {
            if (k < n && idx[k] != -1)
                continue;
            for (long t = start; t + 2 < k && st == RAD_OK; t++) {
                int a = idx[t], b = idx[t + 1], c = idx[t + 2];
                if ((t - start) % 2) {
                    int x = a;
                    a = b;
                    b = x;
                }
                if (a != b && b != c && a != c)
                    st = scene_add_triangle(s, a, b, c, 0, (*faces)++, line);
            }
            start = k + 1;
        }
    }
    free(idx);
    return st;
}

static rad_status read_ply(rad_scene *s, ply_reader *r, const char *data, size_t size,
                           const rad_scene_params *p)
{
    rad_status st = read_header(r, data, size);
    if (st != RAD_OK)
        return st;
    uint16_t one = 1;
    unsigned char little;
    memcpy(&little, &one, 1);
    r->swap = r->format != F_ASCII && (r->format == F_LE) != (little == 1);
    long polygons = 0;
    int vertex_seen = 0;
    for (int i = 0; i < r->ne; i++) {
        const ply_element *e = &r->el[i];
        if (strcmp(e->name, "vertex") == 0) {
            vertex_seen = 1;
            if (find_property(e, "x", 0) < 0 || find_property(e, "y", 0) < 0 || find_property(e, "z", 0) < 0)
                return RAD_ERROR(RAD_EINPUT, "%s:%d: element vertex needs the scalar properties x, y "
                                 "and z", r->path, e->header_line);
        } else if (strcmp(r->el[i].name, "face") == 0 || strcmp(r->el[i].name, "tristrips") == 0)
            polygons += r->el[i].count;
    }
    if (!vertex_seen)
        return RAD_ERROR(RAD_EINPUT, "%s: no vertex element", r->path);
    if (polygons == 0)
        return RAD_ERROR(RAD_EINPUT, "%s: no faces (a point cloud?)", r->path);
    double zero[3] = {0, 0, 0};
    if ((st = scene_add_material(s, "default", p->default_rho, zero)) != RAD_OK)
        return st;
    int faces = 0, skipped = 0;
    for (int i = 0; i < r->ne && st == RAD_OK; i++) {
        const ply_element *e = &r->el[i];
        if (strcmp(e->name, "vertex") == 0)
            st = read_vertices(s, r, e, p->scale);
        else if (strcmp(e->name, "face") == 0 || strcmp(e->name, "tristrips") == 0)
            st = read_faces(s, r, e, e->name[0] == 't', &faces, &skipped);
        else if (e->np > 0) {
            begin(r, e->name, e);
            for (r->item = 0; r->item < e->count && st == RAD_OK; r->item++)
                for (int k = 0; k < e->np && st == RAD_OK; k++)
                    st = skip_property(r, &e->prop[k]);
        }
    }
    if (st == RAD_OK && skipped > 0)
        st = scene_warn(s, "skipped %d point or line primitive(s) (faces of fewer than 3 corners)",
                        skipped);
    return st;
}

rad_status scene_import_ply(rad_scene *s, const char *path, const rad_scene_params *p)
{
    char *data;
    size_t size;
    rad_status st = scene_read_file(path, p->max_file_bytes, &data, &size);
    if (st != RAD_OK)
        return st;
    ply_reader *r = calloc(1, sizeof *r);
    if (!r) {
        free(data);
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory", path);
    }
    r->path = path;
    st = read_ply(s, r, data, size, p);
    free(r);
    free(data);
    return st;
}
