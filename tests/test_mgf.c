/* The MGF reader (core/scene/import_mgf.c): entities, contexts, transforms
 * (nested, mirrored, arrays), includes, colour conversion against hand
 * computations, the curved primitives' areas against the exact ones as the
 * tolerance shrinks, every refusal with its file:line through the program,
 * and scenes/mgf/cornell.mgf against its OBJ twin under `radkit solve`. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "harness.h"
#include "scene_internal.h"
#include "rad_scene.h"

static rad_scene *load_text(const char *name, const char *text, const rad_scene_params *p)
{
    const char *path = harness_write_file(name, text);
    rad_scene *s = NULL;
    rad_status st = rad_scene_load(path, p, &s);
    CHECK_MSG(st == RAD_OK, "%s: %s", name, rad_error_message());
    remove(path);
    return st == RAD_OK ? s : NULL;
}

static const double *corner(const rad_scene *s, int t, int k)
{
    return rad_scene_vertices(s) + 3 * rad_scene_triangles(s)[3 * t + k];
}

static void centroid_normal(const rad_scene *s, int t, double c[3], double n[3])
{
    const double *a = corner(s, t, 0), *b = corner(s, t, 1), *d = corner(s, t, 2);
    double u[3], v[3];
    for (int i = 0; i < 3; i++) {
        c[i] = (a[i] + b[i] + d[i]) / 3;
        u[i] = b[i] - a[i];
        v[i] = d[i] - a[i];
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

static double total_area(const rad_scene *s)
{
    double sum = 0, c[3], n[3];
    for (int t = 0; t < rad_scene_triangle_count(s); t++) {
        centroid_normal(s, t, c, n);
        sum += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    return sum;
}

static const char *VERTS = "v a =\n p 0 0 0\nv b =\n p 1.25 0 0\nv c =\n p 0 2.5 0\n";

TEST(mgf_entities_and_contexts)
{
    char text[1024];
    /* a quad, a vertex redefined after use (later faces see the new point),
     * an alias made with `v id = template`, continuation lines, comments */
    snprintf(text, sizeof text,
             "# comment\n%s v d =\n p 1.25 2.5 0\nm grey =\n sides 1\n c\n rd .4\n ed 1\n"
             "f a b d \\\r\n  c\r\nv e = a\np 0 0 1\nf e b c\nv a\n p 0 0 2\nf a b c\n",
             VERTS);
    rad_scene *s = load_text("ent.mgf", text, NULL);
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 4);
    CHECK(rad_scene_warning_count(s) == 0);
    double c[3], n[3], quad = 0;
    for (int t = 0; t < 2; t++) {
        centroid_normal(s, t, c, n);
        quad += 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    }
    CHECK_NEAR(quad, 1.25 * 2.5, 1e-15, 0); /* the continued line: a b d c */
    centroid_normal(s, 2, c, n);
    CHECK_NEAR(c[2], 1.0 / 3, 1e-15, 0); /* e = a moved to z = 1 */
    centroid_normal(s, 3, c, n);
    CHECK_NEAR(c[2], 2.0 / 3, 1e-15, 0); /* a moved to z = 2 after its first use */
    CHECK(n[2] > 0);                     /* right-hand rule: a b c faces +z */
    CHECK_NEAR(rad_scene_materials(s)[rad_scene_triangle_materials(s)[0]].rho[1], 0.4, 0, 0);
    rad_scene_destroy(s);
}

TEST(mgf_transforms_nested_and_arrays)
{
    char text[2048];
    /* xf -t then nested -rz 90 -s 2: inner first, so b = (1.25,0,0) -> (0,2.5,0)
     * -> + (10,0,0); a 3 x 2 array; a mirror, which keeps the front side. */
    snprintf(text, sizeof text,
             "%sm w =\n sides 1\n rd .5\n"
             "xf -t 10 0 0\nxf -rz 90 -s 2\nf a b c\nxf\nxf\n"
             "xf -t 0 0 5 -a 3 -t 1 0 0 -a 2 -t 0 0 1\nf a b c\nxf\n"
             "xf -mx\nf a b c\nxf\n"
             "xf -i 3 -t 0 1 0\nf a b c\nxf\n",
             VERTS);
    rad_scene *s = load_text("xf.mgf", text, NULL);
    if (!s)
        return;
    CHECK(rad_scene_triangle_count(s) == 1 + 6 + 1 + 1);
    if (rad_scene_triangle_count(s) != 9) {
        rad_scene_destroy(s);
        return;
    }
    const double *b = corner(s, 0, 1), *cc = corner(s, 0, 2);
    CHECK_NEAR(b[0], 10, 1e-15, 1e-15);
    CHECK_NEAR(b[1], 2.5, 1e-15, 1e-15);
    CHECK_NEAR(cc[0], 10 - 5, 1e-15, 1e-15); /* c = (0,2.5) -> (-2.5,0) x 2 */
    CHECK_NEAR(cc[1], 0, 0, 1e-15);
    /* the array: instance (i, j) at (i, 0, 5 + j), in order i outer, j inner */
    int t = 1;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 2; j++, t++) {
            const double *a = corner(s, t, 0);
            CHECK_NEAR(a[0], i, 0, 1e-15);
            CHECK_NEAR(a[2], 5 + j, 0, 1e-15);
        }
    double c[3], n[3];
    centroid_normal(s, 7, c, n);
    CHECK(c[0] < 0);   /* mirrored into x < 0 */
    CHECK(n[2] > 0);   /* and still facing +z: a mirror reverses the corners' order */
    centroid_normal(s, 8, c, n);
    CHECK_NEAR(c[1], 2.5 / 3 + 3, 1e-15, 0); /* -i 3 -t 0 1 0 */
    rad_scene_destroy(s);
}

static void write_at(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    CHECK_MSG(f && fputs(text, f) >= 0, "cannot write %s", path);
    if (f)
        fclose(f);
}

TEST(mgf_includes_relative_with_transforms)
{
    char dir[512], sub[600], path[700], text[1024];
    snprintf(dir, sizeof dir, "%s", harness_temp_path("mgfinc"));
    snprintf(sub, sizeof sub, "%s/parts", dir);
    mkdir(dir, 0700);
    mkdir(sub, 0700);
    /* top -> parts/one.mgf (with -t) -> two.mgf, found beside one.mgf */
    snprintf(text, sizeof text, "%sm w =\n sides 1\n rd .5\ni parts/one.mgf -t 0 0 3 -a 2 -t 0 0 1\n", VERTS);
    snprintf(path, sizeof path, "%s/top.mgf", dir);
    write_at(path, text);
    char one[700], two[700];
    snprintf(one, sizeof one, "%s/one.mgf", sub);
    snprintf(two, sizeof two, "%s/two.mgf", sub);
    write_at(one, "f a b c\ni two.mgf\n");
    write_at(two, "xf -t 7 0 0\nf a b c\nxf\n");
    rad_scene *s = NULL;
    rad_status st = rad_scene_load(path, NULL, &s);
    CHECK_MSG(st == RAD_OK, "%s", rad_error_message());
    if (s) {
        CHECK(rad_scene_triangle_count(s) == 4);
        if (rad_scene_triangle_count(s) == 4) {
            CHECK_NEAR(corner(s, 0, 0)[2], 3, 0, 0);
            CHECK_NEAR(corner(s, 1, 0)[0], 7, 0, 0);
            CHECK_NEAR(corner(s, 1, 0)[2], 3, 0, 0);
            CHECK_NEAR(corner(s, 3, 0)[2], 4, 0, 0);
        }
        rad_scene_destroy(s);
    }
    /* an error inside an include names the included file and its line */
    write_at(two, "f a b c\nf a nowhere c\n");
    char needle[800];
    snprintf(needle, sizeof needle, "%s:2: undefined vertex 'nowhere'", two);
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){path, NULL}, needle);
    remove(two);
    remove(one);
    remove(path);
    rmdir(sub);
    rmdir(dir);
}

