/* radkit's MGF reader: the Materials and Geometry Format [ward1995mgf] of
 * Radiance and RenderPark, in double precision with file:line messages.
 *
 *  1. Files.  Each file (the scene, and every `i` include, resolved relative
 *     to the folder of the file that names it) is read whole
 *     (scene_read_file: a regular file within max_file_bytes; a NUL byte is
 *     refused at its line).  A logical line ends at a newline not escaped by
 *     a backslash and may hold at most max_line_bytes; it splits into words
 *     at blanks, the first word being the entity.  Includes nest at most
 *     MGF_MAX_DEPTH deep, and a file that includes itself, directly or
 *     through others (same device and inode as a file being read), is
 *     refused naming the `i` line.
 *  2. Contexts.  Colours (`c`), materials (`m`) and vertices (`v`) follow the
 *     spec's get/set rules: `c` alone selects the unnamed context, reset to
 *     its default; `c id` selects a defined one (undefined: an error);
 *     `c id =` defines id afresh with the default values, `c id = tmpl` as a
 *     copy of tmpl; attribute entities (`cxy`, `cmix`; `rd`, `ed`, `sides`;
 *     `p`, `n`) change the current context.  Names are global.  A vertex is
 *     placed by the transform in force where a geometric entity uses it, not
 *     where it is defined (the spec's rule).  Objects (`o name` ... `o`) are
 *     only checked for balance.
 *  3. Transforms.  `xf args` opens a context whose transform is applied to
 *     geometry after the transforms of the inner contexts, before those of
 *     the outer ones; each argument (-t dx dy dz, -rx/-ry/-rz degrees
 *     counter-clockwise, -s factor, -mx/-my/-mz mirrors) acts on the object
 *     as already moved by the arguments before it.  `-i N` repeats the
 *     arguments up to the next -i or -a N times; `-a N` makes an array: the
 *     arguments that follow it (up to the next -a) are applied k times in
 *     instance k = 0..N-1, several -a make a grid, and the entities of the
 *     context are read again for each instance (the reader returns to the
 *     line after `xf`).  `i file args` wraps the include in such a context.
 *     A transform with a negative determinant (an odd number of mirrors, a
 *     negative scale) reverses every polygon's corner order, so that front
 *     sides stay front sides.  An `xf` or `o` must end in the file that opened
 *     it; one left open, or an end without an open context, is an error
 *     naming the line.  The work is bounded whatever the input: arrays make
 *     at most MGF_MAX_INSTANCES instances of any entity, files are read at
 *     most MGF_MAX_READS times in all, at most MGF_MAX_STATEMENTS entities
 *     are executed (replays counted), and the triangles may not exceed
 *     max_triangles.
 *  4. Geometry.  `f v1 v2 v3 ...` goes through scene_add_polygon (the fan
 *     when it does not fold, else ear clipping; self-intersecting polygons
 *     are refused), as in every reader.  `fh v1 v2 v3 ... - h1 h2 h3 ... -
 *     ...` (MGF 2.0: contours separated by a lone `-`, the outer one first,
 *     holes in either order) goes through scene_add_polygon_holes: each
 *     hole bridged to the outer ring, the result ear clipped; a contour of
 *     fewer than 3 vertices, a stray `-`, a hole outside the outer contour
 *     or inside another, or crossing contours are errors at the line.  The
 *     triangles of every face keep its file and line, an included file's
 *     too (scene_set_file), for the messages about them.  The curved
 *     primitives are tessellated:
 *       sph vc r            latitude/longitude bands (negative r: inward);
 *       cyl v1 r v2         an open tube from v1 to v2;
 *       cone v1 r1 v2 r2    an open truncated cone (a radius may be 0);
 *       ring vc rmin rmax   an annulus (a disc for rmin 0) facing vc's normal;
 *       torus vc rmin rmax  about vc's normal, tube radius (rmax-rmin)/2;
 *       prism v1..vN len    the face, its copy moved by len against the face
 *                           normal (reversed), and N side quadrilaterals.
 *     Tolerance: every circle is cut into n equal arcs with
 *     n = max(4, ceil(pi / acos(1 - curve_tol))), the fewest for which a
 *     chord's sagitta r (1 - cos(pi/n)) is at most curve_tol times the
 *     radius r: the tessellation stays within curve_tol x radius of the true
 *     surface.  A sphere takes ceil(n/2) latitude bands, a torus n steps
 *     around its tube.  The facets are inscribed, so the area is short by
 *     a relative O(n^-2) = O(curve_tol): (2 pi/n)^2 / 6 ~ (4/3) curve_tol for
 *     a disc or ring, (pi/n)^2 / 6 ~ curve_tol / 3 for a cylinder, about
 *     (5/3) curve_tol for a sphere (papers/mgf.md has the measured figures;
 *     tests/test_mgf.c checks 0 <= error <= 4 curve_tol and the decrease).
 *     The default, 0.0125, gives n = 20, mgflib's 5 divisions per quarter
 *     circle.  Facets are planar (isosceles trapezoids and triangles) and
 *     each is its own face.
 *  5. Materials and colour.  Colour is CIE xy chromaticity (`cxy`; `cmix`
 *     adds its colours' XYZ with each weight as the luminance Y; `cspec` and
 *     `cct`, a spectrum and a blackbody, through the CIE 1931 observer
 *     (cie.c); the default is x = y = 1/3, the equal-energy white).  `rd r` takes the current
 *     colour; the reflectance per channel is rgb = M (X, Y, Z) with Y = r,
 *     X = x Y / y, Z = (1 - x - y) Y / y and M the XYZ -> RGB matrix of
 *     Radiance's primaries (R 0.640 0.330, G 0.290 0.600, B 0.150 0.060)
 *     balanced for the equal-energy white: M maps (1, 1, 1) to (1, 1, 1), so
 *     a neutral colour gives r g b = rd exactly (up to rounding).  `ed e`
 *     does the same with Y = e: the exitance per channel in the file's units
 *     (lumens/m^2 for MGF; radkit's radiosities are then in the same units).
 *     A channel below zero (a colour outside the primaries' gamut) is taken
 *     as 0, and a reflectance channel at or above 1 as rho_white, each with
 *     one counted warning naming the material (refused in strict mode); rd
 *     outside [0, 1] and a negative ed are errors at their line.  A material
 *     becomes a radkit material when a face first uses it with its current
 *     values (the unnamed default material is black and dark, as the spec
 *     says).  Sides: radkit's triangles are one-sided, the front given by
 *     the corner order (right-hand rule).  A face of a material with `sides
 *     1` is made as given; with `sides 2`, the spec's default (and the
 *     unnamed material's), it is followed by its back, the same triangles
 *     reversed with the same material, as a face of its own: a thin sheet
 *     that reflects and emits on both sides, as RenderPark makes it.  One
 *     counted warning says how many faces were doubled (closed solids should
 *     say `sides 1`: their inner sides are otherwise solved as a dark
 *     cavity); scene_finish does not count these pairs as coincident faces.
 *  6. What radkit does not use loads with one counted warning per entity
 *     naming its first place: specular and transmission (`rs`, `ts`, `td`,
 *     `ir`: radkit's surfaces are opaque and diffuse), `ies` luminaires and
 *     unknown entities (the spec asks readers to skip, with a warning, the
 *     entities they do not support).  Strict mode refuses all but the first
 *     group. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "rad_geom.h"
#include "scene_internal.h"

enum {
    MGF_MAX_DEPTH = 16,           /* include nesting */
    MGF_MAX_INSTANCES = 1000000,  /* product of the array counts in force */
    MGF_MAX_XF_OPS = 256,         /* transform arguments of one xf */
    MGF_MAX_SEGMENTS = 4096,      /* circle segments, whatever the tolerance */
    MGF_MAX_READS = 65536         /* file reads in all (includes, and their array instances) */
};

/* Entities executed in all, array replays and includes counted: a bound on
 * the time any input can take (a real scene within max_triangles needs fewer). */
static const long long MGF_MAX_STATEMENTS = 400000000LL;

/* ---- names -------------------------------------------------------------- */

/* A string -> index map, open addressing (FNV-1a). */
typedef struct mgf_names {
    char **key;
    int *val;
    size_t cap, n;
} mgf_names;

static uint64_t hash_name(const char *s)
{
    uint64_t h = 1469598103934665603ull;
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return h;
}

static int names_find(const mgf_names *m, const char *name)
{
    if (!m->cap)
        return -1;
    for (size_t i = hash_name(name) & (m->cap - 1);; i = (i + 1) & (m->cap - 1)) {
        if (!m->key[i])
            return -1;
        if (strcmp(m->key[i], name) == 0)
            return m->val[i];
    }
}

