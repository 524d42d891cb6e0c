/* The scene object: construction, validation, accessors and summary.
 *
 * scene_finish, run after every importer, in order:
 *  1. Replace reflectance / emission by the parameters' overrides.
 *  2. Check every material: 0 <= rho < 1 and E >= 0, finite (the place is the
 *     material's name; OBJ's MTL reader has already named the line).
 *  3. Refuse an empty scene; scale the coordinates (and the camera).
 *  4. Check every coordinate is finite and within RAD_GEOM_MAX_COORD (the
 *     OBJ reader has already checked its vertices at their lines).  Drop
 *     degenerate triangles (rad_geom_triangle_is_degenerate), counted, with
 *     one warning naming the first (its line for OBJ, else its face): an
 *     exporter's sliver says nothing about the rest of the scene.  In strict
 *     mode the first is an error instead.  A scene with no triangle left is
 *     an error.  A polygon whose triangles fold against its area vector (a
 *     fan of a non-convex polygon, from an importer that does not use
 *     scene_add_polygon) is an error.
 *  5. Count unused vertices (a warning), then merge vertices at bit-identical
 *     positions and drop unused ones, so shared corners share an index.
 *  6. Duplicate coincident faces: a face with the same three corners in the
 *     same orientation as an earlier one is dropped, counted, with one
 *     warning naming the first (strict mode: an error).  It adds no surface
 *     and no light, but every copy is one more blocker for every pair behind
 *     it, which costs the visibility of a scene with dozens of copies minutes.
 *     The same corners in the opposite orientation are the two sides of one
 *     surface and are kept, with a warning.  Then warn about a scene without
 *     emitters.
 *  7. Give the default camera when the file had none. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_geom.h"
#include "scene_internal.h"
#include "text_file.h"

void rad_scene_params_default(rad_scene_params *p)
{
    memset(p, 0, sizeof *p);
    p->scale = 1.0;
    p->no_cross_check = 1;
    p->degenerate_rel_tol = 1e-12;
    for (int k = 0; k < 3; k++)
        p->default_rho[k] = 0.5;
    p->max_triangles = 50000000;
    p->rho_white = 0.999;
    p->max_file_bytes = (size_t)1 << 31;
    p->max_line_bytes = 65536;
    p->curve_tol = 0.0125;
}

rad_scene *scene_new(const char *source)
{
    rad_scene *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->source = strdup(source ? source : "(scene)");
    if (!s->source) {
        free(s);
        return NULL;
    }
    return s;
}

void rad_scene_destroy(rad_scene *s)
{
    if (!s)
        return;
    for (int i = 0; i < s->nw; i++)
        free(s->warnings[i]);
    free(s->warnings);
    free(s->source);
    free(s->xyz);
    free(s->tri);
    free(s->tri_mat);
    free(s->tri_face);
    free(s->tri_line);
    free(s->tri_file);
    for (int i = 0; i < s->nfiles; i++)
        free(s->files[i]);
    free(s->files);
    free(s->back_face);
    free(s->mats);
    free(s);
}

/* Grow *p (n elements of size `size`) so that one more fits. */
static int grow(void **p, int *cap, int n, size_t size)
{
    if (n < *cap)
        return 1;
    int next = *cap ? 2 * *cap : 64;
    void *q = realloc(*p, (size_t)next * size);
    if (!q)
        return 0;
    *p = q;
    *cap = next;
    return 1;
}

rad_status scene_add_vertex(rad_scene *s, double x, double y, double z)
{
    if (s->nv >= (1 << 30))
        return RAD_ERROR(RAD_ETOOBIG, "%s: more than 2^30 vertices", s->source);
    if (!grow((void **)&s->xyz, &s->cap_v, s->nv, 3 * sizeof(double)))
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory for %d vertices", s->source, s->nv);
    double *v = s->xyz + 3 * (size_t)s->nv++;
    v[0] = x;
    v[1] = y;
    v[2] = z;
    return RAD_OK;
}

