/* rad_io: the writers of radkit's outputs.
 *
 * - per-face TSV (`solve --out`): `#` comment lines (key = value), one header
 *   row `face area B_r B_g B_b`, one row per face;
 * - PLY with per-vertex colours (`--ply`), ASCII or binary little-endian;
 * - stats JSON (`--stats`) with the keys of DESIGN.md, through a small JSON
 *   emitter that escapes strings and refuses non-finite numbers;
 * - experiment `.dat` files: a `#` header with title, version, parameters and
 *   column names, then tab-separated rows for gnuplot;
 * - the tone map shared with rad_render.
 * Per-face arrays of three channels are n x 3 column-major (channel c of face i
 * is B[i + c n]), as in rad_dense_solve.h.  Numbers are written with %.17g, so
 * a double reads back exactly.  A path of "-" means standard output.
 * Every file is written through rad_io_output (output.c): to a temporary
 * file beside the target, renamed onto it only when every write and the
 * close succeeded, so a failed write leaves no partial file and nothing
 * radkit did not create is ever removed.
 * Errors: RAD_EINVAL for a path that cannot be written (empty, a directory,
 * a missing directory), RAD_EIO for a failed write, naming the path and the
 * system's reason. */
#ifndef RAD_IO_H
#define RAD_IO_H

#include <stddef.h>
#include <stdio.h>

#include "rad_error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A `# key = value` header line. */
typedef struct rad_io_kv {
    const char *key;
    const char *value;
} rad_io_kv;

/* ---- tone map --------------------------------------------------------------
 * display = round(255 * clamp(exposure * B, 0, 1)^(1 / gamma)): a linear
 * exposure, a hard clip at white, then a display gamma (2.2 by default, the
 * usual approximation of sRGB).  No Reinhard curve: radiosity values below the
 * clip are shown proportionally, so images compare by eye across runs. */
typedef struct rad_io_tonemap {
    double exposure; /* default 1 */
    double gamma;    /* default 2.2 */
} rad_io_tonemap;

void rad_io_tonemap_default(rad_io_tonemap *tm);
unsigned char rad_io_tonemap_apply(const rad_io_tonemap *tm, double value);
/* An exposure that maps the given percentile (0..1, e.g. 0.95) of the positive
 * values to white; 1 if there are none.  Lights are usually the top few percent,
 * so 0.95 keeps the lit surfaces visible instead of scaling to the lamp. */
double rad_io_tonemap_auto_exposure(size_t n, const double *values, double percentile);

/* Vertex radiosity: the area-weighted average of the B of the faces that use
 * each vertex (interleaved: vb[3 v + c]); 0 for a vertex no face uses.
 * B is ntris x 3 column-major; areas are computed from xyz. */
rad_status rad_io_vertex_values(size_t nverts, const double *xyz, size_t ntris, const int *tri,
                                const double *B, double *vb);

/* ---- output files ------------------------------------------------------------
 * A file that appears whole or not at all.  A regular file (or a new one) is
 * written to "<target>.tmp.XXXXXX" in the target's directory and renamed onto
 * the target by rad_io_output_commit, keeping the old file's permissions (a
 * new one gets 0666 less the umask); a symbolic link is followed and stays.
 * A target that exists and is not a regular file (a device, a pipe) and
 * standard output ("-") are written in place and never renamed or removed.
 * Not thread-safe for one object; different objects are independent. */
typedef struct rad_io_output {
    FILE *f;          /* write here */
    const char *path; /* as given (borrowed: must outlive the object) */
    char *target;     /* the file the rename replaces (owned), NULL in place */
    char *tmp;        /* the temporary file (in target's allocation), NULL in place */
    int in_place;     /* standard output, a device or a pipe */
} rad_io_output;

/* Whether path can be written, without touching it: RAD_EINVAL naming the
 * path and the problem for an empty path, a directory, a file that is not
 * writable, a directory that does not exist or is not one, or one where files
 * cannot be created.  "-" (standard
 * output) is fine.  Callers check before long work so a typo fails at once. */
rad_status rad_io_output_check(const char *path);
/* rad_io_output_check, then open (binary: "wb").  On failure *out is empty. */
rad_status rad_io_output_open(const char *path, int binary, rad_io_output *out);
/* Flush, check for any failed write, close and rename onto the target.
 * RAD_EIO naming the path and the system's reason ("error writing standard
 * output: ..." for "-"); on failure only the temporary file is removed.  The
 * object is released either way. */
rad_status rad_io_output_commit(rad_io_output *out);
/* Give up: close and remove the temporary file (never the target).  Accepts
 * an empty or already committed object. */
void rad_io_output_discard(rad_io_output *out);
/* 1 when two output paths name the same file: the same text, the same
 * existing file (device and inode: hard or symbolic links), or the same name
 * in the same directory once the directories are resolved. */
int rad_io_output_same(const char *a, const char *b);

/* ---- writers --------------------------------------------------------------- */

/* Per input face: its total area and the area-weighted average of its
 * elements' values.  face_of[i] (< nfaces) is element i's face; elem_B and
 * face_B are n x 3 column-major (face_B: nfaces x 3).  A face without elements
 * gets area 0 and value 0.  RAD_EINPUT for a face index out of range. */
rad_status rad_io_face_averages(size_t nelem, const int *face_of, const double *elem_area,
                                const double *elem_B, size_t nfaces, double *face_area,
                                double *face_B);

