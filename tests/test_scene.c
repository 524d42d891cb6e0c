/* rad_scene: import of every shipped scene and of files in other formats,
 * materials, units, input order, validation and warnings, and the effects
 * plan.  Expected values come from the scene definitions (scenes/README.md),
 * worked out by hand, not from the program's output. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "rad_geom.h"
#include "rad_mesh.h"
#include "rad_scene.h"

static int find_material(const rad_scene *s, const char *name)
{
    for (int m = 0; m < rad_scene_material_count(s); m++)
        if (strcmp(rad_scene_materials(s)[m].name, name) == 0)
            return m;
    return -1;
}

static int has_warning(const rad_scene *s, const char *needle)
{
    for (int w = 0; w < rad_scene_warning_count(s); w++)
        if (strstr(rad_scene_warning(s, w), needle))
            return 1;
    return 0;
}

TEST(scene_every_shipped_scene_loads)
{
    /* name, faces, vertices, total area (from the definitions). */
    struct { const char *path; int faces, vertices; double area; } want[] = {
        {"scenes/furnace_cube/cube.obj", 12, 8, 6 * 1.25 * 1.25},
        /* regular tetrahedron of edge 2 sqrt(2) 1.5: area 4 (sqrt(3)/4) a^2 = 18 sqrt(3) */
        {"scenes/tetrahedron/tetrahedron.obj", 4, 4, 18 * sqrt(3.0)},
        {"scenes/plates_parallel/plates.obj", 4, 8, 2.0},
        {"scenes/plates_perpendicular/plates.obj", 4, 6, 2.0},
        {"scenes/occluder/occluder.obj", 6, 12, 2.25},
        {"scenes/sphere/sphere_0.obj", 20, 12, -1},
        {"scenes/sphere/sphere_1.obj", 80, 42, -1},
        {"scenes/sphere/sphere_2.obj", 320, 162, -1},
        {"scenes/sphere/sphere_3.obj", 1280, 642, -1},
        {"scenes/many_objects/many_64.obj", 12 + 64 * 12, 8 + 64 * 8, -1},
        {"scenes/cornell/cornell.obj", 38, 28, -1},
        /* the room, 2 slabs and 16 boxes: 19 x 12 faces, 19 x 8 vertices */
        {"scenes/slit/slit.obj", 19 * 12, 19 * 8, -1},
    };
    for (size_t k = 0; k < sizeof want / sizeof want[0]; k++) {
        rad_scene *s = harness_scene_load(want[k].path, NULL);
        if (!s)
            continue;
        rad_scene_summary sum;
        rad_scene_summarize(s, &sum);
        CHECK_MSG(sum.faces == want[k].faces, "%s: %d faces", want[k].path, sum.faces);
        CHECK_MSG(sum.vertices == want[k].vertices, "%s: %d vertices", want[k].path, sum.vertices);
        if (want[k].area > 0)
            CHECK_NEAR(sum.total_area, want[k].area, 1e-14, 0.0);
        CHECK(sum.emitters > 0);
        CHECK_MSG(rad_scene_warning_count(s) == 0, "%s: warning '%s'", want[k].path,
                  rad_scene_warning(s, 0));
        rad_scene_destroy(s);
    }
}

/* The icosphere's area grows towards the sphere's 4 pi r^2 from below. */
TEST(scene_sphere_levels_converge_to_the_sphere)
{
    double previous = 0.0, sphere = 4 * RAD_PI * 1.25 * 1.25;
    for (int level = 0; level < 4; level++) {
        char path[64];
        snprintf(path, sizeof path, "scenes/sphere/sphere_%d.obj", level);
        rad_scene *s = harness_scene_load(path, NULL);
        if (!s)
            return;
        rad_scene_summary sum;
        rad_scene_summarize(s, &sum);
        CHECK(sum.total_area > previous && sum.total_area < sphere);
        previous = sum.total_area;
        /* Every face looks at the centre. */
        const double *x = rad_scene_vertices(s);
        for (int t = 0; t < sum.faces; t++) {
            const int *v = rad_scene_triangles(s) + 3 * t;
            rad_vec3 a = rad_vec3_make(x[3 * v[0]], x[3 * v[0] + 1], x[3 * v[0] + 2]);
            rad_vec3 b = rad_vec3_make(x[3 * v[1]], x[3 * v[1] + 1], x[3 * v[1] + 2]);
            rad_vec3 c = rad_vec3_make(x[3 * v[2]], x[3 * v[2] + 1], x[3 * v[2] + 2]);
            CHECK(rad_vec3_dot(rad_geom_triangle_normal(a, b, c), rad_geom_triangle_centroid(a, b, c)) < 0);
        }
        rad_scene_destroy(s);
    }
    CHECK(sphere - previous < 0.02 * sphere);
}

