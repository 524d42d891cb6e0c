/* radkit's OFF and PLY readers on hostile and unusual files (scenes/bad/,
 * scenes/formats/): headers that never end, counts beyond the data, indices
 * out of range, point clouds are refused with the file (and line) named,
 * without hanging (each run is under `timeout`); polygons of any shape, OFF
 * variants and triangle strips load every face.  Expected counts and areas
 * come from the files' construction (their comments), not from the program. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "rad_scene.h"

/* `radkit info FILE` under a 10-second timeout: a hang is exit 124. */
static int run_info(const char *rel, char **out, char **err)
{
    return harness_run((const char *const[]){"/usr/bin/timeout", "10", harness_radkit(), "info",
                                             harness_path(rel), NULL},
                       out, err);
}

/* Refused: exit 2, one line naming the file (and `needle`). */
static void check_refused_at(int line, const char *rel, const char *needle)
{
    char *out = NULL, *err = NULL;
    int rc = run_info(rel, &out, &err);
    const char *base = strrchr(rel, '/') + 1;
    if (rc != 2 || !err || strncmp(err, "radkit: ", 8) != 0 || !strstr(err, base) ||
        !strstr(err, needle) || harness_count_lines(err) != 1)
        harness_fail(__FILE__, line, "%s: exit %d%s, stderr '%s', want exit 2 and '%s'", rel, rc,
                     rc == 124 ? " (timed out)" : "", err ? err : "", needle);
    free(out);
    free(err);
}
#define CHECK_REFUSED(rel, needle) check_refused_at(__LINE__, rel, needle)

/* Total area, and the number of triangles whose normal points along n. */
static double area_facing(const rad_scene *s, const double n[3], int *facing)
{
    const double *x = rad_scene_vertices(s);
    const int *t = rad_scene_triangles(s);
    double area = 0.0;
    *facing = 0;
    for (int i = 0; i < rad_scene_triangle_count(s); i++) {
        const double *a = x + 3 * t[3 * i], *b = x + 3 * t[3 * i + 1], *c = x + 3 * t[3 * i + 2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double w[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
        area += 0.5 * sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        *facing += w[0] * n[0] + w[1] * n[1] + w[2] * n[2] > 0.0;
    }
    return area;
}

TEST(readers_ply_header_without_end_is_refused_not_hung)
{
    CHECK_REFUSED("scenes/bad/ply_truncated_header.ply", "no end_header");
    CHECK_REFUSED("scenes/bad/ply_no_end_header.ply", "is end_header missing?");
}

TEST(readers_ply_counts_beyond_the_data_are_refused)
{
    CHECK_REFUSED("scenes/bad/ply_counts_too_large.ply", "ply_counts_too_large.ply:16: the file ends in face 1 of the 2");
    CHECK_REFUSED("scenes/bad/ply_counts_too_large_binary.ply", "the file ends in vertex 4 of the 8");
}

TEST(readers_off_index_out_of_range_is_refused_at_its_line)
{
    CHECK_REFUSED("scenes/bad/off_index_4.off", "off_index_4.off:11: face index 4 is out of range");
    CHECK_REFUSED("scenes/bad/off_index_negative.off", "off_index_negative.off:11: face index -1 is out of range");
    CHECK_REFUSED("scenes/bad/off_index_huge.off", "off_index_huge.off:11: face index 99999999999 is out of range");
}

TEST(readers_point_cloud_is_refused_with_radkits_message)
{
    CHECK_REFUSED("scenes/bad/point_cloud.ply", "point_cloud.ply: no faces (a point cloud?)");
}

TEST(readers_off_triangles_and_quads_load_every_face)
{
    /* A cube of edge 1.5: 2 triangles and 5 quads are 12 triangles, area 13.5, closed. */
    rad_scene *s = harness_scene_load("scenes/formats/cube_mixed.off", NULL);
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 12);
    CHECK(rad_scene_vertex_count(s) == 8);
    double n[3] = {0, 0, 0};
    int facing;
    CHECK_NEAR(area_facing(s, n, &facing), 13.5, 1e-14, 0.0);
    const int *face = rad_scene_triangle_faces(s);
    int want_face[12] = {0, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6};
    for (int t = 0; t < 12; t++)
        CHECK(face[t] == want_face[t]);
    rad_scene_destroy(s);
    char *out = NULL, *err = NULL, buf[64];
    CHECK(run_info("scenes/formats/cube_mixed.off", &out, &err) == 0);
    CHECK(harness_header(out, "closed", buf, sizeof buf) && strcmp(buf, "yes") == 0);
    free(out);
    free(err);
}

TEST(readers_off_non_convex_polygon_is_triangulated)
{
    /* One L-shaped hexagon (COFF, colours ignored), area 4, wound
     * counter-clockwise seen from +z (shoelace sum +8): every triangle faces +z. */
    rad_scene *s = harness_scene_load("scenes/formats/l_shape.off", NULL);
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 4);
    double up[3] = {0, 0, 1};
    int facing;
    CHECK_NEAR(area_facing(s, up, &facing), 4.0, 1e-15, 0.0);
    CHECK(facing == 4);
    rad_scene_destroy(s);
}

