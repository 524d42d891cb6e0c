/* The input policy for real files (scenes/lenient/, scenes/bad/): what loads
 * with a counted warning (Kd = 1, statements radkit does not use, a missing
 * material library or material, degenerate triangles), what strict mode
 * refuses instead, and what is always refused with its file:line (Kd above 1
 * or negative, coordinates beyond the overflow bound, files that are not
 * regular, too big, with over-long lines or binary data). */
#define _DEFAULT_SOURCE /* realpath */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "harness.h"
#include "rad_scene.h"

static rad_scene_params strict_params(void)
{
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.strict = 1;
    return p;
}

/* The one warning containing `needle` (NULL if none, or if several do). */
static const char *warning_with(const rad_scene *s, const char *needle)
{
    const char *found = NULL;
    for (int w = 0; w < rad_scene_warning_count(s); w++)
        if (strstr(rad_scene_warning(s, w), needle)) {
            if (found)
                return NULL;
            found = rad_scene_warning(s, w);
        }
    return found;
}

static const rad_scene_material *material_named(const rad_scene *s, const char *name)
{
    for (int m = 0; m < rad_scene_material_count(s); m++)
        if (strcmp(rad_scene_materials(s)[m].name, name) == 0)
            return &rad_scene_materials(s)[m];
    return NULL;
}

/* The material of the triangle made from input face `face`. */
static const rad_scene_material *material_of_face(const rad_scene *s, int face)
{
    for (int t = 0; t < rad_scene_triangle_count(s); t++)
        if (rad_scene_triangle_faces(s)[t] == face)
            return &rad_scene_materials(s)[rad_scene_triangle_materials(s)[t]];
    return NULL;
}

#define CHECK_REFUSED(rel, params, needle)                                                   \
    do {                                                                                     \
        rad_scene *s_ = NULL;                                                                \
        rad_error_clear();                                                                   \
        rad_status st_ = harness_scene_load_status(rel, params, &s_);                                        \
        CHECK_MSG(st_ == RAD_EINPUT && s_ == NULL, "%s: status %d", rel, (int)st_);          \
        CHECK_MSG(strstr(rad_error_message(), needle) != NULL, "%s: message '%s' lacks '%s'", \
                  rel, rad_error_message(), needle);                                         \
        rad_scene_destroy(s_);                                                               \
    } while (0)

#define CHECK_WARNING(s, needle)                                                             \
    CHECK_MSG(warning_with(s, needle) != NULL, "no single warning with '%s'", needle)

/* ---- Kd = 1 ------------------------------------------------------------ */

TEST(obj_kd_one_is_the_largest_reflectance)
{
    rad_scene *s = NULL;
    rad_scene_params p;
    rad_scene_params_default(&p);
    CHECK(p.rho_white == 0.999);
    CHECK_MSG(harness_scene_load_status("scenes/lenient/white.obj", NULL, &s) == RAD_OK, "%s", rad_error_message());
    if (!s)
        return;
    const rad_scene_material *white = material_named(s, "white"), *lamp = material_named(s, "lamp"),
                       *tinted = material_named(s, "tinted");
    CHECK(white && lamp && tinted);
    if (white && lamp && tinted) {
        for (int k = 0; k < 3; k++)
            CHECK(white->rho[k] == 0.999 && lamp->rho[k] == 0.999);
        CHECK(tinted->rho[0] == 0.5 && tinted->rho[1] == 0.999 && tinted->rho[2] == 0.25);
        CHECK(lamp->emission[1] == 2.385);
    }
    CHECK_WARNING(s, "3 Kd statement(s) give a reflectance of 1 (first at ");
    CHECK_WARNING(s, "white.mtl:2), taken as 0.999");
    rad_scene_destroy(s);
    rad_scene_params sp = strict_params();
    CHECK_REFUSED("scenes/lenient/white.obj", &sp,
                  "white.mtl:2: material 'white': reflectance Kd r = 1 is outside [0, 1)");
}

