/* OBJ + MTL: radkit's own line reader, with Assimp as an optional cross-check.
 *
 * Why a reader of our own: Assimp reports no line numbers and Debian's build
 * keeps coordinates in single precision (ai_real = float), while every finding
 * must name its line and convergence studies need the file's digits.  The
 * format is small [obj:spec; mtl:spec]:
 *  1. Read the OBJ line by line (text_file.c: regular files only, at most
 *     max_file_bytes, lines of at most max_line_bytes, no NUL bytes).
 *     `v x y z [w | r g b]` adds a vertex (each number parsed whole, as
 *     strtod would: a malformed or non-finite number, or one beyond
 *     RAD_GEOM_MAX_COORD once scaled, is an error at its line).
 *     `f i j k ...` adds a polygon: each corner is `v`, `v/vt`, `v/vt/vn` or
 *     `v//vn`; negative indices count back from the last vertex read; the
 *     polygon keeps its line, face number and the current material.
 *     `usemtl` selects a material by name, `mtllib` reads material libraries
 *     (relative to the OBJ's folder; each file once).
 *     The comment `# radkit camera position X Y Z look_at X Y Z up X Y Z
 *     fov_y DEGREES` gives the camera.
 *  2. After the last line, every index is checked against the vertex count
 *     (forward references are legal OBJ), naming the line of the face, and
 *     each polygon is triangulated in file order by scene_add_polygon (the
 *     fan for convex polygons, ear clipping in its plane otherwise).
 *  3. MTL: `newmtl` opens a material; `Kd r [g b]` is its reflectance, in
 *     [0, 1]; `Ke r [g b]` its emitted exitance, >= 0.  Kd = 1 (white, as
 *     hand-written and exported files say it) is taken as rho_white, the
 *     largest reflectance radkit gives a surface, since radkit's model needs
 *     rho < 1.  A material without Kd gets the default reflectance.
 *  4. What radkit does not use is ignored, as the format intends, with one
 *     counted warning per keyword naming the first place.  Silent: the
 *     statements every exporter writes that carry nothing a diffuse, opaque,
 *     flat-triangle model could use (vt, vn, o, g, s, mg, l and p, which have
 *     no area; Ka, Ks, Ns, Ni, illum, sharpness; d 1 and Tr 0, which say
 *     "opaque").  Warned: free-form geometry (vp, cstype, curv, surf, ...),
 *     call and csh, display attributes (lod, bevel, t, ...), transmission
 *     (Kt, Tf, d < 1, Tr > 0), textures and glossy parameters (map_*, bump,
 *     Pr, Pm, ...), and any keyword radkit does not know.
 *  5. A missing material library, or a usemtl naming no defined material,
 *     gives those faces the default material (default_rho, no emission), with
 *     one counted warning each.
 *  6. Strict mode (params.strict) refuses at its line what 3-5 would load
 *     with a warning: Kd = 1, a missing library or material, free-form
 *     geometry, call/csh and unknown keywords (they may hold geometry radkit
 *     does not see).  Texture, glossy, transmission and display statements
 *     still only warn: radkit's surfaces are opaque and diffuse by definition.
 *  7. On request (no_cross_check = 0; not the default, as Assimp's reader
 *     can crash on malformed files) Assimp imports the same file; if it finds
 *     a different number of triangles, or cannot read it, a warning says so. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_geom.h"
#include "scene_internal.h"
#include "text_file.h"

/* What a keyword radkit does not use is, and so what the warning says. */
typedef enum kw_kind {
    KW_SILENT,       /* no warning */
    KW_FREEFORM,     /* geometry radkit does not load: refused when strict */
    KW_EXTERNAL,     /* other files and commands: refused when strict */
    KW_DISPLAY,      /* display and rendering attributes */
    KW_TRANSMISSION, /* light through the surface */
    KW_LOOK,         /* textures, glossy and PBR parameters */
    KW_UNKNOWN       /* not an OBJ/MTL statement radkit knows: refused when strict */
} kw_kind;

