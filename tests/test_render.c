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
    double ty = tan(cam->fov_y_deg * RAD_PI / 360.0);
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
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, &tm, NULL, rgb, &st) == RAD_OK);
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
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, &tm, NULL, rgb, NULL) == RAD_OK);
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
    CHECK(rad_render_write_png("/nonexistent-dir/x.png", W, H, rgb) == RAD_EINVAL); /* a missing directory: a usage error */
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
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, NULL, NULL, rgb, NULL) == RAD_EINVAL);
    test_camera(&cam);
    cam.fov_y_deg = 180.0;
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, NULL, NULL, rgb, NULL) == RAD_EINVAL);
    test_camera(&cam);
    CHECK(rad_render_image(vis, 4, rect_xyz, 1, rect_tri, B, &cam, NULL, NULL, rgb, NULL) == RAD_EINVAL);
    /* The default view frames the box: the centre pixel sees the rectangle. */
    double lo[3] = {X0, Y0, 0}, hi[3] = {X1, Y1, 0};
    rad_render_camera_default(&cam, lo, hi);
    cam.width = cam.height = 9;
    double G[6] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, G, &cam, NULL, NULL, rgb, NULL) == RAD_OK);
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

/* ---- outlines ---------------------------------------------------------------
 * References by hand for the face-on test camera: the hit of pixel (x, y) is
 * pixel_hit's point; the ray's direction is (sx, sy, -1), so t_hit = eye_z and
 * the footprint is eye_z |(sx, sy, -1)| 2 tan(fov/2) / H. */

static const unsigned char line_rgb[3] = {255, 51, 0}; /* rgb {1, 0.2, 0} * 255 */

static double pixel_footprint(const rad_render_camera *cam, int x, int y)
{
    double ty = tan(cam->fov_y_deg * RAD_PI / 360.0);
    double tx = ty * cam->width / cam->height;
    double sx = (2.0 * (x + 0.5) / cam->width - 1.0) * tx;
    double sy = (1.0 - 2.0 * (y + 0.5) / cam->height) * ty;
    return cam->eye[2] * sqrt(1.0 + sx * sx + sy * sy) * 2.0 * ty / cam->height;
}

/* The pixel whose centre sees the point (hx, hy, 0): pixel_hit inverted. */
static void pixel_of(const rad_render_camera *cam, double hx, double hy, int *x, int *y)
{
    double ty = tan(cam->fov_y_deg * RAD_PI / 360.0);
    double tx = ty * cam->width / cam->height;
    double sx = (hx - cam->eye[0]) / cam->eye[2], sy = (hy - cam->eye[1]) / cam->eye[2];
    *x = (int)floor((sx / tx + 1.0) * cam->width / 2.0);
    *y = (int)floor((1.0 - sy / ty) * cam->height / 2.0);
}

/* Render the uniform-grey rectangle with the given outline (NULL: none)
 * through cam (NULL: test_camera). */
static int render_rect_from(const rad_vis *vis, const rad_render_camera *cam,
                            const rad_render_outline *ol, unsigned char *rgb)
{
    double B[6] = {0.3, 0.3, 0.3, 0.3, 0.3, 0.3};
    rad_render_camera tc;
    test_camera(&tc);
    rad_io_tonemap tm = {1.0, 2.2};
    return rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, cam ? cam : &tc, &tm, ol, rgb,
                            NULL) == RAD_OK;
}

static int render_rect(const rad_vis *vis, const rad_render_outline *ol, unsigned char *rgb)
{
    return render_rect_from(vis, NULL, ol, rgb);
}

/* Compare the image with outline (got) to the one without (plain), pixel by
 * pixel, against the hand distance dist(hx, hy) to the element's boundary:
 * within reach -> line colour, beyond -> the plain render.  Pixels whose hit
 * is within 0.1% of the reach (or of the rectangle's border, hit or miss) are
 * skipped.  Counts the line pixels expected near the diagonal and elsewhere. */