TEST(obj_kd_above_one_or_negative_is_refused)
{
    CHECK_REFUSED("scenes/bad/rho_too_big.obj", NULL,
                  "rho_too_big.mtl:2: material 'm': reflectance Kd g = 1.5 is outside [0, 1]");
    CHECK_REFUSED("scenes/bad/rho_negative.obj", NULL,
                  "rho_negative.mtl:2: material 'm': reflectance Kd r = -0.25 is outside [0, 1]");
}

/* ---- statements radkit does not use ------------------------------------- */

TEST(obj_unused_statements_warn_once_per_keyword)
{
    rad_scene *s = NULL;
    CHECK_MSG(harness_scene_load_status("scenes/lenient/ignored.obj", NULL, &s) == RAD_OK, "%s", rad_error_message());
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 2);
    const rad_scene_material *n = material_of_face(s, 1), *m = material_of_face(s, 0);
    CHECK(m && n && m->rho[0] == 0.5 && n->rho[2] == 0.25 && n->emission[0] == 1.5);
    struct { const char *text; } want[] = {
        {"ignored 2 `t` statement(s) (first at "}, {"ignored.obj:15): "},
        {"ignored 1 `vp` statement(s) (first at "}, {"ignored.obj:7): free-form"},
        {"ignored 1 `cstype` statement(s)"}, {"ignored 1 `deg` statement(s)"},
        {"ignored 1 `curv` statement(s)"}, {"ignored 1 `parm` statement(s)"},
        {"ignored 1 `end` statement(s)"}, {"ignored 1 `call` statement(s)"},
        {"ignored 1 `csh` statement(s)"}, {"ignored 1 `lod` statement(s)"},
        {"ignored 1 `shadow_obj` statement(s)"}, {"ignored 1 `frobnicate` statement(s)"},
        {"ignored.obj:25): not a statement radkit knows"},
        {"ignored 2 `Kt` statement(s) (first at "}, {"ignored.mtl:9): "},
        {"ignored 1 `Tf` statement(s)"}, {"ignored 1 `Pr` statement(s)"},
        {"ignored 1 `Pm` statement(s)"}, {"ignored 1 `map_Kd` statement(s)"},
        {"ignored 1 `d` statement(s) (first at "}, {"ignored.mtl:18)"},
        {"ignored 1 `Tr` statement(s)"}, {"ignored 1 `aniso` statement(s)"},
    };
    for (size_t k = 0; k < sizeof want / sizeof want[0]; k++)
        CHECK_WARNING(s, want[k].text);
    /* Texture coordinates, normals, groups, smoothing and the colours of a
     * specular model carry nothing radkit uses: no warning. */
    const char *silent[] = {"`vt`", "`vn`", "`o`", "`g`", "`s`", "`Ka`", "`Ks`", "`Ns`",
                            "`Ni`", "`illum`", "`usemtl`"};
    for (size_t k = 0; k < sizeof silent / sizeof silent[0]; k++)
        for (int w = 0; w < rad_scene_warning_count(s); w++)
            CHECK_MSG(strstr(rad_scene_warning(s, w), silent[k]) == NULL, "warning %s: %s",
                      silent[k], rad_scene_warning(s, w));
    rad_scene_destroy(s);

    /* Strict: geometry radkit does not load, or a statement it does not know,
     * refuses; known appearance statements (here in the MTL) still warn. */
    rad_scene_params sp = strict_params();
    CHECK_REFUSED("scenes/lenient/ignored.obj", &sp, "ignored.obj:7: `vp`");
    char *mtl = realpath(harness_path("scenes/lenient/ignored.mtl"), NULL), text[1200];
    snprintf(text, sizeof text, "mtllib %s\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
             mtl ? mtl : "?");
    free(mtl);
    const char *obj = harness_write_file("lenient.obj", text);
    s = NULL;
    CHECK_MSG(rad_scene_load(obj, &sp, &s) == RAD_OK, "%s", rad_error_message());
    if (s)
        CHECK_WARNING(s, "ignored 2 `Kt` statement(s)");
    rad_scene_destroy(s);
    obj = harness_write_file("lenient.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nfrobnicate\n");
    s = NULL;
    CHECK(rad_scene_load(obj, &sp, &s) == RAD_EINPUT && s == NULL);
    CHECK_MSG(strstr(rad_error_message(), ":5: `frobnicate` is not a statement radkit knows"),
              "%s", rad_error_message());
    remove(obj);
}