static const char *const kind_reason[] = {
    "",
    "free-form curves and surfaces are not loaded",
    "other files are not read and commands are not run",
    "display and rendering attributes are not used",
    "transmission is not modelled (radkit's surfaces are opaque)",
    "textures and glossy parameters are not used (Kd is the diffuse reflectance)",
    "not a statement radkit knows",
};

typedef struct keyword { const char *key; kw_kind kind; } keyword;

static const keyword obj_keywords[] = {
    {"vt", KW_SILENT}, {"vn", KW_SILENT}, {"o", KW_SILENT}, {"g", KW_SILENT},
    {"s", KW_SILENT}, {"mg", KW_SILENT}, {"l", KW_SILENT}, {"p", KW_SILENT},
    {"vp", KW_FREEFORM}, {"cstype", KW_FREEFORM}, {"deg", KW_FREEFORM}, {"bmat", KW_FREEFORM},
    {"step", KW_FREEFORM}, {"curv", KW_FREEFORM}, {"curv2", KW_FREEFORM}, {"surf", KW_FREEFORM},
    {"parm", KW_FREEFORM}, {"trim", KW_FREEFORM}, {"hole", KW_FREEFORM}, {"scrv", KW_FREEFORM},
    {"sp", KW_FREEFORM}, {"end", KW_FREEFORM}, {"con", KW_FREEFORM},
    {"call", KW_EXTERNAL}, {"csh", KW_EXTERNAL},
    {"bevel", KW_DISPLAY}, {"c_interp", KW_DISPLAY}, {"d_interp", KW_DISPLAY},
    {"lod", KW_DISPLAY}, {"maplib", KW_DISPLAY}, {"usemap", KW_DISPLAY},
    {"shadow_obj", KW_DISPLAY}, {"trace_obj", KW_DISPLAY}, {"ctech", KW_DISPLAY},
    {"stech", KW_DISPLAY}, {"t", KW_DISPLAY},
    {NULL, KW_UNKNOWN}};

static const keyword mtl_keywords[] = {
    {"Ka", KW_SILENT}, {"Ks", KW_SILENT}, {"Ns", KW_SILENT}, {"Ni", KW_SILENT},
    {"illum", KW_SILENT}, {"sharpness", KW_SILENT},
    {"Kt", KW_TRANSMISSION}, {"Tf", KW_TRANSMISSION}, {"d", KW_TRANSMISSION},
    {"Tr", KW_TRANSMISSION},
    {"Pr", KW_LOOK}, {"Pm", KW_LOOK}, {"Ps", KW_LOOK}, {"Pc", KW_LOOK}, {"Pcr", KW_LOOK},
    {"aniso", KW_LOOK}, {"anisor", KW_LOOK}, {"norm", KW_LOOK}, {"bump", KW_LOOK},
    {"disp", KW_LOOK}, {"decal", KW_LOOK}, {"refl", KW_LOOK},
    {NULL, KW_UNKNOWN}};

static kw_kind kind_of(const keyword *table, const char *key)
{
    for (; table->key; table++)
        if (strcmp(table->key, key) == 0)
            return table->kind;
    return KW_UNKNOWN;
}

/* One counted warning: how often, and the first place and name. */
typedef struct note {
    int count;
    char *file; /* owned copy */
    int line;
    char what[80];
    char detail[96];
} note;

/* Distinct ignored keywords kept one by one; the rest are lumped together
 * (a garbage file cannot make the warning list grow without bound). */
#define OBJ_MAX_KEYWORDS 32

typedef struct ignored {
    note n;
    kw_kind kind;
} ignored;

typedef struct obj_face {
    size_t first; /* into corners */
    int n, mat, line;
} obj_face;

typedef struct obj_reader {
    rad_scene *s;
    const char *path;
    const rad_scene_params *p;
    int current_material; /* -1: none yet */
    int default_material; /* -1: not created */
    int *corners;         /* every face's vertex indices, in file order */
    size_t nc, cap_c;
    obj_face *faces;
    int nf, cap_f;
    char **libraries;     /* material library paths tried (each read once) */
    int nlib, cap_lib;
    note kd_one, missing_lib, undefined;
    ignored kw[OBJ_MAX_KEYWORDS];
    int nkw;
    note other_kw;        /* keywords beyond OBJ_MAX_KEYWORDS */
} obj_reader;