TEST(scene_cornell_box_materials_geometry_camera)
{
    rad_scene *s = harness_scene_load("scenes/cornell/cornell.obj", NULL);
    if (!s)
        return;
    int light = find_material(s, "light"), red = find_material(s, "red");
    int green = find_material(s, "green"), white = find_material(s, "white");
    CHECK(light >= 0 && red >= 0 && green >= 0 && white >= 0);
    if (light < 0 || red < 0 || green < 0 || white < 0) {
        rad_scene_destroy(s);
        return;
    }
    const rad_scene_material *m = rad_scene_materials(s);
    /* Light: emission spectrum 0, 8, 15.6, 18.4 at 400..700 nm, linear in
     * between: band means b = 4, g = 11.8, r = 17; exitance = pi x radiance. */
    CHECK_NEAR(m[light].emission[0], RAD_PI * 17.0, 0.0, 5e-7); /* 6 decimals in the MTL */
    CHECK_NEAR(m[light].emission[1], RAD_PI * 11.8, 0.0, 5e-7);
    CHECK_NEAR(m[light].emission[2], RAD_PI * 4.0, 0.0, 5e-7);
    /* Red paint reflects red, green paint green; the white is nearly grey. */
    CHECK(m[red].rho[0] > 0.5 && m[red].rho[1] < 0.1 && m[red].rho[2] < 0.1);
    CHECK(m[green].rho[1] > 0.3 && m[green].rho[0] < 0.2 && m[green].rho[2] < 0.2);
    CHECK(fabs(m[white].rho[0] - m[white].rho[1]) < 0.01 && m[white].rho[2] > 0.7);
    rad_scene_summary sum;
    rad_scene_summarize(s, &sum);
    /* Bounding box of the published geometry in metres. */
    CHECK_NEAR(sum.bbox_min[0], 0.0, 0.0, 1e-15);
    CHECK_NEAR(sum.bbox_max[0], 0.556, 1e-15, 0.0);
    CHECK_NEAR(sum.bbox_max[1], 0.5488, 1e-15, 0.0);
    CHECK_NEAR(sum.bbox_max[2], 0.5592, 1e-15, 0.0);
    /* The light: 0.13 m x 0.105 m, two triangles, facing down. */
    CHECK(sum.emitters == 2);
    CHECK_NEAR(sum.emitting_area, 0.13 * 0.105, 1e-12, 0.0);
    const double *x = rad_scene_vertices(s);
    for (int t = 0; t < sum.faces; t++) {
        const int *v = rad_scene_triangles(s) + 3 * t;
        rad_vec3 a = rad_vec3_make(x[3 * v[0]], x[3 * v[0] + 1], x[3 * v[0] + 2]);
        rad_vec3 b = rad_vec3_make(x[3 * v[1]], x[3 * v[1] + 1], x[3 * v[1] + 2]);
        rad_vec3 c = rad_vec3_make(x[3 * v[2]], x[3 * v[2] + 1], x[3 * v[2] + 2]);
        rad_vec3 n = rad_geom_triangle_normal(a, b, c);
        rad_vec3 g = rad_geom_triangle_centroid(a, b, c);
        int mt = rad_scene_triangle_materials(s)[t];
        /* Room faces look into the room; the light and the ceiling look down. */
        if (mt == light || g.y > 0.5488 - 1e-12)
            CHECK_NEAR(n.y, -1.0, 0.0, 1e-12);
        if (g.y < 1e-12)
            CHECK_NEAR(n.y, 1.0, 0.0, 1e-12);
        if (mt == green)
            CHECK_NEAR(n.x, 1.0, 0.0, 1e-12);
        if (mt == red)
            CHECK(n.x < -0.99);
        if (g.z > 0.5592 - 1e-12)
            CHECK_NEAR(n.z, -1.0, 0.0, 1e-12);
    }
    /* The published camera: (278, 273, -800) mm looking along +z, up +y,
     * focal length 35 mm on a 25 mm film: fov = 2 atan(12.5 / 35). */
    const rad_camera *cam = rad_scene_camera(s);
    CHECK(cam->from_scene == 1);
    CHECK_NEAR(cam->position[0], 0.278, 0.0, 1e-15);
    CHECK_NEAR(cam->position[2], -0.8, 0.0, 1e-15);
    CHECK_NEAR(cam->fov_y_deg, 2 * atan(12.5 / 35.0) * 180 / RAD_PI, 1e-7, 0.0);
    rad_scene_destroy(s);
}

