/* rad_render: camera, primary rays, smooth shading, PNG.
 * 1. Camera frame: f = normalize(look_at - eye), r = normalize(f x up),
 *    u = r x f.  Pixel (x, y) (y from the top) maps to the direction
 *    f + sx r + sy u with sx = (2 (x + 1/2) / W - 1) tan(fov/2) W/H and
 *    sy = (1 - 2 (y + 1/2) / H) tan(fov/2).
 * 2. rad_vis_intersect per row (the ray's tnear is 0: the eye is not on a face).
 * 3. Value = (1 - u - v) V0 + u V1 + v V2 with V the vertex radiosities and
 *    (u, v) Embree's barycentrics of the hit; tone-mapped per channel.
 * 4. Outline (optional): the hit point P = eye + t_hit dir is compared with
 *    the lines through the three edges of its element; if the nearest is
 *    within width_px * footprint, footprint = t_hit |dir| 2 tan(fov/2) / H
 *    (one pixel's size at that distance, across the ray), the pixel takes the
 *    line colour.  For P inside the (convex) element the nearest edge line is
 *    the distance to its boundary, so lines and segments agree.
 * 5. PNG: libpng's simplified write API (png_image_write_to_stdio), 8-bit RGB,
 *    through rad_io_output (a temporary file renamed onto the target).
 * \cite{pharr2016pbrt} (camera model), \cite{gouraud1971continuous} (shading). */
#include "rad_render.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>

#include "rad_geom.h"


void rad_render_camera_default(rad_render_camera *cam, const double lo[3], const double hi[3])
{
    double c[3], half = 0.0;
    for (int k = 0; k < 3; k++) {
        c[k] = 0.5 * (lo[k] + hi[k]);
        half = fmax(half, 0.5 * (hi[k] - lo[k]));
    }
    if (!(half > 0.0))
        half = 1.0;
    cam->fov_y_deg = 40.0;
    /* Back off so the box's half-size subtends at most the half field of view. */
    double dist = half / tan(0.5 * cam->fov_y_deg * RAD_PI / 180.0);
    for (int k = 0; k < 3; k++) {
        cam->look_at[k] = c[k];
        cam->eye[k] = c[k];
        cam->up[k] = k == 1;
    }
    cam->eye[2] = hi[2] + dist;
    cam->width = cam->height = 512;
}

static rad_vec3 v3(const double *p) { return rad_vec3_make(p[0], p[1], p[2]); }

/* Nonzero when p lies within reach of the line through one of the edges of
 * the triangle with corners c[0..8]. */
static int near_element_edge(const double *c, rad_vec3 p, double reach)
{
    for (int e = 0; e < 3; e++) {
        rad_vec3 a = v3(c + 3 * e), ab = rad_vec3_sub(v3(c + 3 * ((e + 1) % 3)), a);
        rad_vec3 ap = rad_vec3_sub(p, a);
        double len = rad_vec3_norm(ab);
        /* A zero-length edge is a point: measure to it instead of dividing by 0. */
        double d = len > 0.0 ? rad_vec3_norm(rad_vec3_cross(ab, ap)) / len : rad_vec3_norm(ap);
        if (d <= reach)
            return 1;
    }
    return 0;
}