/* The keyword as printable text of bounded length (it may be binary junk). */
static void printable(char *out, size_t size, const char *key)
{
    size_t n = 0, cap = size > 4 ? size - 4 : 0;
    for (; key[n] && n < cap; n++)
        out[n] = key[n] > ' ' && key[n] < 127 ? key[n] : '?';
    if (key[n])
        memcpy(out + n++, "...", 3), n += 2;
    out[n] = '\0';
}

static rad_status note_add(note *n, const char *file, int line, const char *what, const char *detail)
{
    if (n->count++ > 0)
        return RAD_OK;
    n->file = strdup(file);
    n->line = line;
    snprintf(n->what, sizeof n->what, "%s", what ? what : "");
    snprintf(n->detail, sizeof n->detail, "%s", detail ? detail : "");
    return n->file ? RAD_OK : RAD_ERROR(RAD_ENOMEM, "no memory");
}

/* A statement radkit does not use: counted, or refused in strict mode. */
static rad_status ignore(obj_reader *r, const char *file, int line, const char *key, kw_kind kind)
{
    if (kind == KW_SILENT)
        return RAD_OK;
    char shown[32];
    printable(shown, sizeof shown, key);
    if (r->p->strict && (kind == KW_FREEFORM || kind == KW_EXTERNAL))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: `%s`: %s (refused in strict mode)", file, line, shown,
                         kind_reason[kind]);
    if (r->p->strict && kind == KW_UNKNOWN)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: `%s` is not a statement radkit knows (refused in "
                         "strict mode)", file, line, shown);
    for (int k = 0; k < r->nkw; k++)
        if (strcmp(r->kw[k].n.what, shown) == 0)
            return note_add(&r->kw[k].n, file, line, shown, NULL);
    if (r->nkw < OBJ_MAX_KEYWORDS) {
        r->kw[r->nkw].kind = kind;
        return note_add(&r->kw[r->nkw++].n, file, line, shown, NULL);
    }
    return note_add(&r->other_kw, file, line, shown, NULL);
}

/* Token tok as a plain decimal ([+-] digits [. digits], a digit at least),
 * where strtod's answer is one correctly rounded division (Clinger 1990):
 * at most 19 significant digits making an integer m <= 2^53, and at most
 * 22 after the point, so that m and 10^k are exact doubles and m / 10^k
 * rounds once, as strtod does.  0 for any other token (strtod reads it):
 * an OBJ's coordinates are nearly all plain decimals, which need none of
 * strtod's arbitrary-precision path. */
static int plain_decimal(const char *tok, double *out)
{
    static const double ten[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                   1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                   1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char *c = tok;
    int negative = *c == '-';
    if (*c == '-' || *c == '+')
        c++;
    uint64_t m = 0;
    int digits = 0, significant = 0, after = 0, point = 0;
    for (;; c++) {
        if (*c == '.' && !point) {
            point = 1;
            continue;
        }
        if (*c < '0' || *c > '9')
            break;
        digits++;
        after += point;
        if (m == 0 && *c == '0')
            continue; /* a leading zero adds no significant digit */
        if (++significant > 19)
            return 0;
        m = 10 * m + (uint64_t)(*c - '0');
    }
    if (*c != '\0' || digits == 0 || after > 22 || m > (uint64_t)1 << 53)
        return 0;
    double v = (double)m / ten[after];
    *out = negative ? -v : v;
    return 1;
}

/* Parse one whole number token; RAD_EINPUT names file:line and what. */
static rad_status parse_number(const char *file, int line, const char *what, const char *tok,
                               double *out)
{
    if (!tok)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s: a number is missing", file, line, what);
    if (plain_decimal(tok, out))
        return RAD_OK;
    char *end = NULL;
    errno = 0;
    double v = strtod(tok, &end);
    if (end == tok || *end != '\0')
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s: malformed number '%.40s'", file, line, what, tok);
    if (isnan(v))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s: NaN value '%.40s'", file, line, what, tok);
    if (!isfinite(v))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s: infinite value '%.40s'", file, line, what, tok);
    *out = v;
    return RAD_OK;
}

/* Read "r [g b]" after a Kd/Ke keyword. */
static rad_status parse_colour(const char *file, int line, const char *key, char **save, double c[3])
{
    char *tok[4];
    int n = 0;
    while (n < 4 && (tok[n] = strtok_r(NULL, " \t", save)) != NULL)
        n++;
    if (n >= 1 && (strcmp(tok[0], "spectral") == 0 || strcmp(tok[0], "xyz") == 0))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s %s is not supported (give r g b)", file, line,
                         key, tok[0]);
    if (n != 1 && n != 3)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s needs 1 or 3 numbers, found %d", file, line, key, n);
    for (int k = 0; k < n; k++) {
        rad_status st = parse_number(file, line, key, tok[k], &c[k]);
        if (st != RAD_OK)
            return st;
    }
    if (n == 1)
        c[1] = c[2] = c[0];
    return RAD_OK;
}