TEST(mgf_include_depth_and_loops)
{
    /* a chain of 18 files: deeper than the limit of 16 */
    char name[64], next[64], text[256], needle[700];
    for (int k = 0; k < 18; k++) {
        snprintf(name, sizeof name, "deep%d.mgf", k);
        snprintf(next, sizeof next, "radkit-test-%ld-deep%d.mgf", (long)getpid(), k + 1);
        snprintf(text, sizeof text, "# level %d\ni %s\n", k, next);
        harness_write_file(name, text);
    }
    snprintf(needle, sizeof needle, "%s:2: includes nest more than 16 deep", harness_temp_path("deep16.mgf"));
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){harness_temp_path("deep0.mgf"), NULL}, needle);
    for (int k = 0; k < 18; k++) {
        snprintf(name, sizeof name, "deep%d.mgf", k);
        remove(harness_temp_path(name));
    }
    /* a loop through two files */
    snprintf(text, sizeof text, "%sm w =\nrd .5\nf a b c\ni radkit-test-%ld-loop2.mgf\n", VERTS, (long)getpid());
    const char *p1 = harness_write_file("loop1.mgf", text);
    snprintf(text, sizeof text, "\n\ni radkit-test-%ld-loop1.mgf\n", (long)getpid());
    const char *p2 = harness_write_file("loop2.mgf", text);
    snprintf(needle, sizeof needle, "%s:3: include loop", p2);
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){p1, NULL}, needle);
    /* a file including itself */
    snprintf(text, sizeof text, "i radkit-test-%ld-self.mgf\n", (long)getpid());
    const char *p3 = harness_write_file("self.mgf", text);
    snprintf(needle, sizeof needle, "%s:1: include loop", p3);
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){p3, NULL}, needle);
    /* an include bomb: 17 files each including the next 4 times (4^16 reads) */
    for (int k = 0; k < 17; k++) {
        snprintf(name, sizeof name, "bomb%d.mgf", k);
        snprintf(next, sizeof next, "radkit-test-%ld-bomb%d.mgf", (long)getpid(), k + 1);
        if (k < 16)
            snprintf(text, sizeof text, "i %s\ni %s\ni %s\ni %s\n", next, next, next, next);
        else
            snprintf(text, sizeof text, "# the end\n");
        harness_write_file(name, text);
    }
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){harness_temp_path("bomb0.mgf"), NULL},
                               "more than 65536 file reads");
    for (int k = 0; k < 17; k++) {
        snprintf(name, sizeof name, "bomb%d.mgf", k);
        remove(harness_temp_path(name));
    }
    /* a missing include names the line that asks for it */
    const char *p4 = harness_write_file("missing.mgf", "\ni no-such-file.mgf\n");
    snprintf(needle, sizeof needle, "%s:2: cannot include", p4);
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){p4, NULL}, needle);
    remove(p1);
    remove(p2);
    remove(p3);
    remove(p4);
}

/* RGB -> XYZ of Radiance's primaries with equal-energy white, built here from
 * the chromaticities alone (the test's own derivation): column c is primary c's
 * (x/y, 1, z/y) times its luminance S_c, where S solves sum_c S_c (x/y, 1, z/y)_c
 * = (1, 1, 1). */
static void forward_matrix(double M[3][3])
{
    const double xy[3][2] = {{0.640, 0.330}, {0.290, 0.600}, {0.150, 0.060}};
    double P[3][4];
    for (int c = 0; c < 3; c++) {
        P[0][c] = xy[c][0] / xy[c][1];
        P[1][c] = 1;
        P[2][c] = (1 - xy[c][0] - xy[c][1]) / xy[c][1];
    }
    for (int i = 0; i < 3; i++)
        P[i][3] = 1;
    /* Gauss-Jordan on [P | 1] */
    for (int k = 0; k < 3; k++) {
        int piv = k;
        for (int i = k + 1; i < 3; i++)
            if (fabs(P[i][k]) > fabs(P[piv][k]))
                piv = i;
        for (int j = 0; j < 4; j++) {
            double t = P[k][j];
            P[k][j] = P[piv][j];
            P[piv][j] = t;
        }
        for (int i = 0; i < 3; i++)
            if (i != k) {
                double f = P[i][k] / P[k][k];
                for (int j = 0; j < 4; j++)
                    P[i][j] -= f * P[k][j];
            }
    }
    double S[3];
    for (int c = 0; c < 3; c++)
        S[c] = P[c][3] / P[c][c];
    for (int c = 0; c < 3; c++) {
        M[0][c] = xy[c][0] / xy[c][1] * S[c];
        M[1][c] = S[c];
        M[2][c] = (1 - xy[c][0] - xy[c][1]) / xy[c][1] * S[c];
    }
}

static const rad_scene_material *material_named(const rad_scene *s, const char *name)
{
    for (int m = 0; m < rad_scene_material_count(s); m++)
        if (strcmp(rad_scene_materials(s)[m].name, name) == 0)
            return &rad_scene_materials(s)[m];
    CHECK_MSG(0, "no material %s", name);
    return NULL;
}