rad_status scene_add_triangle(rad_scene *s, int a, int b, int c, int mat, int face, int line)
{
    if (s->nt >= (1 << 30))
        return RAD_ERROR(RAD_ETOOBIG, "%s: more than 2^30 triangles", s->source);
    if (s->nt >= s->cap_t) {
        int cap = s->cap_t ? 2 * s->cap_t : 64;
        int *t = realloc(s->tri, 3 * (size_t)cap * sizeof *t);
        if (t)
            s->tri = t;
        int *m = realloc(s->tri_mat, (size_t)cap * sizeof *m);
        if (m)
            s->tri_mat = m;
        int *f = realloc(s->tri_face, (size_t)cap * sizeof *f);
        if (f)
            s->tri_face = f;
        int *l = realloc(s->tri_line, (size_t)cap * sizeof *l);
        if (l)
            s->tri_line = l;
        int *fi = realloc(s->tri_file, (size_t)cap * sizeof *fi);
        if (fi)
            s->tri_file = fi;
        if (!t || !m || !f || !l || !fi)
            return RAD_ERROR(RAD_ENOMEM, "%s: no memory for %d triangles", s->source, cap);
        s->cap_t = cap;
    }
    int *t = s->tri + 3 * (size_t)s->nt;
    t[0] = a;
    t[1] = b;
    t[2] = c;
    s->tri_mat[s->nt] = mat;
    s->tri_face[s->nt] = face;
    s->tri_line[s->nt] = line;
    s->tri_file[s->nt] = s->cur_file;
    s->nt++;
    return RAD_OK;
}

rad_status scene_add_file(rad_scene *s, const char *path, int *k)
{
    char *copy = strdup(path);
    if (!copy || !grow((void **)&s->files, &s->cap_files, s->nfiles, sizeof(char *))) {
        free(copy);
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory", path);
    }
    s->files[s->nfiles++] = copy;
    *k = s->nfiles;
    return RAD_OK;
}

void scene_set_file(rad_scene *s, int k) { s->cur_file = k; }

const char *scene_file_name(const rad_scene *s, int k)
{
    return k > 0 && k <= s->nfiles ? s->files[k - 1] : s->source;
}

rad_status scene_mark_back_face(rad_scene *s, int face)
{
    if (face < 0)
        return RAD_OK;
    if (face >= s->cap_back) {
        int cap = s->cap_back ? s->cap_back : 64;
        while (cap <= face)
            cap = cap > (1 << 29) ? face + 1 : 2 * cap;
        unsigned char *q = realloc(s->back_face, (size_t)cap);
        if (!q)
            return RAD_ERROR(RAD_ENOMEM, "%s: no memory", s->source);
        memset(q + s->cap_back, 0, (size_t)(cap - s->cap_back));
        s->back_face = q;
        s->cap_back = cap;
    }
    s->back_face[face] = 1;
    return RAD_OK;
}

static int is_back_face(const rad_scene *s, int face)
{
    return face >= 0 && face < s->cap_back && s->back_face[face];
}

rad_status scene_add_material(rad_scene *s, const char *name, const double rho[3],
                              const double emission[3])
{
    if (!grow((void **)&s->mats, &s->cap_m, s->nm, sizeof(rad_scene_material)))
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory for materials", s->source);
    rad_scene_material *m = &s->mats[s->nm++];
    memset(m, 0, sizeof *m);
    snprintf(m->name, sizeof m->name, "%s", name ? name : "");
    for (int k = 0; k < 3; k++) {
        m->rho[k] = rho[k];
        m->emission[k] = emission[k];
    }
    return RAD_OK;
}