static int find_material(const rad_scene *s, const char *name)
{
    for (int m = 0; m < s->nm; m++)
        if (strcmp(s->mats[m].name, name) == 0)
            return m;
    return -1;
}

/* The rest of the line after a keyword without surrounding blanks ("" if
 * none): a material name may contain spaces. */
static char *rest_of_line(char **save)
{
    static char empty[1];
    char *rest = strtok_r(NULL, "", save);
    if (!rest)
        return empty;
    while (*rest == ' ' || *rest == '\t')
        rest++;
    size_t n = strlen(rest);
    while (n > 0 && (rest[n - 1] == ' ' || rest[n - 1] == '\t'))
        rest[--n] = '\0';
    return rest;
}

/* Kd: each channel in [0, 1]; exactly 1 becomes rho_white (counted), unless strict. */
static rad_status set_reflectance(obj_reader *r, const char *file, int line, int current,
                                  const double c[3])
{
    static const char channel[3] = {'r', 'g', 'b'};
    rad_scene_material *m = &r->s->mats[current];
    double rho[3];
    int ones = 0;
    for (int k = 0; k < 3; k++) {
        if (!(c[k] >= 0.0 && c[k] <= 1.0))
            return RAD_ERROR(RAD_EINPUT, "%s:%d: material '%s': reflectance Kd %c = %g is outside "
                             "[0, 1]", file, line, m->name, channel[k], c[k]);
        if (c[k] == 1.0 && r->p->strict)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: material '%s': reflectance Kd %c = 1 is outside "
                             "[0, 1) (strict mode does not take it as %g)", file, line, m->name,
                             channel[k], r->p->rho_white);
        ones += c[k] == 1.0;
        rho[k] = c[k] == 1.0 ? r->p->rho_white : c[k];
    }
    memcpy(m->rho, rho, sizeof rho);
    return ones ? note_add(&r->kd_one, file, line, m->name, NULL) : RAD_OK;
}