static int names_put(mgf_names *m, const char *name, int val)
{
    if (2 * (m->n + 1) > m->cap) {
        size_t cap = m->cap ? 2 * m->cap : 64;
        char **key = calloc(cap, sizeof *key);
        int *v = calloc(cap, sizeof *v);
        if (!key || !v) {
            free(key);
            free(v);
            return 0;
        }
        for (size_t i = 0; i < m->cap; i++)
            if (m->key[i]) {
                size_t j = hash_name(m->key[i]) & (cap - 1);
                while (key[j])
                    j = (j + 1) & (cap - 1);
                key[j] = m->key[i];
                v[j] = m->val[i];
            }
        free(m->key);
        free(m->val);
        m->key = key;
        m->val = v;
        m->cap = cap;
    }
    size_t i = hash_name(name) & (m->cap - 1);
    while (m->key[i] && strcmp(m->key[i], name) != 0)
        i = (i + 1) & (m->cap - 1);
    if (!m->key[i]) {
        m->key[i] = strdup(name);
        if (!m->key[i])
            return 0;
        m->n++;
    }
    m->val[i] = val;
    return 1;
}

static void names_free(mgf_names *m)
{
    for (size_t i = 0; i < m->cap; i++)
        free(m->key[i]);
    free(m->key);
    free(m->val);
}

/* ---- contexts ----------------------------------------------------------- */

typedef struct mgf_color {
    double x, y;
} mgf_color;

typedef struct mgf_material {
    double rd, ed;
    mgf_color rd_c, ed_c;
    int sides;     /* 2 (the default): its faces are made on both sides; 1: front only */
    int rad_index; /* radkit material with these values, -1 until a face uses them */
    char name[64];
} mgf_material;

typedef struct mgf_vertex {
    double p[3], n[3];
} mgf_vertex;

typedef enum xf_op_kind { XF_T, XF_RX, XF_RY, XF_RZ, XF_S, XF_MX, XF_MY, XF_MZ } xf_op_kind;

typedef struct xf_op {
    xf_op_kind kind;
    double v[3];
} xf_op;

/* x -> A x + b */
typedef struct affine {
    double a[3][3], b[3];
} affine;

/* One xf context: its arguments as segments (plain, repeated -i N, array -a N). */
typedef struct xf_context {
    xf_op *ops;
    int nops;
    int seg_start[MGF_MAX_XF_OPS + 1], seg_kind[MGF_MAX_XF_OPS + 1], seg_count[MGF_MAX_XF_OPS + 1];
    int nseg;
    int k[MGF_MAX_XF_OPS + 1]; /* array odometer, per segment */
    long long instances;       /* product of the array counts of this context */
    affine total;              /* outer contexts' transform after this one's */
    int reverse;               /* det(total) < 0 */
    int depth;                 /* file it was opened in */
    int line;                  /* its line there */
    const char *restart;       /* where its entities start, for the next instance */
    int restart_line;
    long long outer_instances; /* product of the array counts in force around it */
} xf_context;

/* An open file. */
typedef struct mgf_file {
    const char *path;
    char *data;
    const char *p, *end;
    int line;      /* first line of the current logical line */
    int next_line; /* line number of the next line to read */
    dev_t dev;
    ino_t ino;
} mgf_file;

/* A counted warning: how many, and the first place. */
typedef struct mgf_note {
    int count;
    char what[48];
    char file[256];
    int line;
} mgf_note;

enum { NOTE_SPECULAR, NOTE_IES, NOTE_UNKNOWN, NOTE_GAMUT, NOTE_WHITE, NOTE_TWO_SIDED,
       NOTE_COUNT };

typedef struct mgf_reader {
    rad_scene *s;
    const rad_scene_params *p;
    double rgb_from_xyz[3][3];
    int segments;      /* per full circle */
    mgf_names cnames, mnames, vnames;
    mgf_names fnames;  /* included file -> its number in the scene (scene_add_file) */
    mgf_color *colors;
    int ncolors, cap_colors;
    mgf_material *mats;
    int nmats, cap_mats;
    mgf_vertex *verts;
    int nverts, cap_verts;
    mgf_color ucolor;   /* the unnamed contexts */
    mgf_material umat;
    mgf_vertex uvert;
    int ccolor_i, cmat_i, cvert_i; /* current contexts; -1: the unnamed one */
    xf_context *xf;
    int nxf, cap_xf;
    int *obj_line, *obj_depth;
    int nobj, cap_obj;
    mgf_file *files[MGF_MAX_DEPTH + 1];
    int depth;
    int face;          /* faces emitted */
    int *idx;          /* corner scratch */
    int *count;        /* `fh`: corners per contour */
    int cap_count;
    int cap_idx;
    double *pts;       /* 3 per generated point */
    size_t cap_pts;
    char *logical;     /* the current logical line */
    char **argv;
    int cap_argv;
    mgf_note notes[NOTE_COUNT];
    mgf_note unknown[32];
    int nunknown;
    long long reads, statements;
} mgf_reader;

static const affine AFFINE_IDENTITY = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 0, 0}};

/* ---- messages ----------------------------------------------------------- */

static mgf_file *cur(mgf_reader *r) { return r->files[r->depth]; }

static rad_status bad(mgf_reader *r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* RAD_EINPUT at the current file:line. */
static rad_status bad(mgf_reader *r, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    mgf_file *f = cur(r);
    return RAD_ERROR(RAD_EINPUT, "%s:%d: %s", f->path, f->line, msg);
}

static rad_status no_memory(mgf_reader *r)
{
    return RAD_ERROR(RAD_ENOMEM, "%s:%d: no memory", cur(r)->path, cur(r)->line);
}

static void note(mgf_reader *r, mgf_note *n, const char *what)
{
    if (n->count++ == 0) {
        snprintf(n->what, sizeof n->what, "%s", what);
        snprintf(n->file, sizeof n->file, "%s", cur(r)->path);
        n->line = cur(r)->line;
    }
}

/* ---- numbers ------------------------------------------------------------ */

static rad_status number(mgf_reader *r, const char *tok, const char *what, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(tok, &end);
    if (end == tok || *end)
        return bad(r, "%s '%.40s' is not a number", what, tok);
    if (!isfinite(v))
        return bad(r, "%s is %s", what, isnan(v) ? "NaN" : "infinite");
    *out = v;
    return RAD_OK;
}

static rad_status integer(mgf_reader *r, const char *tok, const char *what, long lo, long hi,
                          long *out)
{
    char *end;
    errno = 0;
    long v = strtol(tok, &end, 10);
    if (end == tok || *end)
        return bad(r, "%s '%.40s' is not an integer", what, tok);
    if (errno == ERANGE || v < lo || v > hi)
        return bad(r, "%s %.40s is out of range [%ld, %ld]", what, tok, lo, hi);
    *out = v;
    return RAD_OK;
}

static rad_status expect_args(mgf_reader *r, int argc, int lo, int hi)
{
    if (argc < lo || argc > hi) {
        if (lo == hi)
            return bad(r, "`%s` takes %d argument%s, got %d", r->argv[0], lo - 1,
                       lo == 2 ? "" : "s", argc - 1);
        return bad(r, "`%s` takes %d to %d arguments, got %d", r->argv[0], lo - 1, hi - 1, argc - 1);
    }
    return RAD_OK;
}

/* ---- colour ------------------------------------------------------------- */

static double det3(const double m[3][3])
{
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

static void invert3(const double m[3][3], double out[3][3])
{
    double d = det3(m);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
            out[i][j] = (m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]) / d;
        }
}

/* XYZ -> RGB for Radiance's primaries and the equal-energy white (step 5). */
static void rgb_matrix(double out[3][3])
{
    static const double xy[3][2] = {{0.640, 0.330}, {0.290, 0.600}, {0.150, 0.060}};
    double P[3][3], Pi[3][3];
    for (int c = 0; c < 3; c++) {
        P[0][c] = xy[c][0] / xy[c][1];
        P[1][c] = 1.0;
        P[2][c] = (1.0 - xy[c][0] - xy[c][1]) / xy[c][1];
    }
    invert3(P, Pi);
    double S[3]; /* the primaries' luminances that add up to white (1, 1, 1) */
    for (int c = 0; c < 3; c++)
        S[c] = Pi[c][0] + Pi[c][1] + Pi[c][2];
    double M[3][3];
    for (int i = 0; i < 3; i++)
        for (int c = 0; c < 3; c++)
            M[i][c] = P[i][c] * S[c];
    invert3(M, out);
}

