/* rad_scene: a validated triangle scene, imported from a file, and the
 * effects plan (what a radiosity run on it needs to simulate).
 *
 * The scene is plain data behind an opaque handle: flat arrays of vertex
 * positions (x, y, z doubles), triangles (three vertex indices each, in input
 * order), a material index per triangle and a material table (reflectance and
 * emitted exitance per RGB channel).  No Assimp type appears here.
 *
 * Import (rad_scene_load):
 *   - OBJ + MTL: Kd is the reflectance (albedo per channel), Ke the emitted
 *     exitance (W/m^2).  radkit's own line reader supplies the values in double
 *     precision and every finding as file:line; on request (no_cross_check = 0,
 *     `radkit info --assimp-check`) Assimp imports the same file and its
 *     triangle count is compared (Debian's Assimp stores coordinates in
 *     single precision, which is not enough for convergence studies).
 *   - glTF 2.0 (.gltf, .glb): baseColorFactor is the reflectance, emissiveFactor
 *     times KHR_materials_emissive_strength (when present) the emission.
 *   - MGF (.mgf, radkit's reader, import_mgf.c): `rd` with its colour is the
 *     reflectance, `ed` the emitted exitance, CIE xy converted to RGB with
 *     Radiance's primaries balanced for the equal-energy white (a neutral
 *     colour gives equal channels); transforms, arrays and includes (relative
 *     to the including file, at most 16 deep, no loops); faces with holes
 *     (fh); the curved primitives (sph, cyl, cone, ring, torus, prism)
 *     tessellated within curve_tol; each face of a two-sided material (sides
 *     2, MGF's default) made twice, the second reversed; messages about the
 *     triangles of an included file name that file and line.
 *   - PLY, OFF (radkit's readers), STL and anything else Assimp reads: geometry only; every face
 *     gets the reflectance and emission of the parameters (--rho, --emission).
 * Polygons are triangulated in their plane (the fan when it does not fold,
 * ear clipping otherwise) by radkit's readers, or by Assimp; the triangles
 * keep the order of the input faces and each its face's material.  Vertices at
 * bit-identical positions are merged and unused vertices dropped, so two
 * triangles share a vertex index exactly when they share a corner point.
 *
 * Validation (errors, RAD_EINPUT or RAD_EIO, with the place in the message):
 * missing or unreadable files, files that are not regular (directories,
 * devices, FIFOs), larger than max_file_bytes or (OBJ/MTL) with a line longer
 * than max_line_bytes or a NUL byte, malformed content, NaN/Inf coordinates or
 * coordinates beyond RAD_GEOM_MAX_COORD (after the scale), face indices out of
 * range, reflectance outside [0, 1] (MTL Kd) or [0, 1) (elsewhere), negative
 * emission, an empty scene or one whose every triangle is degenerate.
 * Loaded with a counted warning, naming the first place (all of them refused
 * when params.strict is set):
 *   - MTL Kd = 1 (white), taken as rho_white (0.999), the largest reflectance
 *     radkit gives a surface;
 *   - a material library that does not exist, a usemtl naming a material no
 *     library defines: those faces take the default material (default_rho,
 *     no emission; the overrides apply as to every material);
 *   - degenerate (zero-area) triangles: dropped (rad_scene_dropped_count);
 *   - OBJ/MTL statements radkit does not use, one warning per keyword (strict
 *     mode refuses only the unknown ones and those that describe geometry
 *     radkit does not load: free-form curves and surfaces, call; texture,
 *     specular, transmission and display statements still only warn, since
 *     radkit's surfaces are opaque and diffuse by definition).
 * Other warnings: no emitter, duplicate coincident faces, unused vertices. */
#ifndef RAD_SCENE_H
#define RAD_SCENE_H

#include <stddef.h>

#include "rad_error.h"
#include "rad_mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rad_scene rad_scene;