static void check_outline(const unsigned char *got, const unsigned char *plain, double width,
                          double (*dist)(double, double), int *near_diag, int *near_border,
                          int *bad)
{
    rad_render_camera cam;
    test_camera(&cam);
    const double diag = sqrt((X1 - X0) * (X1 - X0) + (Y1 - Y0) * (Y1 - Y0));
    *near_diag = *near_border = *bad = 0;
    for (int y = 0; y < cam.height; y++)
        for (int x = 0; x < cam.width; x++) {
            double hx, hy;
            pixel_hit(&cam, x, y, &hx, &hy);
            const unsigned char *g = got + 3 * (cam.width * y + x), *p = plain + 3 * (cam.width * y + x);
            double margin = fmin(fmin(hx - X0, X1 - hx), fmin(hy - Y0, Y1 - hy));
            if (fabs(margin) < 1e-6)
                continue;
            if (margin < 0) { /* a miss: black either way */
                *bad += memcmp(g, p, 3) != 0;
                continue;
            }
            double reach = width * pixel_footprint(&cam, x, y), d = dist(hx, hy);
            if (fabs(d - reach) < 1e-3 * reach)
                continue;
            if (d < reach) {
                *bad += memcmp(g, line_rgb, 3) != 0;
                double dd = fabs((hx - X0) * (Y1 - Y0) - (hy - Y0) * (X1 - X0)) / diag;
                if (dd < reach)
                    ++*near_diag;
                else
                    ++*near_border;
            } else {
                *bad += memcmp(g, p, 3) != 0;
            }
        }
}

/* Distance to the boundary of the rendered triangle itself: the rectangle's
 * border or its diagonal (X0, Y0)-(X1, Y1), whichever is nearer. */
static double dist_own_triangles(double hx, double hy)
{
    double border = fmin(fmin(hx - X0, X1 - hx), fmin(hy - Y0, Y1 - hy));
    double diag = fabs((hx - X0) * (Y1 - Y0) - (hy - Y0) * (X1 - X0)) /
                  sqrt((X1 - X0) * (X1 - X0) + (Y1 - Y0) * (Y1 - Y0));
    return fmin(border, diag);
}

/* The big element of the second test: legs along x = X0 and y = Y0 from
 * (X0, Y0), of length BIG_L > (X1 - X0) + (Y1 - Y0), so it holds the rectangle
 * and its hypotenuse x + y = X0 + Y0 + BIG_L stays 0.5 / sqrt 2 away from it. */
#define BIG_L 5.5
static double dist_big_element(double hx, double hy)
{
    return fmin(fmin(hx - X0, hy - Y0), (X0 + Y0 + BIG_L - hx - hy) / sqrt(2.0));
}