/* --scale multiplies coordinates and the camera; areas go with its square. */
TEST(scene_scale_changes_units)
{
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.scale = 1000.0;
    rad_scene *s = NULL;
    CHECK(harness_scene_load_status("scenes/cornell/cornell.obj", &p, &s) == RAD_OK);
    if (!s)
        return;
    rad_scene_summary sum;
    rad_scene_summarize(s, &sum);
    CHECK_NEAR(sum.bbox_max[1], 548.8, 1e-14, 0.0);
    CHECK_NEAR(sum.emitting_area, 130.0 * 105.0, 1e-12, 0.0);
    CHECK_NEAR(rad_scene_camera(s)->position[2], -800.0, 1e-15, 0.0);
    rad_scene_destroy(s);
    p.scale = -1.0;
    CHECK(harness_scene_load_status("scenes/cornell/cornell.obj", &p, &s) == RAD_EINVAL);
}

/* no_cross_check (the default) skips only the Assimp re-read: the scene is
 * the same to the last bit, materials included. */
TEST(scene_no_cross_check_loads_the_same_scene)
{
    rad_scene *a = NULL, *b = harness_scene_load("scenes/cornell/cornell.obj", NULL);
    rad_scene_params p;
    rad_scene_params_default(&p);
    CHECK(p.no_cross_check == 1);
    p.no_cross_check = 0;
    CHECK(harness_scene_load_status("scenes/cornell/cornell.obj", &p, &a) == RAD_OK);
    if (a && b) {
        int nv = rad_scene_vertex_count(a), nt = rad_scene_triangle_count(a);
        CHECK(nv == rad_scene_vertex_count(b) && nt == rad_scene_triangle_count(b));
        if (nv == rad_scene_vertex_count(b) && nt == rad_scene_triangle_count(b)) {
            CHECK(memcmp(rad_scene_vertices(a), rad_scene_vertices(b), 3 * (size_t)nv * sizeof(double)) == 0);
            CHECK(memcmp(rad_scene_triangles(a), rad_scene_triangles(b), 3 * (size_t)nt * sizeof(int)) == 0);
            CHECK(memcmp(rad_scene_triangle_materials(a), rad_scene_triangle_materials(b),
                         (size_t)nt * sizeof(int)) == 0);
            CHECK(rad_scene_warning_count(a) == rad_scene_warning_count(b));
        }
    }
    rad_scene_destroy(a);
    rad_scene_destroy(b);
}

/* A hand-written ASCII PLY (a quad and a triangle, polygon list, an extra
 * vertex property): geometry only, reflectance and emission from the flags. */
TEST(scene_ply_from_another_tool)
{
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.has_rho = 1;
    p.rho[0] = 0.25, p.rho[1] = 0.5, p.rho[2] = 0.75;
    p.has_emission = 1;
    p.emission[0] = p.emission[1] = p.emission[2] = 2.385;
    rad_scene *s = NULL;
    CHECK_MSG(harness_scene_load_status("scenes/formats/quad_tri.ply", &p, &s) == RAD_OK, "%s", rad_error_message());
    if (!s)
        return;
    rad_scene_summary sum;
    rad_scene_summarize(s, &sum);
    CHECK(sum.faces == 3 && sum.vertices == 5);
    /* Quad 2 x 1.5, triangle base 2 with apex (1, 0.75, 2): height sqrt(0.75^2 + 2^2). */
    CHECK_NEAR(sum.total_area, 3.0 + sqrt(0.5625 + 4.0), 1e-7, 0.0);
    /* The quad's two triangles come first (input order) and share face 0. */
    CHECK(rad_scene_triangle_faces(s)[0] == 0 && rad_scene_triangle_faces(s)[1] == 0);
    CHECK(rad_scene_triangle_faces(s)[2] == 1);
    CHECK(rad_scene_material_count(s) == 1);
    CHECK(rad_scene_materials(s)[0].rho[2] == 0.75 && rad_scene_materials(s)[0].emission[1] == 2.385);
    CHECK(sum.emitters == 3 && !has_warning(s, "no emitter"));
    rad_scene_destroy(s);
    /* Without flags: grey 0.5, no emission, and a warning about that. */
    s = harness_scene_load("scenes/formats/quad_tri.ply", NULL);
    if (!s)
        return;
    CHECK(rad_scene_materials(s)[0].rho[0] == 0.5 && rad_scene_materials(s)[0].emission[0] == 0.0);
    CHECK(has_warning(s, "no emitter"));
    rad_scene_destroy(s);
}