static rad_status read_mtl_line(obj_reader *r, const char *mtl_path, int line, char *buf,
                                int *current)
{
    char *save = NULL, *key = strtok_r(buf, " \t", &save);
    if (!key || key[0] == '#')
        return RAD_OK;
    if (strcmp(key, "newmtl") == 0) {
        char *name = rest_of_line(&save);
        if (!*name)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: newmtl without a name", mtl_path, line);
        *current = find_material(r->s, name);
        if (*current >= 0)
            return scene_warn(r->s, "%s:%d: material '%.63s' defined again; the later values win",
                              mtl_path, line, name);
        double zero[3] = {0, 0, 0};
        rad_status st = scene_add_material(r->s, name, r->p->default_rho, zero);
        *current = r->s->nm - 1;
        return st;
    }
    if (strcmp(key, "Kd") == 0 || strcmp(key, "Ke") == 0) {
        double c[3] = {0, 0, 0}; /* parse_colour sets it; GCC cannot always see that */
        if (*current < 0)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: %s before any newmtl", mtl_path, line, key);
        rad_status st = parse_colour(mtl_path, line, key, &save, c);
        if (st != RAD_OK || key[1] == 'd')
            return st != RAD_OK ? st : set_reflectance(r, mtl_path, line, *current, c);
        static const char channel[3] = {'r', 'g', 'b'};
        for (int k = 0; k < 3; k++)
            if (c[k] < 0.0)
                return RAD_ERROR(RAD_EINPUT, "%s:%d: material '%s': negative emission Ke %c = %g",
                                 mtl_path, line, r->s->mats[*current].name, channel[k], c[k]);
        memcpy(r->s->mats[*current].emission, c, sizeof c);
        return RAD_OK;
    }
    kw_kind kind = strncmp(key, "map_", 4) == 0 ? KW_LOOK : kind_of(mtl_keywords, key);
    if (strcmp(key, "d") == 0 || strcmp(key, "Tr") == 0) {
        /* Opaque ("d 1", "Tr 0") says nothing radkit does not assume. */
        char *tok = strtok_r(NULL, " \t", &save), *end = NULL;
        double v = tok ? strtod(tok, &end) : NAN;
        if (tok && end != tok && v == (key[0] == 'd' ? 1.0 : 0.0))
            kind = KW_SILENT;
    }
    return ignore(r, mtl_path, line, key, kind);
}

static rad_status read_mtl(obj_reader *r, const char *mtl_path, int obj_line)
{
    for (int k = 0; k < r->nlib; k++)
        if (strcmp(r->libraries[k], mtl_path) == 0)
            return RAD_OK;
    if (r->nlib == r->cap_lib) {
        int cap = r->cap_lib ? 2 * r->cap_lib : 4;
        char **more = realloc(r->libraries, (size_t)cap * sizeof *more);
        if (!more)
            return RAD_ERROR(RAD_ENOMEM, "no memory");
        r->libraries = more;
        r->cap_lib = cap;
    }
    if (!(r->libraries[r->nlib] = strdup(mtl_path)))
        return RAD_ERROR(RAD_ENOMEM, "no memory");
    r->nlib++;
    scene_text t;
    int open_errno = 0;
    rad_status st = scene_text_open(&t, mtl_path, r->p->max_line_bytes, r->p->max_file_bytes,
                                    &open_errno);
    if (st != RAD_OK && open_errno == ENOENT) {
        if (r->p->strict)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: cannot open material library '%s': %s", r->path,
                             obj_line, mtl_path, strerror(open_errno));
        return note_add(&r->missing_lib, r->path, obj_line, mtl_path, strerror(open_errno));
    }
    if (st != RAD_OK) {
        /* Name the OBJ line too: the library's own message may not say who asked. */
        char why[512];
        snprintf(why, sizeof why, "%s", rad_error_message());
        return RAD_ERROR(st, "%s:%d: material library: %s", r->path, obj_line, why);
    }
    int current = -1;
    char *buf;
    while ((st = scene_text_next(&t, &buf)) == RAD_OK && buf)
        if ((st = read_mtl_line(r, mtl_path, t.line, buf, &current)) != RAD_OK)
            break;
    scene_text_close(&t);
    return st;
}

/* The folder of `path` joined with `name` (absolute names kept). */
static char *sibling_path(const char *path, const char *name)
{
    const char *slash = strrchr(path, '/');
    size_t dir = name[0] == '/' || !slash ? 0 : (size_t)(slash - path + 1);
    char *out = malloc(dir + strlen(name) + 1);
    if (out) {
        memcpy(out, path, dir);
        strcpy(out + dir, name);
    }
    return out;
}

