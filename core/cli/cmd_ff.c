/* radkit ff: the form factor between two triangles by one rule.  A coincident
 * pair (rad_ff: one plane within rounding, opposite normals, overlapping) is
 * refused: its form factor has no single value. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "rad_ff.h"
#include "rad_sys.h"
#include "rad_version.h"

static const char help[] =
    "usage: radkit ff --tri \"x1 y1 z1 x2 y2 z2 x3 y3 z3\" --tri \"...\"\n"
    "                 [--rule RULE] [--tol T] [--repeat K]\n"
    "\n"
    "Form factors F12 and F21 between two triangles, unoccluded, by one rule.\n"
    "Triangle 1 is the first --tri.  Faces are one-sided: the front is the side\n"
    "the counter-clockwise winding's normal (v2 - v1) x (v3 - v1) points to; a\n"
    "pair that faces away or is coplanar is exactly 0 without integration.\n"
    "Coplanar means within rounding (64 machine epsilons of the pair's size and\n"
    "coordinates): any real gap is integrated, so two facing triangles a tiny\n"
    "gap apart give F near 1 (their overlap's share), and a pair that lies in\n"
    "one plane with opposite normals and overlaps (coincident: F jumps from 0 to\n"
    "that share there) is refused (exit 2).  Every test is relative to the\n"
    "triangles' size: a pair scaled by 1e-100 gives the same F; one whose areas\n"
    "fall below 2.2e-308 (double precision's normal range) is refused.\n"
    "\n"
    "  --tri \"...\"    nine coordinates (spaces or commas); give it twice\n"
    "  --rule RULE    vertex       the seed notes' 3 x 3 vertex average\n"
    "                 centroid     one point per triangle\n"
    "                 gauss:P      symmetric rule of degree P (0-40) on both\n"
    "                 analytic:P   inner integral in closed form, outer degree P (0-40)\n"
    "                 ss:N         Sauter-Schwab for adjacent pairs, N (1-32) Gauss\n"
    "                              points per direction\n"
    "                 exact        contour-integral reference (default)\n"
    "                 auto         cheapest rule expected to reach --tol\n"
    "  --tol T        relative tolerance for auto, 0 < T < 1 (default 1e-6)\n"
    "  --repeat K     compute K times and report the mean time (default 1)\n"
    "\n"
    "Output: '#' lines (version, triangles, areas, adjacency), then one row with\n"
    "the columns rule, F12, F21, evals (kernel or closed-form evaluations),\n"
    "seconds (per computation), rel_error (the scheme's estimate of the\n"
    "relative error, nan if it has none), flags (not_facing, guarded: a 0/0 at a\n"
    "shared vertex taken as 0, out_of_range: F outside [0,1], reported\n"
    "unclamped, not_converged; '-' if none), used (the rule auto chose, or the\n"
    "rule itself) and adjacency (disjoint, vertex, edge, same).\n"
    "\n"
    "example: radkit ff --tri \"0 0 0 1 0 0 0 1 0\" --tri \"0 0 0 0 0 1 1 0 0\" --rule ss:8\n";

static rad_status parse_triangle(int which, const char *text, rad_vec3 t[3])
{
    double c[9];
    int n = 0;
    const char *p = text;
    for (;;) {
        while (*p == ' ' || *p == '\t' || *p == ',')
            p++;
        if (!*p)
            break;
        char *end = NULL;
        errno = 0;
        double v = strtod(p, &end);
        if (end == p)
            return RAD_ERROR(RAD_EINVAL, "ff: --tri %d: '%.20s' is not a number", which, p);
        if (n < 9)
            c[n] = v;
        n++;
        if (!isfinite(v))
            return RAD_ERROR(RAD_EINPUT, "ff: --tri %d: coordinate %d is not finite (%.20s)", which, n, p);
        p = end;
    }
    if (n != 9)
        return RAD_ERROR(RAD_EINVAL, "ff: --tri %d: expected 9 coordinates, got %d", which, n);
    for (int k = 0; k < 3; k++)
        t[k] = rad_vec3_make(c[3 * k], c[3 * k + 1], c[3 * k + 2]);
    return RAD_OK;
}

static void flags_text(unsigned f, char *buf, size_t size)
{
    static const char *names[] = {"not_facing", "guarded", "out_of_range", "not_converged",
                                  "coincident"};
    buf[0] = '\0';
    for (int k = 0; k < 5; k++)
        if (f & (1u << k)) {
            if (buf[0])
                strncat(buf, ",", size - strlen(buf) - 1);
            strncat(buf, names[k], size - strlen(buf) - 1);
        }
    if (!buf[0])
        snprintf(buf, size, "-");
}

int cli_ff(int argc, char **argv)
{
    const char *tri_text[2] = {NULL, NULL}, *rule_text = "exact", *tol_text = NULL, *repeat_text = "1";
    int want_help = 0, ntri = 0;
    /* --tri repeats, which cli_parse does not do: collect it here and hand
     * the rest to cli_parse. */
    char *rest[64];
    int nrest = 0;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i];
        const char *val = NULL;
        if (strcmp(a, "--tri") == 0) {
            if (i + 1 >= argc)
                return cli_fail(RAD_ERROR(RAD_EINVAL, "ff: option --tri needs a value"));
            val = argv[++i];
        } else if (strncmp(a, "--tri=", 6) == 0) {
            val = a + 6;
        } else {
            if (nrest >= 63)
                return cli_fail(RAD_ERROR(RAD_EINVAL, "ff: too many arguments"));
            rest[nrest++] = argv[i];
            continue;
        }
        if (ntri >= 2)
            return cli_fail(RAD_ERROR(RAD_EINVAL, "ff: --tri given more than twice"));
        tri_text[ntri++] = val;
    }
    cli_option options[] = {
        {"--rule", &rule_text, NULL, NULL}, {"--tol", &tol_text, NULL, NULL}, {"--repeat", &repeat_text, NULL, NULL},
        {"--help", NULL, &want_help, NULL}, {"-h", NULL, &want_help, NULL},   {NULL, NULL, NULL, NULL},
    };
    rad_status st = cli_parse("ff", nrest, rest, 0, options);
    if (st != RAD_OK)
        return cli_fail(st);
    if (want_help) {
        fputs(help, stdout);
        return 0;
    }
    if (ntri != 2)
        return cli_fail(RAD_ERROR(RAD_EINVAL, "ff: two --tri \"x1 y1 z1 x2 y2 z2 x3 y3 z3\" are required, got %d "
                                          "(see 'radkit ff --help')", ntri));
    rad_vec3 t[2][3];
    for (int k = 0; k < 2; k++)
        if ((st = parse_triangle(k + 1, tri_text[k], t[k])) != RAD_OK)
            return cli_fail(st);
    rad_ff_rule rule;
    if ((st = rad_ff_rule_parse(rule_text, &rule)) != RAD_OK) {
        fprintf(stderr, "radkit: ff: --rule: %s\n", rad_error_message());
        return rad_status_exit_code(st);
    }
    rad_ff_params params;
    rad_ff_params_default(&params);
    if (tol_text) {
        char *end = NULL;
        double tol = strtod(tol_text, &end);
        if (end == tol_text || *end != '\0' || !(tol > 0.0 && tol < 1.0))
            return cli_fail(RAD_ERROR(RAD_EINVAL, "ff: --tol must be a number with 0 < T < 1, got '%s'", tol_text));
        params.tol = tol;
    }
    int repeat = 1;
    if ((st = cli_parse_positive_int("ff: --repeat", repeat_text, 100000000L, &repeat)) != RAD_OK)
        return cli_fail(st);

    rad_ff_result res;
    double t0 = rad_sys_seconds();
    for (int r = 0; r < repeat; r++)
        if ((st = rad_ff_compute(t[0], t[1], rule, &params, &res)) != RAD_OK) {
            fprintf(stderr, "radkit: ff: %s\n", rad_error_message());
            return rad_status_exit_code(st);
        }
    double seconds = (rad_sys_seconds() - t0) / repeat;
    if (res.flags & RAD_FF_FLAG_COINCIDENT)
        return cli_fail(RAD_ERROR(RAD_EINPUT, "ff: the triangles coincide: one plane (within "
                                  "rounding of their size and coordinates), opposite normals, "
                                  "overlapping; F is 0 there for the two sides of one surface but "
                                  "tends to the overlap's share as facing triangles close, so no "
                                  "single value is right; move one off the other's plane"));

    static const char *adj[] = {"disjoint", "vertex", "edge", "same"};
    char rule_name[32], used_name[32], flags[96];
    rad_ff_rule_format(rule, rule_name, sizeof rule_name);
    rad_ff_rule_format(res.used, used_name, sizeof used_name);
    flags_text(res.flags, flags, sizeof flags);
    printf("# radkit %s ff\n", RAD_VERSION);
    for (int k = 0; k < 2; k++)
        printf("# tri%d = %.17g %.17g %.17g  %.17g %.17g %.17g  %.17g %.17g %.17g\n", k + 1, t[k][0].x,
               t[k][0].y, t[k][0].z, t[k][1].x, t[k][1].y, t[k][1].z, t[k][2].x, t[k][2].y, t[k][2].z);
    printf("# A1 = %.17g\n# A2 = %.17g\n# G = A1 F12 = %.17g\n", res.A1, res.A2, res.G);
    printf("# adjacency = %s\n# tol = %g\n# repeat = %d\n", adj[res.adjacency], params.tol, repeat);
    printf("rule\tF12\tF21\tevals\tseconds\trel_error\tflags\tused\tadjacency\n");
    printf("%s\t%.17g\t%.17g\t%ld\t%.6e\t%.3e\t%s\t%s\t%s\n", rule_name, res.F12, res.F21, res.evals,
           seconds, res.rel_error, flags, used_name, adj[res.adjacency]);
    return 0;
}