TEST(scene_off_from_another_tool)
{
    rad_scene *s = harness_scene_load("scenes/formats/tetra.off", NULL);
    if (!s)
        return;
    rad_scene_summary sum;
    rad_scene_summarize(s, &sum);
    CHECK(sum.faces == 4 && sum.vertices == 4);
    /* Corner tetrahedron: three right triangles of area 1/2, one equilateral of side sqrt 2. */
    CHECK_NEAR(sum.total_area, 1.5 + sqrt(3.0) / 2.0, 1e-7, 0.0);
    rad_scene_destroy(s);
}

/* ASCII STL repeats each corner per facet: the importer merges them. */
TEST(scene_stl_from_another_tool)
{
    rad_scene *s = harness_scene_load("scenes/formats/rectangle.stl", NULL);
    if (!s)
        return;
    rad_scene_summary sum;
    rad_scene_summarize(s, &sum);
    CHECK(sum.faces == 2 && sum.vertices == 4);
    CHECK_NEAR(sum.total_area, 3.0, 1e-15, 0.0);
    rad_scene_destroy(s);
}

/* A minimal glTF 2.0 with an embedded base64 buffer, a node translation and
 * KHR_materials_emissive_strength. */
TEST(scene_gltf_from_another_tool)
{
    rad_scene *s = harness_scene_load("scenes/formats/two_triangles.gltf", NULL);
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 2);
    int paint = find_material(s, "paint"), lamp = find_material(s, "lamp");
    CHECK(paint >= 0 && lamp >= 0);
    if (paint >= 0 && lamp >= 0) {
        const rad_scene_material *m = rad_scene_materials(s);
        CHECK(m[paint].rho[0] == 0.625 && m[paint].rho[1] == 0.5 && m[paint].rho[2] == 0.25);
        CHECK(m[paint].emission[0] == 0.0);
        /* emissiveFactor (1, 0.5, 0.25) x emissiveStrength 4 */
        CHECK(m[lamp].emission[0] == 4.0 && m[lamp].emission[1] == 2.0 && m[lamp].emission[2] == 1.0);
        CHECK(rad_scene_triangle_materials(s)[0] == paint && rad_scene_triangle_materials(s)[1] == lamp);
    }
    /* The second mesh is moved by its node: its corners are (0,0,1) +
     * (0.5, 0.25, 2), ... so z = 3 there. */
    rad_scene_summary sum;
    rad_scene_summarize(s, &sum);
    CHECK_NEAR(sum.bbox_max[2], 3.0, 0.0, 1e-15);
    CHECK_NEAR(sum.bbox_max[0], 1.5, 0.0, 1e-15);
    CHECK_NEAR(sum.bbox_max[1], 1.25, 0.0, 1e-15);
    CHECK_NEAR(sum.total_area, 1.0, 1e-15, 0.0);
    rad_scene_destroy(s);
}

/* Polygons keep their place: an OBJ with interleaved materials. */
TEST(scene_obj_keeps_input_order_and_materials)
{
    const char *mtl = harness_write_file("order.mtl", "newmtl a\nKd 0.125 0.25 0.375\nnewmtl b\n"
                                                      "Kd 0.5 0.5 0.5\nKe 0.75 0.75 0.75\n");
    char text[512];
    snprintf(text, sizeof text, "mtllib %s\n"
             "v 0 0 0\nv 2.385 0 0\nv 2.385 1.5 0\nv 0 1.5 0\nv 0 0 1\nv 0 1.5 1\n"
             "usemtl a\nf 1 2 3\nusemtl b\nf 1 2 5\nusemtl a\nf 1/1/1 3/2/2 4/3/3\n"
             "usemtl b\nf -6 -2 -1 -3\n", strrchr(mtl, '/') + 1);
    const char *obj = harness_write_file("order.obj", text);
    rad_scene *s = NULL;
    CHECK_MSG(rad_scene_load(obj, NULL, &s) == RAD_OK, "%s", rad_error_message());
    if (s) {
        CHECK(rad_scene_triangle_count(s) == 5);
        const int *mat = rad_scene_triangle_materials(s), *face = rad_scene_triangle_faces(s);
        const rad_scene_material *m = rad_scene_materials(s);
        const char *names[5] = {"a", "b", "a", "b", "b"};
        int faces[5] = {0, 1, 2, 3, 3};
        for (int t = 0; t < 5; t++) {
            CHECK(strcmp(m[mat[t]].name, names[t]) == 0);
            CHECK(face[t] == faces[t]);
        }
        CHECK(m[find_material(s, "a")].rho[2] == 0.375);
        /* Triangle 1 is (v1, v2, v5) exactly as written, in double precision. */
        const double *x = rad_scene_vertices(s);
        const int *t1 = rad_scene_triangles(s) + 3;
        CHECK(x[3 * t1[1]] == 2.385 && x[3 * t1[2] + 2] == 1.0);
        /* The quad (-6 -2 -1 -3) = (v1 v5 v6 v4) fans into (1 5 6), (1 6 4). */
        const int *t3 = rad_scene_triangles(s) + 9, *t4 = t3 + 3;
        CHECK(x[3 * t3[1] + 2] == 1.0 && x[3 * t3[2] + 1] == 1.5 && x[3 * t3[2] + 2] == 1.0);
        CHECK(t4[0] == t3[0] && t4[1] == t3[2] && x[3 * t4[2] + 1] == 1.5 && x[3 * t4[2] + 2] == 0.0);
        CHECK(rad_scene_warning_count(s) == 0);
        rad_scene_destroy(s);
    }
    remove(mtl);
    remove(obj);
}