TEST(obj_garbage_is_refused_with_its_statements)
{
    CHECK_REFUSED("scenes/bad/garbage.obj", NULL, "no faces");
    CHECK_REFUSED("scenes/bad/garbage.obj", NULL, "ELF???` at ");
    rad_scene_params sp = strict_params();
    CHECK_REFUSED("scenes/bad/garbage.obj", &sp, "garbage.obj:1: `?ELF???` is not a statement");
}

/* ---- missing libraries and materials ------------------------------------ */

TEST(obj_missing_library_takes_the_default_material)
{
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.default_rho[0] = 0.25;
    p.default_rho[1] = 0.375;
    p.default_rho[2] = 0.625;
    rad_scene *s = NULL;
    CHECK_MSG(harness_scene_load_status("scenes/bad/missing_mtl.obj", &p, &s) == RAD_OK, "%s", rad_error_message());
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 1);
    const rad_scene_material *m = material_of_face(s, 0);
    CHECK(m && m->rho[0] == 0.25 && m->rho[1] == 0.375 && m->rho[2] == 0.625 && m->emission[0] == 0);
    CHECK_WARNING(s, "cannot open 1 material librar");
    CHECK_WARNING(s, "missing_mtl.obj:1: ");
    CHECK_WARNING(s, "1 usemtl statement(s) name a material no library defines (first 'm' at ");
    CHECK_WARNING(s, "default material (reflectance 0.25 0.375 0.625, no emission)");
    rad_scene_destroy(s);
    rad_scene_params sp = strict_params();
    CHECK_REFUSED("scenes/bad/missing_mtl.obj", &sp, "missing_mtl.obj:1: cannot open material library");
}

TEST(obj_undefined_material_takes_the_default_material)
{
    rad_scene *s = NULL;
    CHECK_MSG(harness_scene_load_status("scenes/bad/undefined_material.obj", NULL, &s) == RAD_OK, "%s",
              rad_error_message());
    if (s) {
        CHECK(rad_scene_triangle_count(s) == 1);
        const rad_scene_material *m = material_of_face(s, 0);
        CHECK(m && m->rho[0] == 0.5 && m->emission[0] == 0);
        CHECK_WARNING(s, "1 usemtl statement(s) name a material no library defines (first 'nosuch' at ");
        CHECK_WARNING(s, "undefined_material.obj:6)");
    }
    rad_scene_destroy(s);
    s = NULL;
    CHECK_MSG(harness_scene_load_status("scenes/lenient/no_mtllib.obj", NULL, &s) == RAD_OK, "%s", rad_error_message());
    if (s) {
        CHECK(rad_scene_triangle_count(s) == 2);
        CHECK_WARNING(s, "2 usemtl statement(s) name a material no library defines (first 'paint' at ");
        CHECK_WARNING(s, "no_mtllib.obj:6; the file has no mtllib)");
    }
    rad_scene_destroy(s);
    rad_scene_params sp = strict_params();
    CHECK_REFUSED("scenes/bad/undefined_material.obj", &sp,
                  "undefined_material.obj:6: material 'nosuch' is not defined");
    CHECK_REFUSED("scenes/lenient/no_mtllib.obj", &sp, "no_mtllib.obj:6: material 'paint' is not defined");
}

/* ---- degenerate triangles (every format: scene_finish) ------------------ */

