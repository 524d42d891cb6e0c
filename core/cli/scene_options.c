/* The options shared by the commands that read a scene (info, solve). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "cli.h"
#include "rad_scene.h"

const char cli_scene_options_help[] =
    "  --scale S          multiply every coordinate by S > 0 (e.g. 0.001 for mm -> m)\n"
    "  --strict           refuse what otherwise loads with a counted warning: MTL\n"
    "                     Kd = 1 (else taken as 0.999, the largest reflectance\n"
    "                     radkit gives a surface), a missing material library or\n"
    "                     material (else the default material of --rho and\n"
    "                     --emission), degenerate (zero-area) triangles (else\n"
    "                     dropped), unknown OBJ/MTL statements and free-form\n"
    "                     geometry (else ignored).  Texture, glossy, transmission\n"
    "                     and display statements are ignored with a warning even\n"
    "                     then: radkit's surfaces are opaque and diffuse\n"
    "  --drop-degenerate  accepted for compatibility; dropping is the default\n"
    "  --rho \"r g b\"      reflectance of every material, each in [0, 1) (one number\n"
    "                     means grey); PLY/OFF/STL faces get it (default 0.5)\n"
    "  --emission \"r g b\" emitted exitance of every material, W/m^2, >= 0\n"
    "  --curve-tol T      MGF: tessellate sph, cyl, cone, ring and torus so that\n"
    "                     every facet lies within T times the radius of the true\n"
    "                     surface; 1e-6 <= T < 1, default 0.0125 (20 segments a\n"
    "                     circle; their area falls short by about T to 2 T)\n"
    "  --occlusion M, --colour M, --facing-away M, --singular M,\n"
    "  --reflectance M, --clustering M, --contact M\n"
    "                     override one decision of the effects plan: M is auto\n"
    "                     (decide from the scene, the default), on or off.\n"
    "                     occlusion off: no visibility, no rays; colour off: one\n"
    "                     system with each face's channel-mean reflectance, on:\n"
    "                     one system per channel; facing-away off: pairs facing\n"
    "                     away are integrated anyway (dense); singular off:\n"
    "                     touching pairs by the regular rules; reflectance off:\n"
    "                     the default tolerances even near rho 1; clustering\n"
    "                     (hier; auto: from 250000 pairs of triangles facing\n"
    "                     each other, 20000 where nothing can block, always\n"
    "                     above 20000 triangles) on: link through a cluster\n"
    "                     hierarchy, off: link every pair first;\n"
    "                     contact (hier) on: cut each triangle along the lines\n"
    "                     where others stand on it, off: mesh it whole\n";

static const char *const mode_option[RAD_EFFECT_COUNT] = {
    "--occlusion", "--colour", "--facing-away", "--singular", "--reflectance", "--clustering",
    "--contact"};

void cli_scene_options_init(cli_scene_options *o)
{
    o->scale = o->rho = o->emission = o->curve_tol = NULL;
    for (int k = 0; k < RAD_EFFECT_COUNT; k++)
        o->mode[k] = "auto";
    o->strict = o->drop_degenerate = 0;
}

int cli_scene_options_add(cli_scene_options *o, cli_option *t)
{
    int n = 0;
    t[n++] = (cli_option){"--scale", &o->scale, NULL, NULL};
    t[n++] = (cli_option){"--strict", NULL, &o->strict, NULL};
    t[n++] = (cli_option){"--drop-degenerate", NULL, &o->drop_degenerate, NULL};
    t[n++] = (cli_option){"--rho", &o->rho, NULL, NULL};
    t[n++] = (cli_option){"--emission", &o->emission, NULL, NULL};
    t[n++] = (cli_option){"--curve-tol", &o->curve_tol, NULL, NULL};
    for (int k = 0; k < RAD_EFFECT_COUNT; k++)
        t[n++] = (cli_option){mode_option[k], &o->mode[k], NULL, NULL};
    return n;
}

/* "r g b" or "v" (grey) -> three doubles; RAD_EINVAL names the option. */
static rad_status parse_rgb(const char *command, const char *option, const char *text,
                            int below_one, double out[3])
{
    double v[3];
    int n = 0;
    const char *p = text;
    while (n < 3) {
        char *end = NULL;
        errno = 0;
        double x = strtod(p, &end);
        if (end == p)
            break;
        v[n++] = x;
        p = end;
    }
    while (*p == ' ' || *p == '\t')
        p++;
    if ((n != 1 && n != 3) || *p != '\0')
        return RAD_ERROR(RAD_EINVAL, "%s: %s needs one or three numbers, got '%s'", command, option, text);
    if (n == 1)
        v[1] = v[2] = v[0];
    for (int k = 0; k < 3; k++) {
        if (!isfinite(v[k]) || v[k] < 0.0 || (below_one && v[k] >= 1.0))
            return RAD_ERROR(RAD_EINVAL, "%s: %s values must be %s, got '%s'", command, option,
                             below_one ? "in [0, 1)" : "finite and >= 0", text);
        out[k] = v[k];
    }
    return RAD_OK;
}

rad_status cli_scene_options_apply(const char *command, const cli_scene_options *o,
                                   struct rad_scene_params *sp, struct rad_effects_params *ep)
{
    rad_status st;
    if (o->scale) {
        char *end = NULL;
        double s = strtod(o->scale, &end);
        if (end == o->scale || *end != '\0' || !isfinite(s) || !(s > 0.0))
            return RAD_ERROR(RAD_EINVAL, "%s: --scale must be a number > 0, got '%s'", command, o->scale);
        sp->scale = s;
    }
    if (o->curve_tol) {
        /* Below 1e-6 a circle would need more than the reader's 4096 segments. */
        char *end = NULL;
        double t = strtod(o->curve_tol, &end);
        if (end == o->curve_tol || *end != '\0' || !(t >= 1e-6 && t < 1.0))
            return RAD_ERROR(RAD_EINVAL, "%s: --curve-tol must be a number in [1e-6, 1), got '%s'",
                             command, o->curve_tol);
        sp->curve_tol = t;
    }
    sp->strict = o->strict;
    sp->drop_degenerate = o->drop_degenerate;
    if (o->rho) {
        if ((st = parse_rgb(command, "--rho", o->rho, 1, sp->rho)) != RAD_OK)
            return st;
        sp->has_rho = 1;
        for (int k = 0; k < 3; k++)
            sp->default_rho[k] = sp->rho[k];
    }
    if (o->emission) {
        if ((st = parse_rgb(command, "--emission", o->emission, 0, sp->emission)) != RAD_OK)
            return st;
        sp->has_emission = 1;
    }
    rad_effect_mode *modes[RAD_EFFECT_COUNT] = {&ep->occlusion, &ep->colour, &ep->facing_away,
                                                &ep->singular, &ep->reflectance, &ep->clustering,
                                                &ep->contact};
    for (int k = 0; k < RAD_EFFECT_COUNT; k++) {
        char what[64];
        snprintf(what, sizeof what, "%s: %s", command, mode_option[k]);
        if ((st = rad_scene_effect_mode_parse(what, o->mode[k], modes[k])) != RAD_OK)
            return st;
    }
    return RAD_OK;
}
