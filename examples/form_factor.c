/* The form factor between two triangles by two rules, and their difference.
 *
 *   cc form_factor.c -o form_factor $(pkg-config --cflags --libs radkit)
 *   ./form_factor [RULE_A [RULE_B]]        (default: vertex exact)
 *
 * The pair shares an edge at 90 degrees, where the seed notes' vertex rule is
 * blind (it evaluates the kernel only at vertices, and the coupling is
 * concentrated at the shared edge) and `exact` is the contour-integral
 * reference.  The triangles are printed in the form `radkit ff --tri` takes,
 * so the figures can be checked against the program. */
#include <stdio.h>

#include <rad_ff.h>

static int compute(const char *text, const rad_vec3 t1[3], const rad_vec3 t2[3], rad_ff_result *out)
{
    rad_ff_rule rule;
    rad_ff_params params;
    rad_ff_params_default(&params);
    if (rad_ff_rule_parse(text, &rule) != RAD_OK || rad_ff_compute(t1, t2, rule, &params, out) != RAD_OK) {
        fprintf(stderr, "form_factor: %s: %s\n", text, rad_error_message());
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *rule_a = argc > 1 ? argv[1] : "vertex";
    const char *rule_b = argc > 2 ? argv[2] : "exact";
    /* Triangle 1 in the plane z = 0 facing +z, triangle 2 in y = 0 facing +y;
     * they share the edge from (0,0,0) to (1,0,0). */
    const rad_vec3 t1[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const rad_vec3 t2[3] = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}};
    rad_ff_result a, b;
    if (compute(rule_a, t1, t2, &a) || compute(rule_b, t1, t2, &b))
        return 1;

    const rad_vec3 *t[2] = {t1, t2};
    for (int k = 0; k < 2; k++)
        printf("# tri%d = %g %g %g %g %g %g %g %g %g\n", k + 1, t[k][0].x, t[k][0].y, t[k][0].z,
               t[k][1].x, t[k][1].y, t[k][1].z, t[k][2].x, t[k][2].y, t[k][2].z);
    printf("rule\tF12\tF21\tevals\n");
    printf("%s\t%.17g\t%.17g\t%ld\n", rule_a, a.F12, a.F21, a.evals);
    printf("%s\t%.17g\t%.17g\t%ld\n", rule_b, b.F12, b.F21, b.evals);
    printf("# difference F12(%s) - F12(%s) = %.6e (relative %.3e)\n", rule_a, rule_b, a.F12 - b.F12,
           (a.F12 - b.F12) / b.F12);
    return 0;
}
