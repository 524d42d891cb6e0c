/* The manufactured case of experiments/bases, shared by its program
 * (manufactured.c) and the test that checks its orders
 * (tests/test_basis_solve.c): two unit squares facing each other at distance
 * 1 (scenes/plates_parallel: faces 0, 1 at z = 0, faces 2, 3 at z = 1),
 * reflectance 0.5, the radiosity B* = 2 + sin(2x + y + 3z) on both, and the
 * emission E = B* - 0.5 K B* with K B* integrated by a 48 x 48
 * Gauss-Legendre product rule over the other square: the kernel between
 * the squares, 1 / (pi r^4), is smooth at distance 1, so the rule is
 * converged to rounding and independent of radkit's couplings. */
#ifndef MANUFACTURED_CASE_H
#define MANUFACTURED_CASE_H

#include <math.h>

#include "rad_basis.h"
#include "rad_geom.h"
#include "rad_quad.h"
#include "rad_solve.h"

typedef struct manufactured_rule {
    double x[48], w[48]; /* Gauss-Legendre on [0, 1] */
} manufactured_rule;

static inline int manufactured_rule_init(manufactured_rule *m)
{
    return rad_quad_gauss_legendre(48, m->x, m->w) == RAD_OK;
}

static inline double manufactured_b_star(double x, double y, double z)
{
    return 2.0 + sin(2.0 * x + y + 3.0 * z);
}

/* rad_solve_params.emission: the same field in every channel */
static inline double manufactured_emission(int face, rad_vec3 p, int channel, void *ctx)
{
    (void)channel;
    const manufactured_rule *m = ctx;
    double z = face < 2 ? 1.0 : 0.0, g = 0.0; /* the other square's height */
    for (int i = 0; i < 48; i++)
        for (int j = 0; j < 48; j++) {
            double dx = m->x[i] - p.x, dy = m->x[j] - p.y, r2 = dx * dx + dy * dy + 1.0;
            g += m->w[i] * m->w[j] * manufactured_b_star(m->x[i], m->x[j], z) / (RAD_PI * r2 * r2);
        }
    return manufactured_b_star(p.x, p.y, p.z) - 0.5 * g;
}

/* The scene's parameters (every face reflecting 0.5; the emission comes from
 * the field) and a dense solve of order `order` at refinement `refine`. */
static inline void manufactured_scene_params(rad_scene_params *sp)
{
    rad_scene_params_default(sp);
    sp->has_rho = sp->has_emission = 1;
    for (int c = 0; c < 3; c++) {
        sp->rho[c] = 0.5;
        sp->emission[c] = 0.0;
    }
}

static inline void manufactured_solve_params(rad_solve_params *p, int order, int refine,
                                             manufactured_rule *m)
{
    rad_solve_params_default(p);
    p->basis = order;
    p->refine = refine;
    p->emission = manufactured_emission;
    p->emission_ctx = m;
}

/* The L2 error of a dense solution's polynomials against B* (channel 0),
 * by the symmetric degree-10 rule on every element; NAN if it is missing. */
static inline double manufactured_l2_error(const rad_solution *s)
{
    double rs[RAD_QUAD_TRI_MAX_POINTS], rt[RAD_QUAD_TRI_MAX_POINTS], rw[RAD_QUAD_TRI_MAX_POINTS];
    int np = 0, m = rad_basis_size(s->used.basis);
    if (!s->element_coef || rad_quad_tri_symmetric(10, rs, rt, rw, &np) != RAD_OK)
        return NAN;
    double sum = 0.0;
    for (size_t i = 0; i < s->elements; i++) {
        const double *c = s->element_corners + 9 * i;
        rad_vec3 t[3] = {{c[0], c[1], c[2]}, {c[3], c[4], c[5]}, {c[6], c[7], c[8]}};
        double area = rad_geom_triangle_area(t[0], t[1], t[2]);
        for (int k = 0; k < np; k++) {
            rad_vec3 x = rad_geom_triangle_point(t[0], t[1], t[2], rs[k], rt[k]);
            double d = rad_basis_value(s->used.basis, area, s->element_coef + i * (size_t)m,
                                       rs[k], rt[k]) -
                       manufactured_b_star(x.x, x.y, x.z);
            sum += area * rw[k] * d * d;
        }
    }
    return sqrt(sum);
}

#endif
