/* The furnace family through `radkit solve` with default settings: closed
 * scenes where every face emits E and reflects rho, so that B = E / (1 - rho)
 * exactly on every face, whatever blocks what: convex enclosures, a room with
 * one box, with a box 1 mm from a wall, with 27 boxes; rho 0.5, 0.9, 0.99.
 * Every face's error and the area-weighted mean error are checked (targets of
 * the accuracy issue: max 3%, area-mean 1%), and reflectance too close to 1
 * is refused with exit 1 and a message, never answered with a wrong number. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

/* Largest relative error of any face and channel, and the area-weighted mean
 * relative error, of a furnace solve; -1 on failure (reported). */
static void furnace_errors(const char *scene, const char *rho_text, const char *const *extra,
                           double *max_err, double *mean_err)
{
    const char *args[16];
    int n = 0;
    args[n++] = harness_path(scene);
    args[n++] = "--rho";
    args[n++] = rho_text;
    args[n++] = "--quiet";
    for (int k = 0; extra && extra[k] && n < 15; k++)
        args[n++] = extra[k];
    args[n] = NULL;
    char *out = NULL, *err = NULL;
    int code = harness_radkit_run("solve", args, &out, &err);
    *max_err = *mean_err = -1.0;
    CHECK_MSG(code == 0, "%s rho %s: exit %d: %s", scene, rho_text, code, err ? err : "");
    if (code == 0 && out) {
        double rho = atof(rho_text), exact = 2.385 / (1.0 - rho);
        const char *p = strstr(out, "\nface\t");
        p = p ? strchr(p + 1, '\n') : NULL;
        double worst = 0.0, sum = 0.0, area = 0.0;
        int rows = 0;
        while (p && *++p) {
            int f;
            double a, b[3];
            if (sscanf(p, "%d\t%lf\t%lf\t%lf\t%lf", &f, &a, &b[0], &b[1], &b[2]) != 5)
                break;
            for (int c = 0; c < 3; c++)
                worst = fmax(worst, fabs(b[c] - exact) / exact);
            sum += a * (b[0] - exact) / exact;
            area += a;
            rows++;
            p = strchr(p, '\n');
        }
        CHECK_MSG(rows > 0, "%s: no table", scene);
        if (rows > 0) {
            *max_err = worst;
            *mean_err = fabs(sum / area);
        }
    }
    free(out);
    free(err);
}

static void check_furnace(const char *scene, const char *rho, const char *const *extra,
                          double max_tol, double mean_tol)
{
    double worst, mean;
    furnace_errors(scene, rho, extra, &worst, &mean);
    printf("# furnace %s rho %s %s: max %.2e, area-mean %.2e\n", scene, rho,
           extra && extra[0] ? extra[1] ? extra[1] : extra[0] : "dense", worst, mean);
    CHECK_MSG(worst >= 0.0 && worst <= max_tol, "%s rho %s: max error %.3g > %.3g", scene, rho,
              worst, max_tol);
    CHECK_MSG(mean >= 0.0 && mean <= mean_tol, "%s rho %s: mean error %.3g > %.3g", scene, rho,
              mean, mean_tol);
}

TEST(furnace_dense_convex)
{
    const char *rhos[3] = {"0.5", "0.9", "0.99"};
    for (int r = 0; r < 3; r++) {
        check_furnace("scenes/furnace_cube/cube.obj", rhos[r], NULL, 1e-4, 1e-4);
        check_furnace("scenes/sphere/sphere_2.obj", rhos[r], NULL, 1e-4, 1e-4);
    }
}

TEST(furnace_dense_occluded_without_refinement)
{
    const char *rhos[3] = {"0.5", "0.9", "0.99"};
    for (int r = 0; r < 3; r++) {
        check_furnace("scenes/furnace_room/room_box.obj", rhos[r], NULL, 0.03, 0.01);
        check_furnace("scenes/furnace_room/room_hair.obj", rhos[r], NULL, 0.03, 0.01);
    }
    check_furnace("scenes/furnace_room/room_27.obj", "0.5", NULL, 0.03, 0.01);
}

TEST(furnace_reflectance_too_close_to_one_is_refused)
{
    const char *methods[3] = {"dense", "hier", "mc"};
    for (int m = 0; m < 3; m++) {
        char *out = NULL, *err = NULL;
        int code = harness_radkit_run("solve", (const char *[]){
                                          harness_path("scenes/furnace_room/room_box.obj"),
                                          "--rho", "0.99999999", "--method", methods[m], NULL},
                                      &out, &err);
        CHECK_MSG(code == 1, "%s: exit %d, want 1", methods[m], code);
        CHECK_MSG(err && strstr(err, "reflectance") && strstr(err, "0.99999999"),
                  "%s: message '%s'", methods[m], err ? err : "");
        CHECK(out && out[0] == '\0');
        free(out);
        free(err);
    }
}