TEST(scene_bad_inputs_are_refused_with_their_place)
{
    struct { const char *path, *needle; rad_status st; } bad[] = {
        {"scenes/bad/nan_vertex.obj", "nan_vertex.obj:4: vertex coordinate: NaN", RAD_EINPUT},
        {"scenes/bad/inf_vertex.obj", "inf_vertex.obj:3: vertex coordinate: infinite", RAD_EINPUT},
        {"scenes/bad/index_out_of_range.obj", "index_out_of_range.obj:8: face index 9 is out of range", RAD_EINPUT},
        {"scenes/bad/rho_too_big.obj", "rho_too_big.mtl:2: material 'm': reflectance Kd g = 1.5 is outside [0, 1]", RAD_EINPUT},
        {"scenes/bad/negative_emission.obj", "negative_emission.mtl:3: material 'm': negative emission", RAD_EINPUT},
        {"scenes/bad/malformed_number.obj", "malformed_number.obj:3: vertex coordinate: malformed number '0.5x'", RAD_EINPUT},
        {"scenes/bad/no_faces.obj", "no faces", RAD_EINPUT},
        {"scenes/bad/empty.obj", "empty", RAD_EINPUT},
        {"scenes/bad/garbage.obj", "garbage.obj: no faces (empty scene); it has 2 statement(s) radkit ignores", RAD_EINPUT},
        {"scenes/bad/garbage.ply", "garbage.ply:3: element vertex needs the scalar properties x, y and z", RAD_EINPUT},
        {"scenes/bad/no_such_scene.obj", "cannot open", RAD_EINPUT},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        rad_scene *s = NULL;
        rad_error_clear();
        rad_status st = harness_scene_load_status(bad[k].path, NULL, &s);
        CHECK_MSG(st == bad[k].st, "%s: status %d", bad[k].path, (int)st);
        CHECK(s == NULL);
        CHECK_MSG(strstr(rad_error_message(), bad[k].needle) != NULL, "%s: message '%s' lacks '%s'",
                  bad[k].path, rad_error_message(), bad[k].needle);
        rad_scene_destroy(s);
    }
}

TEST(scene_drop_degenerate_counts_and_warns)
{
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.drop_degenerate = 1;
    rad_scene *s = NULL;
    CHECK(harness_scene_load_status("scenes/bad/zero_area.obj", &p, &s) == RAD_OK);
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 1 && rad_scene_dropped_count(s) == 1);
    CHECK(rad_scene_triangle_faces(s)[0] == 0);
    CHECK(has_warning(s, "dropped 1 degenerate"));
    CHECK(has_warning(s, "1 unused vert")); /* v 0 1 0 is never used */
    rad_scene_destroy(s);
}