TEST(render_outline_draws_the_edges_of_the_rendered_triangles)
{
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(rect_xyz, 4, rect_tri, 2, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    enum { N = 64 * 48 * 3 };
    unsigned char *plain = malloc(N), *got = malloc(N);
    double corners[18];
    for (int k = 0; k < 6; k++) /* element k = triangle k */
        memcpy(corners + 3 * k, rect_xyz + 3 * rect_tri[k], 3 * sizeof(double));
    rad_render_outline ol = {corners, 0.6, {1.0, 0.2, 0.0}};
    CHECK(render_rect(vis, NULL, plain));
    CHECK(render_rect(vis, &ol, got));
    int near_diag, near_border, bad;
    check_outline(got, plain, 0.6, dist_own_triangles, &near_diag, &near_border, &bad);
    CHECK_MSG(bad == 0, "%d pixels differ from the hand reference", bad);
    /* The diagonal crosses about 54 pixel columns and the border runs about
     * 2 (54 + 36) pixels; a band 0.6 pixels wide on each side of the diagonal
     * covers at least one pixel per column, one inside the border about 0.6. */
    CHECK_MSG(near_diag >= 50 && near_border >= 80, "%d diagonal, %d border line pixels",
              near_diag, near_border);
    /* The centroids of the two triangles, far from every edge: shaded grey. */
    rad_render_camera cam;
    test_camera(&cam);
    unsigned char grey = (unsigned char)lround(255.0 * pow(0.3, 1.0 / 2.2));
    const double cen[2][2] = {{(X0 + 2 * X1) / 3, (2 * Y0 + Y1) / 3}, {(2 * X0 + X1) / 3, (Y0 + 2 * Y1) / 3}};
    for (int i = 0; i < 2; i++) {
        int x, y;
        pixel_of(&cam, cen[i][0], cen[i][1], &x, &y);
        CHECK(x >= 0 && x < 64 && y >= 0 && y < 48);
        const unsigned char *g = got + 3 * (64 * y + x);
        CHECK_MSG(g[0] == grey && g[1] == grey && g[2] == grey, "centroid %d: %u %u %u, want %u",
                  i, g[0], g[1], g[2], grey);
    }
    free(plain);
    free(got);
    rad_vis_destroy(vis);
}

TEST(render_outline_draws_element_edges_not_triangle_edges)
{
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(rect_xyz, 4, rect_tri, 2, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    enum { N = 64 * 48 * 3 };
    unsigned char *plain = malloc(N), *got = malloc(N);
    /* Both rendered triangles lie in one big element, corners counter-clockwise. */
    const double big[9] = {X0, Y0, 0, X0 + BIG_L, Y0, 0, X0, Y0 + BIG_L, 0};
    double corners[18];
    memcpy(corners, big, sizeof big);
    memcpy(corners + 9, big, sizeof big);
    rad_render_outline ol = {corners, 0.6, {1.0, 0.2, 0.0}};
    CHECK(render_rect(vis, NULL, plain));
    CHECK(render_rect(vis, &ol, got));
    int near_diag, near_border, bad;
    check_outline(got, plain, 0.6, dist_big_element, &near_diag, &near_border, &bad);
    CHECK_MSG(bad == 0, "%d pixels differ from the hand reference", bad);
    /* The left and bottom borders are the element's: drawn (about 36 + 54
     * pixels); near the diagonal only its two ends, where it meets them. */
    CHECK_MSG(near_border >= 60, "%d border line pixels", near_border);
    CHECK_MSG(near_diag <= 6, "%d line pixels near the diagonal", near_diag);
    /* Pixels on the image of the diagonal, away from the drawn borders, equal
     * the render without outline. */
    rad_render_camera cam;
    test_camera(&cam);
    int on_diag = 0, differ = 0;
    for (int i = 1; i < 10; i++) {
        double s = 0.1 * i, hx = X0 + s * (X1 - X0), hy = Y0 + s * (Y1 - Y0);
        int x, y;
        pixel_of(&cam, hx, hy, &x, &y);
        if (x < 0 || x >= 64 || y < 0 || y >= 48)
            continue;
        on_diag++;
        differ += memcmp(got + 3 * (64 * y + x), plain + 3 * (64 * y + x), 3) != 0;
    }
    CHECK(on_diag == 9);
    CHECK_MSG(differ == 0, "%d pixels on the diagonal changed", differ);
    free(plain);
    free(got);
    rad_vis_destroy(vis);
}

/* A band of half-width w inside a convex polygon of perimeter P has area
 * P w - w^2 sum cot(angle/2), so for lines much thinner than the triangles the
 * line pixel count grows like w.  Here each triangle (legs about 59 and 40
 * pixels, angles 90, 34, 56 degrees) gives 2 (85 - 1.5) pixels at w = 0.5 and
 * 2 (255 - 14) at w = 1.5: a ratio of 2.9, so between 2 and 4.  The camera is
 * rolled by 0.37 rad so that no edge runs along a pixel row, where counts
 * step with whole rows instead of following the area. */
TEST(render_outline_pixel_count_grows_with_width)
{
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(rect_xyz, 4, rect_tri, 2, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    rad_render_camera cam;
    test_camera(&cam);
    cam.up[0] = sin(0.37);
    cam.up[1] = cos(0.37);
    cam.fov_y_deg = 40.0;
    cam.width = 96;
    cam.height = 72;
    enum { N = 96 * 72 * 3 };
    unsigned char *img = malloc(N);
    double corners[18];
    for (int k = 0; k < 6; k++)
        memcpy(corners + 3 * k, rect_xyz + 3 * rect_tri[k], 3 * sizeof(double));
    int count[2] = {0, 0};
    const double width[2] = {0.5, 1.5};
    for (int i = 0; i < 2; i++) {
        rad_render_outline ol = {corners, width[i], {1.0, 0.2, 0.0}};
        CHECK(render_rect_from(vis, &cam, &ol, img));
        for (int k = 0; k < N; k += 3)
            count[i] += memcmp(img + k, line_rgb, 3) == 0;
    }
    CHECK(count[0] > 0);
    CHECK_MSG(count[1] >= 2 * count[0] && count[1] <= 4 * count[0], "%d then %d line pixels",
              count[0], count[1]);
    /* The band areas themselves, within 10% (pixel sampling, and footprints up
     * to 7% larger off the image centre): legs 3 and 2 over the central
     * footprint 5 * 2 tan(20 deg) / 72; sum of cot(angle/2) = 1 + 3.303 + 1.868. */
    double fp = 5.0 * 2.0 * tan(20.0 * RAD_PI / 180.0) / 72.0;
    double per = (3.0 + 2.0 + sqrt(13.0)) / fp, cots = 1.0 + 3.303 + 1.868;
    for (int i = 0; i < 2; i++) {
        double area = 2.0 * (per * width[i] - width[i] * width[i] * cots);
        CHECK_NEAR(count[i], area, 0.1, 0.0);
    }
    free(img);
    rad_vis_destroy(vis);
}

TEST(render_outline_rejects_bad_arguments)
{
    rad_vis *vis = NULL;
    CHECK(rad_vis_create(rect_xyz, 4, rect_tri, 2, NULL, &vis) == RAD_OK);
    if (!vis)
        return;
    unsigned char *img = malloc(64 * 48 * 3);
    double corners[18] = {0};
    const rad_render_outline good = {corners, 0.6, {1.0, 0.2, 0.0}};
    rad_render_outline ol = good;
    CHECK(render_rect(vis, &ol, img)); /* the baseline is accepted */
    const double widths[4] = {0.0, -0.6, NAN, INFINITY};
    for (int i = 0; i < 4; i++) {
        ol = good;
        ol.width_px = widths[i];
        CHECK(!render_rect(vis, &ol, img));
    }
    const double colours[3] = {-0.01, 1.01, NAN};
    for (int c = 0; c < 3; c++)
        for (int i = 0; i < 3; i++) {
            ol = good;
            ol.rgb[c] = colours[i];
            CHECK(!render_rect(vis, &ol, img));
        }
    ol = good;
    ol.corners = NULL;
    CHECK(!render_rect(vis, &ol, img));
    /* The status is RAD_EINVAL, not just a failure. */
    double B[6] = {0};
    rad_render_camera cam;
    test_camera(&cam);
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, NULL, &ol, img, NULL) == RAD_EINVAL);
    ol = good;
    ol.width_px = 0.0;
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, NULL, &ol, img, NULL) == RAD_EINVAL);
    ol = good;
    ol.rgb[1] = 2.0;
    CHECK(rad_render_image(vis, 4, rect_xyz, 2, rect_tri, B, &cam, NULL, &ol, img, NULL) == RAD_EINVAL);
    free(img);
    rad_vis_destroy(vis);
}
