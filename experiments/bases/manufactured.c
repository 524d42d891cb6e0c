/* The manufactured case of experiments/bases: two unit squares facing each
 * other at distance 1 (scenes/plates_parallel), reflectance 0.5, radiosity
 * B* = 2 + sin(2x + y + 3z) on both, emission E = B* - 0.5 K B* with K B*
 * integrated here by a 48 x 48 Gauss-Legendre product rule (the kernel
 * 1 / (pi r^4) between the squares is smooth).  For each basis and uniform
 * refinement: the L2 error of the dense Galerkin solution against B*.
 *
 * usage: manufactured SCENE MAX_REFINE_P0 MAX_REFINE_P1 MAX_REFINE_P2
 * prints: basis refine elements unknowns l2_error time_s */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "rad_basis.h"
#include "rad_geom.h"
#include "rad_quad.h"
#include "rad_solve.h"

typedef struct rule48 {
    double x[48], w[48];
} rule48;

static double b_star(double x, double y, double z) { return 2.0 + sin(2.0 * x + y + 3.0 * z); }

static double emission_field(int face, rad_vec3 p, int channel, void *ctx)
{
    (void)channel;
    const rule48 *m = ctx;
    double z = face < 2 ? 1.0 : 0.0, g = 0.0; /* the other square's height */
    for (int i = 0; i < 48; i++)
        for (int j = 0; j < 48; j++) {
            double dx = m->x[i] - p.x, dy = m->x[j] - p.y, r2 = dx * dx + dy * dy + 1.0;
            g += m->w[i] * m->w[j] * b_star(m->x[i], m->x[j], z) / (RAD_PI * r2 * r2);
        }
    return b_star(p.x, p.y, p.z) - 0.5 * g;
}

static double l2_error(const rad_solution *s)
{
    double rs[RAD_QUAD_TRI_MAX_POINTS], rt[RAD_QUAD_TRI_MAX_POINTS], rw[RAD_QUAD_TRI_MAX_POINTS];
    int np = 0, m = rad_basis_size(s->used.basis);
    if (rad_quad_tri_symmetric(10, rs, rt, rw, &np) != RAD_OK)
        return NAN;
    double sum = 0.0;
    for (size_t i = 0; i < s->elements; i++) {
        const double *c = s->element_corners + 9 * i;
        rad_vec3 t[3] = {{c[0], c[1], c[2]}, {c[3], c[4], c[5]}, {c[6], c[7], c[8]}};
        double area = rad_geom_triangle_area(t[0], t[1], t[2]);
        for (int k = 0; k < np; k++) {
            rad_vec3 x = rad_geom_triangle_point(t[0], t[1], t[2], rs[k], rt[k]);
            double d = rad_basis_value(s->used.basis, area, s->element_coef + i * (size_t)m,
                                       rs[k], rt[k]) - b_star(x.x, x.y, x.z);
            sum += area * rw[k] * d * d;
        }
    }
    return sqrt(sum);
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: manufactured SCENE MAX_REFINE_P0 MAX_REFINE_P1 MAX_REFINE_P2\n");
        return 2;
    }
    rule48 m;
    if (rad_quad_gauss_legendre(48, m.x, m.w) != RAD_OK)
        return 1;
    rad_scene_params sp;
    rad_scene_params_default(&sp);
    sp.has_rho = sp.has_emission = 1;
    for (int c = 0; c < 3; c++) {
        sp.rho[c] = 0.5;
        sp.emission[c] = 0.0;
    }
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
            rad_solve_params_default(&p);
            p.basis = order;
            p.refine = r;
            p.emission = emission_field;
            p.emission_ctx = &m;
            rad_solution *s = NULL;
            if (rad_solve_run(scene, &p, &s) != RAD_OK) {
                fprintf(stderr, "manufactured: p%d refine %d: %s\n", order, r, rad_error_message());
                rad_scene_destroy(scene);
                return 1;
            }
            printf("p%d\t%d\t%zu\t%zu\t%.6e\t%.4f\n", order, r, s->elements,
                   s->elements * (size_t)rad_basis_size(order), l2_error(s), s->total_seconds);
            fflush(stdout);
            rad_solution_destroy(s);
        }
    }
    rad_scene_destroy(scene);
    return 0;
}