/* rgb of chromaticity c at luminance Y.  Chromaticities within 1e-12 of
 * (1/3, 1/3) are the equal-energy white, whose channels are Y exactly (1/3
 * has no exact double, and the matrix product would differ in the last bit). */
static void color_rgb(const mgf_reader *r, mgf_color c, double Y, double rgb[3])
{
    if (fabs(c.x - 1.0 / 3.0) < 1e-12 && fabs(c.y - 1.0 / 3.0) < 1e-12) {
        rgb[0] = rgb[1] = rgb[2] = Y;
        return;
    }
    double X = c.x * Y / c.y, Z = (1.0 - c.x - c.y) * Y / c.y, xyz[3] = {X, Y, Z};
    for (int i = 0; i < 3; i++)
        rgb[i] = r->rgb_from_xyz[i][0] * xyz[0] + r->rgb_from_xyz[i][1] * xyz[1] +
                 r->rgb_from_xyz[i][2] * xyz[2];
}

/* ---- transforms --------------------------------------------------------- */

/* out = a after b (x -> a(b(x))) */
static affine compose(const affine *a, const affine *b)
{
    affine o;
    for (int i = 0; i < 3; i++) {
        o.b[i] = a->b[i];
        for (int j = 0; j < 3; j++) {
            o.a[i][j] = 0;
            for (int k = 0; k < 3; k++)
                o.a[i][j] += a->a[i][k] * b->a[k][j];
            o.b[i] += a->a[i][j] * b->b[j];
        }
    }
    return o;
}

static affine op_affine(const xf_op *op)
{
    affine t = AFFINE_IDENTITY;
    double c, s;
    switch (op->kind) {
    case XF_T:
        for (int i = 0; i < 3; i++)
            t.b[i] = op->v[i];
        break;
    case XF_RX:
    case XF_RY:
    case XF_RZ: {
        double rad = op->v[0] * (RAD_PI / 180.0);
        c = cos(rad);
        s = sin(rad);
        int i = op->kind == XF_RX ? 1 : op->kind == XF_RY ? 2 : 0;
        int j = (i + 1) % 3; /* rotate i towards j: (y,z), (z,x), (x,y) */
        t.a[i][i] = c;
        t.a[i][j] = -s;
        t.a[j][i] = s;
        t.a[j][j] = c;
        break;
    }
    case XF_S:
        for (int i = 0; i < 3; i++)
            t.a[i][i] = op->v[0];
        break;
    case XF_MX:
        t.a[0][0] = -1;
        break;
    case XF_MY:
        t.a[1][1] = -1;
        break;
    case XF_MZ:
        t.a[2][2] = -1;
        break;
    }
    return t;
}

/* The context's own transform for its current instance. */
static affine xf_own(const xf_context *x)
{
    affine t = AFFINE_IDENTITY;
    for (int g = 0; g < x->nseg; g++) {
        int times = x->seg_kind[g] == 0 ? 1 : x->seg_kind[g] == 1 ? x->seg_count[g] : x->k[g];
        for (int rep = 0; rep < times; rep++)
            for (int o = x->seg_start[g]; o < x->seg_start[g + 1]; o++) {
                affine a = op_affine(&x->ops[o]);
                t = compose(&a, &t);
            }
    }
    return t;
}

static void xf_pop(mgf_reader *r)
{
    free(r->xf[r->nxf - 1].ops);
    r->nxf--;
}

static const affine *current_xf(const mgf_reader *r)
{
    return r->nxf ? &r->xf[r->nxf - 1].total : &AFFINE_IDENTITY;
}

static void xf_update(mgf_reader *r, xf_context *x)
{
    affine own = xf_own(x);
    const affine *outer = x == r->xf ? &AFFINE_IDENTITY : &x[-1].total;
    x->total = compose(outer, &own);
    x->reverse = det3(x->total.a) < 0;
}

static rad_status xf_parse(mgf_reader *r, xf_context *x, char **argv, int argc);

/* Parse transform arguments argv[0..argc-1] and open a context (nothing is
 * left open on failure). */
static rad_status xf_push(mgf_reader *r, char **argv, int argc)
{
    if (r->nxf == r->cap_xf) {
        int cap = r->cap_xf ? 2 * r->cap_xf : 8;
        if (cap > 4096)
            return bad(r, "transform contexts nest more than 4096 deep");
        xf_context *q = realloc(r->xf, (size_t)cap * sizeof *q);
        if (!q)
            return no_memory(r);
        r->xf = q;
        r->cap_xf = cap;
    }
    xf_context *x = &r->xf[r->nxf];
    memset(x, 0, sizeof *x);
    if (argc > 0 && !(x->ops = malloc((size_t)argc * sizeof *x->ops)))
        return no_memory(r);
    rad_status st = xf_parse(r, x, argv, argc);
    if (st != RAD_OK) {
        free(x->ops);
        return st;
    }
    r->nxf++;
    x->outer_instances = r->nxf > 1 ? x[-1].outer_instances * x[-1].instances : 1;
    if (x->outer_instances * x->instances > MGF_MAX_INSTANCES) {
        xf_pop(r);
        return bad(r, "nested arrays make more than %d instances", MGF_MAX_INSTANCES);
    }
    x->depth = r->depth;
    x->line = cur(r)->line;
    x->restart = cur(r)->p;
    x->restart_line = cur(r)->next_line;
    xf_update(r, x);
    return RAD_OK;
}

static rad_status xf_parse(mgf_reader *r, xf_context *x, char **argv, int argc)
{
    x->seg_start[0] = 0;
    x->nseg = 1;
    x->instances = 1;
    for (int a = 0; a < argc;) {
        const char *w = argv[a];
        xf_op op = {XF_T, {0, 0, 0}};
        rad_status st;
        if (x->nops >= MGF_MAX_XF_OPS || x->nseg > MGF_MAX_XF_OPS)
            return bad(r, "more than %d transform arguments", MGF_MAX_XF_OPS);
        if (strcmp(w, "-a") == 0 || strcmp(w, "-i") == 0) {
            long n;
            if (a + 1 >= argc)
                return bad(r, "`%s` needs a count", w);
            if ((st = integer(r, argv[a + 1], w[1] == 'a' ? "array count" : "repeat count", 1,
                              MGF_MAX_INSTANCES, &n)) != RAD_OK)
                return st;
            x->seg_start[x->nseg] = x->nops;
            x->seg_kind[x->nseg] = w[1] == 'a' ? 2 : 1;
            x->seg_count[x->nseg] = (int)n;
            x->nseg++;
            if (w[1] == 'a')
                x->instances *= n;
            if (x->instances > MGF_MAX_INSTANCES)
                return bad(r, "arrays of more than %d instances", MGF_MAX_INSTANCES);
            a += 2;
            continue;
        }
        int nv = 0;
        if (strcmp(w, "-t") == 0)
            op.kind = XF_T, nv = 3;
        else if (strcmp(w, "-rx") == 0)
            op.kind = XF_RX, nv = 1;
        else if (strcmp(w, "-ry") == 0)
            op.kind = XF_RY, nv = 1;
        else if (strcmp(w, "-rz") == 0)
            op.kind = XF_RZ, nv = 1;
        else if (strcmp(w, "-s") == 0)
            op.kind = XF_S, nv = 1;
        else if (strcmp(w, "-mx") == 0)
            op.kind = XF_MX;
        else if (strcmp(w, "-my") == 0)
            op.kind = XF_MY;
        else if (strcmp(w, "-mz") == 0)
            op.kind = XF_MZ;
        else if (strcmp(w, "-n") == 0 && a + 1 < argc) {
            a += 2; /* an instance name: nothing to do */
            continue;
        } else
            return bad(r, "unknown transform argument '%.40s'", w);
        if (a + nv >= argc + (nv == 0))
            return bad(r, "`%s` needs %d number%s", w, nv, nv == 1 ? "" : "s");
        for (int k = 0; k < nv; k++)
            if ((st = number(r, argv[a + 1 + k], w, &op.v[k])) != RAD_OK)
                return st;
        if (op.kind == XF_S && op.v[0] == 0.0)
            return bad(r, "a scale factor of 0");
        x->ops[x->nops++] = op;
        a += 1 + nv;
    }
    x->seg_start[x->nseg] = x->nops;
    return RAD_OK;
}

/* Advance the innermost context's array odometer: 1 when another instance
 * follows (the transform updated), 0 after the last. */
static int xf_next_instance(mgf_reader *r)
{
    xf_context *x = &r->xf[r->nxf - 1];
    for (int g = x->nseg - 1; g >= 0; g--) {
        if (x->seg_kind[g] != 2)
            continue;
        if (++x->k[g] < x->seg_count[g]) {
            xf_update(r, x);
            return 1;
        }
        x->k[g] = 0;
    }
    return 0;
}

