/* End to end: `radkit info` on every shipped scene and on files in other
 * formats, its output contract (key = value lines, the material table), the
 * effects plan with reasons and overrides, and every bad input: exit 2,
 * nothing on stdout, one line on stderr naming the problem and its place. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

static int value_is(const char *out, const char *key, const char *want)
{
    char buf[512];
    const char *v = harness_header(out, key, buf, sizeof buf);
    return v && strcmp(v, want) == 0;
}

TEST(cli_info_help_explains_every_option)
{
    char *out, *err;
    CHECK(harness_radkit_run("info", (const char *[]){"--help", NULL}, &out, &err) == 0);
    const char *opts[] = {"--scale", "--drop-degenerate", "--rho", "--emission", "--occlusion",
                          "--colour", "--facing-away", "--singular", "--reflectance", "auto",
                          "example:"};
    for (size_t k = 0; k < sizeof opts / sizeof opts[0]; k++)
        CHECK_MSG(strstr(out, opts[k]) != NULL, "help lacks %s", opts[k]);
    free(out);
    free(err);
    const char *argv[] = {harness_radkit(), "--help", NULL};
    CHECK(harness_run(argv, &out, &err) == 0);
    CHECK(strstr(out, "info") != NULL);
    free(out);
    free(err);
}

TEST(cli_info_every_shipped_scene)
{
    const char *scenes[] = {
        "scenes/cornell/cornell.obj", "scenes/furnace_cube/cube.obj",
        "scenes/tetrahedron/tetrahedron.obj", "scenes/sphere/sphere_0.obj",
        "scenes/sphere/sphere_3.obj", "scenes/plates_parallel/plates.obj",
        "scenes/plates_perpendicular/plates.obj", "scenes/occluder/occluder.obj",
        "scenes/many_objects/many_64.obj", "scenes/formats/quad_tri.ply",
        "scenes/formats/tetra.off", "scenes/formats/two_triangles.gltf",
        "scenes/formats/rectangle.stl"};
    const char *keys[] = {"faces", "vertices", "materials", "emitters", "total_area", "bbox_min",
                          "bbox_max", "closed", "convex", "components", "pairs_shared_edge",
                          "pairs_shared_vertex", "effect_occlusion", "effect_occlusion_reason",
                          "effect_colour", "effect_colour_reason", "effect_facing_away",
                          "effect_singular", "effect_reflectance", "effect_reflectance_reason",
                          "effect_clustering", "effect_clustering_reason",
                          "camera_position", "warnings"};
    for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; k++) {
        char *out, *err, buf[512];
        int code = harness_radkit_run("info", (const char *[]){harness_path(scenes[k]), NULL}, &out, &err);
        CHECK_MSG(code == 0, "%s: exit %d: %s", scenes[k], code, err);
        CHECK_MSG(strcmp(err, "") == 0, "%s: stderr %s", scenes[k], err);
        for (size_t j = 0; j < sizeof keys / sizeof keys[0]; j++)
            CHECK_MSG(harness_header(out, keys[j], buf, sizeof buf), "%s: no '# %s' line", scenes[k], keys[j]);
        CHECK(strstr(out, "\nmaterial\tname\trho_r\trho_g\trho_b\tE_r\tE_g\tE_b\tfaces\tarea\n") != NULL);
        free(out);
        free(err);
    }
}

TEST(cli_info_reports_the_cube)
{
    char *out, *err, buf[256];
    CHECK(harness_radkit_run("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), NULL}, &out, &err) == 0);
    CHECK(value_is(out, "faces", "12") && value_is(out, "vertices", "8"));
    CHECK(value_is(out, "emitters", "12") && value_is(out, "materials", "1"));
    CHECK(value_is(out, "total_area", "9.375")); /* 6 x 1.25^2 */
    CHECK(value_is(out, "bbox_max", "1.25 1.25 1.25"));
    CHECK(value_is(out, "closed", "yes") && value_is(out, "convex", "yes"));
    CHECK(value_is(out, "pairs_shared_edge", "18") && value_is(out, "pairs_shared_vertex", "28"));
    CHECK(value_is(out, "effect_occlusion", "off") && value_is(out, "effect_colour", "off"));
    CHECK(strstr(harness_header(out, "effect_occlusion_reason", buf, sizeof buf), "convex") != NULL);
    /* The material row: the MTL's values. */
    CHECK(strstr(out, "\n0\tfurnace\t0.375\t0.375\t0.375\t2.385\t2.385\t2.385\t12\t9.375\n") != NULL);
    free(out);
    free(err);
    /* Overrides. */
    CHECK(harness_radkit_run("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--occlusion", "on",
                                "--colour=on", "--singular", "off", NULL}, &out, &err) == 0);
    CHECK(value_is(out, "effect_occlusion", "on") && value_is(out, "effect_colour", "on"));
    CHECK(value_is(out, "effect_singular", "off"));
    CHECK(strstr(harness_header(out, "effect_occlusion_reason", buf, sizeof buf), "forced on") != NULL);
    free(out);
    free(err);
    /* --scale 2: areas x 4; --rho / --emission replace the materials. */
    CHECK(harness_radkit_run("info", (const char *[]){"--scale", "2", harness_path("scenes/furnace_cube/cube.obj"), "--rho",
                                "0.25 0.5 0.75", "--emission", "3", NULL}, &out, &err) == 0);
    CHECK(value_is(out, "total_area", "37.5"));
    CHECK(strstr(out, "\n0\tfurnace\t0.25\t0.5\t0.75\t3\t3\t3\t12\t37.5\n") != NULL);
    CHECK(value_is(out, "effect_colour", "on"));
    free(out);
    free(err);
}