TEST(mgf_colour_conversion)
{
    char text[2048];
    snprintf(text, sizeof text,
             "%s"
             "m grey =\n c\n rd .6375\n"
             "m tinted =\n c\n cxy .4 .4\n rd .2\n c\n ed 10\n"
             "m glow =\n c\n cxy 0.45 0.41\n ed 12.5\n"
             "c redc =\n cxy .64 .33\nc bluec =\n cxy .15 .06\n"
             "m mix =\n c mixed =\n cmix 1 redc 3 bluec\n rd .02\n"
             "m grey\nf a b c\nm tinted\nf a b c\nm glow\nf a b c\nm mix\nf a b c\n",
             VERTS);
    rad_scene *s = load_text("colour.mgf", text, NULL);
    if (!s)
        return;
    const rad_scene_material *g = material_named(s, "grey"), *t = material_named(s, "tinted"),
                             *e = material_named(s, "glow"), *m = material_named(s, "mix");
    if (g && t && e && m) {
        /* neutral: every channel exactly rd */
        for (int k = 0; k < 3; k++)
            CHECK(g->rho[k] == 0.6375 && t->emission[k] == 10.0);
        /* hand computation (Python, the same primaries): xy (0.4, 0.4), Y 0.2 */
        CHECK_NEAR(t->rho[0], 0.2398463227222832, 1e-14, 0);
        CHECK_NEAR(t->rho[1], 0.1956178444532175, 1e-14, 0);
        CHECK_NEAR(t->rho[2], 0.08227848101265817, 1e-14, 0);
        /* independently: the forward matrix takes rgb back to the chromaticity */
        double M[3][3], xyz[3];
        forward_matrix(M);
        for (int i = 0; i < 3; i++)
            xyz[i] = M[i][0] * e->emission[0] + M[i][1] * e->emission[1] + M[i][2] * e->emission[2];
        double sum = xyz[0] + xyz[1] + xyz[2];
        CHECK_NEAR(xyz[1], 12.5, 1e-13, 0);
        CHECK_NEAR(xyz[0] / sum, 0.45, 1e-13, 0);
        CHECK_NEAR(xyz[1] / sum, 0.41, 1e-13, 0);
        /* cmix of the red and blue primaries, weights = luminances: pure R and B,
         * R : B luminance 1 : 3, total Y = rd */
        CHECK_NEAR(m->rho[1], 0, 0, 1e-12);
        CHECK_NEAR(M[1][0] * m->rho[0], 0.02 * 0.25, 1e-12, 0);
        CHECK_NEAR(M[1][2] * m->rho[2], 0.02 * 0.75, 1e-12, 0);
    }
    rad_scene_destroy(s);
    /* out of gamut and white: loaded, clamped, one warning each; strict refuses */
    snprintf(text, sizeof text, "%sm sat =\n c\n cxy .1 .8\n rd .5\nm white =\n c\n rd 1\n"
             "m sat\nf a b c\nm white\nf a c b\n", VERTS);
    s = load_text("gamut.mgf", text, NULL);
    if (s) {
        const rad_scene_material *sat = material_named(s, "sat"), *w = material_named(s, "white");
        CHECK(sat && sat->rho[0] == 0 && sat->rho[2] == 0 && sat->rho[1] > 0);
        CHECK(w && w->rho[0] == 0.999 && w->rho[2] == 0.999);
        int found = 0;
        for (int i = 0; i < rad_scene_warning_count(s); i++)
            found += strstr(rad_scene_warning(s, i), "1 material(s) (first 'sat', used at ") != NULL ||
                     strstr(rad_scene_warning(s, i), "1 material(s) (first 'white', used at ") != NULL;
        CHECK(found == 2);
        rad_scene_destroy(s);
    }
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.strict = 1;
    const char *path = harness_write_file("gamut.mgf", text);
    CHECK(rad_scene_load(path, &p, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "gamut.mgf:15: material 'sat'") != NULL);
    remove(path);
}

typedef struct shape_case {
    const char *name, *text;
    double exact;
} shape_case;

TEST(mgf_curved_primitives_converge)
{
    const double pi = RAD_PI, r = 0.7351;
    /* centre (0.3, -0.2, 1.1), normal along (1, 2, 2)/3 for ring and torus */
    const char *base = "m w =\n sides 1\n rd .5\nv c =\n p 0.3 -0.2 1.1\n n 1 2 2\nv top =\n p 0.3 1.7 1.1\n"
                       "v p1 =\n p 0 0 0\nv p2 =\n p 1.5 0 0\nv p3 =\n p 1.5 0.8 0\nv p4 =\n p 0 0.8 0\n";
    double slant = sqrt(1.9 * 1.9 + (0.9 - 0.2) * (0.9 - 0.2));
    shape_case cases[] = {
        {"sphere", "sph c 0.7351\n", 4 * pi * r * r},
        {"inward sphere", "sph c -0.7351\n", 4 * pi * r * r},
        {"cylinder", "cyl c 0.7351 top\n", 2 * pi * r * 1.9},
        {"cone", "cone c 0.9 top 0.2\n", pi * (0.9 + 0.2) * slant},
        {"apex cone", "cone c 0.9 top 0\n", pi * 0.9 * sqrt(1.9 * 1.9 + 0.81)},
        {"ring", "ring c 0.25 0.7351\n", pi * (r * r - 0.0625)},
        {"disc", "ring c 0 0.7351\n", pi * r * r},
        {"torus", "torus c 0.3 0.7351\n", 4 * pi * pi * (0.3 + r) / 2 * (r - 0.3) / 2},
        {"prism", "prism p1 p2 p3 p4 0.45\n", 2 * 1.5 * 0.8 + 2 * (1.5 + 0.8) * 0.45},
    };
    const double tols[3] = {1e-2, 1e-3, 1e-4};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        double err[3];
        for (int i = 0; i < 3; i++) {
            char text[1024];
            snprintf(text, sizeof text, "%s%s", base, cases[k].text);
            rad_scene_params p;
            rad_scene_params_default(&p);
            p.curve_tol = tols[i];
            rad_scene *s = load_text("curved.mgf", text, &p);
            if (!s)
                return;
            err[i] = (cases[k].exact - total_area(s)) / cases[k].exact;
            /* inscribed facets: never more area; within 4 x the tolerance */
            CHECK_MSG(err[i] >= -1e-13 && err[i] <= 4 * tols[i], "%s, tol %g: relative area error %g",
                      cases[k].name, tols[i], err[i]);
            /* orientation: facets face away from the centre of the solid (inward
             * for the negative radius); ring and disc face the vertex normal */
            int bad = 0;
            for (int t = 0; t < rad_scene_triangle_count(s); t++) {
                double c[3], n[3], o[3] = {0.3, -0.2, 1.1};
                centroid_normal(s, t, c, n);
                double d;
                if (strstr(cases[k].name, "ring") || strstr(cases[k].name, "disc"))
                    d = n[0] + 2 * n[1] + 2 * n[2];
                else if (strcmp(cases[k].name, "prism") == 0)
                    d = n[0] * (c[0] - 0.75) + n[1] * (c[1] - 0.4) + n[2] * (c[2] + 0.225);
                else if (strcmp(cases[k].name, "torus") == 0) {
                    /* away from the tube's centre circle */
                    double a[3] = {1.0 / 3, 2.0 / 3, 2.0 / 3}, q[3], h = 0, rq = 0;
                    for (int j = 0; j < 3; j++)
                        h += (c[j] - o[j]) * a[j];
                    for (int j = 0; j < 3; j++) {
                        q[j] = c[j] - o[j] - h * a[j];
                        rq += q[j] * q[j];
                    }
                    rq = sqrt(rq);
                    d = 0;
                    for (int j = 0; j < 3; j++)
                        d += n[j] * (c[j] - o[j] - q[j] / rq * (0.3 + r) / 2);
                } else {
                    double ax = 0, axis[3] = {0, 1, 0}; /* cyl/cone axis: +y from c */
                    if (strstr(cases[k].name, "sphere"))
                        axis[1] = 0;
                    for (int j = 0; j < 3; j++)
                        ax += (c[j] - o[j]) * axis[j];
                    d = 0;
                    for (int j = 0; j < 3; j++)
                        d += n[j] * (c[j] - o[j] - ax * axis[j]);
                }
                if (strcmp(cases[k].name, "inward sphere") == 0)
                    d = -d;
                bad += !(d > 0);
            }
            CHECK_MSG(bad == 0, "%s: %d facets face the wrong way", cases[k].name, bad);
            rad_scene_destroy(s);
        }
        if (strcmp(cases[k].name, "prism") == 0)
            CHECK_NEAR(err[0], 0, 0, 1e-14); /* flat: exact at any tolerance */
        else
            CHECK_MSG(err[2] < err[0] / 50, "%s: errors %g, %g, %g do not fall with the tolerance",
                      cases[k].name, err[0], err[1], err[2]);
    }
}

