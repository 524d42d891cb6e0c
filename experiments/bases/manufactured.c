/* The manufactured case of experiments/bases: two unit squares facing each
 * other at distance 1 (scenes/plates_parallel), reflectance 0.5, radiosity
 * B* = 2 + sin(2x + y + 3z) on both, emission E = B* - 0.5 K B* with K B*
 * integrated here by a 48 x 48 Gauss-Legendre product rule (the kernel
 * 1 / (pi r^4) between the squares is smooth).  For each basis and uniform
 * refinement: the L2 error of the dense Galerkin solution against B*
 * (the case itself: manufactured_case.h, shared with the tests).
 *
 * usage: manufactured SCENE MAX_REFINE_P0 MAX_REFINE_P1 MAX_REFINE_P2
 * prints: basis refine elements unknowns l2_error time_s
 *
 * usage: manufactured --hier SCENE EPS...
 * the same case solved by hier with p1 and p2 elements at each eps (p0's
 * hier, rad_hier, takes no emission field); prints: basis eps elements
 * unknowns l2_error time_s */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "manufactured_case.h"

/* One run: dense at refinement `refine`, or hier at eps `eps` (not NULL);
 * its row printed.  0, or 1 when the solve fails. */
static int run(const rad_scene *scene, manufactured_rule *m, int order, int refine,
               const char *eps)
{
    rad_solve_params p;
    manufactured_solve_params(&p, order, eps ? 0 : refine, m);
    if (eps) {
        p.method = RAD_SOLVE_HIER;
        p.hier.eps = atof(eps);
    }
    rad_solution *s = NULL;
    if (rad_solve_run(scene, &p, &s) != RAD_OK) {
        if (eps)
            fprintf(stderr, "manufactured: p%d eps %s: %s\n", order, eps, rad_error_message());
        else
            fprintf(stderr, "manufactured: p%d refine %d: %s\n", order, refine,
                    rad_error_message());
        return 1;
    }
    if (eps)
        printf("p%d\t%s", order, eps);
    else
        printf("p%d\t%d", order, refine);
    printf("\t%zu\t%zu\t%.6e\t%.4f\n", s->elements,
           s->elements * (size_t)rad_basis_size(order), manufactured_l2_error(s),
           s->total_seconds);
    fflush(stdout);
    rad_solution_destroy(s);
    return 0;
}

int main(int argc, char **argv)
{
    int hier = argc >= 4 && strcmp(argv[1], "--hier") == 0;
    if (!hier && argc != 5) {
        fprintf(stderr, "usage: manufactured SCENE MAX_REFINE_P0 MAX_REFINE_P1 MAX_REFINE_P2\n"
                        "       manufactured --hier SCENE EPS...\n");
        return 2;
    }
    manufactured_rule m;
    if (!manufactured_rule_init(&m))
        return 1;
    rad_scene_params sp;
    manufactured_scene_params(&sp);
    rad_scene *scene = NULL;
    if (rad_scene_load(argv[1 + hier], &sp, &scene) != RAD_OK) {
        fprintf(stderr, "manufactured: %s\n", rad_error_message());
        return 2;
    }
    printf("basis\t%s\telements\tunknowns\tl2_error\ttime_s\n", hier ? "eps" : "refine");
    int failed = 0;
    for (int order = hier ? 1 : 0; order <= 2 && !failed; order++) {
        int count = hier ? argc - 3 : atoi(argv[2 + order]) + 1;
        for (int i = 0; i < count && !failed; i++)
            failed = run(scene, &m, order, i, hier ? argv[3 + i] : NULL);
    }
    rad_scene_destroy(scene);
    return failed;
}