static rad_status read_camera(obj_reader *r, int line, char **save)
{
    static const char *const keys[4] = {"position", "look_at", "up", "fov_y"};
    double *dest[4] = {r->s->camera.position, r->s->camera.look_at, r->s->camera.up,
                       &r->s->camera.fov_y_deg};
    for (int k = 0; k < 4; k++) {
        char *word = strtok_r(NULL, " \t", save);
        if (!word || strcmp(word, keys[k]) != 0)
            return RAD_ERROR(RAD_EINPUT, "%s:%d: radkit camera: expected '%s'", r->path, line, keys[k]);
        for (int c = 0; c < (k < 3 ? 3 : 1); c++) {
            rad_status st = parse_number(r->path, line, "radkit camera",
                                         strtok_r(NULL, " \t", save), &dest[k][c]);
            if (st != RAD_OK)
                return st;
        }
    }
    if (!(r->s->camera.fov_y_deg > 0.0 && r->s->camera.fov_y_deg < 180.0))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: radkit camera: fov_y must be in (0, 180) degrees",
                         r->path, line);
    r->s->camera.from_scene = 1;
    return RAD_OK;
}

static rad_status read_vertex(obj_reader *r, int line, char **save)
{
    double c[3];
    for (int k = 0; k < 3; k++) {
        rad_status st = parse_number(r->path, line, "vertex coordinate", strtok_r(NULL, " \t", save),
                                     &c[k]);
        if (st != RAD_OK)
            return st;
        /* The bound scene_finish applies to every format, here with the line. */
        double scale = r->p->scale, x = c[k] * scale;
        if (scale > 0.0 && isfinite(scale) && !(fabs(x) <= RAD_GEOM_MAX_COORD)) {
            char after[48] = "";
            if (scale != 1.0)
                snprintf(after, sizeof after, " (after scale %g)", scale);
            return RAD_ERROR(RAD_EINPUT, "%s:%d: vertex coordinate %g%s is beyond %g, where "
                             "form-factor products overflow; scale the scene down", r->path, line,
                             x, after, RAD_GEOM_MAX_COORD);
        }
    }
    return scene_add_vertex(r->s, c[0], c[1], c[2]);
}

/* One face corner "v[/vt[/vn]]" -> 0-based vertex index (range checked later). */
static rad_status parse_corner(obj_reader *r, int line, const char *tok, int *out)
{
    char *end = NULL;
    errno = 0;
    long idx = strtol(tok, &end, 10);
    if (end == tok || (*end != '\0' && *end != '/') || errno == ERANGE)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: malformed face index '%.40s'", r->path, line, tok);
    if (idx == 0)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: face index 0 is out of range (OBJ counts from 1)",
                         r->path, line);
    long v = idx > 0 ? idx - 1 : r->s->nv + idx;
    if (v < 0)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: face index %ld is out of range (%d vertices so far)",
                         r->path, line, idx, r->s->nv);
    if (v >= (1L << 30))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: face index %ld is out of range", r->path, line, idx);
    *out = (int)v;
    return RAD_OK;
}

static rad_status default_material(obj_reader *r, int *out)
{
    if (r->default_material < 0) {
        double zero[3] = {0, 0, 0};
        rad_status st = scene_add_material(r->s, "default", r->p->default_rho, zero);
        if (st != RAD_OK)
            return st;
        r->default_material = r->s->nm - 1;
    }
    *out = r->default_material;
    return RAD_OK;
}

static rad_status read_face(obj_reader *r, int line, char **save)
{
    rad_status st = RAD_OK;
    if (r->current_material < 0 && (st = default_material(r, &r->current_material)) != RAD_OK)
        return st;
    if (r->nf == r->cap_f) {
        if (r->cap_f >= (1 << 29))
            return RAD_ERROR(RAD_ETOOBIG, "%s:%d: more than 2^29 faces", r->path, line);
        int cap = r->cap_f ? 2 * r->cap_f : 64;
        obj_face *more = realloc(r->faces, (size_t)cap * sizeof *more);
        if (!more)
            return RAD_ERROR(RAD_ENOMEM, "%s:%d: no memory for %d faces", r->path, line, cap);
        r->faces = more;
        r->cap_f = cap;
    }
    obj_face *face = &r->faces[r->nf];
    *face = (obj_face){r->nc, 0, r->current_material, line};
    char *tok;
    while ((tok = strtok_r(NULL, " \t", save)) != NULL) {
        if (r->nc == r->cap_c) {
            size_t cap = r->cap_c ? 2 * r->cap_c : 256;
            int *more = realloc(r->corners, cap * sizeof *more);
            if (!more)
                return RAD_ERROR(RAD_ENOMEM, "%s:%d: no memory for %zu face corners", r->path,
                                 line, cap);
            r->corners = more;
            r->cap_c = cap;
        }
        if ((st = parse_corner(r, line, tok, &r->corners[r->nc])) != RAD_OK)
            return st;
        r->nc++;
        face->n++;
    }
    if (face->n < 3)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: a face needs at least 3 vertices, found %d", r->path,
                         line, face->n);
    r->nf++;
    return RAD_OK;
}