/* The per-face table (header row face, area, B_r, B_g, B_b, then one row per
 * face) to an open stream; rad_io_write_faces_tsv and `radkit solve` use it. */
void rad_io_print_faces(FILE *f, size_t n, const double *area, const double *B);
/* The same with three more columns se_r, se_g, se_b (standard errors, n x 3
 * column-major) when se is not NULL. */
void rad_io_print_faces_se(FILE *f, size_t n, const double *area, const double *B,
                           const double *se);

rad_status rad_io_write_faces_tsv(const char *path, size_t n, const double *area, const double *B,
                                  const rad_io_kv *header, size_t nheader);

/* Vertex positions as float, colours as the tone-mapped vertex values
 * (rad_io_vertex_values), faces as lists of three ints. */
rad_status rad_io_write_ply(const char *path, size_t nverts, const double *xyz, size_t ntris,
                            const int *tri, const double *B, const rad_io_tonemap *tm, int binary);

/* columns: ncols names; data: nrows x ncols, row-major. */
rad_status rad_io_write_dat(const char *path, const char *title, const rad_io_kv *header,
                            size_t nheader, size_t ncols, const char *const *columns,
                            size_t nrows, const double *data);

/* ---- reading a per-face table back, and comparing two ---------------------- */

/* A per-face table as `radkit solve` writes it: n rows in face order, area,
 * B (n x 3 column-major) and, for tables with se_r se_g se_b columns (Monte
 * Carlo), the standard errors (NULL otherwise).  One allocation, owned. */
typedef struct rad_io_faces {
    size_t n;
    double *area, *B, *se;
} rad_io_faces;

/* '#' lines are skipped; the header row must be face area B_r B_g B_b
 * [se_r se_g se_b], the rows numbered 0, 1, ... with finite numbers.
 * RAD_EINPUT (a file that cannot be opened; path:line and what is wrong),
 * RAD_EIO (a read error). */
rad_status rad_io_read_faces_tsv(const char *path, rad_io_faces *out);
void rad_io_faces_free(rad_io_faces *faces);

/* The error of B against a reference B_ref (n x 3 column-major each; E the
 * faces' emission, or NULL for none; se_ref the reference's standard errors,
 * or NULL), every figure relative to R, the reference's area-weighted mean
 * reflected radiosity (compare.c opens with the formulas). */
typedef struct rad_io_face_errors {
    double mean_reflected; /* R */
    double l1, l2, worst;  /* area-weighted L1 and L2 of |B - B_ref|, and the largest, over R */
    int worst_face;        /* where the largest is */
    double ref_l1;         /* the reference's own standard error, as l1 (0 without se) */
    double ref_worst;      /* its standard error at the worst face, over R */
    double power;          /* (P - P_ref) / P_ref, P = sum over faces and channels of A B:
                              the relative error of the total power leaving the faces */
} rad_io_face_errors;

/* RAD_EINPUT when the faces have no area, R is not positive or a value is
 * not finite. */
rad_status rad_io_face_error(size_t n, const double *area, const double *E, const double *B,
                             const double *B_ref, const double *se_ref, rad_io_face_errors *out);

/* ---- stats JSON ------------------------------------------------------------- */

typedef struct rad_io_phase {
    const char *name;
    double seconds;
} rad_io_phase;

/* A named figure (a count, a ratio) for the "details" object. */
typedef struct rad_io_figure {
    const char *name;
    double value;
} rad_io_figure;

typedef struct rad_io_effect {
    const char *name;   /* e.g. "occlusion" */
    const char *value;  /* e.g. "off" */
    const char *reason; /* e.g. "convex closed enclosure" */
} rad_io_effect;

typedef struct rad_io_stats {
    const char *method;
    long long faces, elements, links, rays, kernel_evals;
    const rad_io_phase *phases; /* time_s: one key per phase, plus "total" */
    size_t nphases;
    double total_seconds;
    double memory_peak_bytes;
    const rad_io_effect *effects; /* effects: {name: {value, reason}} */
    size_t neffects;
    const char *solver_name;
    long long solver_iterations;
    double solver_residual;
    /* method-specific figures (e.g. hier's links by type), written as the
       object "details": {name: value}; may be empty */
    const rad_io_figure *details;
    size_t ndetails;
    /* runs over MPI ranks (radkit-mpi): top-level "ranks" and
       "memory_peak_bytes_per_rank" (the largest rank's), when ranks > 0 */
    int ranks;
    double memory_peak_bytes_per_rank;
} rad_io_stats;

rad_status rad_io_write_stats_json(const char *path, const rad_io_stats *stats);

/* The emitter under it, for callers that add keys of their own.  Calls after
 * an error do nothing; rad_io_json_finish returns the first error (a
 * non-finite number names its key) and checks the nesting is closed. */
typedef struct rad_io_json {
    FILE *f;
    int depth;
    int first[32]; /* per level: nothing written yet */
    rad_status status;
} rad_io_json;

void rad_io_json_start(rad_io_json *j, FILE *f); /* opens the top-level object */
void rad_io_json_object(rad_io_json *j, const char *key);  /* key: {  */
void rad_io_json_end(rad_io_json *j);                      /* }       */
void rad_io_json_string(rad_io_json *j, const char *key, const char *value);
void rad_io_json_number(rad_io_json *j, const char *key, double value);
void rad_io_json_integer(rad_io_json *j, const char *key, long long value);
rad_status rad_io_json_finish(rad_io_json *j); /* closes the top-level object */

#ifdef __cplusplus
}
#endif
#endif