TEST(mgf_warnings_and_strict)
{
    char text[1024];
    snprintf(text, sizeof text,
             "%sm w =\n rd .5\n rs .1 .05\n sides 2\n c\n cct 3000\n rd .5\n"
             "frobnicate 1 2\nf a b c\nfrobnicate\nies lamp.ies -m 2\n",
             VERTS);
    rad_scene *s = load_text("warn.mgf", text, NULL);
    if (s) {
        /* specular, ies, unknown, two-sided, and no emitter */
        CHECK(rad_scene_warning_count(s) == 5);
        int unknown = 0, ies = 0, specular = 0;
        for (int i = 0; i < rad_scene_warning_count(s); i++) {
            const char *w = rad_scene_warning(s, i);
            unknown += strstr(w, "ignored 2 `frobnicate` statement(s) (first at") != NULL;
            ies += strstr(w, "1 `ies` statement(s) (first at ") != NULL &&
                   strstr(w, "warn.mgf:17): IES luminaires are not read: skipped with this "
                             "warning, as MGF asks of entities a reader does not support") != NULL;
            specular += strstr(w, "1 `rs` statement(s)") != NULL;
        }
        CHECK(unknown == 1 && ies == 1 && specular == 1);
        rad_scene_destroy(s);
    }
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.strict = 1;
    const char *path = harness_write_file("warn.mgf", text);
    rad_scene *t = NULL;
    CHECK(rad_scene_load(path, &p, &t) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "warn.mgf:14: `frobnicate`") != NULL);
    remove(path);
}

typedef struct bad_case {
    const char *text, *needle;
} bad_case;

TEST(mgf_bad_input_exits_2_with_file_line)
{
    const bad_case cases[] = {
        {"v a =\n p 0 0 0\nf a b a\n", ":3: undefined vertex 'b'"},
        {"v a =\n p 0 0 1e400\n", ":2: coordinate is infinite"},
        {"v a =\n p 0 0 nan\n", ":2: coordinate is NaN"},
        {"v a =\n p 0 0.x 0\n", ":2: coordinate '0.x' is not a number"},
        {"v a =\n p 0 0\n", ":2: `p` takes 3 arguments, got 2"},
        {"\nxf -t 1 0 0\nv a =\n", ":2: `xf` is not ended in this file"},
        {"o box\n o lid\n o\n", ":1: object `o` is not ended in this file"},
        {"\n\nxf\n", ":3: `xf` ends a transform, but none is open"},
        {"o\n", ":1: `o` ends an object, but none is open"},
        {"xf -t 1 0\n", ":1: `-t` needs 3 numbers"},
        {"xf -rq 5\n", ":1: unknown transform argument '-rq'"},
        {"xf -a 0 -t 1 0 0\n", ":1: array count 0 is out of range"},
        {"xf -a 1000 -a 1001\n", ":1: arrays of more than 1000000 instances"},
        {"m nothing\n", ":1: undefined material 'nothing'"},
        {"c\ncmix 1 nowhere\n", ":2: undefined colour 'nowhere'"},
        {"m x =\n rd 1.5\n", ":2: diffuse reflectance 1.5 is outside [0, 1]"},
        {"m x =\n ed -1\n", ":2: negative emittance -1"},
        {"c\n cxy .7 .5\n", ":2: chromaticity 0.7 0.5"},
        {"c\n cspec 700 400 1 1\n", ":2: wavelengths 700 .. 400 nm"},
        {"c\n cspec 400 700 1 -1\n", ":2: negative spectral value -1"},
        {"c\n cspec 900 1000 1 1\n", ":2: the spectrum is dark"},
        {"c\n cspec 400 700 1\n", ":2: `cspec` takes"},
        {"c\n cct -5\n", ":2: colour temperature -5 K"},
        {"c\n cct 20\n", ":2: colour temperature 20 K"},
        {"v a =\n p 0 0 0\nring a 0 1\n", ":3: `ring` needs a normal at vertex 'a'"},
        {"v a =\n p 0 0 0\nv b = a\nf a b\n", ":4: `f` needs at least 3 vertices"},
        {"v a =\n p 0 0 0\nsph a 0\n", ":3: a sphere of radius 0"},
        {"v a =\np 0 0 0\nv b =\np 1 0 0\nv c =\np 1 1 0\nv d =\np 0 1 0\nf a c b d\n",
         ":9: face 0 is a self-intersecting polygon"},
        {"v a =\n p 0 0 0\n", ": no faces"},
        {"i\n", ":1: `i` needs a file name"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const char *path = harness_write_file("bad.mgf", cases[k].text);
        char needle[700];
        snprintf(needle, sizeof needle, "%s%s", path, cases[k].needle);
        HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){path, NULL}, needle);
        remove(path);
    }
    /* a NUL byte and an over-long line */
    const char *path = harness_temp_path("nul.mgf");
    FILE *f = fopen(path, "wb");
    if (f) {
        fwrite("# ok\nv a\0 =\n", 1, 12, f);
        fclose(f);
    }
    char needle[700];
    snprintf(needle, sizeof needle, "%s:2: a NUL byte", path);
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){path, NULL}, needle);
    remove(path);
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.max_line_bytes = 16;
    path = harness_write_file("long.mgf", "# short\n# a comment that is far too long\n");
    rad_scene *s = NULL;
    CHECK(rad_scene_load(path, &p, &s) == RAD_EINPUT);
    CHECK(strstr(rad_error_message(), "long.mgf:2: the line is longer than 16 bytes") != NULL);
    p = (rad_scene_params){0};
    rad_scene_params_default(&p);
    p.curve_tol = 0;
    CHECK(rad_scene_load(path, &p, &s) == RAD_EINVAL);
    remove(path);
}

