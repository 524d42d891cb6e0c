/* OBJ + MTL: radkit's own line reader, with Assimp as a cross-check.
 *
 * Why a reader of our own: Assimp reports no line numbers and Debian's build
 * keeps coordinates in single precision (ai_real = float), while every finding
 * must name its line and convergence studies need the file's digits.  The
 * format is small [obj:spec; mtl:spec]:
 *  1. Read the OBJ line by line.  `v x y z [w | r g b]` adds a vertex (each
 *     number parsed whole with strtod: a malformed or non-finite number is an
 *     error at its line).  `f i j k ...` adds a polygon: each corner is
 *     `v`, `v/vt`, `v/vt/vn` or `v//vn`; negative indices count back from the
 *     last vertex read; the polygon is fan-triangulated (0,1,2), (0,2,3), ...
 *     in order, every triangle keeping the face's line, face number and the
 *     current material.  `usemtl` selects a material by name, `mtllib` reads
 *     material libraries (relative to the OBJ's folder).  Statements that do
 *     not change the radiosity problem (vt, vn, o, g, s, l, p, and the
 *     free-form geometry ones) are ignored; anything else is an error.
 *     The comment `# radkit camera position X Y Z look_at X Y Z up X Y Z
 *     fov_y DEGREES` gives the camera.
 *  2. After the last line, every index is checked against the vertex count
 *     (forward references are legal OBJ), naming the line of the face.
 *  3. MTL: `newmtl` opens a material; `Kd r [g b]` is its reflectance, which
 *     must lie in [0, 1); `Ke r [g b]` its emitted exitance, which must be >= 0.
 *     A material without Kd gets the default reflectance.  Other statements
 *     (Ka, Ks, Ns, d, illum, map_*) are ignored.
 *  4. Assimp imports the same file; if it finds a different number of
 *     triangles, or cannot read it, a warning says so. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene_internal.h"

typedef struct obj_reader {
    rad_scene *s;
    const char *path;
    const rad_scene_params *p;
    int current_material; /* -1: none yet */
    int default_material; /* -1: not created */
    int faces;            /* polygons read */
    int libraries;        /* mtllib files read */
    int ignored_lines;
} obj_reader;

static const char *const ignored_statements[] = {
    "vt", "vn", "vp", "o", "g", "s", "l", "p", "mg", "bevel", "c_interp", "d_interp", "lod",
    "maplib", "usemap", "shadow_obj", "trace_obj", "ctech", "stech", "cstype", "deg", "bmat",
    "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv", "sp", "end", "con", NULL};

static const char *const ignored_mtl[] = {
    "Ka", "Ks", "Ns", "Ni", "d", "Tr", "Tf", "illum", "sharpness", "Pr", "Pm", "Ps", "Pc",
    "Pcr", "aniso", "anisor", "norm", "bump", "disp", "decal", "refl", NULL};

static int in_list(const char *word, const char *const *list)
{
    for (; *list; list++)
        if (strcmp(word, *list) == 0)
            return 1;
    return 0;
}