TEST(cli_info_drop_degenerate)
{
    char *out, *err;
    CHECK(harness_radkit_run("info", (const char *[]){harness_path("scenes/bad/zero_area.obj"), "--drop-degenerate", NULL}, &out,
               &err) == 0);
    CHECK(value_is(out, "faces", "1") && value_is(out, "dropped_degenerate", "1"));
    CHECK(strstr(out, "# warning = dropped 1 degenerate") != NULL);
    free(out);
    free(err);
}

TEST(cli_info_rejects_every_bad_input)
{
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/missing_mtl.obj"), "--strict", NULL},
               "missing_mtl.obj:1: cannot open material library");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/nan_vertex.obj"), NULL}, "nan_vertex.obj:4: vertex coordinate: NaN");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/inf_vertex.obj"), NULL}, "inf_vertex.obj:3:");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/index_out_of_range.obj"), NULL},
               "index_out_of_range.obj:8: face index 9 is out of range");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/zero_area.obj"), "--strict", NULL}, "zero_area.obj:9: degenerate (zero-area)");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/rho_too_big.obj"), NULL}, "rho_too_big.mtl:2: material 'm': reflectance");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/negative_emission.obj"), NULL},
               "negative_emission.mtl:3: material 'm': negative emission");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/malformed_number.obj"), NULL}, "malformed_number.obj:3:");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/undefined_material.obj"), "--strict", NULL}, "undefined_material.obj:6:");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/no_faces.obj"), NULL}, "no faces");
    /* Other formats name the face: Assimp must not drop the degenerate one. */
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/zero_area.ply"), "--strict", NULL}, "degenerate (zero-area) triangle");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/index_out_of_range.ply"), NULL}, "out of range");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/empty.obj"), NULL}, "empty");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/garbage.obj"), NULL}, "garbage.obj: no faces (empty scene); it has 2 statement(s) radkit ignores");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/garbage.ply"), NULL}, "garbage.ply:3: element vertex needs the scalar properties");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/no_such_file.obj"), NULL}, "no_such_file.obj: cannot open");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad"), NULL}, "bad: not a regular file (a directory)");
    /* Usage errors. */
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){NULL}, "SCENE");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), harness_path("scenes/cornell/cornell.obj"), NULL},
               "more than one scene");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--scale", "0", NULL}, "--scale");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--scale", "2x", NULL}, "--scale");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--rho", "0.5 1 0.5", NULL}, "--rho");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--rho", "0.5 0.5", NULL}, "--rho");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--emission", "-1", NULL}, "--emission");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--occlusion", "maybe", NULL}, "--occlusion");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/furnace_cube/cube.obj"), "--frobnicate", NULL}, "--frobnicate");
}