rad_status scene_warn(rad_scene *s, const char *fmt, ...)
{
    char buf[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    char *copy = strdup(buf);
    if (!copy || !grow((void **)&s->warnings, &s->cap_w, s->nw, sizeof(char *))) {
        free(copy);
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory for warnings", s->source);
    }
    s->warnings[s->nw++] = copy;
    return RAD_OK;
}

/* ---- finishing ----------------------------------------------------------- */

/* Overrides apply to every material; only materials some face uses are
 * checked (importers may add defaults nobody uses). */
static rad_status check_materials(rad_scene *s, const rad_scene_params *p)
{
    static const char channel[3] = {'r', 'g', 'b'};
    for (int m = 0; m < s->nm; m++) {
        rad_scene_material *mat = &s->mats[m];
        if (p->has_rho)
            memcpy(mat->rho, p->rho, sizeof mat->rho);
        if (p->has_emission)
            memcpy(mat->emission, p->emission, sizeof mat->emission);
        int used = 0;
        for (int t = 0; t < s->nt && !used; t++)
            used = s->tri_mat[t] == m;
        for (int k = 0; k < 3 && used; k++) {
            double r = mat->rho[k], e = mat->emission[k];
            if (!(r >= 0.0 && r < 1.0))
                return RAD_ERROR(RAD_EINPUT,
                                 "%s: material '%s': reflectance %c = %g is outside [0, 1)%s",
                                 s->source, mat->name, channel[k], r,
                                 p->has_rho ? " (from --rho)" : "");
            if (!(e >= 0.0) || !isfinite(e))
                return RAD_ERROR(RAD_EINPUT, "%s: material '%s': emission %c = %g is %s%s",
                                 s->source, mat->name, channel[k], e,
                                 isfinite(e) ? "negative" : "not finite",
                                 p->has_emission ? " (from --emission)" : "");
        }
    }
    return RAD_OK;
}

typedef struct keyed_point {
    double x[3];
    int v;
} keyed_point;

static int compare_points(const void *pa, const void *pb)
{
    const keyed_point *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->x[k] != b->x[k])
            return a->x[k] < b->x[k] ? -1 : 1;
    return a->v < b->v ? -1 : a->v > b->v;
}

static int same_point(const keyed_point *a, const keyed_point *b)
{
    return a->x[0] == b->x[0] && a->x[1] == b->x[1] && a->x[2] == b->x[2];
}

/* Merge bit-identical positions (== comparison; -0 equals 0) and drop unused
 * vertices; renumber the triangles.  New vertices are numbered in order of
 * first use by the triangles, so the result follows the input order. */
static rad_status weld(rad_scene *s)
{
    rad_status st = RAD_OK;
    keyed_point *order = malloc((size_t)s->nv * sizeof *order + 1);
    int *group = malloc((size_t)s->nv * sizeof *group + 1);
    int *renum = malloc((size_t)s->nv * sizeof *renum + 1);
    char *used = calloc((size_t)s->nv + 1, 1);
    double *xyz = malloc(3 * (size_t)s->nv * sizeof *xyz + 1);
    if (!order || !group || !renum || !used || !xyz) {
        st = RAD_ERROR(RAD_ENOMEM, "%s: no memory to merge vertices", s->source);
        goto out;
    }
    for (size_t i = 0; i < 3 * (size_t)s->nt; i++)
        used[s->tri[i]] = 1;
    int count = 0;
    for (int v = 0; v < s->nv; v++)
        if (used[v]) {
            memcpy(order[count].x, s->xyz + 3 * (size_t)v, sizeof order[count].x);
            order[count++].v = v;
        }
    qsort(order, (size_t)count, sizeof *order, compare_points);
    /* group[v] = the smallest original index at the same position. */
    for (int i = 0; i < count;) {
        int j = i;
        while (j < count && same_point(&order[i], &order[j]))
            j++;
        for (int k = i; k < j; k++)
            group[order[k].v] = order[i].v; /* sorted by index within a run */
        i = j;
    }
    for (int v = 0; v < s->nv; v++)
        renum[v] = -1;
    int nv = 0;
    for (size_t i = 0; i < 3 * (size_t)s->nt; i++) {
        int rep = group[s->tri[i]];
        if (renum[rep] < 0) {
            renum[rep] = nv;
            memcpy(xyz + 3 * (size_t)nv, s->xyz + 3 * (size_t)rep, 3 * sizeof *xyz);
            nv++;
        }
        s->tri[i] = renum[rep];
    }
    free(s->xyz);
    s->xyz = xyz;
    xyz = NULL;
    s->nv = nv;
    s->cap_v = nv;
out:
    free(order);
    free(group);
    free(renum);
    free(used);
    free(xyz);
    return st;
}

typedef struct keyed_face {
    int v[3]; /* sorted corners */
    int odd;  /* the face's corners are an odd permutation of v (the other side) */
    int t;
} keyed_face;

