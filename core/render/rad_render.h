/* rad_render: pictures of a radiosity solution.
 *
 * A pinhole camera shoots one primary ray through each pixel centre with
 * rad_vis_intersect (Embree); the hit's barycentrics interpolate the vertex
 * radiosities (the area-weighted averages of rad_io_vertex_values), i.e.
 * Gouraud smooth shading of the piecewise-constant solution; the result goes
 * through the tone map of rad_io.h (exposure, clip at white, gamma 2.2) to
 * 8-bit sRGB-like values; misses are black.  Pixels are independent, computed
 * in an OpenMP loop over rows: the image does not depend on the thread count.
 * Faces are shaded from both sides (a camera outside a closed box sees the
 * backs of its walls; cull them by placing the camera inside).  Optionally,
 * element edges are drawn over the shading (rad_render_outline). */
#ifndef RAD_RENDER_H
#define RAD_RENDER_H

#include <stddef.h>

#include "rad_error.h"
#include "rad_io.h"
#include "rad_vis.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct rad_render_camera {
    double eye[3];     /* position */
    double look_at[3]; /* a point the view centre passes through */
    double up[3];      /* the image's up direction (need not be orthogonal to the view) */
    double fov_y_deg;  /* vertical field of view, degrees, in (0, 180) */
    int width, height; /* pixels, 1 .. 16384 each */
} rad_render_camera;

/* A default view of the box [lo, hi]: from in front of its +z face, on its
 * centre line, looking along -z with +y up, far enough back for a 40 degree
 * vertical view to frame it; 512 x 512 pixels. */
void rad_render_camera_default(rad_render_camera *cam, const double lo[3], const double hi[3]);

/* Element edges drawn over the image, to show where (hierarchical) refinement
 * went.  The rendered triangle k lies in the element whose corners are
 * corners[9k .. 9k+8] (for a dense solve the element is the rendered triangle
 * itself; for a hierarchical one, the leaf that a triangle of the conforming
 * display mesh lies in).  A pixel whose hit point P lies within width_px
 * pixels' footprint of one of that element's edges takes the colour rgb
 * instead of its shaded value.  Distance is measured from P to the line
 * through each edge: P lies in the element, and for a point inside a convex
 * polygon the nearest boundary point is on the nearest edge line, so this is
 * the distance to the element's boundary.  The footprint is the size of one
 * pixel at the hit's distance, measured perpendicular to the ray:
 * t_hit |dir| 2 tan(fov/2) / height.  It is not corrected for slant, so faces
 * seen at a grazing angle get thinner lines (by down to the cosine of the
 * angle between ray and normal, depending on the edge's direction).  An edge
 * shared by two visible elements is drawn from both sides: about 2 width_px
 * pixels wide in all.
 * Edges of the rendered triangles that are not element edges are not drawn. */
typedef struct rad_render_outline {
    const double *corners; /* 9 per rendered triangle (3 corners, xyz each) */
    double width_px;       /* line half-width in pixels, finite and > 0 (e.g. 0.6) */
    double rgb[3];         /* line colour, each in [0,1], written as lround(255 rgb), no tone map */
} rad_render_outline;

/* Render: vis must have been built from the same xyz/tri (nverts, ntris); B is
 * ntris x 3 column-major.  tm may be NULL (rad_io_tonemap_default); outline
 * may be NULL (no lines).  rgb receives width * height * 3 bytes, rows from
 * the top.  stats (may be NULL) counts the primary rays.  RAD_EINVAL for a
 * bad camera or outline (NULL corners, width_px not finite and > 0, a colour
 * outside [0,1]). */
rad_status rad_render_image(const rad_vis *vis, size_t nverts, const double *xyz, size_t ntris,
                            const int *tri, const double *B, const rad_render_camera *cam,
                            const rad_io_tonemap *tm, const rad_render_outline *outline,
                            unsigned char *rgb, rad_vis_stats *stats);

/* A mesh for display: every vertex of tri (ntris triangles over xyz) is split
 * by the plane and material of the triangles that use it, so that smooth
 * (vertex-averaged) shading never mixes surfaces across a crease or a
 * material boundary.  Triangles keep their order and corner order; material
 * may be NULL (one material).  *xyz_out (3 per vertex) and *tri_out (3 per
 * triangle) are malloc'ed for the caller to free. */
rad_status rad_render_shading_mesh(const double *xyz, const int *tri, size_t ntris,
                                   const int *material, double **xyz_out, size_t *nv_out,
                                   int **tri_out);

/* Write 8-bit RGB (rows from the top) as PNG with libpng.  RAD_EIO with
 * libpng's message on failure. */
rad_status rad_render_write_png(const char *path, int width, int height, const unsigned char *rgb);

#ifdef __cplusplus
}
#endif
#endif
