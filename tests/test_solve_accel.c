/* The hierarchy's solve with Anderson mixing of its steps (the default,
 * core/hier/accel.c) against plain Jacobi steps (--anderson 0): the same
 * fixed point, reached in fewer steps where light bounces many times.  The
 * furnace (B = E / (1 - rho) exactly) is the independent reference. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

/* Run `radkit solve` with args; the table (NULL on failure, reported) and its
 * step count. */
static char *solve_run(const char *const *args, long *iterations)
{
    char *out = NULL, *err = NULL;
    int code = harness_radkit_run("solve", args, &out, &err);
    CHECK_MSG(code == 0, "%s: exit %d: %s", args[0], code, err ? err : "");
    free(err);
    char buf[64];
    *iterations = -1;
    if (code != 0 || !harness_header(out, "iterations", buf, sizeof buf)) {
        free(out);
        return NULL;
    }
    *iterations = atol(buf);
    return out;
}

/* The largest relative error of any face against B = E / (1 - rho), E = 2.385. */
static double furnace_worst(const char *out, double rho)
{
    static double B[3 * 4096];
    int rows = harness_face_table(out, B, 4096);
    CHECK(rows > 0);
    double exact = 2.385 / (1.0 - rho), worst = 0.0;
    for (int i = 0; i < 3 * rows; i++)
        worst = fmax(worst, fabs(B[i] - exact) / exact);
    return rows > 0 ? worst : INFINITY;
}

TEST(anderson_furnace_in_fewer_steps)
{
    /* rho 0.99: a plain step shrinks the error by about 0.99, so Jacobi
       takes hundreds of steps; the mixing, a few.  Both answers within the
       furnace target of the exact one, with and without clusters. */
    const char *methods[2] = {"hier", "cluster"};
    for (int m = 0; m < 2; m++) {
        const char *scene = harness_path("scenes/furnace_room/room_27.obj");
        long mixed, plain;
        char *a = solve_run((const char *[]){scene, "--rho", "0.99", "--method", methods[m],
                                             "--quiet", NULL},
                            &mixed);
        char *b = solve_run((const char *[]){scene, "--rho", "0.99", "--method", methods[m],
                                             "--anderson", "0", "--quiet", NULL},
                            &plain);
        if (a && b) {
            double ea = furnace_worst(a, 0.99), eb = furnace_worst(b, 0.99);
            printf("# room_27 rho 0.99 %s: %ld steps (max error %.2e), --anderson 0: %ld (%.2e)\n",
                   methods[m], mixed, ea, plain, eb);
            CHECK_MSG(ea <= 0.03 && eb <= 0.03, "%s: max errors %.3g, %.3g", methods[m], ea, eb);
            CHECK_MSG(mixed > 0 && 3 * mixed <= plain, "%s: %ld steps against %ld", methods[m],
                      mixed, plain);
        }
        free(a);
        free(b);
    }
}

TEST(anderson_reaches_the_same_fixed_point)
{
    /* 64 boxes lit from the ceiling, every reflectance 0.9: the two solves
       stop within final_share eps R = 1e-3 R of the same fixed point, so
       they differ by at most 2e-3 R on any face (radkit compare's worst,
       relative to the mean reflected radiosity R); mixing saves a quarter
       of the steps at least, in the last solve and the bound's transport
       (the solves between rounds stop at round_tol eps R, mostly before
       mixing could pay). */
    const char *scene = harness_path("scenes/many_objects/many_64.obj");
    long mixed, plain;
    char *a = solve_run((const char *[]){scene, "--rho", "0.9", "--method", "cluster", "--quiet",
                                         NULL},
                        &mixed);
    char *b = solve_run((const char *[]){scene, "--rho", "0.9", "--method", "cluster",
                                         "--anderson", "0", "--quiet", NULL},
                        &plain);
    if (a && b) {
        const char *ta = harness_write_file("accel_mixed.tsv", a);
        const char *tb = harness_write_file("accel_plain.tsv", b);
        char *out = NULL, *err = NULL;
        int code = harness_radkit_run("compare", (const char *[]){scene, ta, tb, NULL}, &out, &err);
        CHECK_MSG(code == 0, "compare: exit %d: %s", code, err ? err : "");
        char buf[64];
        double worst = code == 0 && harness_header(out, "error_worst", buf, sizeof buf)
                           ? atof(buf)
                           : INFINITY;
        printf("# many_64 rho 0.9: %ld steps, --anderson 0: %ld; worst difference %.2e R\n",
               mixed, plain, worst);
        CHECK_MSG(worst <= 2e-3, "worst difference %.3g R", worst);
        CHECK_MSG(mixed > 0 && 4 * mixed <= 3 * plain, "%ld steps against %ld", mixed, plain);
        free(out);
        free(err);
    }
    free(a);
    free(b);
}

TEST(anderson_bad_values_are_refused)
{
    const char *scene = harness_path("scenes/furnace_room/room_box.obj");
    const struct {
        const char *method, *value;
    } bad[] = {{"hier", "9"}, {"cluster", "-1"}, {"hier", "two"}, {"dense", "2"}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++)
        HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--method", bad[k].method,
                                                             "--anderson", bad[k].value, NULL},
                                   "--anderson");
    /* p1 and p2 solve by plain steps: the option is refused, not ignored */
    HARNESS_EXPECT_USAGE_ERROR("solve", (const char *[]){scene, "--method", "hier", "--basis", "p1",
                                                         "--anderson", "2", NULL},
                               "--anderson");
}
