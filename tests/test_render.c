/* rad_render against a camera model and ray-plane intersection written here,
 * and the PNG through libpng's reader. */
#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "rad_render.h"

/* A rectangle in the plane z = 0, facing +z: [X0, X1] x [Y0, Y1]. */
#define X0 (-1.3)
#define X1 1.7
#define Y0 (-1.1)
#define Y1 0.9
static const double rect_xyz[12] = {X0, Y0, 0, X1, Y0, 0, X1, Y1, 0, X0, Y1, 0};
static const int rect_tri[6] = {0, 1, 2, 0, 2, 3};

static void test_camera(rad_render_camera *cam)
{
    const double eye[3] = {0.2, -0.1, 5.0}, at[3] = {0.2, -0.1, 0.0}, up[3] = {0, 1, 0};
    memcpy(cam->eye, eye, sizeof eye);
    memcpy(cam->look_at, at, sizeof at);
    memcpy(cam->up, up, sizeof up);
    cam->fov_y_deg = 30.0;
    cam->width = 64;
    cam->height = 48;
}

/* The hit point of pixel (x, y) on z = 0 for this axis-aligned camera, by its
 * own derivation: the eye looks down -z with +y up, so image right is +x. */
static void pixel_hit(const rad_render_camera *cam, int x, int y, double *hx, double *hy)
{
    double ty = tan(cam->fov_y_deg * 3.14159265358979323846 / 360.0);
    double tx = ty * cam->width / cam->height;
    double sx = (2.0 * (x + 0.5) / cam->width - 1.0) * tx;
    double sy = (1.0 - 2.0 * (y + 0.5) / cam->height) * ty;
    double dist = cam->eye[2]; /* direction (sx, sy, -1) reaches z = 0 at t = dist */
    *hx = cam->eye[0] + sx * dist;
    *hy = cam->eye[1] + sy * dist;
}

TEST(render_uniform_quad_matches_the_tone_map)
{
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(rect_xyz, 4, rect_tri, 2, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    double B[6] = {0.3, 0.3, 0.55, 0.55, 0.8, 0.8};
    rad_render_camera cam;
    test_camera(&cam);
    rad_io_tonemap tm = {1.15, 2.2};
    unsigned char *rgb = malloc(64 * 48 * 3);
    rad_vis_stats st = {0, 0, 0};
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, &tm, rgb, &st) == RAD_OK);
    CHECK(st.rays == 64 * 48);
    unsigned char want_in[3];
    for (int c = 0; c < 3; c++) /* clamp(1.15 B)^(1/2.2) * 255, rounded */
        want_in[c] = (unsigned char)lround(255.0 * pow(fmin(1.0, 1.15 * B[2 * c]), 1.0 / 2.2));
    int inside = 0, outside = 0, bad = 0;
    for (int y = 0; y < 48; y++)
        for (int x = 0; x < 64; x++) {
            double hx, hy;
            pixel_hit(&cam, x, y, &hx, &hy);
            double margin = fmin(fmin(hx - X0, X1 - hx), fmin(hy - Y0, Y1 - hy));
            if (fabs(margin) < 1e-6)
                continue; /* on the edge: either answer is right */
            const unsigned char *p = rgb + 3 * (64 * y + x);
            for (int c = 0; c < 3; c++)
                bad += p[c] != (margin > 0 ? want_in[c] : 0);
            if (margin > 0)
                inside++;
            else
                outside++;
        }
    CHECK_MSG(bad == 0, "%d channel values differ from the tone map", bad);
    CHECK(inside > 500 && outside > 200); /* both regions are in the picture */
    free(rgb);
    rad_vis_destroy(vis);
}

TEST(render_smooth_shading_interpolates_vertex_values)
{
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(rect_xyz, 4, rect_tri, 2, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    /* Triangle 0 (0,1,2) and 1 (0,2,3) have equal areas; grey B 0.2 and 0.6.
     * Vertex values: v1 = 0.2, v3 = 0.6, shared v0 = v2 = 0.4.  On triangle 0,
     * the point (x, y) has barycentric weights from the rectangle's coordinates
     * s = (x - X0)/(X1 - X0), r = (y - Y0)/(Y1 - Y0): w1 = s - r, w2 = r, w0 = 1 - s
     * (where s >= r); on triangle 1: w2 = s, w3 = r - s, w0 = 1 - r. */
    double B[6] = {0.2, 0.6, 0.2, 0.6, 0.2, 0.6};
    rad_render_camera cam;
    test_camera(&cam);
    rad_io_tonemap tm = {1.0, 2.2};
    unsigned char *rgb = malloc(64 * 48 * 3);
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, &tm, rgb, NULL) == RAD_OK);
    int checked = 0, bad = 0;
    for (int y = 0; y < 48; y++)
        for (int x = 0; x < 64; x++) {
            double hx, hy;
            pixel_hit(&cam, x, y, &hx, &hy);
            double s = (hx - X0) / (X1 - X0), r = (hy - Y0) / (Y1 - Y0);
            if (s < 1e-6 || s > 1 - 1e-6 || r < 1e-6 || r > 1 - 1e-6 || fabs(s - r) < 1e-6)
                continue;
            double val = s >= r ? (1 - s) * 0.4 + (s - r) * 0.2 + r * 0.4
                                : (1 - r) * 0.4 + s * 0.4 + (r - s) * 0.6;
            int want = (int)lround(255.0 * pow(val, 1.0 / 2.2));
            int got = rgb[3 * (64 * y + x)];
            bad += abs(got - want) > 1; /* float rays: one level of rounding */
            checked++;
        }
    CHECK_MSG(bad == 0, "%d of %d pixels off the interpolated value", bad, checked);
    CHECK(checked > 500);
    free(rgb);
    rad_vis_destroy(vis);
}