TEST(mgf_cornell_twin_same_answers)
{
    char *out[2] = {NULL, NULL}, *err[2] = {NULL, NULL};
    const char *scenes[2] = {harness_path("scenes/mgf/cornell.mgf"),
                             harness_path("scenes/mgf/cornell_twin.obj")};
    enum { MAXF = 64 };
    double B[2][3 * MAXF];
    int n[2];
    for (int k = 0; k < 2; k++) {
        int rc = harness_radkit_run("solve", (const char *const[]){scenes[k], NULL}, &out[k], &err[k]);
        CHECK_MSG(rc == 0, "radkit solve %s: %s", scenes[k], err[k] ? err[k] : "");
        n[k] = out[k] ? harness_face_table(out[k], B[k], MAXF) : -1;
    }
    CHECK(n[0] == 38 && n[1] == 38);
    for (int f = 0; n[0] == 38 && n[1] == 38 && f < 3 * 38; f++)
        CHECK_NEAR(B[0][f], B[1][f], 1e-12, 1e-15);
    /* the light is the only emitter, and something is lit */
    CHECK(n[0] == 38 && B[0][3 * 10] > 1);
    for (int k = 0; k < 2; k++) {
        free(out[k]);
        free(err[k]);
    }
}

static double flat(double nm, void *ctx)
{
    (void)nm;
    (void)ctx;
    return 1.0;
}

static double narrow_550(double nm, void *ctx)
{
    (void)ctx;
    return fabs(nm - 550.0) < 1.0 ? 1.0 : 0.0;
}

/* The CIE 1931 chromaticities of cie.c against the tabulated observer's:
 * illuminant A (a blackbody at 2856 K) is (0.44757, 0.40745), the
 * equal-energy spectrum (1/3, 1/3), the spectral locus at 550 nm (0.30160,
 * 0.69232) (CIE 15:2004).  The fit's far red is weak: light at 700 nm alone
 * comes out at x = 0.57 (0.73 tabulated); broad spectra do not notice. */
TEST(mgf_spectral_colours_match_the_cie_observer)
{
    double x = 0, y = 0;
    CHECK(scene_cie_xy_blackbody(2856.0, &x, &y));
    printf("# illuminant A: (%.5f, %.5f), tabulated (0.44757, 0.40745)\n", x, y);
    CHECK_MSG(fabs(x - 0.44757) < 3e-3 && fabs(y - 0.40745) < 3e-3, "A: %g %g", x, y);
    CHECK(scene_cie_xy(flat, NULL, &x, &y));
    printf("# equal-energy white: (%.5f, %.5f)\n", x, y);
    CHECK_MSG(fabs(x - 1.0 / 3) < 3e-3 && fabs(y - 1.0 / 3) < 3e-3, "E: %g %g", x, y);
    CHECK(scene_cie_xy(narrow_550, NULL, &x, &y));
    printf("# 550 nm: (%.5f, %.5f), tabulated (0.30160, 0.69232)\n", x, y);
    CHECK_MSG(fabs(x - 0.30160) < 5e-3 && fabs(y - 0.69232) < 5e-3, "550 nm: %g %g", x, y);
    CHECK(!scene_cie_xy_blackbody(-1.0, &x, &y));
    /* in a scene: a warm blackbody reflects red above green above blue, a
       flat spectrum as neutral as cxy 1/3 1/3 */
    char text[512];
    snprintf(text, sizeof text,
             "%sm warm =\n sides 1\n c\n cct 2856\n rd .5\nf a b c\nm flat =\n sides 1\n c\n cspec 380 780 1 1 1\n"
             " rd .5\n ed 1\nf a c b\n",
             VERTS);
    rad_scene *s = load_text("spectral.mgf", text, NULL);
    if (s) {
        const rad_scene_material *w = &rad_scene_materials(s)[rad_scene_triangle_materials(s)[0]];
        const rad_scene_material *f = &rad_scene_materials(s)[rad_scene_triangle_materials(s)[1]];
        printf("# cct 2856, rd .5: rgb %.3f %.3f %.3f; flat cspec: %.3f %.3f %.3f\n", w->rho[0],
               w->rho[1], w->rho[2], f->rho[0], f->rho[1], f->rho[2]);
        CHECK(w->rho[0] > w->rho[1] && w->rho[1] > w->rho[2]);
        for (int k = 0; k < 3; k++)
            CHECK_NEAR(f->rho[k], 0.5, 2e-2, 0);
        rad_scene_destroy(s);
    }
}

/* ---- faces with holes (fh), two-sided materials, --curve-tol, places in includes ---- */

/* Vertices of a plane figure: name x y per point, at z = 0. */
static void add_points2(char *text, size_t size, const char *const *name, const double (*xy)[2],
                        int n)
{
    for (int k = 0; k < n; k++) {
        size_t at = strlen(text);
        snprintf(text + at, size - at, "v %s =\n p %.17g %.17g 0\n", name[k], xy[k][0], xy[k][1]);
    }
}

static int lines_in(const char *text)
{
    int n = 0;
    for (; *text; text++)
        n += *text == '\n';
    return n;
}

/* Is p strictly inside the axis-aligned box lo..hi (x, y)? */
static int in_box(const double *p, double x0, double y0, double x1, double y1)
{
    return p[0] > x0 && p[0] < x1 && p[1] > y0 && p[1] < y1;
}