typedef struct rad_scene_material {
    char name[64];
    double rho[3];      /* reflectance (albedo) per RGB channel, 0 <= rho < 1 */
    double emission[3]; /* emitted exitance E per RGB channel, W/m^2, >= 0 */
} rad_scene_material;

/* A pinhole camera: where it is, what it looks at, its up vector and its
 * vertical field of view.  from_scene is 1 when the file gave it (an OBJ
 * comment "# radkit camera ..." or a glTF/Assimp camera), 0 for the default
 * view (rad_scene_load documents it). */
typedef struct rad_camera {
    double position[3], look_at[3], up[3];
    double fov_y_deg;
    int from_scene;
} rad_camera;

typedef struct rad_scene_params {
    double scale;              /* every coordinate is multiplied by it (units -> metres); > 0 */
    int strict;                /* 1: refuse what otherwise loads with a warning (above) */
    int drop_degenerate;       /* unused: degenerate triangles are dropped unless strict
                                  (kept so that callers setting it still compile) */
    double degenerate_rel_tol; /* rad_geom_triangle_is_degenerate tolerance */
    int has_rho;               /* 1: rho below replaces every material's reflectance */
    double rho[3];
    int has_emission;          /* 1: emission below replaces every material's emission */
    double emission[3];
    double default_rho[3];     /* reflectance of faces that have no material (PLY, OFF, STL) */
    size_t max_triangles;      /* refuse bigger scenes with RAD_ETOOBIG */
    double rho_white;          /* the reflectance an MTL's Kd = 1 stands for, < 1 */
    size_t max_file_bytes;     /* refuse scene files (and material libraries) above it */
    size_t max_line_bytes;     /* refuse OBJ/MTL lines longer than this (line break not
                                  counted): memory stays bounded on any input */
    double curve_tol;          /* MGF curved primitives: largest distance from the true
                                  surface to its facets, relative to the radius; in (0, 1) */
    int no_cross_check;        /* 0: also re-read an OBJ with Assimp and warn when its
                                  triangle count differs.  Default 1: Assimp's OBJ
                                  reader runs in this process and dereferences null
                                  on some malformed files (a material statement
                                  before any newmtl), and Debian's Assimp 5.2 spends
                                  ~50 ms clearing a buffer on every OBJ */
} rad_scene_params;

/* scale 1, not strict, tolerance 1e-12, no overrides, default reflectance
 * 0.5 grey, at most 50 million triangles, Kd = 1 taken as 0.999 (errors are
 * then amplified at most 1000 times, well inside the effects plan's limit of
 * 10^6: white walls stay solvable at modest cost), files up to 2 GiB, lines
 * up to 64 KiB, MGF curve tolerance 0.0125 (20 segments a circle). */
void rad_scene_params_default(rad_scene_params *params);

/* Import a scene file (format by extension, see above) and validate it.
 * params may be NULL (defaults).  The default camera, when the file has none,
 * looks at the centre of the bounding box from the -z side, at a distance
 * that fits the bounding sphere in a 40 degree vertical field, up = +y. */
rad_status rad_scene_load(const char *path, const rad_scene_params *params, rad_scene **out);

/* Build a scene from arrays (copied): xyz has 3*nv doubles, tri 3*nt indices,
 * tri_material nt indices into materials (or NULL: all material 0).  It is
 * validated like a file; `name` stands in for the file name in messages. */
rad_status rad_scene_create(const char *name, const double *xyz, int nv, const int *tri, int nt,
                            const int *tri_material, const rad_scene_material *materials, int nm,
                            const rad_scene_params *params, rad_scene **out);

void rad_scene_destroy(rad_scene *scene);

int rad_scene_vertex_count(const rad_scene *scene);
int rad_scene_triangle_count(const rad_scene *scene);
int rad_scene_material_count(const rad_scene *scene);
const double *rad_scene_vertices(const rad_scene *scene);          /* 3 per vertex */
const int *rad_scene_triangles(const rad_scene *scene);            /* 3 per triangle */
const int *rad_scene_triangle_materials(const rad_scene *scene);   /* 1 per triangle */
/* The input face (0-based, in file order) each triangle came from: polygons
 * split into several triangles share it.  Dropped faces still count. */