TEST(render_png_round_trips_through_libpng)
{
    enum { W = 37, H = 23 };
    unsigned char rgb[W * H * 3];
    for (int k = 0; k < W * H * 3; k++)
        rgb[k] = (unsigned char)((k * 7919) % 251);
    char path[256];
    snprintf(path, sizeof path, "/tmp/radkit_test_render_%d.png", (int)getpid());
    CHECK(rad_render_write_png(path, W, H, rgb) == RAD_OK);
    png_image image;
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    CHECK(png_image_begin_read_from_file(&image, path));
    CHECK(image.width == W && image.height == H);
    image.format = PNG_FORMAT_RGB;
    unsigned char back[W * H * 3];
    CHECK(png_image_finish_read(&image, NULL, back, W * 3, NULL));
    CHECK(memcmp(back, rgb, sizeof rgb) == 0);
    remove(path);
    CHECK(rad_render_write_png("/nonexistent-dir/x.png", W, H, rgb) == RAD_EIO);
}

TEST(render_rejects_bad_cameras)
{
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(rect_xyz, 4, rect_tri, 2, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    double B[6] = {0};
    unsigned char rgb[3 * 64 * 48];
    rad_render_camera cam;
    test_camera(&cam);
    cam.up[1] = 0.0;
    cam.up[2] = 1.0; /* parallel to the view */
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, NULL, rgb, NULL) == RAD_EINVAL);
    test_camera(&cam);
    cam.fov_y_deg = 180.0;
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, NULL, rgb, NULL) == RAD_EINVAL);
    test_camera(&cam);
    CHECK(rad_render_image(vis, 4, rect_xyz, 1, rect_tri, B, &cam, NULL, rgb, NULL) == RAD_EINVAL);
    /* The default view frames the box: the centre pixel sees the rectangle. */
    double lo[3] = {X0, Y0, 0}, hi[3] = {X1, Y1, 0};
    rad_render_camera_default(&cam, lo, hi);
    cam.width = cam.height = 9;
    double G[6] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, G, &cam, NULL, rgb, NULL) == RAD_OK);
    CHECK(rgb[3 * (9 * 4 + 4)] == (unsigned char)lround(255.0 * pow(0.5, 1.0 / 2.2)));
    CHECK(rgb[0] == 0 || rgb[0] == rgb[3 * (9 * 4 + 4)]);
    rad_vis_destroy(vis);
}

/* The shading mesh splits vertices at creases and material boundaries only:
 * a closed cube of 12 triangles over 8 corners has 6 flat faces of 4 corners,
 * so 24 shading vertices; the two triangles of a face share their diagonal;
 * a different material on one of them splits that diagonal too. */
TEST(render_shading_mesh_splits_at_creases_and_materials)
{
    double xyz[24];
    for (int v = 0; v < 8; v++) {
        xyz[3 * v] = (v & 1) ? 1.7 : 0.0;
        xyz[3 * v + 1] = (v & 2) ? 2.385 : 0.0;
        xyz[3 * v + 2] = (v & 4) ? 0.9 : 0.0;
    }
    /* Faces as corner quads (a b c d in order around the face), two triangles each. */
    int quads[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    int tri[36];
    for (int f = 0; f < 6; f++) {
        int *q = quads[f], t[6] = {q[0], q[1], q[2], q[0], q[2], q[3]};
        memcpy(tri + 6 * f, t, sizeof t);
    }
    double *sx = NULL;
    int *st = NULL;
    size_t nv = 0;
    CHECK(rad_render_shading_mesh(xyz, tri, 12, NULL, &sx, &nv, &st) == RAD_OK);
    CHECK_MSG(nv == 24, "%zu shading vertices", nv);
    for (int k = 0; k < 36; k++)
        for (int c = 0; c < 3; c++)
            CHECK(sx[3 * st[k] + c] == xyz[3 * tri[k] + c]); /* positions kept */
    for (int f = 0; f < 6; f++) /* the diagonal corners q0 and q2 are shared within a face */
        CHECK(st[6 * f] == st[6 * f + 3] && st[6 * f + 2] == st[6 * f + 4]);
    free(sx);
    free(st);

    int material[12] = {0};
    material[1] = 1; /* the second triangle of face 0 */
    CHECK(rad_render_shading_mesh(xyz, tri, 12, material, &sx, &nv, &st) == RAD_OK);
    CHECK_MSG(nv == 26, "%zu shading vertices with a second material", nv);
    CHECK(st[0] != st[3] && st[2] != st[4]);
    free(sx);
    free(st);
}