TEST(mgf_faces_with_holes_area_and_triangles)
{
    static const char *const names[8] = {"o1", "o2", "o3", "o4", "h1", "h2", "h3", "h4"};
    const double sq[8][2] = {{0, 0}, {2.9, 0}, {2.9, 2.9}, {0, 2.9},
                             {0.7, 0.7}, {1.85, 0.7}, {1.85, 1.85}, {0.7, 1.85}};
    const double exact = 2.9 * 2.9 - 1.15 * 1.15;
    /* the hole in either winding: the same face */
    const char *faces[2] = {"fh o1 o2 o3 o4 - h1 h2 h3 h4\n", "fh o1 o2 o3 o4 - h4 h3 h2 h1\n"};
    for (int w = 0; w < 2; w++) {
        char text[4096] = "m w =\n sides 1\n rd .5\n";
        add_points2(text, sizeof text, names, sq, 8);
        strcat(text, faces[w]);
        rad_scene *s = load_text("holes.mgf", text, NULL);
        if (!s)
            return;
        /* 8 corners, one hole: a triangulation of the annulus has 8 + 2 - 2 triangles */
        CHECK_MSG(rad_scene_triangle_count(s) == 8, "%d triangles", rad_scene_triangle_count(s));
        CHECK_NEAR(total_area(s), exact, 1e-14, 0);
        CHECK(rad_scene_warning_count(s) == 1); /* no emitter */
        for (int t = 0; t < rad_scene_triangle_count(s); t++) {
            double c[3], n[3];
            centroid_normal(s, t, c, n);
            CHECK_MSG(n[2] > 0, "triangle %d does not face +z", t);
            CHECK_MSG(!in_box(c, 0.7, 0.7, 1.85, 1.85), "triangle %d lies in the hole", t);
        }
        rad_scene_destroy(s);
    }
    /* nine holes in a grid, alternate windings: every hole bridged, to the
     * outer ring or to a hole joined before it */
    {
        char text[16384] = "m w =\n sides 1\n rd .5\n";
        const double outer[4][2] = {{0, 0}, {3.1, 0}, {3.1, 3.1}, {0, 3.1}};
        add_points2(text, sizeof text, names, outer, 4);
        char line[2048] = "fh o1 o2 o3 o4";
        double exact9 = 3.1 * 3.1, side = 0.55;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double x0 = 0.3 + i * 1.0, y0 = 0.35 + j * 0.97;
                double xy[4][2] = {{x0, y0}, {x0 + side, y0}, {x0 + side, y0 + side}, {x0, y0 + side}};
                char nm[4][16];
                const char *np[4];
                for (int k = 0; k < 4; k++) {
                    int kk = (i + j) % 2 ? 3 - k : k;
                    snprintf(nm[k], sizeof nm[k], "g%d%d%d", i, j, kk);
                    np[k] = nm[k];
                }
                double ordered[4][2];
                for (int k = 0; k < 4; k++)
                    memcpy(ordered[k], xy[(i + j) % 2 ? 3 - k : k], sizeof ordered[k]);
                add_points2(text, sizeof text, np, (const double(*)[2])ordered, 4);
                size_t at = strlen(line);
                snprintf(line + at, sizeof line - at, " - %s %s %s %s", np[0], np[1], np[2], np[3]);
                exact9 -= side * side;
            }
        strcat(line, "\n");
        strcat(text, line);
        rad_scene *s = load_text("grid.mgf", text, NULL);
        if (s) {
            CHECK_MSG(rad_scene_triangle_count(s) == 40 + 2 * 9 - 2, "%d triangles",
                      rad_scene_triangle_count(s));
            CHECK_NEAR(total_area(s), exact9, 1e-13, 0);
            for (int t = 0; t < rad_scene_triangle_count(s); t++) {
                double c[3], n[3];
                centroid_normal(s, t, c, n);
                CHECK_MSG(n[2] > 0, "grid: triangle %d does not face +z", t);
            }
            rad_scene_destroy(s);
        }
    }
    /* a non-convex outer contour (an L) with a triangular hole and a square
     * one, in a tilted plane under a mirror: area, count, one orientation */
    {
        static const char *const ln[13] = {"a1", "a2", "a3", "a4", "a5", "a6",
                                           "t1", "t2", "t3", "q1", "q2", "q3", "q4"};
        const double L[13][2] = {{0, 0}, {2.3, 0}, {2.3, 0.9}, {0.95, 0.9}, {0.95, 2.6}, {0, 2.6},
                                 {0.2, 0.15}, {1.9, 0.2}, {0.4, 0.7},
                                 {0.25, 1.2}, {0.7, 1.2}, {0.7, 2.2}, {0.25, 2.2}};
        double exact_l = 2.3 * 0.9 + 0.95 * 1.7 - 0.5 * fabs((1.9 - 0.2) * (0.7 - 0.15) -
                                                              (0.4 - 0.2) * (0.2 - 0.15)) -
                         0.45 * 1.0;
        char text[4096] = "m w =\n sides 1\n rd .5\nxf -rx 37 -ry -21 -mz -t 0.3 0.1 2\n";
        add_points2(text, sizeof text, ln, L, 13);
        strcat(text, "fh a1 a2 a3 a4 a5 a6 - t1 t2 t3 - q1 q2 q3 q4\nxf\n");
        rad_scene *s = load_text("tilted.mgf", text, NULL);
        if (s) {
            CHECK_MSG(rad_scene_triangle_count(s) == 13 + 2 * 2 - 2, "%d triangles",
                      rad_scene_triangle_count(s));
            CHECK_NEAR(total_area(s), exact_l, 1e-13, 0);
            double c[3], n0[3], n[3];
            centroid_normal(s, 0, c, n0);
            for (int t = 1; t < rad_scene_triangle_count(s); t++) {
                centroid_normal(s, t, c, n);
                CHECK_MSG(n[0] * n0[0] + n[1] * n0[1] + n[2] * n0[2] > 0,
                          "tilted: triangle %d faces the other way", t);
            }
            rad_scene_destroy(s);
        }
    }
}

TEST(mgf_faces_with_holes_bad_input)
{
    static const char *const names[20] = {"a", "b", "c", "d", "e", "f", "g", "x", "y", "z",
                                          "p1", "p2", "p3", "p4", "r1", "r2", "r3", "r4", "s1", "s2"};
    const double xy[20][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {0.5, 0.5}, {1, 0.5}, {0.5, 1},
                              {3, 3}, {4, 3}, {3, 4},
                              /* two holes whose edges cross, no corner inside the other */
                              {0.1, 0.5}, {1.5, 0.5}, {1.5, 0.8}, {0.1, 0.8},
                              {0.8, 0.3}, {1.1, 0.3}, {1.1, 1.9}, {0.8, 1.9},
                              /* a hole inside the hole e f g */
                              {0.55, 0.55}, {0.7, 0.55}};
    char prefix[4096] = "m w =\n sides 1\n rd .5\n";
    add_points2(prefix, sizeof prefix, names, xy, 20);
    strcat(prefix, "v s3 =\n p 0.55 0.7 0\n");
    const bad_case cases[] = {
        {"fh a b c d - e f\n", "`fh`: hole 1 has 2 vertices; it needs at least 3"},
        {"fh a b c d - e f g - e f\n", "`fh`: hole 2 has 2 vertices"},
        {"fh a b - e f g\n", "`fh`: the outer contour has 2 vertices"},
        {"fh a b c d - e f nowhere\n", "undefined vertex 'nowhere'"},
        {"fh - a b c d\n", "`fh`: a stray `-` (argument 1)"},
        {"fh a b c d - - e f g\n", "`fh`: a stray `-` (argument 6)"},
        {"fh a b c d - e f g -\n", "`fh`: a stray `-` (argument 9)"},
        {"fh\n", "`fh` needs at least 3 vertices, got 0"},
        {"fh a b c d - x y z\n", "face 0 has a hole that is not inside its outer contour"},
        {"fh a b c d - p1 p2 p3 p4 - r1 r2 r3 r4\n", "face 0 has contours that cross each other"},
        {"fh a b c d - e f g - s1 s2 s3\n", "face 0 has a hole inside another hole"},
        {"fh a b c d - a b c d\n", "face 0 has a hole that is not inside its outer contour"},
    };
    int line = lines_in(prefix) + 1;
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char text[8192];
        snprintf(text, sizeof text, "%s%s", prefix, cases[k].text);
        const char *path = harness_write_file("badfh.mgf", text);
        char needle[800];
        snprintf(needle, sizeof needle, "%s:%d: %s", path, line, cases[k].needle);
        HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){path, NULL}, needle);
        remove(path);
    }
}

/* A floor, a light above it and, between them, a two-sided plate with a
 * hole through which the light reaches the floor. */