TEST(scene_create_from_arrays_validates_and_warns)
{
    /* Two coincident triangles (one reversed) and an unused vertex. */
    const double xyz[] = {0, 0, 0, 2.385, 0, 0, 0, 1.5, 0, 9, 9, 9};
    const int tri[] = {0, 1, 2, 0, 2, 1};
    rad_scene_material mat = {"grey", {0.5, 0.5, 0.5}, {0, 0, 0}};
    rad_scene *s = NULL;
    CHECK(rad_scene_create("arrays", xyz, 4, tri, 2, NULL, &mat, 1, NULL, &s) == RAD_OK);
    if (s) {
        CHECK(has_warning(s, "back to back"));
        CHECK(has_warning(s, "unused"));
        CHECK(has_warning(s, "no emitter"));
        CHECK(rad_scene_vertex_count(s) == 3);
        CHECK(rad_scene_camera(s)->from_scene == 0 && rad_scene_camera(s)->fov_y_deg == 40.0);
        rad_scene_destroy(s);
    }
    rad_scene_material hot = {"bad", {0.5, 1.0, 0.5}, {0, 0, 0}};
    CHECK(rad_scene_create("arrays", xyz, 4, tri, 1, NULL, &hot, 1, NULL, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "reflectance g = 1") != NULL);
    const int out_of_range[] = {0, 1, 4};
    CHECK(rad_scene_create("arrays", xyz, 4, out_of_range, 1, NULL, &mat, 1, NULL, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "out of range") != NULL);
    const double nan_xyz[] = {0, 0, 0, 1, 0, 0, 0, NAN, 0};
    CHECK(rad_scene_create("arrays", nan_xyz, 3, tri, 1, NULL, &mat, 1, NULL, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "NaN") != NULL);
    CHECK(rad_scene_create("arrays", xyz, 4, tri, 0, NULL, &mat, 1, NULL, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "empty") != NULL);
    rad_scene_destroy(NULL);
}

static rad_status plan_for(const char *rel, const rad_effects_params *ep, rad_effects_plan *plan)
{
    rad_scene *s = harness_scene_load(rel, NULL);
    if (!s)
        return RAD_EINPUT;
    rad_mesh *m = NULL;
    rad_status st = rad_mesh_create(rad_scene_vertices(s), rad_scene_vertex_count(s),
                                    rad_scene_triangles(s), rad_scene_triangle_count(s), NULL, &m);
    if (st == RAD_OK)
        st = rad_scene_effects_plan(s, m, ep, plan);
    rad_mesh_destroy(m);
    rad_scene_destroy(s);
    return st;
}

TEST(scene_effects_plan_decisions)
{
    rad_effects_plan plan;
    /* Closed convex enclosure, grey: no occlusion, one channel. */
    CHECK(plan_for("scenes/furnace_cube/cube.obj", NULL, &plan) == RAD_OK);
    CHECK(plan.occlusion.on == 0 && strstr(plan.occlusion.reason, "convex"));
    CHECK(plan.colour.on == 0);
    CHECK(plan.singular.on == 1 && plan.pairs_singular == 12 + 28);
    CHECK(plan.pairs_adjacent_coplanar == 6);
    /* Opposite sides of the cube face away from each other?  No: they face
     * each other.  The facing-away pairs of a closed convex cube are the
     * coplanar halves of a side (6): each lies in the other's plane. */
    CHECK(plan.pairs_facing_away == 6 && plan.pairs_total == 66);
    /* Occluder: a plate between two plates: occlusion per pair. */
    CHECK(plan_for("scenes/occluder/occluder.obj", NULL, &plan) == RAD_OK);
    CHECK(plan.occlusion.on == 1);
    /* Parallel plates: nothing can block, nothing touches. */
    CHECK(plan_for("scenes/plates_parallel/plates.obj", NULL, &plan) == RAD_OK);
    CHECK(plan.occlusion.on == 0 && plan.singular.on == 0);
    /* Cornell: coloured walls, occlusion by the blocks. */
    CHECK(plan_for("scenes/cornell/cornell.obj", NULL, &plan) == RAD_OK);
    CHECK(plan.colour.on == 1 && plan.occlusion.on == 1);
    /* Overrides win and say so. */
    rad_effects_params ep;
    rad_scene_effects_params_default(&ep);
    ep.occlusion = RAD_EFFECT_ON;
    ep.colour = RAD_EFFECT_ON;
    CHECK(plan_for("scenes/furnace_cube/cube.obj", &ep, &plan) == RAD_OK);
    CHECK(plan.occlusion.on == 1 && plan.occlusion.forced == 1);
    CHECK(strstr(plan.occlusion.reason, "forced on") != NULL);
    CHECK(plan.colour.on == 1 && plan.colour.forced);
    rad_effect_mode mode;
    CHECK(rad_scene_effect_mode_parse("x", "on", &mode) == RAD_OK && mode == RAD_EFFECT_ON);
    CHECK(rad_scene_effect_mode_parse("x", "maybe", &mode) == RAD_EINVAL);
}