rad_status rad_render_image(const rad_vis *vis, size_t nverts, const double *xyz, size_t ntris,
                            const int *tri, const double *B, const rad_render_camera *cam,
                            const rad_io_tonemap *tm, const rad_render_outline *outline,
                            unsigned char *rgb, rad_vis_stats *stats)
{
    if (!vis || !cam || !rgb || (nverts && !xyz) || (ntris && (!tri || !B)))
        return RAD_ERROR(RAD_EINVAL, "render: NULL argument");
    unsigned char line_rgb[3] = {0, 0, 0};
    if (outline) {
        if (!outline->corners)
            return RAD_ERROR(RAD_EINVAL, "render: outline without element corners");
        if (!(outline->width_px > 0.0) || !isfinite(outline->width_px))
            return RAD_ERROR(RAD_EINVAL, "render: outline width %g pixels (use a finite value > 0)",
                             outline->width_px);
        for (int c = 0; c < 3; c++) {
            if (!(outline->rgb[c] >= 0.0 && outline->rgb[c] <= 1.0))
                return RAD_ERROR(RAD_EINVAL, "render: outline colour channel %d is %g (use 0 .. 1)",
                                 c, outline->rgb[c]);
            line_rgb[c] = (unsigned char)lround(255.0 * outline->rgb[c]);
        }
    }
    if (rad_vis_triangle_count(vis) != ntris)
        return RAD_ERROR(RAD_EINVAL, "render: the visibility scene has %zu triangles, the "
                         "solution %zu", rad_vis_triangle_count(vis), ntris);
    if (cam->width < 1 || cam->height < 1 || cam->width > 16384 || cam->height > 16384)
        return RAD_ERROR(RAD_EINVAL, "render: image size %d x %d (use 1 .. 16384)", cam->width,
                         cam->height);
    if (!(cam->fov_y_deg > 0.0 && cam->fov_y_deg < 180.0))
        return RAD_ERROR(RAD_EINVAL, "render: field of view %g degrees (use 0 .. 180)",
                         cam->fov_y_deg);
    rad_vec3 eye = v3(cam->eye), f = rad_vec3_sub(v3(cam->look_at), eye);
    double flen = rad_vec3_norm(f);
    if (!(flen > 0.0) || !rad_vec3_is_finite(eye) || !isfinite(flen))
        return RAD_ERROR(RAD_EINVAL, "render: the camera looks at its own position");
    f = rad_vec3_scale(f, 1.0 / flen);
    rad_vec3 r = rad_vec3_cross(f, v3(cam->up));
    double rlen = rad_vec3_norm(r);
    if (!(rlen > 1e-9 * rad_vec3_norm(v3(cam->up))) || !isfinite(rlen))
        return RAD_ERROR(RAD_EINVAL, "render: the up vector is parallel to the view direction");
    r = rad_vec3_scale(r, 1.0 / rlen);
    rad_vec3 u = rad_vec3_cross(r, f);
    rad_io_tonemap deftm;
    if (!tm) {
        rad_io_tonemap_default(&deftm);
        tm = &deftm;
    }

    int w = cam->width, h = cam->height;
    double *vb = malloc((3 * nverts + 1) * sizeof *vb);
    if (!vb)
        return RAD_ERROR(RAD_ENOMEM, "render: no memory for %zu vertex values", nverts);
    rad_status status = rad_io_vertex_values(nverts, xyz, ntris, tri, B, vb);
    if (status != RAD_OK) {
        free(vb);
        return status;
    }
    double ty = tan(0.5 * cam->fov_y_deg * RAD_PI / 180.0), tx = ty * (double)w / (double)h;
    /* One pixel's height at unit distance along a ray; the outline's reach is
     * width_px of these times the hit's distance. */
    double pixel_angle = 2.0 * ty / (double)h;
    unsigned long long rays = 0;
    int failed = 0;
#pragma omp parallel reduction(+ : rays) reduction(| : failed)
    {
        double *org = malloc((size_t)w * 3 * sizeof *org), *dir = malloc((size_t)w * 3 * sizeof *dir);
        double *bu = malloc((size_t)w * sizeof *bu), *bv = malloc((size_t)w * sizeof *bv);
        int *ht = malloc((size_t)w * sizeof *ht);
        double *th = outline ? malloc((size_t)w * sizeof *th) : NULL;
        if (!org || !dir || !bu || !bv || !ht || (outline && !th))
            failed = 1;
#pragma omp for schedule(dynamic, 4)
        for (int y = 0; y < h; y++) {
            if (failed)
                continue;
            double sy = (1.0 - 2.0 * (y + 0.5) / h) * ty;
            for (int x = 0; x < w; x++) {
                double sx = (2.0 * (x + 0.5) / w - 1.0) * tx;
                rad_vec3 d = rad_vec3_add(f, rad_vec3_add(rad_vec3_scale(r, sx), rad_vec3_scale(u, sy)));
                org[3 * x] = eye.x; org[3 * x + 1] = eye.y; org[3 * x + 2] = eye.z;
                dir[3 * x] = d.x; dir[3 * x + 1] = d.y; dir[3 * x + 2] = d.z;
            }
            rad_vis_stats st = {0, 0, 0};
            rad_vis_intersect(vis, (size_t)w, org, dir, 0.0, ht, th, bu, bv, &st);
            rays += st.rays;
            unsigned char *row = rgb + (size_t)y * (size_t)w * 3;
            for (int x = 0; x < w; x++) {
                if (ht[x] < 0) {
                    row[3 * x] = row[3 * x + 1] = row[3 * x + 2] = 0;
                    continue;
                }
                if (outline) {
                    rad_vec3 d = v3(dir + 3 * x);
                    rad_vec3 p = rad_vec3_add(eye, rad_vec3_scale(d, th[x]));
                    double reach = outline->width_px * th[x] * rad_vec3_norm(d) * pixel_angle;
                    if (near_element_edge(outline->corners + 9 * (size_t)ht[x], p, reach)) {
                        memcpy(row + 3 * x, line_rgb, 3);
                        continue;
                    }
                }
                const int *t = tri + 3 * (size_t)ht[x];
                double w1 = bu[x], w2 = bv[x], w0 = 1.0 - w1 - w2;
                for (int c = 0; c < 3; c++) {
                    double val = w0 * vb[3 * (size_t)t[0] + c] + w1 * vb[3 * (size_t)t[1] + c] +
                                 w2 * vb[3 * (size_t)t[2] + c];
                    row[3 * x + c] = rad_io_tonemap_apply(tm, val);
                }
            }
        }
        free(org);
        free(dir);
        free(bu);
        free(bv);
        free(ht);
        free(th);
    }
    free(vb);
    if (failed)
        return RAD_ERROR(RAD_ENOMEM, "render: no memory for a row of %d pixels", w);
    if (stats)
        stats->rays += rays;
    return RAD_OK;
}

rad_status rad_render_write_png(const char *path, int width, int height, const unsigned char *rgb)
{
    if (!path || !rgb || width < 1 || height < 1)
        return RAD_ERROR(RAD_EINVAL, "PNG: bad arguments (%d x %d)", width, height);
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = (png_uint_32)width;
    image.height = (png_uint_32)height;
    image.format = PNG_FORMAT_RGB;
    /* Through rad_io_output, not png_image_write_to_file: that one removes
       the path when a write fails, whatever the path was. */
    rad_io_output o;
    rad_status st = rad_io_output_open(path, 1, &o);
    if (st != RAD_OK)
        return st;
    if (!png_image_write_to_stdio(&image, o.f, 0, rgb, (png_int_32)width * 3, NULL)) {
        int err = errno;
        st = RAD_ERROR(RAD_EIO, "%s: cannot write PNG: %s (%s)", path, image.message,
                       strerror(err ? err : EIO));
        png_image_free(&image);
        rad_io_output_discard(&o);
        return st;
    }
    return rad_io_output_commit(&o);
}