static const char *const PLATE_SCENE =
    "m floor =\n sides 1\n rd .55\nm light =\n sides 1\n rd .2\n ed 12\nm plate =\n rd .63\n"
    "v f1 =\n p 0 0 0\nv f2 =\n p 1.2 0 0\nv f3 =\n p 1.2 1.1 0\nv f4 =\n p 0 1.1 0\n"
    "v l1 =\n p 0.2 0.15 1.05\nv l2 =\n p 0.2 0.95 1.05\nv l3 =\n p 1.0 0.95 1.05\n"
    "v l4 =\n p 1.0 0.15 1.05\n"
    "v o1 =\n p 0 0 0.5\nv o2 =\n p 1.2 0 0.5\nv o3 =\n p 1.2 1.1 0.5\nv o4 =\n p 0 1.1 0.5\n"
    "v h1 =\n p 0.31 0.28 0.5\nv h2 =\n p 0.83 0.28 0.5\nv h3 =\n p 0.83 0.71 0.5\n"
    "v h4 =\n p 0.31 0.71 0.5\n"
    "m floor\nf f1 f2 f3 f4\nm light\nf l1 l2 l3 l4\nm plate\n";

/* The plate written with `fh` and as eight triangles of the annulus (a
 * triangulation of our own, not the reader's): `radkit solve` must give the
 * floor and the light the same radiosity, and each side of the plate the same
 * area-weighted mean, up to the difference of the two discretizations. */
TEST(mgf_faces_with_holes_solve_as_triangles)
{
    const char *plates[2] = {"fh o1 o2 o3 o4 - h1 h2 h3 h4\n",
                             "f o1 o2 h2\nf o1 h2 h1\nf o2 o3 h3\nf o2 h3 h2\n"
                             "f o3 o4 h4\nf o3 h4 h3\nf o4 o1 h1\nf o4 h1 h4\n"};
    enum { MAXF = 32 };
    double B[2][3 * MAXF], mean[2][2];
    int n[2] = {-1, -1};
    for (int k = 0; k < 2; k++) {
        char text[4096], *out = NULL, *err = NULL;
        snprintf(text, sizeof text, "%s%s", PLATE_SCENE, plates[k]);
        const char *path = harness_write_file(k ? "plate_tri.mgf" : "plate_fh.mgf", text);
        int rc = harness_radkit_run("solve", (const char *const[]){path, NULL}, &out, &err);
        CHECK_MSG(rc == 0, "radkit solve: %s", err ? err : "");
        n[k] = out ? harness_face_table(out, B[k], MAXF) : -1;
        rad_scene *s = NULL;
        CHECK(rad_scene_load(path, NULL, &s) == RAD_OK);
        /* plate rows: area-weighted mean of the green channel, by side */
        double sum[2] = {0, 0}, area[2] = {0, 0};
        for (int t = 4; s && t < rad_scene_triangle_count(s) && t < n[k]; t++) {
            double c[3], nn[3];
            centroid_normal(s, t, c, nn);
            double a = 0.5 * sqrt(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
            int up = nn[2] > 0;
            sum[up] += a * B[k][3 * t + 1];
            area[up] += a;
        }
        for (int side = 0; side < 2; side++) {
            CHECK_NEAR(area[side], 1.2 * 1.1 - 0.52 * 0.43, 1e-13, 0);
            mean[k][side] = area[side] > 0 ? sum[side] / area[side] : 0;
        }
        rad_scene_destroy(s);
        remove(path);
        free(out);
        free(err);
    }
    /* 2 + 2 triangles, and the plate's 8 on each side */
    CHECK(n[0] == 20 && n[1] == 20);
    if (n[0] != 20 || n[1] != 20)
        return;
    printf("# floor %.6f %.6f, light %.6f %.6f; plate top %.6f %.6f, bottom %.6f %.6f\n",
           B[0][1], B[1][1], B[0][7], B[1][7], mean[0][1], mean[1][1], mean[0][0], mean[1][0]);
    for (int f = 0; f < 4; f++)
        CHECK_NEAR(B[0][3 * f + 1], B[1][3 * f + 1], 2e-3, 0);
    for (int side = 0; side < 2; side++)
        CHECK_NEAR(mean[0][side], mean[1][side], 2e-3, 0);
    /* the floor is lit through the hole: well above what the plate's
     * underside alone gives it */
    CHECK(B[0][1] > 3 * mean[0][0] * 0.55);
}

TEST(mgf_two_sided_materials)
{
    char text[1024];
    /* sides 2 (stated, and the default): the face, then its back */
    const char *mats[3] = {"m w =\n sides 2\n rd .5\n", "m w =\n rd .5\n", ""};
    for (int k = 0; k < 3; k++) {
        snprintf(text, sizeof text, "%s%sf a b c\n", VERTS, mats[k]);
        rad_scene *s = load_text("two.mgf", text, NULL);
        if (!s)
            return;
        CHECK_MSG(rad_scene_triangle_count(s) == 2, "case %d: %d triangles", k,
                  rad_scene_triangle_count(s));
        if (rad_scene_triangle_count(s) == 2) {
            const int *t = rad_scene_triangles(s);
            CHECK(t[3] == t[2] && t[4] == t[1] && t[5] == t[0]); /* reversed */
            CHECK(rad_scene_triangle_materials(s)[0] == rad_scene_triangle_materials(s)[1]);
            double c[3], n0[3], n1[3];
            centroid_normal(s, 0, c, n0);
            centroid_normal(s, 1, c, n1);
            CHECK(n0[2] > 0 && n1[2] < 0);
        }
        /* one warning for the doubled faces (and none about coincident faces
         * back to back), and no emitter */
        int two = 0, coincident = 0;
        for (int i = 0; i < rad_scene_warning_count(s); i++) {
            const char *w = rad_scene_warning(s, i);
            two += strstr(w, "1 face(s) of two-sided materials (`sides 2`, MGF's default): each "
                             "face is made on both sides") != NULL &&
                   strstr(w, k == 2 ? "(first of '(unnamed)', at " : "(first of 'w', at ") != NULL;
            coincident += strstr(w, "back to back") != NULL;
        }
        CHECK_MSG(two == 1 && coincident == 0 && rad_scene_warning_count(s) == 2, "case %d", k);
        rad_scene_destroy(s);
    }
    /* sides 1: the face alone; two faces drawn back to back on purpose still
     * get scene_finish's warning */
    snprintf(text, sizeof text, "%sm w =\n sides 1\n rd .5\nf a b c\nf c b a\n", VERTS);
    rad_scene *s = load_text("one.mgf", text, NULL);
    if (s) {
        CHECK(rad_scene_triangle_count(s) == 2);
        int coincident = 0;
        for (int i = 0; i < rad_scene_warning_count(s); i++)
            coincident += strstr(rad_scene_warning(s, i), "back to back") != NULL;
        CHECK(coincident == 1);
        rad_scene_destroy(s);
    }
    /* A furnace: a closed box (inward, sides 1) with a tilted sheet inside,
     * every surface rho 0.5 and E 1, so B = E / (1 - rho) = 2 everywhere when
     * the sheet has both sides.  With `sides 1` its back is a black hole in
     * the enclosure and the walls facing it fall short. */
    const char *box =
        "m wall =\n sides 1\n rd .5\n"
        "v a =\n p 0 0 0\nv b =\n p 1.3 0 0\nv c =\n p 1.3 1.3 0\nv d =\n p 0 1.3 0\n"
        "v e =\n p 0 0 1.3\nv f =\n p 1.3 0 1.3\nv g =\n p 1.3 1.3 1.3\nv h =\n p 0 1.3 1.3\n"
        "f a b c d\nf e h g f\nf a e f b\nf b f g c\nf c g h d\nf d h e a\n"
        "v s1 =\n p 0.35 0.4 0.62\nv s2 =\n p 0.95 0.4 0.62\nv s3 =\n p 0.95 0.9 0.71\n"
        "v s4 =\n p 0.35 0.9 0.71\n";
    for (int sides = 1; sides <= 2; sides++) {
        char *out = NULL, *err = NULL;
        snprintf(text, sizeof text, "%sm sheet =\n sides %d\n rd .5\nf s1 s2 s3 s4\n", box, sides);
        const char *path = harness_write_file("furnace.mgf", text);
        int rc = harness_radkit_run("solve", (const char *const[]){path, "--rho", "0.5",
                                                                  "--emission", "1", NULL},
                                    &out, &err);
        CHECK_MSG(rc == 0, "radkit solve: %s", err ? err : "");
        enum { MAXF = 32 };
        double B[3 * MAXF], worst = 0;
        int n = out ? harness_face_table(out, B, MAXF) : -1;
        CHECK(n == 12 + 2 * sides);
        for (int f = 0; f < n; f++)
            worst = fmax(worst, fabs(B[3 * f + 1] - 2.0) / 2.0);
        printf("# furnace with a sheet of sides %d: worst face %.2e from B = 2\n", sides, worst);
        if (sides == 2)
            CHECK_MSG(worst < 2e-3, "two-sided sheet: worst %g", worst);
        else
            CHECK_MSG(worst > 2e-2, "one-sided sheet: worst %g", worst);
        remove(path);
        free(out);
        free(err);
    }
}

/* --curve-tol: a finer tolerance gives a sphere's area closer to 4 pi r^2;
 * a bad value exits 2 naming the option. */
TEST(mgf_curve_tol_option)
{
    const char *path = harness_write_file("sphere.mgf", "m w =\n sides 1\n rd .5\n ed 1\n"
                                                        "v c =\n p 0.2 -0.4 1.3\nsph c 0.6173\n");
    const double exact = 4 * RAD_PI * 0.6173 * 0.6173;
    const char *tols[3] = {NULL, "0.003", "0.0004"};
    double err[3] = {1, 1, 1};
    for (int k = 0; k < 3; k++) {
        char *out = NULL, *errs = NULL, buf[64];
        const char *args[4] = {path, k ? "--curve-tol" : NULL, tols[k], NULL};
        int rc = harness_radkit_run("info", args, &out, &errs);
        CHECK_MSG(rc == 0, "radkit info: %s", errs ? errs : "");
        const char *a = harness_header(out, "total_area", buf, sizeof buf);
        CHECK(a != NULL);
        if (a)
            err[k] = (exact - strtod(a, NULL)) / exact;
        free(out);
        free(errs);
    }
    printf("# sphere area shortfall: default %.3e, 0.003 %.3e, 0.0004 %.3e\n", err[0], err[1],
           err[2]);
    /* inscribed facets: short, within 4 tolerances, and falling */
    CHECK(err[0] > 0 && err[0] <= 4 * 0.0125);
    CHECK(err[1] > 0 && err[1] <= 4 * 0.003 && err[1] < err[0] / 3);
    CHECK(err[2] > 0 && err[2] <= 4 * 0.0004 && err[2] < err[1] / 5);
    const char *bad[4] = {"0", "1", "2e-7", "fine"};
    for (int k = 0; k < 4; k++) {
        char needle[128];
        snprintf(needle, sizeof needle, "info: --curve-tol must be a number in [1e-6, 1), got '%s'",
                 bad[k]);
        HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){path, "--curve-tol", bad[k], NULL},
                                   needle);
    }
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *const[]){path, "--curve-tol", "-0.01", NULL},
                               "solve: --curve-tol must be a number");
    remove(path);
}