static int compare_faces(const void *pa, const void *pb)
{
    const keyed_face *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->v[k] != b->v[k])
            return a->v[k] < b->v[k] ? -1 : 1;
    if (a->odd != b->odd)
        return a->odd - b->odd;
    return a->t < b->t ? -1 : a->t > b->t;
}

static void sort3(int *t)
{
    int a = t[0], b = t[1], c = t[2], x;
    if (a > b) { x = a; a = b; b = x; }
    if (b > c) { x = b; b = c; c = x; }
    if (a > b) { x = a; a = b; b = x; }
    t[0] = a;
    t[1] = b;
    t[2] = c;
}

rad_status scene_check_coordinate(const char *path, int line, long vertex, double x, double scale)
{
    double scaled = x * scale;
    if (!(scale > 0.0) || !isfinite(scale) || fabs(scaled) <= RAD_GEOM_MAX_COORD)
        return RAD_OK; /* a bad scale is scene_finish's to refuse */
    char after[48] = "";
    if (scale != 1.0)
        snprintf(after, sizeof after, " (after scale %g)", scale);
    if (line > 0)
        return RAD_ERROR(RAD_EINPUT, "%s:%d: vertex %ld: coordinate %g%s is beyond %g, where "
                         "form-factor products overflow; scale the scene down", path, line, vertex,
                         scaled, after, RAD_GEOM_MAX_COORD);
    return RAD_ERROR(RAD_EINPUT, "%s: vertex %ld: coordinate %g%s is beyond %g, where form-factor "
                     "products overflow; scale the scene down", path, vertex, scaled, after,
                     RAD_GEOM_MAX_COORD);
}

/* Parity of the permutation taking t to sorted order: 0 even, 1 odd. */
static int odd_order(const int *t)
{
    return ((t[0] > t[1]) + (t[0] > t[2]) + (t[1] > t[2])) & 1;
}

static rad_status drop_duplicates(rad_scene *s, const rad_scene_params *p)
{
    keyed_face *keys = malloc((size_t)s->nt * sizeof *keys + 1);
    unsigned char *drop = calloc((size_t)s->nt + 1, 1);
    if (!keys || !drop) {
        free(keys);
        free(drop);
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory to look for duplicate faces", s->source);
    }
    for (int t = 0; t < s->nt; t++) {
        memcpy(keys[t].v, s->tri + 3 * (size_t)t, sizeof keys[t].v);
        keys[t].odd = odd_order(keys[t].v);
        sort3(keys[t].v);
        keys[t].t = t;
    }
    qsort(keys, (size_t)s->nt, sizeof *keys, compare_faces);
    int same = 0, opposite = 0, same_a = -1, same_b = -1, opp_a = -1, opp_b = -1;
    for (int i = 1; i < s->nt; i++) {
        if (memcmp(keys[i].v, keys[i - 1].v, sizeof keys[i].v) != 0)
            continue;
        if (keys[i].odd == keys[i - 1].odd) {
            /* sorted by input order within a side: keep the first */
            drop[keys[i].t] = 1;
            if (same++ == 0) {
                same_a = keys[i - 1].t;
                same_b = keys[i].t;
            }
        } else if (is_back_face(s, s->tri_face[keys[i - 1].t]) ||
                   is_back_face(s, s->tri_face[keys[i].t])) {
            continue; /* the two sides of a two-sided face, made so on purpose */
        } else if (opposite++ == 0) {
            opp_a = s->tri_face[keys[i - 1].t];
            opp_b = s->tri_face[keys[i].t];
        }
    }
    free(keys);
    rad_status st = RAD_OK;
    if (same > 0 && p->strict) {
        st = RAD_ERROR(RAD_EINPUT, "%s: face %d repeats face %d (the same corners, the same side; "
                       "refused in strict mode)", s->source, s->tri_face[same_b], s->tri_face[same_a]);
    } else if (same > 0) {
        int first_a = s->tri_face[same_a], first_b = s->tri_face[same_b], kept = 0;
        for (int t = 0; t < s->nt; t++) {
            if (drop[t])
                continue;
            if (kept != t) {
                memcpy(s->tri + 3 * (size_t)kept, s->tri + 3 * (size_t)t, 3 * sizeof *s->tri);
                s->tri_mat[kept] = s->tri_mat[t];
                s->tri_face[kept] = s->tri_face[t];
                s->tri_line[kept] = s->tri_line[t];
                s->tri_file[kept] = s->tri_file[t];
            }
            kept++;
        }
        s->nt = kept;
        st = scene_warn(s, "dropped %d duplicate face(s) (the same corners on the same side as an "
                        "earlier face; first: face %d repeats face %d)", same, first_b, first_a);
    }
    if (st == RAD_OK && opposite > 0)
        st = scene_warn(s, "%d pair(s) of coincident faces back to back (the two sides of one "
                        "surface), e.g. faces %d and %d", opposite, opp_a, opp_b);
    free(drop);
    return st;
}