/* ---- geometry ----------------------------------------------------------- */

static rad_status material_index(mgf_reader *r, int *out)
{
    mgf_material *m = r->cmat_i < 0 ? &r->umat : &r->mats[r->cmat_i];
    if (m->rad_index < 0) {
        double rho[3], e[3];
        color_rgb(r, m->rd_c, m->rd, rho);
        color_rgb(r, m->ed_c, m->ed, e);
        int gamut = 0, white = 0;
        for (int k = 0; k < 3; k++) {
            if (rho[k] < 0 || e[k] < 0)
                gamut = 1;
            if (rho[k] < 0)
                rho[k] = 0;
            if (e[k] < 0)
                e[k] = 0;
            if (rho[k] >= r->p->rho_white) {
                white = 1;
                rho[k] = r->p->rho_white;
            }
        }
        const char *name = m->name[0] ? m->name : "(unnamed)";
        if (gamut && r->p->strict)
            return bad(r, "material '%s': its colour lies outside the RGB primaries' gamut "
                          "(a negative channel; refused in strict mode)", name);
        if (white && r->p->strict)
            return bad(r, "material '%s': a reflectance channel of %g or more (refused in strict "
                          "mode)", name, r->p->rho_white);
        if (gamut)
            note(r, &r->notes[NOTE_GAMUT], name);
        if (white)
            note(r, &r->notes[NOTE_WHITE], name);
        rad_status st = scene_add_material(r->s, m->name[0] ? m->name : "mgf-default", rho, e);
        if (st != RAD_OK)
            return st;
        m->rad_index = r->s->nm - 1;
    }
    *out = m->rad_index;
    return RAD_OK;
}

/* Add the n points pts (file coordinates) transformed, their indices in r->idx. */
static rad_status add_points(mgf_reader *r, const double *pts, int n)
{
    if (n > r->cap_idx) {
        int *q = realloc(r->idx, (size_t)n * sizeof *q);
        if (!q)
            return no_memory(r);
        r->idx = q;
        r->cap_idx = n;
    }
    const affine *t = current_xf(r);
    for (int i = 0; i < n; i++) {
        double q[3];
        for (int k = 0; k < 3; k++)
            q[k] = t->a[k][0] * pts[3 * i] + t->a[k][1] * pts[3 * i + 1] +
                   t->a[k][2] * pts[3 * i + 2] + t->b[k];
        rad_status st;
        for (int k = 0; k < 3; k++) {
            if (!isfinite(q[k]))
                return bad(r, "a transformed coordinate overflows");
            if ((st = scene_check_coordinate(cur(r)->path, cur(r)->line, r->s->nv, q[k],
                                             r->p->scale)) != RAD_OK)
                return st;
        }
        if ((st = scene_add_vertex(r->s, q[0], q[1], q[2])) != RAD_OK)
            return st;
        r->idx[i] = r->s->nv - 1;
    }
    return RAD_OK;
}

/* One face (file coordinates) of the current material: ncontours contours of
 * count[c] points each, one after the other in pts, the outer boundary first
 * and then its holes (`fh`); `flip` reverses it.  The face of a two-sided
 * material is followed by its back: the same triangles reversed, with the
 * same material, as a face of its own (step 5). */
static rad_status emit_face(mgf_reader *r, const double *pts, const int *count, int ncontours,
                            int flip)
{
    const mgf_material *m = r->cmat_i < 0 ? &r->umat : &r->mats[r->cmat_i];
    long long n = 0;
    for (int c = 0; c < ncontours; c++)
        n += count[c];
    if (r->s->nt + (n + 2LL * ncontours - 4) * m->sides > (long long)r->p->max_triangles)
        return RAD_ERROR(RAD_ETOOBIG, "%s:%d: more than %zu triangles", cur(r)->path,
                         cur(r)->line, r->p->max_triangles);
    int mat = 0;
    rad_status st = material_index(r, &mat);
    if (st == RAD_OK)
        st = add_points(r, pts, (int)n);
    if (st != RAD_OK)
        return st;
    if (flip != (r->nxf ? r->xf[r->nxf - 1].reverse : 0))
        for (int c = 0, at = 0; c < ncontours; at += count[c++])
            for (int i = at, j = at + count[c] - 1; i < j; i++, j--) {
                int t = r->idx[i];
                r->idx[i] = r->idx[j];
                r->idx[j] = t;
            }
    int t0 = r->s->nt, line = cur(r)->line;
    st = ncontours == 1 ? scene_add_polygon(r->s, r->idx, count[0], mat, r->face++, line)
                        : scene_add_polygon_holes(r->s, r->idx, count, ncontours, mat, r->face++,
                                                  line);
    if (st != RAD_OK || m->sides == 1)
        return st;
    int back = r->face++, t1 = r->s->nt;
    note(r, &r->notes[NOTE_TWO_SIDED], m->name[0] ? m->name : "(unnamed)");
    st = scene_mark_back_face(r->s, back);
    for (int t = t0; t < t1 && st == RAD_OK; t++) {
        const int *v = r->s->tri + 3 * (size_t)t;
        int a = v[0], b = v[1], c = v[2]; /* read before the array may move */
        st = scene_add_triangle(r->s, c, b, a, mat, back, line);
    }
    return st;
}

/* One polygon (file coordinates) of the current material; `flip` reverses it. */
static rad_status emit(mgf_reader *r, const double *pts, int n, int flip)
{
    return emit_face(r, pts, &n, 1, flip);
}

static rad_status vertex_ref(mgf_reader *r, const char *name, const mgf_vertex **out)
{
    int i = names_find(&r->vnames, name);
    if (i < 0)
        return bad(r, "undefined vertex '%.60s'", name);
    *out = &r->verts[i];
    return RAD_OK;
}

