/* radkit compare: the error of one per-face table against a reference (a
 * Monte Carlo table with standard errors, or any other), in the measures the
 * studies and tests use (rad_io_face_error).  The scene supplies each face's
 * emission (the reflected part is what is compared) and checks that both
 * tables are of its faces. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "rad_geom.h"
#include "rad_io.h"
#include "rad_scene.h"
#include "rad_version.h"

static const char help_head[] =
    "usage: radkit compare SCENE TABLE REFERENCE [scene options]\n"
    "\n"
    "The error of the per-face table TABLE (radkit solve --out) against the\n"
    "per-face table REFERENCE (e.g. radkit solve --method mc, whose standard\n"
    "errors are then reported too), for the faces of SCENE: with R the\n"
    "reference's area-weighted mean reflected radiosity (B - E, the three\n"
    "channels averaged),\n"
    "  error_l1     area-weighted mean of |B - B_ref| over the channels, over R\n"
    "  error_l2     area-weighted root mean square of B - B_ref, over R\n"
    "  error_worst  the largest |B - B_ref| of any face and channel, over R\n"
    "  error_power  (P - P_ref) / P_ref, P the power leaving the faces (the sum\n"
    "               over faces and channels of area x B), signed\n"
    "  reference_se_l1, reference_se_worst: the reference's own standard error\n"
    "               in the same measures (0 for a table without se columns).\n"
    "\n"
    ;

static const char help_tail[] =
    "\n"
    "Output: those '#' lines, worst_face and mean_reflected, then columns face,\n"
    "area, d_r, d_g, d_b (B - B_ref).  The scene options must be those the\n"
    "tables were made with (e.g. the same --rho); the tables must have one row\n"
    "per triangle of the scene, with the same areas.\n"
    "\n"
    "example: radkit compare scenes/cornell/cornell.obj hier.tsv \\\n"
    "             experiments/reference/data/cornell.tsv\n";

int cli_compare(int argc, char **argv)
{
    const char *scene_path = NULL, *paths[2] = {NULL, NULL};
    int help = 0;
    cli_scene_options so;
    cli_scene_options_init(&so);
    cli_option table[5 + CLI_SCENE_OPTION_COUNT + 1] = {
        {"", &scene_path, NULL, "scene"},
        {"", &paths[0], NULL, "table"},
        {"", &paths[1], NULL, "reference table"},
        {"--help", NULL, &help, NULL},
        {"-h", NULL, &help, NULL},
    };
    int nopt = 5;
    nopt += cli_scene_options_add(&so, table + nopt);
    table[nopt] = (cli_option){NULL, NULL, NULL, NULL};
    rad_status st = cli_parse("compare", argc, argv, 2, table);
    if (st != RAD_OK)
        return cli_fail(st);
    if (help) {
        printf("%s%s%s", help_head, cli_scene_options_help, help_tail);
        return 0;
    }
    if (!scene_path || !paths[1])
        return cli_fail(RAD_ERROR(RAD_EINVAL, "compare: expected SCENE TABLE REFERENCE (see "
                                              "'radkit compare --help')"));
    rad_scene_params sp;
    rad_effects_params ep;
    rad_scene_params_default(&sp);
    rad_scene_effects_params_default(&ep);
    sp.no_cross_check = 1;
    if ((st = cli_scene_options_apply("compare", &so, &sp, &ep)) != RAD_OK)
        return cli_fail(st);

    rad_scene *scene = NULL;
    rad_io_faces t[2];
    memset(t, 0, sizeof t);
    double *E = NULL;
    if ((st = rad_scene_load(scene_path, &sp, &scene)) != RAD_OK)
        return cli_fail(st);
    for (int k = 0; k < 2 && st == RAD_OK; k++)
        st = rad_io_read_faces_tsv(paths[k], &t[k]);
    if (st != RAD_OK)
        goto done;
    size_t n = (size_t)rad_scene_triangle_count(scene);
    const double *xyz = rad_scene_vertices(scene);
    const int *tri = rad_scene_triangles(scene), *mat = rad_scene_triangle_materials(scene);
    const rad_scene_material *mats = rad_scene_materials(scene);
    for (int k = 0; k < 2; k++) {
        if (t[k].n != n) {
            st = RAD_ERROR(RAD_EINPUT, "compare: %s has %zu faces, the scene %zu", paths[k],
                           t[k].n, n);
            goto done;
        }
        for (size_t i = 0; i < n; i++) {
            rad_vec3 v[3];
            for (int c = 0; c < 3; c++) {
                const double *p = xyz + 3 * (size_t)tri[3 * i + c];
                v[c] = rad_vec3_make(p[0], p[1], p[2]);
            }
            double a = rad_geom_triangle_area(v[0], v[1], v[2]);
            if (!(fabs(t[k].area[i] - a) <= 1e-9 * a)) {
                st = RAD_ERROR(RAD_EINPUT, "compare: %s: face %zu has area %.17g, the scene's "
                               "triangle %.17g: a table of another scene?", paths[k], i,
                               t[k].area[i], a);
                goto done;
            }
        }
    }
    E = malloc(3 * n * sizeof *E);
    if (!E) {
        st = RAD_ERROR(RAD_ENOMEM, "compare: no memory for %zu faces", n);
        goto done;
    }
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++)
            E[i + c * n] = mats[mat[i]].emission[c];
    rad_io_face_errors fe;
    if ((st = rad_io_face_error(n, t[1].area, E, t[0].B, t[1].B, t[1].se, &fe)) != RAD_OK)
        goto done;
    printf("# radkit %s compare\n# scene = %s\n# table = %s\n# reference = %s\n# faces = %zu\n",
           RAD_VERSION, scene_path, paths[0], paths[1], n);
    printf("# mean_reflected = %.6e\n# error_l1 = %.6e\n# error_l2 = %.6e\n# error_worst = %.6e\n"
           "# worst_face = %d\n# reference_se_l1 = %.6e\n# reference_se_worst = %.6e\n"
           "# error_power = %.6e\n",
           fe.mean_reflected, fe.l1, fe.l2, fe.worst, fe.worst_face, fe.ref_l1, fe.ref_worst,
           fe.power);
    printf("face\tarea\td_r\td_g\td_b\n");
    for (size_t i = 0; i < n; i++)
        printf("%zu\t%.17g\t%.6e\t%.6e\t%.6e\n", i, t[1].area[i], t[0].B[i] - t[1].B[i],
               t[0].B[i + n] - t[1].B[i + n], t[0].B[i + 2 * n] - t[1].B[i + 2 * n]);
    rad_io_output std_out = {stdout, "-", NULL, NULL, 1};
    st = rad_io_output_commit(&std_out); /* a full disk or closed pipe: exit 1 */
done:
    free(E);
    rad_io_faces_free(&t[0]);
    rad_io_faces_free(&t[1]);
    rad_scene_destroy(scene);
    return st == RAD_OK ? 0 : cli_fail(st);
}