TEST(scene_degenerate_triangles_are_dropped_by_default)
{
    rad_scene *s = NULL;
    CHECK_MSG(harness_scene_load_status("scenes/bad/zero_area.obj", NULL, &s) == RAD_OK, "%s", rad_error_message());
    if (s) {
        CHECK(rad_scene_triangle_count(s) == 1 && rad_scene_dropped_count(s) == 1);
        CHECK_WARNING(s, "dropped 1 degenerate (zero-area) triangle(s) (first at ");
        CHECK_WARNING(s, "zero_area.obj:9, face 1)");
    }
    rad_scene_destroy(s);
    /* The old option is accepted and changes nothing. */
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.drop_degenerate = 1;
    s = NULL;
    CHECK(harness_scene_load_status("scenes/bad/zero_area.obj", &p, &s) == RAD_OK);
    CHECK(s && rad_scene_dropped_count(s) == 1);
    rad_scene_destroy(s);
    rad_scene_params sp = strict_params();
    CHECK_REFUSED("scenes/bad/zero_area.obj", &sp, "zero_area.obj:9: degenerate (zero-area) triangle in face 1");
    CHECK_REFUSED("scenes/bad/all_degenerate.obj", NULL, "no faces left after dropping 2 degenerate");
    /* Arrays (and every other format) name the face. */
    const double xyz[] = {0, 0, 0, 2.385, 0, 0, 0, 1.5, 0, 4.77, 0, 0};
    const int tri[] = {0, 1, 2, 0, 1, 3};
    rad_scene_material mat = {"grey", {0.5, 0.5, 0.5}, {1, 1, 1}};
    s = NULL;
    CHECK(rad_scene_create("arrays", xyz, 4, tri, 2, NULL, &mat, 1, NULL, &s) == RAD_OK);
    if (s) {
        CHECK(rad_scene_triangle_count(s) == 1);
        CHECK_WARNING(s, "dropped 1 degenerate (zero-area) triangle(s) (first: face 1)");
    }
    rad_scene_destroy(s);
    s = NULL;
    CHECK(rad_scene_create("arrays", xyz, 4, tri, 2, NULL, &mat, 1, &sp, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "arrays: face 1: degenerate") != NULL);
}

/* ---- coordinates beyond the overflow bound ------------------------------ */

TEST(obj_huge_coordinate_names_its_line)
{
    CHECK_REFUSED("scenes/bad/huge_vertex.obj", NULL, "huge_vertex.obj:3: vertex coordinate 1e+308");
    /* The bound applies after the scale: 1e70 m x 1e10 is refused at its
     * line, 1e80 mm x 1e-10 loads. */
    const char *obj = harness_write_file("huge.obj", "v 0 0 0\nv 1e70 0 0\nv 0 1e70 1e70\nf 1 2 3\n");
    rad_scene_params p;
    rad_scene_params_default(&p);
    rad_scene *s = NULL;
    CHECK(rad_scene_load(obj, &p, &s) == RAD_OK);
    rad_scene_destroy(s);
    p.scale = 1e10;
    s = NULL;
    CHECK(rad_scene_load(obj, &p, &s) == RAD_EINPUT && !s);
    CHECK_MSG(strstr(rad_error_message(), ":2: vertex coordinate 1e+80 (after scale 1e+10)"), "%s",
              rad_error_message());
    obj = harness_write_file("huge.obj", "v 0 0 0\nv 1e80 0 0\nv 0 1e80 0\nf 1 2 3\n");
    p.scale = 1e-10;
    s = NULL;
    CHECK_MSG(rad_scene_load(obj, &p, &s) == RAD_OK, "%s", rad_error_message());
    rad_scene_destroy(s);
    remove(obj);
}

/* ---- files that are not regular, too big, binary, with long lines -------- */

static void write_file(const char *path, const char *head, size_t filler, const char *tail)
{
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (!f)
        return;
    fputs(head, f);
    for (size_t i = 0; i < filler; i++)
        fputc('x', f);
    fwrite(tail, 1, strlen(tail) + (tail[0] == '\0'), f); /* "" writes one NUL byte */
    fclose(f);
}

