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

static int hier_sweep(const char *path, int neps, char **eps)
{
    manufactured_rule m;
    if (!manufactured_rule_init(&m))
        return 1;
    rad_scene_params sp;
    manufactured_scene_params(&sp);
    rad_scene *scene = NULL;
    if (rad_scene_load(path, &sp, &scene) != RAD_OK) {
        fprintf(stderr, "manufactured: %s\n", rad_error_message());
        return 2;
    }
    printf("basis\teps\telements\tunknowns\tl2_error\ttime_s\n");
    for (int order = 1; order <= 2; order++)
        for (int i = 0; i < neps; i++) {
            rad_solve_params p;
            manufactured_solve_params(&p, order, 0, &m);
            p.method = RAD_SOLVE_HIER;
            p.hier.eps = atof(eps[i]);
            rad_solution *s = NULL;
            if (rad_solve_run(scene, &p, &s) != RAD_OK) {
                fprintf(stderr, "manufactured: hier p%d eps %s: %s\n", order, eps[i],
                        rad_error_message());
                rad_scene_destroy(scene);
                return 1;
            }
            printf("p%d\t%s\t%zu\t%zu\t%.6e\t%.4f\n", order, eps[i], s->elements,
                   s->elements * (size_t)rad_basis_size(order), manufactured_l2_error(s),
                   s->total_seconds);
            fflush(stdout);
            rad_solution_destroy(s);
        }
    rad_scene_destroy(scene);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 4 && strcmp(argv[1], "--hier") == 0)
        return hier_sweep(argv[2], argc - 3, argv + 3);
    if (argc != 5) {
        fprintf(stderr, "usage: manufactured SCENE MAX_REFINE_P0 MAX_REFINE_P1 MAX_REFINE_P2\n");
        return 2;
    }
    manufactured_rule m;
    if (!manufactured_rule_init(&m))
        return 1;
    rad_scene_params sp;
    manufactured_scene_params(&sp);
    rad_scene *scene = NULL;
    if (rad_scene_load(argv[1], &sp, &scene) != RAD_OK) {
        fprintf(stderr, "manufactured: %s\n", rad_error_message());
        return 2;
    }
    printf("basis\trefine\telements\tunknowns\tl2_error\ttime_s\n");
    for (int order = 0; order <= 2; order++) {
        int max_refine = atoi(argv[2 + order]);
        for (int r = 0; r <= max_refine; r++) {
            rad_solve_params p;
            manufactured_solve_params(&p, order, r, &m);
            rad_solution *s = NULL;
            if (rad_solve_run(scene, &p, &s) != RAD_OK) {
                fprintf(stderr, "manufactured: p%d refine %d: %s\n", order, r, rad_error_message());
                rad_scene_destroy(scene);
                return 1;
            }
            printf("p%d\t%d\t%zu\t%zu\t%.6e\t%.4f\n", order, r, s->elements,
                   s->elements * (size_t)rad_basis_size(order), manufactured_l2_error(s),
                   s->total_seconds);
            fflush(stdout);
            rad_solution_destroy(s);
        }
    }
    rad_scene_destroy(scene);
    return 0;
}
