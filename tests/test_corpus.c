/* The meshes of Debian's libcgal-demo package (data.tar.gz: OFF, PLY and STL
 * files written by many tools), each loaded by radkit: it must load with the
 * triangle count CGAL's own reader gives (CGAL::IO::read_polygon_soup, through
 * rad_mesh_count_polygon_soup: sum of n - 2 over its polygons), degenerate
 * triangles dropped and counted included, or be refused with RAD_EINPUT and
 * a message naming the file.  Refusals are listed below with their reason, so
 * that a new refusal (or a listed file that starts loading) fails the test.
 * The package is installed by `make deps` (core/scene/module.mk); without it
 * the test fails, it does not skip. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "harness.h"
#include "rad_mesh.h"
#include "rad_scene.h"

static const char *const TARBALL = "/usr/share/doc/libcgal-dev/data.tar.gz";

/* Files radkit refuses, relative to data/, with a part of the message. */
static const struct {
    const char *file, *needle;
} refusals[] = {
    /* Point clouds: vertices only (or "element face 0"). */
    {"meshes/b9.ply", "no faces (a point cloud?)"},
    {"points_3/ball.ply", "no faces (a point cloud?)"},
    {"points_3/b9_training.ply", "no faces (a point cloud?)"},
    {"points_3/building.ply", "no faces (a point cloud?)"},
    {"points_3/circles.ply", "no faces (a point cloud?)"},
    {"points_3/colors.ply", "no faces (a point cloud?)"},
    {"points_3/example.ply", "no faces (a point cloud?)"},
    {"points_3/hippo1.ply", "no faces (a point cloud?)"},
    {"points_3/hippo2.ply", "no faces (a point cloud?)"},
    {"points_3/oni.ply", "no faces (a point cloud?)"},
    {"points_3/spheres.ply", "no faces (a point cloud?)"},
    {"points_3/kitten.off", "no faces (a point cloud?)"},
};

typedef struct file_list {
    char **path;
    int n, cap;
} file_list;

static int mesh_extension(const char *name)
{
    const char *dot = strrchr(name, '.');
    return dot && (strcmp(dot, ".off") == 0 || strcmp(dot, ".ply") == 0 || strcmp(dot, ".stl") == 0 ||
                   strcmp(dot, ".obj") == 0);
}

static void collect(const char *dir, file_list *out)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.')
            continue;
        char path[4096];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        struct stat st;
        if (stat(path, &st) != 0)
            continue;
        if (S_ISDIR(st.st_mode)) {
            collect(path, out);
        } else if (S_ISREG(st.st_mode) && mesh_extension(e->d_name)) {
            if (out->n == out->cap) {
                out->cap = out->cap ? 2 * out->cap : 256;
                out->path = realloc(out->path, (size_t)out->cap * sizeof *out->path);
            }
            out->path[out->n++] = strdup(path);
        }
    }
    closedir(d);
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static const char *expected_refusal(const char *rel)
{
    for (size_t i = 0; i < sizeof refusals / sizeof refusals[0]; i++)
        if (strcmp(refusals[i].file, rel) == 0)
            return refusals[i].needle;
    return NULL;
}

TEST(corpus_cgal_demo_meshes_load_with_cgal_counts_or_are_refused)
{
    if (access(TARBALL, R_OK) != 0) {
        CHECK_MSG(0, "%s is missing: install libcgal-demo (make deps)", TARBALL);
        return;
    }
    char dir[] = "/tmp/radkit-corpus-XXXXXX";
    if (!mkdtemp(dir)) {
        CHECK_MSG(0, "mkdtemp failed");
        return;
    }
    char *out = NULL, *err = NULL;
    int rc = harness_run((const char *const[]){"/bin/tar", "xzf", TARBALL, "-C", dir, "data/meshes",
                                               "data/points_3", NULL},
                         &out, &err);
    CHECK_MSG(rc == 0, "tar: %s", err ? err : "");
    free(out);
    free(err);
    char data[64];
    snprintf(data, sizeof data, "%s/data", dir);
    file_list files = {0};
    collect(data, &files);
    qsort(files.path, (size_t)files.n, sizeof *files.path, by_name);
    CHECK_MSG(files.n >= 150, "only %d meshes in %s", files.n, TARBALL);

    int loaded = 0, refused = 0, matched_refusals = 0;
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.no_cross_check = 1;
    for (int i = 0; i < files.n; i++) {
        const char *path = files.path[i], *rel = path + strlen(data) + 1;
        const char *want_refusal = expected_refusal(rel);
        rad_scene *s = NULL;
        rad_status st = rad_scene_load(path, &p, &s);
        if (st != RAD_OK) {
            refused++;
            const char *msg = rad_error_message();
            CHECK_MSG(st == RAD_EINPUT && strstr(msg, path) != NULL,
                      "%s: refused with status %d and a message not naming it: %s", rel, (int)st, msg);
            CHECK_MSG(want_refusal != NULL, "%s: refused unexpectedly: %s", rel, msg);
            if (want_refusal) {
                CHECK_MSG(strstr(msg, want_refusal) != NULL, "%s: refused with '%s', want '%s'", rel,
                          msg, want_refusal);
                matched_refusals++;
            }
            continue;
        }
        loaded++;
        CHECK_MSG(!want_refusal, "%s: loads, but is listed as refused (%s)", rel,
                  want_refusal ? want_refusal : "");
        long polygons = 0, triangles = 0;
        long got = (long)rad_scene_triangle_count(s) + rad_scene_dropped_count(s);
        if (rad_mesh_count_polygon_soup(path, &polygons, &triangles) != RAD_OK)
            CHECK_MSG(0, "%s: CGAL cannot read it: %s", rel, rad_error_message());
        else
            CHECK_MSG(got == triangles, "%s: radkit has %ld triangles (%d dropped), CGAL's polygons "
                      "make %ld", rel, got, rad_scene_dropped_count(s), triangles);
        rad_scene_destroy(s);
    }
    CHECK_MSG(matched_refusals == (int)(sizeof refusals / sizeof refusals[0]),
              "%d of the %zu listed refusals seen", matched_refusals,
              sizeof refusals / sizeof refusals[0]);
    printf("    corpus: %d meshes, %d loaded, %d refused\n", files.n, loaded, refused);
    for (int i = 0; i < files.n; i++)
        free(files.path[i]);
    free(files.path);
    /* The program too: exit 2 and one line naming the file, for each refusal. */
    for (size_t i = 0; i < sizeof refusals / sizeof refusals[0]; i++) {
        char path[256];
        snprintf(path, sizeof path, "%s/%s", data, refusals[i].file);
        HARNESS_EXPECT_USAGE_ERROR("info", (const char *[]){path, NULL}, refusals[i].needle);
    }
    rc = harness_run((const char *const[]){"/bin/rm", "-rf", dir, NULL}, &out, &err);
    CHECK(rc == 0);
    free(out);
    free(err);
}