TEST(readers_ply_binary_tristrips_load_every_triangle)
{
    /* Big-endian, an extra vertex property between x and y and an extra
     * element after the strips: 2 strips over a 3 x 2 grid of 0.5 x 0.75
     * cells are 12 triangles of area 2.25, all facing the first one's way:
     * (0, 0.75), (0, 0), (0.5, 0.75) winds counter-clockwise about +z. */
    rad_scene *s = harness_scene_load("scenes/formats/tristrips.ply", NULL);
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 12);
    double up[3] = {0, 0, 1};
    int facing;
    CHECK_NEAR(area_facing(s, up, &facing), 2.25, 1e-15, 0.0);
    CHECK_MSG(facing == 12, "%d of 12 triangles face +z", facing);
    rad_scene_destroy(s);
}

TEST(readers_off_double_precision_comments_and_bad_numbers)
{
    const char *path;
    /* Coordinates beyond float precision survive; comments and blank lines are
     * skipped; the counts may share the keyword's line. */
    path = harness_write_file("readers-a.off",
                              "OFF 3 1 0 # counts on the keyword line\n\n# a comment\n"
                              "0.12345678901234567 0 0\n1.000000000000001 0 0  # trailing\n"
                              "0 2.385 0\n3 0 1 2\n");
    rad_scene *s = NULL;
    CHECK_MSG(rad_scene_load(path, NULL, &s) == RAD_OK, "%s", rad_error_message());
    if (s) {
        const double *x = rad_scene_vertices(s);
        CHECK(x[0] == 0.12345678901234567 && x[3] == 1.000000000000001);
        rad_scene_destroy(s);
    }
    path = harness_write_file("readers-b.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n");
    CHECK(rad_scene_load(path, NULL, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "b.off:4: vertex coordinate is NaN") != NULL);
    path = harness_write_file("readers-c.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n5 0 1 2\n");
    CHECK(rad_scene_load(path, NULL, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "c.off:6:") != NULL);
    path = harness_write_file("readers-d.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n");
    CHECK(rad_scene_load(path, NULL, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "ends after 3 of the 4 vertices") != NULL);
    path = harness_write_file("readers-e.ply",
                              "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nelement face 1\n"
                              "property list uchar int vertex_indices\nend_header\n"
                              "0 0 0\n1 0 0\n0 1 0\n255 0 1 2\n");
    CHECK(rad_scene_load(path, NULL, &s) == RAD_EINPUT); /* a list of 255 in a few bytes */
    CHECK(strstr(rad_error_message(), "ends in face 0 of the 1") != NULL);
    const char *written[] = {"readers-a.off", "readers-b.off", "readers-c.off", "readers-d.off",
                             "readers-e.ply"};
    for (size_t k = 0; k < sizeof written / sizeof written[0]; k++)
        unlink(harness_temp_path(written[k]));
}

/* A coordinate beyond 1e75 (where products of coordinates overflow in the
 * form factors) is refused at its line in OFF and ascii PLY, as NaN is. */
TEST(readers_huge_coordinate_names_its_line)
{
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){harness_path("scenes/bad/off_huge_coordinate.off"), NULL},
                               "off_huge_coordinate.off:4: vertex 1: coordinate 1e+308 is beyond");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){harness_path("scenes/bad/ply_huge_coordinate.ply"), NULL},
                               "ply_huge_coordinate.ply:11: vertex 1: coordinate 1e+308 is beyond");
}