static void default_camera(rad_scene *s)
{
    rad_scene_summary sum;
    rad_scene_summarize(s, &sum);
    double c[3], r = 0.0;
    for (int k = 0; k < 3; k++) {
        c[k] = 0.5 * (sum.bbox_min[k] + sum.bbox_max[k]);
        double h = 0.5 * (sum.bbox_max[k] - sum.bbox_min[k]);
        r += h * h;
    }
    r = sqrt(r);
    double fov = 40.0;
    double dist = r > 0.0 ? r / sin(0.5 * fov * (RAD_PI / 180.0)) : 1.0;
    rad_camera *cam = &s->camera;
    memset(cam, 0, sizeof *cam);
    for (int k = 0; k < 3; k++) {
        cam->position[k] = c[k];
        cam->look_at[k] = c[k];
    }
    cam->position[2] -= dist;
    cam->up[1] = 1.0;
    cam->fov_y_deg = fov;
    cam->from_scene = 0;
}

/* A polygon split into a fan is valid only when no fan triangle folds back
 * against the polygon's area vector (a non-convex or self-overlapping
 * polygon); consecutive triangles of one input face are its fan. */
static rad_status check_fans(const rad_scene *s)
{
    for (int t0 = 0; t0 < s->nt;) {
        int t1 = t0 + 1;
        while (t1 < s->nt && s->tri_face[t1] == s->tri_face[t0])
            t1++;
        if (t1 - t0 > 1) {
            rad_vec3 sum = rad_vec3_make(0, 0, 0);
            for (int pass = 0; pass < 2; pass++)
                for (int t = t0; t < t1; t++) {
                    const int *v = s->tri + 3 * (size_t)t;
                    rad_vec3 a = rad_vec3_make(s->xyz[3 * v[0]], s->xyz[3 * v[0] + 1], s->xyz[3 * v[0] + 2]);
                    rad_vec3 b = rad_vec3_make(s->xyz[3 * v[1]], s->xyz[3 * v[1] + 1], s->xyz[3 * v[1] + 2]);
                    rad_vec3 c = rad_vec3_make(s->xyz[3 * v[2]], s->xyz[3 * v[2] + 1], s->xyz[3 * v[2] + 2]);
                    rad_vec3 n = rad_vec3_cross(rad_vec3_sub(b, a), rad_vec3_sub(c, a));
                    if (pass == 0)
                        sum = rad_vec3_add(sum, n);
                    else if (rad_vec3_dot(n, sum) < 0.0) {
                        if (s->tri_line[t] > 0)
                            return RAD_ERROR(RAD_EINPUT, "%s:%d: face %d is a non-convex polygon "
                                             "(its fan triangulation folds); split it into triangles",
                                             scene_file_name(s, s->tri_file[t]), s->tri_line[t],
                                             s->tri_face[t]);
                        return RAD_ERROR(RAD_EINPUT, "%s: face %d is a non-convex polygon (its fan "
                                         "triangulation folds); split it into triangles",
                                         s->source, s->tri_face[t]);
                    }
                }
        }
        t0 = t1;
    }
    return RAD_OK;
}