static double *points(mgf_reader *r, size_t n)
{
    if (3 * n > r->cap_pts) {
        double *q = realloc(r->pts, 3 * n * sizeof *q);
        if (!q)
            return NULL;
        r->pts = q;
        r->cap_pts = 3 * n;
    }
    return r->pts;
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double norm(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

/* An orthonormal frame (u, v, w) with w along axis (unit). */
static void frame(const double w[3], double u[3], double v[3])
{
    double h[3] = {0, 0, 0};
    int k = fabs(w[0]) <= fabs(w[1]) && fabs(w[0]) <= fabs(w[2]) ? 0 : fabs(w[1]) <= fabs(w[2]) ? 1 : 2;
    h[k] = 1;
    cross(w, h, u);
    double nu = norm(u);
    for (int i = 0; i < 3; i++)
        u[i] /= nu;
    cross(w, u, v);
}

/* A surface of revolution about centre + h w: the profile (rho[k], h[k]),
 * k = 0..K, swept around w in r->segments steps.  Facet (k, j) has the
 * corners (k, j), (k+1, j), (k+1, j+1), (k, j+1), normal along
 * d(rho) w - d(h) radial; `flip` reverses every facet. */
static rad_status revolve(mgf_reader *r, const double c[3], const double w[3], const double *rho,
                          const double *h, int K, int flip)
{
    int n = r->segments;
    double u[3], v[3];
    frame(w, u, v);
    double *ring = points(r, 2 * (size_t)(n + 1) + 4);
    if (!ring)
        return no_memory(r);
    for (int k = 0; k < K; k++)
        for (int j = 0; j < n; j++) {
            double quad[12];
            int m = 0;
            const int kk[4] = {k, k + 1, k + 1, k}, jj[4] = {j, j, j + 1, j + 1};
            for (int q = 0; q < 4; q++) {
                double phi = 2.0 * RAD_PI * (jj[q] % n) / n, cs = cos(phi), sn = sin(phi);
                double pt[3];
                for (int i = 0; i < 3; i++)
                    pt[i] = c[i] + h[kk[q]] * w[i] + rho[kk[q]] * (cs * u[i] + sn * v[i]);
                /* a corner on the axis is shared by both of its facet's sides */
                if (rho[kk[q]] == 0.0 && m > 0 && memcmp(quad + 3 * (m - 1), pt, sizeof pt) == 0)
                    continue;
                if (rho[kk[q]] == 0.0 && q == 3 && memcmp(quad, pt, sizeof pt) == 0)
                    continue;
                memcpy(quad + 3 * m, pt, sizeof pt);
                m++;
            }
            if (m < 3)
                continue;
            rad_status st = emit(r, quad, m, flip);
            if (st != RAD_OK)
                return st;
        }
    return RAD_OK;
}

/* A vertex's normal, unit; RAD_EINPUT when it has none. */
static rad_status vertex_normal(mgf_reader *r, const char *name, const mgf_vertex *vx, double w[3])
{
    double len = norm(vx->n);
    if (!(len > 0))
        return bad(r, "`%s` needs a normal at vertex '%.60s' (an `n` entity)", r->argv[0], name);
    for (int i = 0; i < 3; i++)
        w[i] = vx->n[i] / len;
    return RAD_OK;
}

static rad_status ent_face(mgf_reader *r, int argc)
{
    if (argc < 4)
        return bad(r, "`f` needs at least 3 vertices, got %d", argc - 1);
    double *pts = points(r, (size_t)argc);
    if (!pts)
        return no_memory(r);
    for (int i = 1; i < argc; i++) {
        const mgf_vertex *vx = NULL;
        rad_status st = vertex_ref(r, r->argv[i], &vx);
        if (st != RAD_OK)
            return st;
        memcpy(pts + 3 * (i - 1), vx->p, sizeof vx->p);
    }
    return emit(r, pts, argc - 1, 0);
}

/* fh v1 v2 v3 ... [- h1 h2 h3 ... [- ...]]: a face with holes, the contours
 * separated by a lone `-`. */
static rad_status ent_face_holes(mgf_reader *r, int argc)
{
    int ncontours = 1;
    for (int i = 1; i < argc; i++)
        ncontours += strcmp(r->argv[i], "-") == 0;
    if (ncontours > r->cap_count) {
        int *q = realloc(r->count, (size_t)ncontours * sizeof *q);
        if (!q)
            return no_memory(r);
        r->count = q;
        r->cap_count = ncontours;
    }
    double *pts = points(r, (size_t)argc);
    if (!pts)
        return no_memory(r);
    if (argc < 4)
        return bad(r, "`fh` needs at least 3 vertices, got %d", argc - 1);
    int c = 0, n = 0;
    r->count[0] = 0;
    for (int i = 1; i <= argc; i++) {
        if (i == argc || strcmp(r->argv[i], "-") == 0) {
            if (r->count[c] == 0)
                return bad(r, "`fh`: a stray `-` (argument %d): a `-` separates two contours, "
                              "the outer one first", i == argc ? i - 1 : i);
            if (r->count[c] < 3 && c == 0)
                return bad(r, "`fh`: the outer contour has %d vertices; it needs at least 3",
                           r->count[c]);
            if (r->count[c] < 3)
                return bad(r, "`fh`: hole %d has %d vertices; it needs at least 3", c, r->count[c]);
            if (i < argc)
                r->count[++c] = 0;
            continue;
        }
        const mgf_vertex *vx = NULL;
        rad_status st = vertex_ref(r, r->argv[i], &vx);
        if (st != RAD_OK)
            return st;
        memcpy(pts + 3 * n++, vx->p, sizeof vx->p);
        r->count[c]++;
    }
    return emit_face(r, pts, r->count, ncontours, 0);
}

static rad_status ent_prism(mgf_reader *r, int argc)
{
    if (argc < 5)
        return bad(r, "`prism` needs at least 3 vertices and a length");
    int n = argc - 2;
    double len;
    rad_status st = number(r, r->argv[argc - 1], "prism length", &len);
    if (st != RAD_OK)
        return st;
    if (len == 0.0)
        return bad(r, "a prism of length 0");
    double *base = malloc(2 * 3 * (size_t)n * sizeof *base);
    if (!base)
        return no_memory(r);
    double *top = base + 3 * (size_t)n, N[3] = {0, 0, 0};
    for (int i = 0; i < n && st == RAD_OK; i++) {
        const mgf_vertex *vx = NULL;
        if ((st = vertex_ref(r, r->argv[1 + i], &vx)) == RAD_OK)
            memcpy(base + 3 * i, vx->p, sizeof vx->p);
    }
    for (int i = 0; i < n && st == RAD_OK; i++) { /* Newell's normal */
        const double *a = base + 3 * i, *b = base + 3 * ((i + 1) % n);
        N[0] += (a[1] - b[1]) * (a[2] + b[2]);
        N[1] += (a[2] - b[2]) * (a[0] + b[0]);
        N[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    double nl = norm(N);
    if (st == RAD_OK && !(nl > 0))
        st = bad(r, "the prism's face has no area (no normal to extrude along)");
    if (st == RAD_OK) {
        for (int i = 0; i < n; i++)
            for (int k = 0; k < 3; k++)
                top[3 * (n - 1 - i) + k] = base[3 * i + k] - len * N[k] / nl;
        st = emit(r, base, n, 0);
    }
    if (st == RAD_OK)
        st = emit(r, top, n, 0);
    for (int i = 0; i < n && st == RAD_OK; i++) {
        int j = (i + 1) % n;
        double quad[12];
        memcpy(quad, base + 3 * i, 3 * sizeof *quad);
        memcpy(quad + 3, top + 3 * (n - 1 - i), 3 * sizeof *quad);
        memcpy(quad + 6, top + 3 * (n - 1 - j), 3 * sizeof *quad);
        memcpy(quad + 9, base + 3 * j, 3 * sizeof *quad);
        st = emit(r, quad, 4, 0);
    }
    free(base);
    return st;
}

/* sph, cyl, cone, ring, torus */
static rad_status ent_curved(mgf_reader *r, int argc)
{
    const char *e = r->argv[0];
    rad_status st;
    const mgf_vertex *a = NULL, *b = NULL;
    double r1, r2 = 0, c[3], w[3] = {0, 0, 1};
    int n = r->segments;
    if (strcmp(e, "sph") == 0) {
        if ((st = expect_args(r, argc, 3, 3)) != RAD_OK ||
            (st = vertex_ref(r, r->argv[1], &a)) != RAD_OK ||
            (st = number(r, r->argv[2], "sphere radius", &r1)) != RAD_OK)
            return st;
        if (r1 == 0)
            return bad(r, "a sphere of radius 0");
        int K = (n + 1) / 2;
        double *rho = malloc(2 * (size_t)(K + 1) * sizeof *rho);
        if (!rho)
            return no_memory(r);
        double *h = rho + K + 1, R = fabs(r1);
        for (int k = 0; k <= K; k++) {
            double th = RAD_PI * k / K;
            rho[k] = k == 0 || k == K ? 0.0 : R * sin(th);
            h[k] = k == 0 ? R : k == K ? -R : R * cos(th);
        }
        st = revolve(r, a->p, w, rho, h, K, r1 < 0);
        free(rho);
        return st;
    }
    if (strcmp(e, "cyl") == 0 || strcmp(e, "cone") == 0) {
        int cone = e[1] == 'o';
        if ((st = expect_args(r, argc, cone ? 5 : 4, cone ? 5 : 4)) != RAD_OK ||
            (st = vertex_ref(r, r->argv[1], &a)) != RAD_OK ||
            (st = number(r, r->argv[2], "radius", &r1)) != RAD_OK ||
            (st = vertex_ref(r, r->argv[3], &b)) != RAD_OK)
            return st;
        if (cone) {
            if ((st = number(r, r->argv[4], "radius", &r2)) != RAD_OK)
                return st;
        } else
            r2 = r1;
        if ((r1 < 0 && r2 > 0) || (r1 > 0 && r2 < 0) || (r1 == 0 && r2 == 0))
            return bad(r, "radii %g and %g: both of one sign, not both 0", r1, r2);
        double d[3] = {b->p[0] - a->p[0], b->p[1] - a->p[1], b->p[2] - a->p[2]}, L = norm(d);
        if (!(L > 0))
            return bad(r, "`%s` between coincident vertices", e);
        for (int i = 0; i < 3; i++)
            w[i] = d[i] / L;
        double rho[2] = {fabs(r2), fabs(r1)}, h[2] = {L, 0};
        return revolve(r, a->p, w, rho, h, 1, r1 < 0 || r2 < 0);
    }
    /* ring, torus */
    if ((st = expect_args(r, argc, 4, 4)) != RAD_OK ||
        (st = vertex_ref(r, r->argv[1], &a)) != RAD_OK ||
        (st = vertex_normal(r, r->argv[1], a, w)) != RAD_OK ||
        (st = number(r, r->argv[2], "inner radius", &r1)) != RAD_OK ||
        (st = number(r, r->argv[3], "outer radius", &r2)) != RAD_OK)
        return st;
    memcpy(c, a->p, sizeof c);
    if (strcmp(e, "ring") == 0) {
        if (!(r1 >= 0 && r2 > r1))
            return bad(r, "ring radii %g %g: need 0 <= rmin < rmax", r1, r2);
        double rho[2] = {r1, r2}, h[2] = {0, 0};
        return revolve(r, c, w, rho, h, 1, 0);
    }
    if ((r1 < 0 && r2 > 0) || (r1 > 0 && r2 < 0) || !(fabs(r2) > fabs(r1)))
        return bad(r, "torus radii %g %g: one sign, |rmax| > |rmin|", r1, r2);
    double R = 0.5 * (fabs(r1) + fabs(r2)), tube = 0.5 * (fabs(r2) - fabs(r1));
    double *rho = malloc(2 * (size_t)(n + 1) * sizeof *rho);
    if (!rho)
        return no_memory(r);
    double *h = rho + n + 1;
    for (int k = 0; k <= n; k++) {
        double psi = -2.0 * RAD_PI * (k % n) / n;
        rho[k] = R + tube * cos(psi);
        h[k] = tube * sin(psi);
    }
    st = revolve(r, c, w, rho, h, n, r1 < 0 || r2 < 0);
    free(rho);
    return st;
}

/* ---- contexts: c, m, v -------------------------------------------------- */

static int grow_array(void **p, int *cap, int n, size_t size)
{
    if (n < *cap)
        return 1;
    int next = *cap ? 2 * *cap : 16;
    void *q = realloc(*p, (size_t)next * size);
    if (!q)
        return 0;
    *p = q;
    *cap = next;
    return 1;
}

static const mgf_color COLOR_DEFAULT = {1.0 / 3.0, 1.0 / 3.0};

static mgf_color *color_at(mgf_reader *r, int i) { return i < 0 ? &r->ucolor : &r->colors[i]; }
static mgf_material *mat_at(mgf_reader *r, int i) { return i < 0 ? &r->umat : &r->mats[i]; }
static mgf_vertex *vert_at(mgf_reader *r, int i) { return i < 0 ? &r->uvert : &r->verts[i]; }

static void default_material(mgf_material *m, const char *name)
{
    memset(m, 0, sizeof *m);
    m->rd_c = m->ed_c = COLOR_DEFAULT;
    m->sides = 2; /* the spec's default */
    m->rad_index = -1;
    snprintf(m->name, sizeof m->name, "%s", name ? name : "");
}

/* c, m, v: [id [= [template]]].  kind 0 colour, 1 material, 2 vertex. */
static rad_status ent_context(mgf_reader *r, int argc, int kind)
{
    mgf_names *names = kind == 0 ? &r->cnames : kind == 1 ? &r->mnames : &r->vnames;
    int *current = kind == 0 ? &r->ccolor_i : kind == 1 ? &r->cmat_i : &r->cvert_i;
    const char *what = kind == 0 ? "colour" : kind == 1 ? "material" : "vertex";
    rad_status st;
    if ((st = expect_args(r, argc, 1, 4)) != RAD_OK)
        return st;
    if (argc == 1) {
        *current = -1;
        if (kind == 0)
            r->ucolor = COLOR_DEFAULT;
        else if (kind == 1)
            default_material(&r->umat, NULL);
        else
            memset(&r->uvert, 0, sizeof r->uvert);
        return RAD_OK;
    }
    const char *id = r->argv[1];
    int i = names_find(names, id);
    if (argc == 2) {
        if (i < 0)
            return bad(r, "undefined %s '%.60s'", what, id);
        *current = i;
        return RAD_OK;
    }
    if (strcmp(r->argv[2], "=") != 0)
        return bad(r, "`%s %.40s %.40s`: expected `=`", r->argv[0], id, r->argv[2]);
    int t = -2;
    if (argc == 4 && (t = names_find(names, r->argv[3])) < 0)
        return bad(r, "undefined %s '%.60s'", what, r->argv[3]);
    if (i < 0) {
        int ok = kind == 0   ? grow_array((void **)&r->colors, &r->cap_colors, r->ncolors, sizeof *r->colors)
                 : kind == 1 ? grow_array((void **)&r->mats, &r->cap_mats, r->nmats, sizeof *r->mats)
                             : grow_array((void **)&r->verts, &r->cap_verts, r->nverts, sizeof *r->verts);
        i = kind == 0 ? r->ncolors++ : kind == 1 ? r->nmats++ : r->nverts++;
        if (!ok || !names_put(names, id, i))
            return no_memory(r);
    }
    if (kind == 0)
        *color_at(r, i) = t >= 0 ? *color_at(r, t) : COLOR_DEFAULT;
    else if (kind == 1) {
        if (t >= 0)
            *mat_at(r, i) = *mat_at(r, t);
        else
            default_material(mat_at(r, i), NULL);
        snprintf(mat_at(r, i)->name, sizeof mat_at(r, i)->name, "%s", id);
        mat_at(r, i)->rad_index = -1;
    } else if (t >= 0)
        *vert_at(r, i) = *vert_at(r, t);
    else
        memset(vert_at(r, i), 0, sizeof(mgf_vertex));
    *current = i;
    return RAD_OK;
}

static rad_status ent_cxy(mgf_reader *r, int argc)
{
    double x, y;
    rad_status st;
    if ((st = expect_args(r, argc, 3, 3)) != RAD_OK ||
        (st = number(r, r->argv[1], "x", &x)) != RAD_OK ||
        (st = number(r, r->argv[2], "y", &y)) != RAD_OK)
        return st;
    if (!(x >= 0 && y > 0 && x + y <= 1))
        return bad(r, "chromaticity %g %g: need x >= 0, y > 0, x + y <= 1", x, y);
    mgf_color *c = color_at(r, r->ccolor_i);
    c->x = x;
    c->y = y;
    return RAD_OK;
}

/* cspec lmin lmax v1 v2 ...: values at evenly spaced wavelengths, linear
 * between them and 0 outside. */
typedef struct mgf_spectrum {
    double lo, hi;
    const double *v;
    int n;
} mgf_spectrum;

static double spectrum_at(double nm, void *ctx)
{
    const mgf_spectrum *s = ctx;
    if (nm < s->lo || nm > s->hi)
        return 0.0;
    double u = (nm - s->lo) / (s->hi - s->lo) * (s->n - 1);
    int i = (int)u;
    if (i >= s->n - 1)
        return s->v[s->n - 1];
    return s->v[i] + (u - i) * (s->v[i + 1] - s->v[i]);
}

static rad_status ent_cspec(mgf_reader *r, int argc)
{
    enum { MAX_SAMPLES = 4096 };
    if (argc < 5 || argc - 3 > MAX_SAMPLES)
        return bad(r, "`cspec` takes the lowest and highest wavelength and 2 to %d values",
                   MAX_SAMPLES);
    double lo, hi, *v = malloc((size_t)(argc - 3) * sizeof *v);
    if (!v)
        return RAD_ERROR(RAD_ENOMEM, "mgf: out of memory");
    rad_status st = number(r, r->argv[1], "lowest wavelength", &lo);
    if (st == RAD_OK)
        st = number(r, r->argv[2], "highest wavelength", &hi);
    for (int a = 3; a < argc && st == RAD_OK; a++)
        if ((st = number(r, r->argv[a], "spectral value", &v[a - 3])) == RAD_OK && v[a - 3] < 0)
            st = bad(r, "negative spectral value %g", v[a - 3]);
    if (st == RAD_OK && !(lo > 0 && hi > lo))
        st = bad(r, "wavelengths %g .. %g nm: need 0 < lowest < highest", lo, hi);
    double x, y;
    mgf_spectrum sp = {lo, hi, v, argc - 3};
    if (st == RAD_OK && !scene_cie_xy(spectrum_at, &sp, &x, &y))
        st = bad(r, "the spectrum is dark between 360 and 830 nm: no colour");
    free(v);
    if (st != RAD_OK)
        return st;
    mgf_color *c = color_at(r, r->ccolor_i);
    c->x = x;
    c->y = y;
    return RAD_OK;
}

/* cct T: the colour of a blackbody at T kelvin. */
static rad_status ent_cct(mgf_reader *r, int argc)
{
    double T, x, y;
    rad_status st;
    if ((st = expect_args(r, argc, 2, 2)) != RAD_OK ||
        (st = number(r, r->argv[1], "temperature", &T)) != RAD_OK)
        return st;
    if (!(T > 0) || !scene_cie_xy_blackbody(T, &x, &y))
        return bad(r, "colour temperature %g K: need a blackbody that glows between 360 and "
                      "830 nm", T);
    mgf_color *c = color_at(r, r->ccolor_i);
    c->x = x;
    c->y = y;
    return RAD_OK;
}

/* cmix w1 c1 w2 c2 ...: the XYZ of each colour with Y = its weight, added. */
static rad_status ent_cmix(mgf_reader *r, int argc)
{
    if (argc < 3 || argc % 2 == 0)
        return bad(r, "`cmix` takes pairs of weight and colour");
    double X = 0, Y = 0, Z = 0;
    for (int a = 1; a < argc; a += 2) {
        double wgt;
        rad_status st = number(r, r->argv[a], "weight", &wgt);
        if (st != RAD_OK)
            return st;
        if (wgt < 0)
            return bad(r, "negative weight %g", wgt);
        int i = names_find(&r->cnames, r->argv[a + 1]);
        if (i < 0)
            return bad(r, "undefined colour '%.60s'", r->argv[a + 1]);
        const mgf_color *c = &r->colors[i];
        X += wgt * c->x / c->y;
        Y += wgt;
        Z += wgt * (1 - c->x - c->y) / c->y;
    }
    if (!(Y > 0))
        return bad(r, "`cmix` weights add up to 0");
    mgf_color *c = color_at(r, r->ccolor_i);
    c->x = X / (X + Y + Z);
    c->y = Y / (X + Y + Z);
    return RAD_OK;
}

/* rd, ed, td, rs, ts, ir, sides */
static rad_status ent_material_attr(mgf_reader *r, int argc)
{
    const char *e = r->argv[0];
    mgf_material *m = mat_at(r, r->cmat_i);
    rad_status st;
    double v;
    if (strcmp(e, "sides") == 0) {
        long sides;
        if ((st = expect_args(r, argc, 2, 2)) != RAD_OK ||
            (st = integer(r, r->argv[1], "sides", 1, 2, &sides)) != RAD_OK)
            return st;
        m->sides = (int)sides;
        return RAD_OK;
    }
    int two = strcmp(e, "rs") == 0 || strcmp(e, "ts") == 0 || strcmp(e, "ir") == 0;
    if ((st = expect_args(r, argc, two ? 3 : 2, two ? 3 : 2)) != RAD_OK ||
        (st = number(r, r->argv[1], e, &v)) != RAD_OK)
        return st;
    if (two && (st = number(r, r->argv[2], e, &(double){0})) != RAD_OK)
        return st;
    if (strcmp(e, "rd") == 0) {
        if (!(v >= 0 && v <= 1))
            return bad(r, "diffuse reflectance %g is outside [0, 1]", v);
        m->rd = v;
        m->rd_c = *color_at(r, r->ccolor_i);
        m->rad_index = -1;
    } else if (strcmp(e, "ed") == 0) {
        if (!(v >= 0))
            return bad(r, "negative emittance %g", v);
        m->ed = v;
        m->ed_c = *color_at(r, r->ccolor_i);
        m->rad_index = -1;
    } else if (strcmp(e, "ir") != 0 && v != 0)
        note(r, &r->notes[NOTE_SPECULAR], e);
    return RAD_OK;
}

static rad_status ent_vertex_attr(mgf_reader *r, int argc)
{
    mgf_vertex *v = vert_at(r, r->cvert_i);
    double *dst = r->argv[0][0] == 'p' ? v->p : v->n;
    double q[3];
    rad_status st;
    if ((st = expect_args(r, argc, 4, 4)) != RAD_OK)
        return st;
    for (int k = 0; k < 3; k++)
        if ((st = number(r, r->argv[1 + k], r->argv[0][0] == 'p' ? "coordinate" : "normal",
                         &q[k])) != RAD_OK)
            return st;
    memcpy(dst, q, sizeof q);
    return RAD_OK;
}

/* ---- files -------------------------------------------------------------- */

/* The next logical line split into r->argv; 0 at the end of the file. */
static rad_status next_entity(mgf_reader *r, int *argc)
{
    mgf_file *f = cur(r);
    *argc = 0;
    for (;;) {
        if (f->p >= f->end)
            return RAD_OK;
        f->line = f->next_line;
        size_t n = 0;
        while (f->p < f->end) {
            char c = *f->p++;
            if (c == '\r' && f->p < f->end && *f->p == '\n')
                continue; /* CRLF: so that a backslash before it still continues */
            if (c == '\n') {
                f->next_line++;
                if (n > 0 && r->logical[n - 1] == '\\') {
                    r->logical[n - 1] = ' ';
                    continue;
                }
                break;
            }
            if (c == '\0')
                return RAD_ERROR(RAD_EINPUT, "%s:%d: a NUL byte: not a text file", f->path,
                                 f->next_line);
            if (n >= r->p->max_line_bytes)
                return RAD_ERROR(RAD_EINPUT, "%s:%d: the line is longer than %zu bytes", f->path,
                                 f->line, r->p->max_line_bytes);
            r->logical[n++] = c == '\r' || c == '\t' || c == '\f' || c == '\v' ? ' ' : c;
        }
        r->logical[n] = '\0';
        char *save, *w = strtok_r(r->logical, " ", &save);
        if (!w || w[0] == '#')
            continue;
        while (w) {
            if (*argc + 1 >= r->cap_argv) {
                int cap = r->cap_argv ? 2 * r->cap_argv : 64;
                char **q = realloc(r->argv, (size_t)cap * sizeof *q);
                if (!q)
                    return no_memory(r);
                r->argv = q;
                r->cap_argv = cap;
            }
            r->argv[(*argc)++] = w;
            w = strtok_r(NULL, " ", &save);
        }
        r->argv[*argc] = NULL;
        return RAD_OK;
    }
}

static rad_status read_file(mgf_reader *r, const char *path);

/* A path relative to the folder of `base` (unless absolute). */
static char *relative_path(const char *base, const char *name)
{
    const char *slash = strrchr(base, '/');
    size_t dir = name[0] == '/' || !slash ? 0 : (size_t)(slash - base) + 1;
    char *out = malloc(dir + strlen(name) + 1);
    if (out) {
        memcpy(out, base, dir);
        strcpy(out + dir, name);
    }
    return out;
}

static rad_status ent_include(mgf_reader *r, int argc)
{
    if (argc < 2)
        return bad(r, "`i` needs a file name");
    if (r->depth >= MGF_MAX_DEPTH)
        return bad(r, "includes nest more than %d deep", MGF_MAX_DEPTH);
    char *path = relative_path(cur(r)->path, r->argv[1]);
    if (!path)
        return no_memory(r);
    /* The transform arguments are copied: reading the file reuses r->argv. */
    int nx = argc - 2;
    char *copy = NULL, **xargs = NULL;
    size_t bytes = 0;
    for (int a = 2; a < argc; a++)
        bytes += strlen(r->argv[a]) + 1;
    rad_status st = RAD_OK;
    if (nx > 0) {
        copy = malloc(bytes);
        xargs = malloc((size_t)nx * sizeof *xargs);
        if (!copy || !xargs)
            st = no_memory(r);
        for (int a = 0, at = 0; a < nx && st == RAD_OK; a++) {
            xargs[a] = strcpy(copy + at, r->argv[a + 2]);
            at += (int)strlen(r->argv[a + 2]) + 1;
        }
    }
    int pushed = 0;
    if (st == RAD_OK && nx > 0 && (st = xf_push(r, xargs, nx)) == RAD_OK)
        pushed = 1;
    while (st == RAD_OK) {
        st = read_file(r, path);
        if (st != RAD_OK || !pushed || !xf_next_instance(r))
            break;
    }
    if (pushed && r->nxf)
        xf_pop(r);
    free(copy);
    free(xargs);
    free(path);
    return st;
}

static int is(const char *a, const char *b) { return strcmp(a, b) == 0; }

static rad_status entity(mgf_reader *r, int argc)
{
    const char *e = r->argv[0];
    if (is(e, "f"))
        return ent_face(r, argc);
    if (is(e, "fh"))
        return ent_face_holes(r, argc);
    if (is(e, "v"))
        return ent_context(r, argc, 2);
    if (is(e, "p") || is(e, "n"))
        return ent_vertex_attr(r, argc);
    if (is(e, "m"))
        return ent_context(r, argc, 1);
    if (is(e, "c"))
        return ent_context(r, argc, 0);
    if (is(e, "cxy"))
        return ent_cxy(r, argc);
    if (is(e, "cmix"))
        return ent_cmix(r, argc);
    if (is(e, "cspec"))
        return ent_cspec(r, argc);
    if (is(e, "cct"))
        return ent_cct(r, argc);
    if (is(e, "rd") || is(e, "ed") || is(e, "td") || is(e, "rs") || is(e, "ts") || is(e, "ir") ||
        is(e, "sides"))
        return ent_material_attr(r, argc);
    if (is(e, "sph") || is(e, "cyl") || is(e, "cone") || is(e, "ring") || is(e, "torus"))
        return ent_curved(r, argc);
    if (is(e, "prism"))
        return ent_prism(r, argc);
    if (is(e, "i"))
        return ent_include(r, argc);
    if (is(e, "o")) {
        if (argc == 1) {
            if (r->nobj == 0 || r->obj_depth[r->nobj - 1] != r->depth)
                return bad(r, "`o` ends an object, but none is open in this file");
            r->nobj--;
            return RAD_OK;
        }
        if (!grow_array((void **)&r->obj_line, &r->cap_obj, r->nobj, sizeof(int)))
            return no_memory(r);
        int *q = realloc(r->obj_depth, (size_t)r->cap_obj * sizeof *q);
        if (!q)
            return no_memory(r);
        r->obj_depth = q;
        r->obj_line[r->nobj] = cur(r)->line;
        r->obj_depth[r->nobj++] = r->depth;
        return RAD_OK;
    }
    if (is(e, "xf")) {
        if (argc > 1)
            return xf_push(r, r->argv + 1, argc - 1);
        if (r->nxf == 0 || r->xf[r->nxf - 1].depth != r->depth)
            return bad(r, "`xf` ends a transform, but none is open in this file");
        xf_context *x = &r->xf[r->nxf - 1];
        if (xf_next_instance(r)) {
            cur(r)->p = x->restart;
            cur(r)->next_line = x->restart_line;
            return RAD_OK;
        }
        xf_pop(r);
        return RAD_OK;
    }
    const char *why = NULL;
    int kind = NOTE_UNKNOWN;
    if (is(e, "ies")) {
        kind = NOTE_IES;
        why = "IES luminaires are not read";
    }
    if (r->p->strict)
        return bad(r, "`%.40s`: %s (refused in strict mode)", e, why ? why : "unknown entity");
    if (kind != NOTE_UNKNOWN) {
        note(r, &r->notes[kind], e);
        return RAD_OK;
    }
    for (int k = 0; k < r->nunknown; k++)
        if (strcmp(r->unknown[k].what, e) == 0) {
            r->unknown[k].count++;
            return RAD_OK;
        }
    note(r, r->nunknown < 32 ? &r->unknown[r->nunknown++] : &r->notes[NOTE_UNKNOWN], e);
    return RAD_OK;
}

static rad_status read_file(mgf_reader *r, const char *path)
{
    struct stat sb;
    memset(&sb, 0, sizeof sb);
    if (stat(path, &sb) == 0)
        for (int d = 0; d <= r->depth && r->files[d]; d++)
            if (r->files[d]->dev == sb.st_dev && r->files[d]->ino == sb.st_ino)
                return bad(r, "include loop: '%s' is already being read", path);
    if (++r->reads > MGF_MAX_READS)
        return bad(r, "more than %d file reads (includes, with their array instances)",
                   MGF_MAX_READS);
    mgf_file f = {path, NULL, NULL, NULL, 0, 1, sb.st_dev, sb.st_ino};
    size_t size;
    rad_status st = scene_read_file(path, r->p->max_file_bytes, &f.data, &size);
    if (st != RAD_OK) {
        if (r->files[0]) /* an include: name the line that asked for it */
            return bad(r, "cannot include: %s", rad_error_message());
        return st;
    }
    f.p = f.data;
    f.end = f.data + size;
    /* the triangles of an included file name it (the scene's own is file 0) */
    int file_k = 0, outer_k = r->s->cur_file;
    if (r->files[0] && (file_k = names_find(&r->fnames, path)) < 0 &&
        ((st = scene_add_file(r->s, path, &file_k)) != RAD_OK ||
         !names_put(&r->fnames, path, file_k))) {
        free(f.data);
        return st != RAD_OK ? st : no_memory(r);
    }
    scene_set_file(r->s, file_k);
    int depth = r->files[0] ? r->depth + 1 : 0;
    int outer = r->depth;
    r->depth = depth;
    r->files[depth] = &f;
    int argc;
    while (st == RAD_OK && (st = next_entity(r, &argc)) == RAD_OK && argc > 0)
        st = ++r->statements > MGF_MAX_STATEMENTS
                 ? bad(r, "more than %lld entities read (array instances and includes counted)",
                       MGF_MAX_STATEMENTS)
                 : entity(r, argc);
    if (st == RAD_OK && r->nxf && r->xf[r->nxf - 1].depth == depth)
        st = RAD_ERROR(RAD_EINPUT, "%s:%d: `xf` is not ended in this file (the file ends at line %d)",
                       path, r->xf[r->nxf - 1].line, f.next_line - 1);
    if (st == RAD_OK && r->nobj && r->obj_depth[r->nobj - 1] == depth)
        st = RAD_ERROR(RAD_EINPUT, "%s:%d: object `o` is not ended in this file (the file ends at "
                       "line %d)", path, r->obj_line[r->nobj - 1], f.next_line - 1);
    while (r->nxf && r->xf[r->nxf - 1].depth == depth)
        xf_pop(r);
    while (r->nobj && r->obj_depth[r->nobj - 1] == depth)
        r->nobj--;
    r->files[depth] = NULL;
    r->depth = outer;
    scene_set_file(r->s, outer_k);
    free(f.data);
    return st;
}

static rad_status report(mgf_reader *r)
{
    static const char *reason[NOTE_COUNT] = {
        "radkit's surfaces are opaque and diffuse: specular and transmitted parts are dropped",
        "IES luminaires are not read: skipped with this warning, as MGF asks of entities a "
        "reader does not support; their geometry and emission are missing",
        "unknown entities",
        "colours outside the RGB primaries' gamut: negative channels taken as 0",
        "reflectance channels of rho_white or more: taken as rho_white",
        "two-sided materials (`sides 2`, MGF's default): each face is made on both sides, the "
        "back a reversed copy with the same material (a thin sheet, lit and emitting on both "
        "sides); give closed solids `sides 1`"};
    rad_status st = RAD_OK;
    for (int k = 0; k < NOTE_COUNT && st == RAD_OK; k++) {
        const mgf_note *n = &r->notes[k];
        if (n->count && k == NOTE_TWO_SIDED)
            st = scene_warn(r->s, "%d face(s) of %s (first of '%s', at %s:%d)", n->count,
                            reason[k], n->what, n->file, n->line);
        else if (n->count && k >= NOTE_GAMUT)
            st = scene_warn(r->s, "%d material(s) (first '%s', used at %s:%d): %s", n->count,
                            n->what, n->file, n->line, reason[k]);
        else if (n->count)
            st = scene_warn(r->s, "%d `%s` statement(s) (first at %s:%d): %s", n->count, n->what,
                            n->file, n->line, reason[k]);
    }
    for (int k = 0; k < r->nunknown && st == RAD_OK; k++)
        st = scene_warn(r->s, "ignored %d `%s` statement(s) (first at %s:%d): not an MGF entity "
                        "radkit knows", r->unknown[k].count, r->unknown[k].what, r->unknown[k].file,
                        r->unknown[k].line);
    return st;
}

int scene_mgf_segments(double tol)
{
    if (!(tol > 0) || !(tol < 1))
        return -1;
    double n = ceil(RAD_PI / acos(1.0 - tol));
    return n < 4 ? 4 : n > MGF_MAX_SEGMENTS ? MGF_MAX_SEGMENTS : (int)n;
}

rad_status scene_import_mgf(rad_scene *s, const char *path, const rad_scene_params *p)
{
    int segments = scene_mgf_segments(p->curve_tol);
    if (segments < 0)
        return RAD_ERROR(RAD_EINVAL, "the curve tolerance must be in (0, 1), got %g", p->curve_tol);
    mgf_reader *r = calloc(1, sizeof *r);
    char *logical = malloc(p->max_line_bytes + 1);
    if (!r || !logical) {
        free(r);
        free(logical);
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory", path);
    }
    r->s = s;
    r->p = p;
    r->segments = segments;
    r->logical = logical;
    rgb_matrix(r->rgb_from_xyz);
    r->ucolor = COLOR_DEFAULT;
    default_material(&r->umat, NULL);
    r->ccolor_i = r->cmat_i = r->cvert_i = -1;
    rad_status st = read_file(r, path);
    if (st == RAD_OK && s->nt == 0 && r->face == 0)
        st = RAD_ERROR(RAD_EINPUT, "%s: no faces (no `f` or other geometric entity)", path);
    if (st == RAD_OK)
        st = report(r);
    while (r->nxf)
        xf_pop(r);
    names_free(&r->cnames);
    names_free(&r->mnames);
    names_free(&r->vnames);
    names_free(&r->fnames);
    free(r->colors);
    free(r->mats);
    free(r->verts);
    free(r->xf);
    free(r->obj_line);
    free(r->obj_depth);
    free(r->idx);
    free(r->count);
    free(r->pts);
    free(r->argv);
    free(r->logical);
    free(r);
    return st;
}