TEST(obj_refuses_files_that_are_not_regular_or_too_big)
{
    CHECK_REFUSED("scenes/bad/mtllib_dev_zero.obj", NULL, "/dev/zero: not a regular file (a character device)");
    CHECK_REFUSED("/dev/zero", NULL, "/dev/zero: not a regular file");
    CHECK_REFUSED("scenes/bad", NULL, "bad: not a regular file (a directory)");
    char fifo[256];
    snprintf(fifo, sizeof fifo, "/tmp/radkit-fifo-%d.obj", (int)getpid());
    remove(fifo);
    CHECK(mkfifo(fifo, 0600) == 0);
    CHECK_REFUSED(fifo, NULL, "not a regular file (a FIFO)");
    remove(fifo);
    rad_scene_params p;
    rad_scene_params_default(&p);
    CHECK(p.max_file_bytes == (size_t)1 << 31 && p.max_line_bytes == 65536);
    p.max_file_bytes = 1000;
    CHECK_REFUSED("scenes/cornell/cornell.obj", &p, "cornell.obj: the file has");
    CHECK_REFUSED("scenes/cornell/cornell.obj", &p, "bytes, more than the limit of 1000");
    /* The same limit for a material library (a small OBJ, a bigger MTL). */
    char obj[256], mtl[256], head[512];
    snprintf(obj, sizeof obj, "/tmp/radkit-big-%d.obj", (int)getpid());
    snprintf(mtl, sizeof mtl, "/tmp/radkit-big-%d.mtl", (int)getpid());
    snprintf(head, sizeof head, "mtllib radkit-big-%d.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
             (int)getpid());
    write_file(obj, head, 0, "\n");
    write_file(mtl, "# ", 300, "\nnewmtl m\n");
    p.max_file_bytes = 200;
    CHECK_REFUSED(obj, &p, ".mtl: the file has 312 bytes, more than the limit of 200");
    remove(obj);
    remove(mtl);
}

TEST(obj_refuses_long_lines_and_binary_data)
{
    char obj[256], mtl[256];
    snprintf(obj, sizeof obj, "/tmp/radkit-long-%d.obj", (int)getpid());
    snprintf(mtl, sizeof mtl, "/tmp/radkit-long-%d.mtl", (int)getpid());
    write_file(obj, "v 0 0 0\n# ", 70000, "\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK_REFUSED(obj, NULL, ":2: the line is longer than 65536 bytes");
    /* A line of exactly the limit (line break not counted) loads. */
    write_file(obj, "v 0 0 0\n# ", 65536 - 2, "\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    rad_scene *s = NULL;
    CHECK_MSG(harness_scene_load_status(obj, NULL, &s) == RAD_OK, "%s", rad_error_message());
    rad_scene_destroy(s);
    write_file(obj, "v 0 0 0\n# ", 65536 - 1, "\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK_REFUSED(obj, NULL, ":2: the line is longer than 65536 bytes");
    /* In a material library. */
    char head[512];
    snprintf(head, sizeof head, "mtllib %s\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n", mtl);
    write_file(obj, head, 0, "\n");
    write_file(mtl, "newmtl m\nKd 0.5\n", 100000, "\n");
    CHECK_REFUSED(obj, NULL, ".mtl:3: the line is longer than 65536 bytes");
    /* A NUL byte: not a text file. */
    write_file(mtl, "newmtl m\nKd 0.5\n", 3, "");
    CHECK_REFUSED(obj, NULL, ".mtl:3: a NUL byte: not a text file");
    write_file(obj, "v 0 0 0\nv 1 0 0\n", 0, "");
    CHECK_REFUSED(obj, NULL, ".obj:3: a NUL byte: not a text file");
    remove(obj);
    remove(mtl);
}

/* ---- the command line ---------------------------------------------------- */

TEST(cli_info_lenient_warnings_and_strict)
{
    char *out, *err;
    CHECK(harness_radkit_run("info", (const char *[]){"--help", NULL}, &out, &err) == 0);
    CHECK(strstr(out, "--strict") != NULL && strstr(out, "--drop-degenerate") != NULL);
    CHECK(strstr(out, "0.999") != NULL);
    free(out);
    free(err);
    CHECK(harness_radkit_run("info", (const char *[]){harness_path("scenes/lenient/white.obj"), NULL}, &out, &err) == 0);
    CHECK(strstr(out, "# warning = 3 Kd statement(s) give a reflectance of 1") != NULL);
    CHECK(strstr(out, "\tlamp\t0.999\t0.999\t0.999\t2.385\t2.385\t2.385\t1\t") != NULL);
    char buf[512];
    const char *reason = harness_header(out, "effect_reflectance_reason", buf, sizeof buf);
    CHECK(reason && strstr(reason, "0.999") != NULL);
    free(out);
    free(err);
    CHECK(harness_radkit_run("info", (const char *[]){harness_path("scenes/bad/missing_mtl.obj"), NULL}, &out, &err) == 0);
    CHECK(strstr(out, "# warning = cannot open 1 material librar") != NULL);
    free(out);
    free(err);
    CHECK(harness_radkit_run("info", (const char *[]){harness_path("scenes/bad/zero_area.obj"), NULL}, &out, &err) == 0);
    CHECK(strstr(out, "# dropped_degenerate = 1\n") != NULL);
    free(out);
    free(err);
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/lenient/white.obj"), "--strict", NULL},
                               "white.mtl:2: material 'white': reflectance Kd r = 1");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/missing_mtl.obj"), "--strict", NULL},
                               "missing_mtl.obj:1: cannot open material library");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/undefined_material.obj"), "--strict", NULL},
                               "undefined_material.obj:6: material 'nosuch' is not defined");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/zero_area.obj"), "--strict", NULL},
                               "zero_area.obj:9: degenerate");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/lenient/ignored.obj"), "--strict", NULL},
                               "ignored.obj:7: `vp`");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/huge_vertex.obj"), NULL},
                               "huge_vertex.obj:3: vertex coordinate");
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){harness_path("scenes/bad/mtllib_dev_zero.obj"), NULL},
                               "/dev/zero: not a regular file");
}