rad_status scene_finish(rad_scene *s, const rad_scene_params *p)
{
    rad_status st;
    if (!(p->scale > 0.0) || !isfinite(p->scale))
        return RAD_ERROR(RAD_EINVAL, "scale must be a positive number, got %g", p->scale);
    if ((st = check_materials(s, p)) != RAD_OK)
        return st;
    if (s->nt == 0)
        return RAD_ERROR(RAD_EINPUT, "%s: the scene has no faces (empty scene)", s->source);
    if ((size_t)s->nt > p->max_triangles)
        return RAD_ERROR(RAD_ETOOBIG, "%s: %d triangles is more than the limit of %zu", s->source,
                         s->nt, p->max_triangles);
    for (int t = 0; t < s->nt; t++)
        if (s->tri_mat[t] < 0 || s->tri_mat[t] >= s->nm)
            return RAD_ERROR(RAD_EINPUT, "%s: face %d has no valid material", s->source, s->tri_face[t]);
    for (size_t i = 0; i < 3 * (size_t)s->nv; i++) {
        s->xyz[i] *= p->scale;
        if (!isfinite(s->xyz[i]))
            return RAD_ERROR(RAD_EINPUT, "%s: vertex %zu has a %s coordinate", s->source, i / 3,
                             isnan(s->xyz[i]) ? "NaN" : "infinite");
        if (fabs(s->xyz[i]) > RAD_GEOM_MAX_COORD)
            return RAD_ERROR(RAD_EINPUT, "%s: vertex %zu has coordinate %g (after --scale %g), beyond "
                             "%g, where form-factor products overflow; scale the scene down",
                             s->source, i / 3, s->xyz[i], p->scale, RAD_GEOM_MAX_COORD);
    }
    if (s->camera.from_scene)
        for (int k = 0; k < 3; k++) {
            s->camera.position[k] *= p->scale;
            s->camera.look_at[k] *= p->scale;
        }

    /* Degenerate triangles: dropped and counted, or an error in strict mode. */
    int kept = 0, first_line = 0, first_face = -1, first_file = 0;
    char *used = calloc((size_t)s->nv + 1, 1);
    if (!used)
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory", s->source);
    for (size_t i = 0; i < 3 * (size_t)s->nt; i++)
        used[s->tri[i]] = 1;
    int unused = 0;
    for (int v = 0; v < s->nv; v++)
        unused += !used[v];
    free(used);
    for (int t = 0; t < s->nt; t++) {
        const int *v = s->tri + 3 * (size_t)t;
        rad_vec3 a = rad_vec3_make(s->xyz[3 * v[0]], s->xyz[3 * v[0] + 1], s->xyz[3 * v[0] + 2]);
        rad_vec3 b = rad_vec3_make(s->xyz[3 * v[1]], s->xyz[3 * v[1] + 1], s->xyz[3 * v[1] + 2]);
        rad_vec3 c = rad_vec3_make(s->xyz[3 * v[2]], s->xyz[3 * v[2] + 1], s->xyz[3 * v[2] + 2]);
        if (rad_geom_triangle_is_degenerate(a, b, c, p->degenerate_rel_tol)) {
            if (p->strict) {
                if (s->tri_line[t] > 0)
                    return RAD_ERROR(RAD_EINPUT, "%s:%d: degenerate (zero-area) triangle in face %d "
                                     "(refused in strict mode)", scene_file_name(s, s->tri_file[t]),
                                     s->tri_line[t], s->tri_face[t]);
                return RAD_ERROR(RAD_EINPUT, "%s: face %d: degenerate (zero-area) triangle "
                                 "(refused in strict mode)", s->source, s->tri_face[t]);
            }
            if (s->dropped++ == 0) {
                first_line = s->tri_line[t];
                first_face = s->tri_face[t];
                first_file = s->tri_file[t];
            }
            continue;
        }
        if (kept != t) {
            memcpy(s->tri + 3 * (size_t)kept, v, 3 * sizeof *v);
            s->tri_mat[kept] = s->tri_mat[t];
            s->tri_face[kept] = s->tri_face[t];
            s->tri_line[kept] = s->tri_line[t];
            s->tri_file[kept] = s->tri_file[t];
        }
        kept++;
    }
    s->nt = kept;
    if ((st = check_fans(s)) != RAD_OK)
        return st;
    if (s->nt == 0)
        return RAD_ERROR(RAD_EINPUT, "%s: no faces left after dropping %d degenerate (zero-area) "
                         "triangle(s)", s->source, s->dropped);
    if (s->dropped > 0) {
        st = first_line > 0
                 ? scene_warn(s, "dropped %d degenerate (zero-area) triangle(s) (first at %s:%d, "
                              "face %d)", s->dropped, scene_file_name(s, first_file), first_line,
                              first_face)
                 : scene_warn(s, "dropped %d degenerate (zero-area) triangle(s) (first: face %d)",
                              s->dropped, first_face);
        if (st != RAD_OK)
            return st;
    }
    if (unused > 0 &&
        (st = scene_warn(s, "%d unused vertices (not referenced by any face)", unused)) != RAD_OK)
        return st;
    if ((st = weld(s)) != RAD_OK || (st = drop_duplicates(s, p)) != RAD_OK)
        return st;
    rad_scene_summary sum;
    rad_scene_summarize(s, &sum);
    if (sum.emitters == 0 && (st = scene_warn(s, "no emitter: every emission is zero, so the "
                                                 "radiosity is zero everywhere")) != RAD_OK)
        return st;
    if (!s->camera.from_scene)
        default_camera(s);
    return RAD_OK;
}