static rad_status use_material(obj_reader *r, int line, char **save)
{
    char *name = rest_of_line(save);
    int m = find_material(r->s, name);
    if (m >= 0) {
        r->current_material = m;
        return RAD_OK;
    }
    const char *why = r->nlib ? "" : "; the file has no mtllib";
    if (r->p->strict)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: material '%.63s' is not defined%s", r->path, line, name,
                         r->nlib ? " in the material libraries" : " (no mtllib before it)");
    rad_status st = default_material(r, &r->current_material);
    return st != RAD_OK ? st : note_add(&r->undefined, r->path, line, name, why);
}

static rad_status read_obj_line(obj_reader *r, int line, char *buf)
{
    char *save = NULL;
    if (strncmp(buf, "# radkit camera", 15) == 0) {
        strtok_r(buf, " \t", &save);  /* # */
        strtok_r(NULL, " \t", &save); /* radkit */
        strtok_r(NULL, " \t", &save); /* camera */
        return read_camera(r, line, &save);
    }
    char *key = strtok_r(buf, " \t", &save);
    if (!key || key[0] == '#')
        return RAD_OK;
    if (strcmp(key, "v") == 0)
        return read_vertex(r, line, &save);
    if (strcmp(key, "f") == 0)
        return read_face(r, line, &save);
    if (strcmp(key, "usemtl") == 0)
        return use_material(r, line, &save);
    if (strcmp(key, "mtllib") == 0) {
        char *name;
        rad_status st = RAD_OK;
        while (st == RAD_OK && (name = strtok_r(NULL, " \t", &save)) != NULL) {
            char *mtl = sibling_path(r->path, name);
            st = mtl ? read_mtl(r, mtl, line) : RAD_ERROR(RAD_ENOMEM, "no memory");
            free(mtl);
        }
        return st;
    }
    return ignore(r, r->path, line, key, kind_of(obj_keywords, key));
}

/* The counted warnings, in a fixed order. */
static rad_status report(obj_reader *r)
{
    rad_scene *s = r->s;
    const rad_scene_params *p = r->p;
    char def[160];
    if (p->has_emission)
        snprintf(def, sizeof def, "reflectance %g %g %g, emission %g %g %g", p->default_rho[0],
                 p->default_rho[1], p->default_rho[2], p->emission[0], p->emission[1],
                 p->emission[2]);
    else
        snprintf(def, sizeof def, "reflectance %g %g %g, no emission", p->default_rho[0],
                 p->default_rho[1], p->default_rho[2]);
    rad_status st = RAD_OK;
    if (r->kd_one.count)
        st = scene_warn(s, "%d Kd statement(s) give a reflectance of 1 (first at %s:%d), taken as "
                        "%g, the largest reflectance radkit gives a surface", r->kd_one.count,
                        r->kd_one.file, r->kd_one.line, p->rho_white);
    if (st == RAD_OK && r->missing_lib.count)
        st = scene_warn(s, "cannot open %d material librar%s (first '%s' at %s:%d: %s); their "
                        "materials are not defined", r->missing_lib.count,
                        r->missing_lib.count == 1 ? "y" : "ies", r->missing_lib.what,
                        r->missing_lib.file, r->missing_lib.line, r->missing_lib.detail);
    if (st == RAD_OK && r->undefined.count)
        st = scene_warn(s, "%d usemtl statement(s) name a material no library defines (first '%s' "
                        "at %s:%d%s); their faces take the default material (%s)",
                        r->undefined.count, r->undefined.what, r->undefined.file,
                        r->undefined.line, r->undefined.detail, def);
    for (int k = 0; k < r->nkw && st == RAD_OK; k++)
        st = scene_warn(s, "ignored %d `%s` statement(s) (first at %s:%d): %s", r->kw[k].n.count,
                        r->kw[k].n.what, r->kw[k].n.file, r->kw[k].n.line,
                        kind_reason[r->kw[k].kind]);
    if (st == RAD_OK && r->other_kw.count)
        st = scene_warn(s, "ignored %d more statement(s) with other keywords (first `%s` at %s:%d)",
                        r->other_kw.count, r->other_kw.what, r->other_kw.file, r->other_kw.line);
    return st;
}