const int *rad_scene_triangle_faces(const rad_scene *scene);
const rad_scene_material *rad_scene_materials(const rad_scene *scene);
const rad_camera *rad_scene_camera(const rad_scene *scene);
const char *rad_scene_source(const rad_scene *scene);
/* Triangles dropped as degenerate (none in strict mode, which refuses them). */
int rad_scene_dropped_count(const rad_scene *scene);
int rad_scene_warning_count(const rad_scene *scene);
const char *rad_scene_warning(const rad_scene *scene, int i);

/* Figures of the whole scene. */
typedef struct rad_scene_summary {
    int faces, vertices, materials;
    int emitters;            /* triangles with some emission > 0 */
    double total_area;       /* sum of triangle areas */
    double emitting_area;
    double bbox_min[3], bbox_max[3];
    int grey_reflectance;    /* 1: rho_r = rho_g = rho_b for every used material */
    int grey_emission;       /* 1: the same for emission */
} rad_scene_summary;

void rad_scene_summarize(const rad_scene *scene, rad_scene_summary *summary);

/* ---- the effects plan (DESIGN.md, "Effects") ---------------------------- */

typedef enum rad_effect_mode {
    RAD_EFFECT_AUTO = 0, /* decide from the scene */
    RAD_EFFECT_ON,       /* forced on by the user */
    RAD_EFFECT_OFF       /* forced off by the user */
} rad_effect_mode;

/* Parse "auto", "on" or "off"; RAD_EINVAL names `what` otherwise. */
rad_status rad_scene_effect_mode_parse(const char *what, const char *text, rad_effect_mode *out);

typedef struct rad_effects_params {
    rad_effect_mode occlusion, colour, facing_away, singular, reflectance, clustering, contact;
    double cluster_min_pairs; /* clustering from this many pairs of input triangles that
                                 face each other on (hier's initial links), where faces
                                 can block each other; above pair_scan_max_faces (not
                                 counted) always */
    double cluster_min_pairs_clear; /* the same where nothing can block (occlusion off) */
    int pair_scan_max_faces;  /* count facing-away pairs only up to this many faces (O(n^2)) */
    double grey_tol;          /* channels within this absolute difference are grey */
    double plane_rel_tol;     /* a corner within plane_rel_tol x |n| (|b-a| + |c-a|) of a
                                 face's plane counts as on it (facing-away test) */
    double near_one;          /* reflectance from which tolerances are tightened */
    double max_amplification; /* refuse scenes whose 1 / (1 - rho_max) exceeds this */
    double contact_rel_tol;   /* a corner within this times the longer longest edge of a
                                 triangle's plane lies on it (contact lines) */
    double contact_near_rel;  /* an edge within this times its own triangle's longest
                                 edge above a triangle's plane hovers over it: it cuts
                                 the triangle like a contact line (default 0.1: under
                                 a box a tenth of its size away the radiosity still
                                 turns within about that distance of its outline,
                                 often narrower than the elements min_area allows) */
    double contact_near_rel_large; /* the same over a triangle large beside the edge's
                                      (RAD_MESH_HOVER_LARGE times its size; default
                                      0.25: a box side a fifth of its size from a
                                      wall sees mostly the patch its own shadow
                                      darkens, which the wall's elements, each
                                      much larger, average with the lit wall) */
    int threads;              /* OpenMP threads of the contact cut; 0: OpenMP's default */
} rad_effects_params;

/* Everything automatic; clustering from 2.5e5 facing pairs among
 * occluders (5e6 with tightening, which is on), 2e4 where nothing can
 * block, always above the pair scan; pair scan up to
 * 20000 faces; grey within 1e-12;
 * plane tolerance 1e-12;
 * reflectance near 1 from 0.5; refusal beyond an amplification of 10^6;
 * contact within 1e-6, hovering within 0.1 of a triangle's size (0.25 over
 * one RAD_MESH_HOVER_LARGE times larger). */
