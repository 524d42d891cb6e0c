/* Hierarchical radiosity on a scene file: the per-face table of
 * `radkit solve SCENE --method hier` (same defaults, same numbers).
 *
 *   cc solve_scene.c -o solve_scene $(pkg-config --cflags --libs radkit)
 *   ./solve_scene scenes/cornell/cornell.obj
 *
 * Load the scene (rad_scene), run the library's solve pipeline (rad_solve:
 * mesh, effects plan, visibility, hierarchical refinement and solve), and
 * print one row per input triangle: face, area, B_r, B_g, B_b, the area
 * average of its leaves' radiosity (rad_io). */
#include <stdio.h>

#include <rad_io.h>
#include <rad_scene.h>
#include <rad_solve.h>

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: solve_scene SCENE\n");
        return 2;
    }
    rad_scene_params scene_params;
    rad_scene_params_default(&scene_params);
    rad_solve_params params;
    rad_solve_params_default(&params);
    params.method = RAD_SOLVE_HIER;

    rad_scene *scene = NULL;
    rad_solution *solution = NULL;
    rad_status st = rad_scene_load(argv[1], &scene_params, &scene);
    if (st == RAD_OK)
        st = rad_solve_run(scene, &params, &solution);
    if (st != RAD_OK) {
        fprintf(stderr, "solve_scene: %s\n", rad_error_message());
        rad_scene_destroy(scene);
        return rad_status_exit_code(st);
    }
    printf("# scene = %s\n# method = %s\n# eps = %g\n# faces = %d\n# leaves = %zu\n",
           argv[1], rad_solve_method_name(solution->method), solution->used.hier.eps,
           solution->faces, solution->elements);
    printf("# error_estimate = %.3e\n# error_target_met = %s\n", solution->hier.bound_face_max,
           solution->hier.target_met ? "yes" : "no");
    rad_io_print_faces(stdout, (size_t)solution->faces, solution->face_area, solution->face_B);
    rad_solution_destroy(solution);
    rad_scene_destroy(scene);
    return 0;
}
