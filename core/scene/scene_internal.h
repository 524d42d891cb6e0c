/* Internal to rad_scene: the scene object and the helpers its importers share. */
#ifndef RAD_SCENE_INTERNAL_H
#define RAD_SCENE_INTERNAL_H

#include "rad_scene.h"

struct rad_scene {
    char *source;
    double *xyz;      /* 3 per vertex */
    int nv, cap_v;
    int *tri;         /* 3 per triangle */
    int *tri_mat;     /* material per triangle */
    int *tri_face;    /* input face per triangle */
    int *tri_line;    /* input line per triangle (0 when the format has none) */
    int *tri_file;    /* file of that line: 0 the source, k > 0 files[k - 1] */
    int nt, cap_t;
    char **files;     /* other files triangles come from (included files) */
    int nfiles, cap_files;
    int cur_file;     /* the file scene_add_triangle records (scene_set_file) */
    unsigned char *back_face; /* 1 for a face an importer made as the reverse side of the
                                 face before it (MGF's two-sided materials), by face */
    int cap_back;
    rad_scene_material *mats;
    int nm, cap_m;
    rad_camera camera;
    int dropped;
    char **warnings;
    int nw, cap_w;
};

/* Growth helpers: RAD_ENOMEM on failure. */
rad_status scene_add_vertex(rad_scene *s, double x, double y, double z);
rad_status scene_add_triangle(rad_scene *s, int a, int b, int c, int mat, int face, int line);
/* Files other than the source (an MGF include): scene_add_file records a
 * copy of path and returns its number (> 0); scene_set_file(s, k) makes the
 * triangles added next, and the messages about them, name file k (0: the
 * source) with their lines.  scene_file_name gives file k's name. */
rad_status scene_add_file(rad_scene *s, const char *path, int *k);
void scene_set_file(rad_scene *s, int k);
const char *scene_file_name(const rad_scene *s, int k);
/* Mark `face` as the reverse side of the face before it, made on purpose
 * (MGF's two-sided materials): scene_finish does not warn about it as a
 * coincident face back to back. */
rad_status scene_mark_back_face(rad_scene *s, int face);
/* Triangulate the polygon idx[0..n-1] (existing vertices) into triangles that
 * keep `face` and `line`: the fan (0,1,2), (0,2,3), ... when it does not fold
 * (every convex polygon), else ear clipping in the polygon's plane.  RAD_EINPUT
 * naming the face for n < 3, an index out of range or a self-intersecting
 * polygon (polygon.c). */
rad_status scene_add_polygon(rad_scene *s, const int *idx, int n, int mat, int face, int line);
/* The same for a polygon with holes: ncontours contours of count[c] corners
 * each, one after the other in idx, the first the outer boundary (its corner
 * order gives the front side), the others holes (either order).  Each hole is
 * bridged to the outer ring and the weakly simple polygon that makes is ear
 * clipped (polygon.c).  RAD_EINPUT naming the face for a contour of fewer
 * than 3 corners, an outer contour without area, a hole outside the outer
 * contour or inside another hole, or contours that cross. */
rad_status scene_add_polygon_holes(rad_scene *s, const int *idx, const int *count, int ncontours,
                                   int mat, int face, int line);
rad_status scene_add_material(rad_scene *s, const char *name, const double rho[3],
                              const double emission[3]);
rad_status scene_warn(rad_scene *s, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
rad_scene *scene_new(const char *source);
/* A coordinate read at path:line (line 0: a binary file; vertex names it)
 * once multiplied by scale: RAD_EINPUT there when beyond RAD_GEOM_MAX_COORD,
 * the bound scene_finish applies to every format, so that the message can
 * name the place. */
rad_status scene_check_coordinate(const char *path, int line, long vertex, double x, double scale);

/* Importers fill a new scene; scene_finish validates and normalises it. */
rad_status scene_import_obj(rad_scene *s, const char *path, const rad_scene_params *p);
rad_status scene_import_assimp(rad_scene *s, const char *path, const rad_scene_params *p);
/* radkit's own OFF and PLY readers (import_off.c, import_ply.c). */
rad_status scene_import_off(rad_scene *s, const char *path, const rad_scene_params *p);
rad_status scene_import_ply(rad_scene *s, const char *path, const rad_scene_params *p);
/* radkit's MGF reader (import_mgf.c). */
rad_status scene_import_mgf(rad_scene *s, const char *path, const rad_scene_params *p);
/* Segments per full circle of the MGF reader's curved primitives for a
 * curve tolerance (rad_scene_params.curve_tol); -1 outside (0, 1). */
int scene_mgf_segments(double tol);
/* The whole of a regular file of at most max_bytes, NUL-terminated (free it). */
rad_status scene_read_file(const char *path, size_t max_bytes, char **data, size_t *size);
/* Import `path` with Assimp only to count its triangles and materials (the
 * cross-check of the OBJ reader). */
rad_status scene_assimp_count(const char *path, long *triangles, long *materials);
/* KHR_materials_emissive_strength of each glTF material (1 where absent), read
 * from the file's JSON; returns how many materials it found (0 on any problem). */
int scene_gltf_emissive_strengths(const char *path, double *strength, int cap);
rad_status scene_finish(rad_scene *s, const rad_scene_params *p);

/* cie.c: the CIE 1931 xy chromaticity of a spectral distribution (a
 * function of the wavelength in nm, >= 0) or of a blackbody at `kelvin`;
 * 0 when the spectrum is negative, not finite or dark in 360 .. 830 nm. */
int scene_cie_xy(double (*spectrum)(double nm, void *ctx), void *ctx, double *x, double *y);
int scene_cie_xy_blackbody(double kelvin, double *x, double *y);

#endif