/* Clustering for hier is decided by the pairs facing each other (pairs_total
 * minus pairs_facing_away, checked against a brute force below) against a
 * threshold that depends on whether anything can block: the Cornell box
 * (occluded, 38 triangles) is on once cluster_min_pairs is lowered to its
 * own count of facing pairs and off one pair above; the cube (nothing
 * blocks) follows cluster_min_pairs_clear instead; above the scan limit,
 * where pairs are not counted, it is on whatever the thresholds. */
TEST(scene_effects_clustering_by_facing_pairs)
{
    rad_effects_plan plan;
    rad_effects_params ep;
    rad_scene_effects_params_default(&ep);
    CHECK(plan_for("scenes/cornell/cornell.obj", &ep, &plan) == RAD_OK);
    double facing = (double)(plan.pairs_total - plan.pairs_facing_away);
    CHECK(plan.occlusion.on == 1 && facing > 0.0 && plan.clustering.on == 0);
    ep.cluster_min_pairs_clear = 1.0; /* not read where faces can block */
    ep.cluster_min_pairs = facing;
    CHECK(plan_for("scenes/cornell/cornell.obj", &ep, &plan) == RAD_OK);
    CHECK_MSG(plan.clustering.on == 1 && strstr(plan.clustering.reason, "face each other") &&
                  strstr(plan.clustering.reason, "can block"),
              "%s", plan.clustering.reason);
    ep.cluster_min_pairs = facing + 1.0;
    CHECK(plan_for("scenes/cornell/cornell.obj", &ep, &plan) == RAD_OK);
    CHECK(plan.clustering.on == 0);
    ep.cluster_min_pairs_clear = facing + 1.0; /* the cube has 60 facing pairs */
    ep.cluster_min_pairs = 1.0;
    CHECK(plan_for("scenes/furnace_cube/cube.obj", &ep, &plan) == RAD_OK);
    CHECK(plan.occlusion.on == 0 && plan.clustering.on == 0);
    ep.cluster_min_pairs_clear = 60.0;
    CHECK(plan_for("scenes/furnace_cube/cube.obj", &ep, &plan) == RAD_OK);
    CHECK(plan.clustering.on == 1);
    rad_scene_effects_params_default(&ep);
    ep.pair_scan_max_faces = 10;
    CHECK(plan_for("scenes/cornell/cornell.obj", &ep, &plan) == RAD_OK);
    CHECK_MSG(plan.pairs_facing_away == -1 && plan.clustering.on == 1 &&
                  strstr(plan.clustering.reason, "counted"),
              "%s", plan.clustering.reason);
}

/* Facing-away pairs counted against a brute-force reference: a pair is zero
 * when all of one triangle's corners are on or behind the other's plane. */
TEST(scene_effects_facing_away_count_independent)
{
    rad_scene *s = harness_scene_load("scenes/cornell/cornell.obj", NULL);
    if (!s)
        return;
    rad_mesh *m = NULL;
    CHECK(rad_mesh_create(rad_scene_vertices(s), rad_scene_vertex_count(s), rad_scene_triangles(s),
                          rad_scene_triangle_count(s), NULL, &m) == RAD_OK);
    rad_effects_plan plan;
    CHECK(rad_scene_effects_plan(s, m, NULL, &plan) == RAD_OK);
    /* Reference: sample the kernel's cosine factors at the corners and
     * centroids; a pair facing away has no point pair with both cosines > 0. */
    const double *x = rad_scene_vertices(s);
    const int *t = rad_scene_triangles(s);
    int n = rad_scene_triangle_count(s);
    long long away = 0;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            rad_vec3 P[2][4], N[2];
            for (int k = 0; k < 2; k++) {
                const int *v = t + 3 * (k ? j : i);
                for (int c = 0; c < 3; c++)
                    P[k][c] = rad_vec3_make(x[3 * v[c]], x[3 * v[c] + 1], x[3 * v[c] + 2]);
                P[k][3] = rad_geom_triangle_centroid(P[k][0], P[k][1], P[k][2]);
                N[k] = rad_geom_triangle_normal(P[k][0], P[k][1], P[k][2]);
            }
            int any = 0;
            for (int a = 0; a < 4 && !any; a++)
                for (int b = 0; b < 4 && !any; b++) {
                    rad_vec3 d = rad_vec3_sub(P[1][b], P[0][a]);
                    any = rad_vec3_dot(N[0], d) > 1e-12 && -rad_vec3_dot(N[1], d) > 1e-12;
                }
            away += !any;
        }
    CHECK_MSG(plan.pairs_facing_away == away, "plan %lld, reference %lld", plan.pairs_facing_away, away);
    rad_mesh_destroy(m);
    rad_scene_destroy(s);
}