/* ---- loading ------------------------------------------------------------- */

static int has_extension(const char *path, const char *ext)
{
    size_t n = strlen(path), e = strlen(ext);
    if (n < e)
        return 0;
    for (size_t i = 0; i < e; i++)
        if (tolower((unsigned char)path[n - e + i]) != ext[i])
            return 0;
    return 1;
}

rad_status rad_scene_load(const char *path, const rad_scene_params *params, rad_scene **out)
{
    rad_scene_params defaults;
    if (!params) {
        rad_scene_params_default(&defaults);
        params = &defaults;
    }
    if (!out || !path || !*path)
        return RAD_ERROR(RAD_EINVAL, "rad_scene_load: no file name");
    *out = NULL;
    /* Every format: a regular file within the size limit, so that no
     * importer meets a FIFO, a device or a directory. */
    FILE *probe = NULL;
    long long size = 0;
    rad_status st = scene_open_regular(path, params->max_file_bytes, &probe, &size, NULL);
    if (st != RAD_OK)
        return st;
    fclose(probe);
    if (size == 0)
        return RAD_ERROR(RAD_EINPUT, "%s: the file is empty (empty scene)", path);
    rad_scene *s = scene_new(path);
    if (!s)
        return RAD_ERROR(RAD_ENOMEM, "%s: no memory", path);
    st = has_extension(path, ".obj")   ? scene_import_obj(s, path, params)
         : has_extension(path, ".off") ? scene_import_off(s, path, params)
         : has_extension(path, ".ply") ? scene_import_ply(s, path, params)
         : has_extension(path, ".mgf") ? scene_import_mgf(s, path, params)
                                       : scene_import_assimp(s, path, params);
    if (st == RAD_OK)
        st = scene_finish(s, params);
    if (st != RAD_OK) {
        rad_scene_destroy(s);
        return st;
    }
    *out = s;
    return RAD_OK;
}