/* Warnings and errors about the triangles of an included file name that
 * file and its line, not the scene file's. */
TEST(mgf_included_triangles_name_their_file)
{
    char dir[512], top[700], inc[700], text[1024], needle[900];
    snprintf(dir, sizeof dir, "%s", harness_temp_path("mgfplace"));
    mkdir(dir, 0700);
    snprintf(top, sizeof top, "%s/top.mgf", dir);
    snprintf(inc, sizeof inc, "%s/part.mgf", dir);
    snprintf(text, sizeof text, "%sm w =\n sides 1\n rd .5\n ed 1\nf a b c\ni part.mgf\nf a c b\n",
             VERTS);
    write_at(top, text);
    /* line 4 of the include: a degenerate triangle (a repeated corner) */
    write_at(inc, "# part\nv q =\n p 0 0 5\nf q q b\n");
    rad_scene *s = NULL;
    CHECK_MSG(rad_scene_load(top, NULL, &s) == RAD_OK, "%s", rad_error_message());
    if (s) {
        snprintf(needle, sizeof needle, "dropped 1 degenerate (zero-area) triangle(s) (first at %s:4, "
                 "face 1)", inc);
        int found = 0;
        for (int i = 0; i < rad_scene_warning_count(s); i++)
            found += strstr(rad_scene_warning(s, i), needle) != NULL;
        CHECK_MSG(found == 1, "no warning naming %s:4", inc);
        rad_scene_destroy(s);
    }
    rad_scene_params p;
    rad_scene_params_default(&p);
    p.strict = 1;
    CHECK(rad_scene_load(top, &p, &s) == RAD_EINPUT);
    snprintf(needle, sizeof needle, "%s:4: degenerate (zero-area) triangle in face 1", inc);
    CHECK_MSG(strstr(rad_error_message(), needle) != NULL, "%s", rad_error_message());
    /* through the program: a polygon whose fan folds (scene_finish's check) on
     * line 7 of the include, and a figure eight (the triangulation's) on line 9 */
    write_at(inc, "v q1 =\n p 0 0 0\nv q2 =\n p 1 1 0\nv q3 =\n p 1 0 0\nf q1 q2 q3 c\n");
    snprintf(needle, sizeof needle, "%s:7: face 1 is a non-convex polygon", inc);
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){top, NULL}, needle);
    write_at(inc, "v q1 =\n p 0 0 0\nv q2 =\n p 1 0 0\nv q3 =\n p 1 1 0\nv q4 =\n p 0 1 0\n"
                  "f q1 q3 q2 q4\n");
    snprintf(needle, sizeof needle, "%s:9: face 1 is a self-intersecting polygon", inc);
    HARNESS_EXPECT_USAGE_ERROR("info", (const char *const[]){top, NULL}, needle);
    remove(inc);
    remove(top);
    rmdir(dir);
}