void rad_scene_effects_params_default(rad_effects_params *params);

typedef struct rad_effect_decision {
    int on;             /* the decision */
    int forced;         /* 1 when a flag overrode the automatic decision */
    char reason[256];   /* why, in one sentence */
} rad_effect_decision;

typedef struct rad_effects_plan {
    /* on: some pair may be occluded, test visibility per pair (rays where no
     * shaft or convexity test excludes blockers); off: no face can block any pair. */
    rad_effect_decision occlusion;
    /* on: three systems (RGB); off: one scalar system (grey reflectance). */
    rad_effect_decision colour;
    /* on: pairs facing away from each other are zero without integration. */
    rad_effect_decision facing_away;
    /* on: edge/vertex-adjacent non-coplanar pairs get singular quadrature. */
    rad_effect_decision singular;
    /* on: the largest reflectance is near 1, so that errors of the form
     * factors and of the solver's stopping test are amplified by up to
     * 1 / (1 - rho_max): their tolerances are multiplied by `tighten`. */
    rad_effect_decision reflectance;
    /* on: hierarchical radiosity links from a cluster hierarchy instead of
     * every pair of input triangles (rad_hier params.cluster). */
    rad_effect_decision clustering;
    /* on: some triangle has another standing on it (or hovering within
     * contact_near_rel of its size above it, contact_near_rel_large above a
     * triangle large beside it) along a segment through its
     * inside (rad_mesh_split_contacts):
     * hierarchical radiosity cuts it there before meshing, so that no
     * element straddles the line where its radiosity jumps. */
    rad_effect_decision contact;
    int contact_faces;            /* input triangles with contact segments */
    int contact_pieces;           /* the pieces they are cut into */
    double rho_max;               /* the largest reflectance of any face and channel */
    /* 1 when every point sees only front faces, so that every row of form
     * factors sums to exactly 1: every component is closed, one (the
     * enclosure, the largest by volume) faces inward and every other faces
     * outward.  Hierarchical radiosity then normalizes its rows. */
    int sealed;
    double tighten;               /* (1 - rho_max) / (1 - near_one) when reflectance is on, else 1 */
    /* Not empty when no method of radkit can reach its accuracy on this scene
     * (reflectance within 1 / max_amplification of 1): the reason, which the
     * solvers report with RAD_ENUMERIC. */
    char refusal[256];
    long long pairs_total;        /* n (n - 1) / 2 */
    long long pairs_facing_away;  /* -1 when not counted (more faces than the scan limit) */
    int pairs_singular;           /* adjacent, non-coplanar */
    int pairs_adjacent_coplanar;  /* adjacent and coplanar: the kernel vanishes */
} rad_effects_plan;

/* Decide the plan for a scene and its mesh (built from the same triangles). */
rad_status rad_scene_effects_plan(const rad_scene *scene, const rad_mesh *mesh,
                                  const rad_effects_params *params, rad_effects_plan *plan);
/* The same, and the contact cut the plan's contact decision is made from
 * (rad_mesh_split_contacts with params' tolerances; the caller frees it with
 * rad_mesh_contacts_free, on success or not), so that a solve that cuts
 * along the contacts need not cut again: on a scene of a million triangles
 * the cut takes seconds. */
rad_status rad_scene_effects_plan_cut(const rad_scene *scene, const rad_mesh *mesh,
                                      const rad_effects_params *params, rad_effects_plan *plan,
                                      rad_mesh_contacts *cut);

/* The decisions in a fixed order with their names ("occlusion", "colour",
 * "facing_away", "singular", "reflectance", "clustering", "contact"), for
 * printing. */
#define RAD_EFFECT_COUNT 7
void rad_scene_effects_list(const rad_effects_plan *plan,
                            const rad_effect_decision *decisions[RAD_EFFECT_COUNT],
                            const char *names[RAD_EFFECT_COUNT]);

#ifdef __cplusplus
}
#endif
#endif