/* Every index in range (forward references are legal), then the polygons in
 * file order. */
static rad_status triangulate(obj_reader *r)
{
    rad_scene *s = r->s;
    for (int f = 0; f < r->nf; f++) {
        const obj_face *face = &r->faces[f];
        const int *idx = r->corners + face->first;
        for (int k = 0; k < face->n; k++)
            if (idx[k] >= s->nv)
                return RAD_ERROR(RAD_EINPUT, "%s:%d: face index %d is out of range (%d vertices)",
                                 r->path, face->line, idx[k] + 1, s->nv);
        rad_status st = scene_add_polygon(s, idx, face->n, face->mat, f, face->line);
        if (st != RAD_OK)
            return st;
    }
    return RAD_OK;
}

static void note_free(note *n) { free(n->file); }

static void reader_free(obj_reader *r)
{
    free(r->corners);
    free(r->faces);
    for (int k = 0; k < r->nlib; k++)
        free(r->libraries[k]);
    free(r->libraries);
    note_free(&r->kd_one);
    note_free(&r->missing_lib);
    note_free(&r->undefined);
    note_free(&r->other_kw);
    for (int k = 0; k < r->nkw; k++)
        note_free(&r->kw[k].n);
}

rad_status scene_import_obj(rad_scene *s, const char *path, const rad_scene_params *p)
{
    obj_reader r;
    memset(&r, 0, sizeof r);
    r.s = s;
    r.path = path;
    r.p = p;
    r.current_material = r.default_material = -1;
    scene_text t;
    rad_status st = scene_text_open(&t, path, p->max_line_bytes, p->max_file_bytes, NULL);
    if (st != RAD_OK)
        return st;
    char *buf;
    while ((st = scene_text_next(&t, &buf)) == RAD_OK && buf)
        if ((st = read_obj_line(&r, t.line, buf)) != RAD_OK)
            break;
    scene_text_close(&t);
    if (st == RAD_OK && r.nf == 0) {
        if (r.nkw > 0 || r.other_kw.count > 0) {
            const note *first = r.nkw ? &r.kw[0].n : &r.other_kw;
            int count = r.other_kw.count;
            for (int k = 0; k < r.nkw; k++)
                count += r.kw[k].n.count;
            st = RAD_ERROR(RAD_EINPUT, "%s: no faces (empty scene); it has %d statement(s) radkit "
                           "ignores, the first `%s` at %s:%d", path, count, first->what,
                           first->file, first->line);
        } else {
            st = RAD_ERROR(RAD_EINPUT, "%s: no faces (empty scene)", path);
        }
    }
    if (st == RAD_OK)
        st = triangulate(&r);
    if (st == RAD_OK)
        st = report(&r);
    reader_free(&r);
    if (st != RAD_OK || p->no_cross_check)
        return st;
    /* The cross-check with Assimp. */
    long assimp_tris = 0, assimp_mats = 0;
    if (scene_assimp_count(path, &assimp_tris, &assimp_mats) != RAD_OK)
        return scene_warn(s, "Assimp could not read this file (%s); radkit's reader did",
                          rad_error_message());
    if (assimp_tris != s->nt)
        return scene_warn(s, "Assimp reads %ld triangles, radkit's reader %d", assimp_tris, s->nt);
    return RAD_OK;
}