/* ---- non-convex polygons ------------------------------------------------ */

TEST(obj_nonconvex_polygon_is_triangulated)
{
    /* The dart (2,0) (0.5,0.5) (0,2) (0,0): its fan from the first corner
     * folds; the polygon's area is 1 (shoelace). */
    rad_scene *s = NULL;
    CHECK_MSG(harness_scene_load_status("scenes/lenient/nonconvex_polygon.obj", NULL, &s) == RAD_OK, "%s",
              rad_error_message());
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 2);
    rad_scene_summary sum;
    rad_scene_summarize(s, &sum);
    CHECK_NEAR(sum.total_area, 1.0, 1e-15, 0.0);
    CHECK(rad_scene_triangle_faces(s)[0] == 0 && rad_scene_triangle_faces(s)[1] == 0);
    /* Every triangle faces +z, as the polygon winds. */
    const double *x = rad_scene_vertices(s);
    for (int t = 0; t < 2; t++) {
        const int *v = rad_scene_triangles(s) + 3 * t;
        double ux = x[3 * v[1]] - x[3 * v[0]], uy = x[3 * v[1] + 1] - x[3 * v[0] + 1];
        double wx = x[3 * v[2]] - x[3 * v[0]], wy = x[3 * v[2] + 1] - x[3 * v[0] + 1];
        CHECK(ux * wy - uy * wx > 0.0);
    }
    rad_scene_destroy(s);
}

TEST(cli_solve_lenient_warnings_on_stderr)
{
    /* solve loads what info loads and prints each counted warning once on
     * stderr; the solution is the one of the file without the sliver. */
    char *out, *err;
    int code = harness_radkit_run("solve", (const char *[]){harness_path("scenes/bad/zero_area.obj"), NULL}, &out, &err);
    CHECK_MSG(code == 0, "exit %d: %s", code, err);
    CHECK(strstr(err, "radkit: warning: dropped 1 degenerate (zero-area) triangle(s) (first at ") != NULL);
    CHECK(strstr(out, "# warning = dropped 1 degenerate") != NULL);
    double B[6];
    CHECK(harness_face_table(out, B, 2) == 1);
    free(out);
    free(err);
}

/* A material statement before any newmtl, as hand-written MTL files have it:
 * radkit ignores it with its warning.  Assimp's OBJ reader dereferences null
 * on it, so info no longer re-reads OBJ files with Assimp unless asked
 * (--assimp-check); the fuzzer found the crash. */
TEST(obj_material_statement_before_newmtl_loads)
{
    char *out = NULL, *err = NULL;
    const char *const args[] = {harness_path("scenes/lenient/material_before_newmtl.obj"), NULL};
    int code = harness_radkit_run("info", args, &out, &err);
    CHECK_MSG(code == 0, "info: exit %d: %s", code, err ? err : "");
    CHECK(out && strstr(out, "# faces = 1\n"));
    CHECK(out && strstr(out, "ignored 1 `map_Kd` statement(s)"));
    free(out);
    free(err);
}