/* The plan's contact decision is made from a cut the caller may keep
 * (rad_scene_effects_plan_cut), which the solve then meshes instead of
 * cutting again: it is the cut rad_mesh_split_contacts makes with the
 * plan's tolerances, piece for piece, and the plan's counts are its own.
 * The box under the lit ceiling is cut (its top's outline on the ceiling);
 * the Cornell box, with the defaults' hover share, too (its blocks stand on
 * the floor).  A NULL cut is refused. */
TEST(scene_effects_plan_keeps_its_contact_cut)
{
    const char *scenes[] = {"scenes/contact/box_under_ceiling.obj", "scenes/cornell/cornell.obj"};
    for (int k = 0; k < 2; k++) {
        rad_scene *s = harness_scene_load(scenes[k], NULL);
        if (!s)
            continue;
        rad_mesh *m = NULL;
        CHECK(rad_mesh_create(rad_scene_vertices(s), rad_scene_vertex_count(s),
                              rad_scene_triangles(s), rad_scene_triangle_count(s), NULL,
                              &m) == RAD_OK);
        rad_effects_params ep;
        rad_scene_effects_params_default(&ep);
        rad_effects_plan plan;
        rad_mesh_contacts kept, direct;
        CHECK(rad_scene_effects_plan_cut(s, m, &ep, &plan, &kept) == RAD_OK);
        CHECK(rad_mesh_split_contacts(rad_scene_vertices(s), (size_t)rad_scene_vertex_count(s),
                                      rad_scene_triangles(s),
                                      (size_t)rad_scene_triangle_count(s), ep.contact_rel_tol,
                                      ep.contact_near_rel, ep.contact_near_rel_large, 0, &direct) == RAD_OK);
        CHECK_MSG(kept.faces_split > 0 && plan.contact.on, "%s: %zu faces cut", scenes[k],
                  kept.faces_split);
        CHECK(kept.nt == direct.nt && kept.nv == direct.nv &&
              kept.faces_split == direct.faces_split && kept.segments == direct.segments);
        if (kept.nt == direct.nt && kept.nv == direct.nv)
            CHECK(memcmp(kept.tri, direct.tri, 3 * kept.nt * sizeof *kept.tri) == 0 &&
                  memcmp(kept.parent, direct.parent, kept.nt * sizeof *kept.parent) == 0 &&
                  memcmp(kept.xyz, direct.xyz, 3 * kept.nv * sizeof *kept.xyz) == 0);
        CHECK(plan.contact_faces == (int)kept.faces_split &&
              plan.contact_pieces ==
                  (int)(kept.nt - ((size_t)rad_scene_triangle_count(s) - kept.faces_split)));
        rad_mesh_contacts_free(&kept);
        rad_mesh_contacts_free(&direct);
        CHECK(rad_scene_effects_plan_cut(s, m, &ep, &plan, NULL) == RAD_EINVAL);
        rad_mesh_destroy(m);
        rad_scene_destroy(s);
    }
}

/* A face repeated on the same side (in any rotation of its corners) adds no
 * surface; dozens of copies made every pair behind them minutes of
 * visibility.  Copies are dropped and counted, the first kept; the other
 * side of a face is a surface of its own and stays; strict mode refuses. */
TEST(scene_duplicate_faces_on_one_side_are_dropped)
{
    const double xyz[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const int tri[] = {0, 1, 2, 0, 1, 2, 1, 2, 0, 0, 2, 1, 0, 3, 1};
    rad_scene_material mat = {"grey", {0.5, 0.5, 0.5}, {1, 1, 1}};
    rad_scene *s = NULL;
    CHECK(rad_scene_create("arrays", xyz, 4, tri, 5, NULL, &mat, 1, NULL, &s) == RAD_OK);
    if (s) {
        CHECK(rad_scene_triangle_count(s) == 3);
        const int *faces = rad_scene_triangle_faces(s);
        CHECK(faces[0] == 0 && faces[1] == 3 && faces[2] == 4);
        CHECK(has_warning(s, "dropped 2 duplicate face(s)"));
        CHECK(has_warning(s, "face 1 repeats face 0"));
        CHECK(has_warning(s, "1 pair(s) of coincident faces back to back"));
        rad_scene_destroy(s);
    }
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.strict = 1;
    CHECK(rad_scene_create("arrays", xyz, 4, tri, 5, NULL, &mat, 1, &p, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "face 1 repeats face 0") != NULL);
}