rad_status rad_scene_create(const char *name, const double *xyz, int nv, const int *tri, int nt,
                            const int *tri_material, const rad_scene_material *materials, int nm,
                            const rad_scene_params *params, rad_scene **out)
{
    rad_scene_params defaults;
    if (!params) {
        rad_scene_params_default(&defaults);
        params = &defaults;
    }
    if (!out)
        return RAD_ERROR(RAD_EINVAL, "rad_scene_create: out is NULL");
    *out = NULL;
    if (nv < 0 || nt < 0 || nm < 1 || !materials || (nv > 0 && !xyz) || (nt > 0 && !tri))
        return RAD_ERROR(RAD_EINVAL, "rad_scene_create: bad arrays (nv %d, nt %d, nm %d)", nv, nt, nm);
    rad_scene *s = scene_new(name);
    if (!s)
        return RAD_ERROR(RAD_ENOMEM, "rad_scene_create: no memory");
    rad_status st = RAD_OK;
    for (int v = 0; v < nv && st == RAD_OK; v++)
        st = scene_add_vertex(s, xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
    for (int m = 0; m < nm && st == RAD_OK; m++)
        st = scene_add_material(s, materials[m].name, materials[m].rho, materials[m].emission);
    for (int t = 0; t < nt && st == RAD_OK; t++) {
        for (int k = 0; k < 3; k++)
            if (tri[3 * t + k] < 0 || tri[3 * t + k] >= nv)
                st = RAD_ERROR(RAD_EINPUT, "%s: face %d: vertex index %d out of range (%d vertices)",
                               s->source, t, tri[3 * t + k], nv);
        if (st == RAD_OK)
            st = scene_add_triangle(s, tri[3 * t], tri[3 * t + 1], tri[3 * t + 2],
                                    tri_material ? tri_material[t] : 0, t, 0);
    }
    if (st == RAD_OK)
        st = scene_finish(s, params);
    if (st != RAD_OK) {
        rad_scene_destroy(s);
        return st;
    }
    *out = s;
    return RAD_OK;
}

/* ---- accessors ----------------------------------------------------------- */

int rad_scene_vertex_count(const rad_scene *s) { return s ? s->nv : 0; }
int rad_scene_triangle_count(const rad_scene *s) { return s ? s->nt : 0; }
int rad_scene_material_count(const rad_scene *s) { return s ? s->nm : 0; }
const double *rad_scene_vertices(const rad_scene *s) { return s ? s->xyz : NULL; }
const int *rad_scene_triangles(const rad_scene *s) { return s ? s->tri : NULL; }
const int *rad_scene_triangle_materials(const rad_scene *s) { return s ? s->tri_mat : NULL; }
const int *rad_scene_triangle_faces(const rad_scene *s) { return s ? s->tri_face : NULL; }
const rad_scene_material *rad_scene_materials(const rad_scene *s) { return s ? s->mats : NULL; }
const rad_camera *rad_scene_camera(const rad_scene *s) { return s ? &s->camera : NULL; }
const char *rad_scene_source(const rad_scene *s) { return s ? s->source : ""; }
int rad_scene_dropped_count(const rad_scene *s) { return s ? s->dropped : 0; }
int rad_scene_warning_count(const rad_scene *s) { return s ? s->nw : 0; }

const char *rad_scene_warning(const rad_scene *s, int i)
{
    return s && i >= 0 && i < s->nw ? s->warnings[i] : "";
}

void rad_scene_summarize(const rad_scene *s, rad_scene_summary *sum)
{
    memset(sum, 0, sizeof *sum);
    if (!s)
        return;
    sum->faces = s->nt;
    sum->vertices = s->nv;
    sum->materials = s->nm;
    sum->grey_reflectance = 1;
    sum->grey_emission = 1;
    for (int k = 0; k < 3; k++) {
        sum->bbox_min[k] = s->nv ? INFINITY : 0.0;
        sum->bbox_max[k] = s->nv ? -INFINITY : 0.0;
    }
    for (int v = 0; v < s->nv; v++)
        for (int k = 0; k < 3; k++) {
            sum->bbox_min[k] = fmin(sum->bbox_min[k], s->xyz[3 * v + k]);
            sum->bbox_max[k] = fmax(sum->bbox_max[k], s->xyz[3 * v + k]);
        }
    for (int t = 0; t < s->nt; t++) {
        const int *v = s->tri + 3 * (size_t)t;
        rad_vec3 a = rad_vec3_make(s->xyz[3 * v[0]], s->xyz[3 * v[0] + 1], s->xyz[3 * v[0] + 2]);
        rad_vec3 b = rad_vec3_make(s->xyz[3 * v[1]], s->xyz[3 * v[1] + 1], s->xyz[3 * v[1] + 2]);
        rad_vec3 c = rad_vec3_make(s->xyz[3 * v[2]], s->xyz[3 * v[2] + 1], s->xyz[3 * v[2] + 2]);
        double area = rad_geom_triangle_area(a, b, c);
        const rad_scene_material *m = &s->mats[s->tri_mat[t]];
        sum->total_area += area;
        if (m->emission[0] > 0.0 || m->emission[1] > 0.0 || m->emission[2] > 0.0) {
            sum->emitters++;
            sum->emitting_area += area;
        }
        if (m->rho[0] != m->rho[1] || m->rho[1] != m->rho[2])
            sum->grey_reflectance = 0;
        if (m->emission[0] != m->emission[1] || m->emission[1] != m->emission[2])
            sum->grey_emission = 0;
    }
}
