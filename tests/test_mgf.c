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
             "# comment\n%s v d =\n p 1.25 2.5 0\nm grey =\n c\n rd .4\n ed 1\n"
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
             "%sm w =\n rd .5\n"
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
    snprintf(text, sizeof text, "%sm w =\n rd .5\ni parts/one.mgf -t 0 0 3 -a 2 -t 0 0 1\n", VERTS);
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
    const char *base = "m w =\n rd .5\nv c =\n p 0.3 -0.2 1.1\n n 1 2 2\nv top =\n p 0.3 1.7 1.1\n"
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
             "frobnicate 1 2\nf a b c\nfrobnicate\nfh a b c\n",
             VERTS);
    rad_scene *s = load_text("warn.mgf", text, NULL);
    if (s) {
        CHECK(rad_scene_warning_count(s) == 4); /* the three, and no emitter */
        int unknown = 0;
        for (int i = 0; i < rad_scene_warning_count(s); i++)
            unknown += strstr(rad_scene_warning(s, i), "ignored 2 `frobnicate` statement(s) (first at") != NULL;
        CHECK(unknown == 1);
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
             "%sm warm =\n c\n cct 2856\n rd .5\nf a b c\nm flat =\n c\n cspec 380 780 1 1 1\n"
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
