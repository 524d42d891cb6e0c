/* radkit solve: what every method shares (solve.h): the check of the output
 * paths before any work, the outputs made from a solution on a display mesh
 * (PLY with vertex colours, the PNG) and the effects lines. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_io.h"
#include "rad_render.h"
#include "rad_sys.h"
#include "solve.h"

rad_status solve_parse_double(const char *option, const char *text, double lo, double *out)
{
    char *end = NULL;
    double v = strtod(text, &end);
    if (end == text || *end != '\0' || !isfinite(v) || !(v > lo))
        return RAD_ERROR(RAD_EINVAL, "solve: %s must be a number > %g, got '%s'", option, lo, text);
    *out = v;
    return RAD_OK;
}

rad_status solve_check_outputs(const solve_options *o)
{
    const char *names[4] = {"--out", "--ply", "--png", "--stats"};
    /* the table goes to standard output when --out is not given */
    const char *paths[4] = {o->out ? o->out : "-", o->ply, o->png, o->stats};
    for (int k = 0; k < 4; k++) {
        if (!paths[k])
            continue;
        if (rad_io_output_check(paths[k]) != RAD_OK) {
            char why[512];
            snprintf(why, sizeof why, "%s", rad_error_message());
            return RAD_ERROR(RAD_EINVAL, "solve: %s: %s", names[k], why);
        }
        if (o->scene && rad_io_output_same(paths[k], o->scene))
            return RAD_ERROR(RAD_EINVAL, "solve: %s '%s' is the scene file, which it would "
                                         "overwrite", names[k], paths[k]);
        for (int j = 0; j < k; j++)
            if (paths[j] && rad_io_output_same(paths[j], paths[k])) {
                if (j == 0 && !o->out)
                    return RAD_ERROR(RAD_EINVAL, "solve: %s '%s' is standard output, where the "
                                                 "table goes without --out; give --out FILE",
                                     names[k], paths[k]);
                return RAD_ERROR(RAD_EINVAL, "solve: %s '%s' and %s '%s' are the same file; "
                                             "give each output its own path", names[j], paths[j],
                                 names[k], paths[k]);
            }
    }
    return RAD_OK;
}

rad_status solve_parse_image(const solve_options *o, int *width, int *height, double *exposure)
{
    *width = *height = 512;
    *exposure = 0.0;
    if (o->size) {
        char tail = 0;
        if (sscanf(o->size, "%dx%d%c", width, height, &tail) != 2 || *width < 1 || *height < 1 ||
            *width > 16384 || *height > 16384)
            return RAD_ERROR(RAD_EINVAL, "solve: --image-size must be WxH with 1 <= W, H <= "
                                         "16384, got '%s'", o->size);
    }
    if (o->exposure)
        return solve_parse_double("--exposure", o->exposure, 0.0, exposure);
    return RAD_OK;
}

/* The exposure that maps the 95th percentile of the radiosity of non-emitting
 * triangles to white: lamps are left to clip, lit surfaces stay visible. */
static double auto_exposure(size_t n, const double *B, const double *E)
{
    double *vals = malloc(3 * n * sizeof *vals);
    if (!vals)
        return 1.0;
    size_t m = 0;
    for (size_t i = 0; i < n; i++)
        if (E[i] + E[i + n] + E[i + 2 * n] <= 0.0)
            for (int c = 0; c < 3; c++)
                vals[m++] = B[i + (size_t)c * n];
    double x = m ? rad_io_tonemap_auto_exposure(m, vals, 0.95)
                 : rad_io_tonemap_auto_exposure(3 * n, B, 0.95);
    free(vals);
    return x;
}

rad_status solve_write_display(const solve_options *o, const rad_scene *scene,
                               const rad_solution *sol, double *render_s)
{
    const solve_display dd = {sol->display_nv, sol->display_nt, sol->display_xyz,
                              sol->display_tri, sol->display_material, sol->display_E,
                              sol->display_B, sol->display_corners};
    const solve_display *d = &dd;
    *render_s = 0.0;
    if (!o->ply && !o->png)
        return RAD_OK;
    int width, height;
    double exposure;
    rad_status st = solve_parse_image(o, &width, &height, &exposure);
    if (st != RAD_OK)
        return st;
    rad_io_tonemap tm;
    rad_io_tonemap_default(&tm);
    tm.exposure = exposure > 0.0 ? exposure : auto_exposure(d->nt, d->B, d->E);
    double *xyz = NULL;
    int *tri = NULL;
    size_t nv = 0;
    rad_vis *vis = NULL;
    unsigned char *rgb = NULL;
    /* vertices split at creases and material boundaries: smooth shading never
       mixes two surfaces */
    if ((st = rad_render_shading_mesh(d->xyz, d->tri, d->nt, d->material, &xyz, &nv, &tri)) !=
        RAD_OK)
        return st;
    if (o->ply && (st = rad_io_write_ply(o->ply, nv, xyz, d->nt, tri, d->B, &tm, 0)) != RAD_OK)
        goto out;
    if (o->png) {
        double t0 = rad_sys_seconds();
        rad_vis_params vp;
        rad_vis_params_default(&vp);
        if ((st = rad_vis_create(xyz, nv, tri, d->nt, &vp, &vis)) != RAD_OK)
            goto out;
        const rad_camera *sc = rad_scene_camera(scene);
        rad_render_camera cam;
        memcpy(cam.eye, sc->position, sizeof cam.eye);
        memcpy(cam.look_at, sc->look_at, sizeof cam.look_at);
        memcpy(cam.up, sc->up, sizeof cam.up);
        cam.fov_y_deg = sc->fov_y_deg;
        cam.width = width;
        cam.height = height;
        rgb = malloc((size_t)width * (size_t)height * 3);
        if (!rgb) {
            st = RAD_ERROR(RAD_ENOMEM, "solve: no memory for a %dx%d image", width, height);
            goto out;
        }
        /* --edges: thin dark lines where elements meet */
        rad_render_outline outline = {d->element_corners, 0.6, {0.05, 0.05, 0.05}};
        rad_vis_stats vs = {0, 0, 0};
        st = rad_render_image(vis, nv, xyz, d->nt, tri, d->B, &cam, &tm,
                              o->edges && d->element_corners ? &outline : NULL, rgb, &vs);
        if (st == RAD_OK)
            st = rad_render_write_png(o->png, width, height, rgb);
        if (st != RAD_OK)
            goto out;
        *render_s = rad_sys_seconds() - t0;
    }
out:
    free(rgb);
    rad_vis_destroy(vis);
    free(xyz);
    free(tri);
    return st;
}

void solve_print_effects(FILE *out, const rad_effects_plan *plan)
{
    const rad_effect_decision *dec[RAD_EFFECT_COUNT];
    const char *names[RAD_EFFECT_COUNT];
    rad_scene_effects_list(plan, dec, names);
    for (int k = 0; k < RAD_EFFECT_COUNT; k++)
        fprintf(out, "# effect_%s = %s\n# effect_%s_reason = %s\n", names[k],
                dec[k]->on ? "on" : "off", names[k], dec[k]->reason);
}

void solve_effects_json(const rad_effects_plan *plan, rad_io_effect effects[RAD_EFFECT_COUNT])
{
    const rad_effect_decision *dec[RAD_EFFECT_COUNT];
    const char *names[RAD_EFFECT_COUNT];
    rad_scene_effects_list(plan, dec, names);
    for (int k = 0; k < RAD_EFFECT_COUNT; k++)
        effects[k] = (rad_io_effect){names[k], dec[k]->on ? "on" : "off", dec[k]->reason};
}