/* Parse one whole number token; RAD_EINPUT names file:line and what. */
static rad_status parse_number(const char *file, int line, const char *what, const char *tok,
                               double *out)
{
    if (!tok)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s: a number is missing", file, line, what);
    char *end = NULL;
    errno = 0;
    double v = strtod(tok, &end);
    if (end == tok || *end != '\0')
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s: malformed number '%s'", file, line, what, tok);
    if (isnan(v))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s: NaN value '%s'", file, line, what, tok);
    if (!isfinite(v))
        return RAD_ERROR(RAD_EINPUT, "%s:%d: %s: infinite value '%s'", file, line, what, tok);
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

static rad_status read_mtl(obj_reader *r, const char *mtl_path, int obj_line)
{
    FILE *f = fopen(mtl_path, "r");
    if (!f)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: cannot open material library '%s': %s", r->path,
                         obj_line, mtl_path, strerror(errno));
    rad_status st = RAD_OK;
    char *buf = NULL;
    size_t cap = 0;
    int line = 0, current = -1;
    static const char channel[3] = {'r', 'g', 'b'};
    while (st == RAD_OK && getline(&buf, &cap, f) >= 0) {
        line++;
        buf[strcspn(buf, "\r\n")] = '\0';
        char *save = NULL, *key = strtok_r(buf, " \t", &save);
        if (!key || key[0] == '#')
            continue;
        if (strcmp(key, "newmtl") == 0) {
            char *name = strtok_r(NULL, "\r\n", &save);
            while (name && (*name == ' ' || *name == '\t'))
                name++;
            if (!name || !*name) {
                st = RAD_ERROR(RAD_EINPUT, "%s:%d: newmtl without a name", mtl_path, line);
                break;
            }
            current = find_material(r->s, name);
            if (current >= 0) {
                st = scene_warn(r->s, "%s:%d: material '%s' defined again; the later values win",
                                mtl_path, line, name);
            } else {
                double zero[3] = {0, 0, 0};
                st = scene_add_material(r->s, name, r->p->default_rho, zero);
                current = r->s->nm - 1;
            }
        } else if (strcmp(key, "Kd") == 0 || strcmp(key, "Ke") == 0) {
            double c[3];
            if (current < 0) {
                st = RAD_ERROR(RAD_EINPUT, "%s:%d: %s before any newmtl", mtl_path, line, key);
                break;
            }
            if ((st = parse_colour(mtl_path, line, key, &save, c)) != RAD_OK)
                break;
            int kd = key[1] == 'd';
            for (int k = 0; k < 3 && st == RAD_OK; k++) {
                if (kd && !(c[k] >= 0.0 && c[k] < 1.0))
                    st = RAD_ERROR(RAD_EINPUT,
                                   "%s:%d: material '%s': reflectance Kd %c = %g is outside [0, 1)",
                                   mtl_path, line, r->s->mats[current].name, channel[k], c[k]);
                else if (!kd && c[k] < 0.0)
                    st = RAD_ERROR(RAD_EINPUT,
                                   "%s:%d: material '%s': negative emission Ke %c = %g", mtl_path,
                                   line, r->s->mats[current].name, channel[k], c[k]);
            }
            if (st == RAD_OK)
                memcpy(kd ? r->s->mats[current].rho : r->s->mats[current].emission, c, sizeof c);
        } else if (!in_list(key, ignored_mtl) && strncmp(key, "map_", 4) != 0) {
            st = RAD_ERROR(RAD_EINPUT, "%s:%d: unknown MTL statement '%s'", mtl_path, line, key);
        }
    }
    if (st == RAD_OK && ferror(f))
        st = RAD_ERROR(RAD_EINPUT, "%s: read error", mtl_path);
    free(buf);
    fclose(f);
    r->libraries++;
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

/* One face corner "v[/vt[/vn]]" -> 0-based vertex index (range checked later). */
static rad_status parse_corner(obj_reader *r, int line, const char *tok, int *out)
{
    char *end = NULL;
    errno = 0;
    long idx = strtol(tok, &end, 10);
    if (end == tok || (*end != '\0' && *end != '/') || errno == ERANGE)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: malformed face index '%s'", r->path, line, tok);
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

static rad_status read_face(obj_reader *r, int line, char **save)
{
    int first = -1, prev = -1, corners = 0;
    rad_status st = RAD_OK;
    if (r->current_material < 0) {
        if (r->default_material < 0) {
            double zero[3] = {0, 0, 0};
            if ((st = scene_add_material(r->s, "default", r->p->default_rho, zero)) != RAD_OK)
                return st;
            r->default_material = r->s->nm - 1;
        }
        r->current_material = r->default_material;
    }
    char *tok;
    while ((tok = strtok_r(NULL, " \t", save)) != NULL) {
        int v = -1;
        if ((st = parse_corner(r, line, tok, &v)) != RAD_OK)
            return st;
        if (corners == 0)
            first = v;
        else if (corners >= 2 &&
                 (st = scene_add_triangle(r->s, first, prev, v, r->current_material, r->faces,
                                          line)) != RAD_OK)
            return st;
        prev = v;
        corners++;
    }
    if (corners < 3)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: a face needs at least 3 vertices, found %d", r->path,
                         line, corners);
    r->faces++;
    return RAD_OK;
}

static rad_status read_obj(obj_reader *r, FILE *f)
{
    rad_status st = RAD_OK;
    char *buf = NULL;
    size_t cap = 0;
    int line = 0;
    while (st == RAD_OK && getline(&buf, &cap, f) >= 0) {
        line++;
        buf[strcspn(buf, "\r\n")] = '\0';
        if (strncmp(buf, "# radkit camera", 15) == 0) {
            char *save = NULL;
            strtok_r(buf, " \t", &save); /* # */
            strtok_r(NULL, " \t", &save); /* radkit */
            strtok_r(NULL, " \t", &save); /* camera */
            st = read_camera(r, line, &save);
            continue;
        }
        char *save = NULL, *key = strtok_r(buf, " \t", &save);
        if (!key || key[0] == '#')
            continue;
        if (strcmp(key, "v") == 0) {
            double c[3];
            for (int k = 0; k < 3 && st == RAD_OK; k++)
                st = parse_number(r->path, line, "vertex coordinate", strtok_r(NULL, " \t", &save), &c[k]);
            if (st == RAD_OK)
                st = scene_add_vertex(r->s, c[0], c[1], c[2]);
        } else if (strcmp(key, "f") == 0) {
            st = read_face(r, line, &save);
        } else if (strcmp(key, "usemtl") == 0) {
            char *name = strtok_r(NULL, "\r\n", &save);
            while (name && (*name == ' ' || *name == '\t'))
                name++;
            int m = name ? find_material(r->s, name) : -1;
            if (m < 0)
                st = RAD_ERROR(RAD_EINPUT, "%s:%d: material '%s' is not defined%s", r->path, line,
                               name ? name : "", r->libraries ? " in the material libraries"
                                                               : " (no mtllib before it)");
            r->current_material = m;
        } else if (strcmp(key, "mtllib") == 0) {
            char *name;
            while (st == RAD_OK && (name = strtok_r(NULL, " \t", &save)) != NULL) {
                char *mtl = sibling_path(r->path, name);
                st = mtl ? read_mtl(r, mtl, line) : RAD_ERROR(RAD_ENOMEM, "no memory");
                free(mtl);
            }
        } else if (in_list(key, ignored_statements)) {
            r->ignored_lines++;
        } else {
            st = RAD_ERROR(RAD_EINPUT, "%s:%d: unknown OBJ statement '%.40s'", r->path, line, key);
        }
    }
    if (st == RAD_OK && ferror(f))
        st = RAD_ERROR(RAD_EINPUT, "%s: read error", r->path);
    free(buf);
    return st;
}

rad_status scene_import_obj(rad_scene *s, const char *path, const rad_scene_params *p)
{
    FILE *f = fopen(path, "r");
    if (!f)
        return RAD_ERROR(RAD_EINPUT, "%s: cannot open: %s", path, strerror(errno));
    obj_reader r = {s, path, p, -1, -1, 0, 0, 0};
    rad_status st = read_obj(&r, f);
    fclose(f);
    if (st != RAD_OK)
        return st;
    for (int t = 0; t < s->nt; t++)
        for (int k = 0; k < 3; k++)
            if (s->tri[3 * t + k] >= s->nv)
                return RAD_ERROR(RAD_EINPUT, "%s:%d: face index %d is out of range (%d vertices)",
                                 path, s->tri_line[t], s->tri[3 * t + k] + 1, s->nv);
    if (s->nt == 0)
        return RAD_ERROR(RAD_EINPUT, "%s: no faces (empty scene)", path);
    /* The cross-check with Assimp. */
    if (p->no_cross_check)
        return RAD_OK;
    long assimp_tris = 0, assimp_mats = 0;
    if (scene_assimp_count(path, &assimp_tris, &assimp_mats) != RAD_OK)
        return scene_warn(s, "Assimp could not read this file (%s); radkit's reader did",
                          rad_error_message());
    if (assimp_tris != s->nt)
        return scene_warn(s, "Assimp reads %ld triangles, radkit's reader %d", assimp_tris, s->nt);
    return RAD_OK;
}
