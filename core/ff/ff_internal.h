/* Internal to rad_ff: the prepared pair every scheme works on. */
#ifndef RAD_FF_INTERNAL_H
#define RAD_FF_INTERNAL_H

#include "rad_ff.h"


/* The pair in normalised coordinates: origin at ti[0], lengths divided by the
 * longest edge of the pair, so every scheme sees sizes of order 1 whatever the
 * input's scale or position (scale and translation invariance to rounding). */
typedef struct ff_pair {
    rad_vec3 p[2][3]; /* vertices, normalised */
    rad_vec3 n[2];    /* unit normals */
    double A[2];      /* areas, normalised */
    int map[3];       /* ti vertex -> tj vertex, or -1 */
    rad_ff_adjacency adj;
} ff_pair;

/* What a scheme returns: G in normalised units and its bookkeeping. */
typedef struct ff_value {
    double G, rel_error;
    long evals, guarded;
    unsigned flags;
} ff_value;

static inline double ff_kernel(rad_vec3 x, rad_vec3 nx, rad_vec3 y, rad_vec3 ny, long *guarded)
{
    rad_vec3 d = rad_vec3_sub(y, x);
    double r2 = rad_vec3_dot(d, d);
    if (!(r2 > 0.0)) {
        if (guarded)
            (*guarded)++;
        return 0.0;
    }
    double ci = rad_vec3_dot(nx, d), cj = -rad_vec3_dot(ny, d);
    if (!(ci > 0.0) || !(cj > 0.0))
        return 0.0;
    return (ci / r2) * (cj / r2) * (1.0 / RAD_PI);
}

/* Clip polygon in[0..n) (n <= FF_CLIP_MAX) to the open half-space
 * {y : nrm . (y - o) > 0}; out needs n + 1 entries.  Returns the new vertex
 * count (0 if empty, or n out of range). */
#define FF_CLIP_MAX 8
int ff_clip(const rad_vec3 *in, int n, rad_vec3 nrm, rad_vec3 o, rad_vec3 *out);

ff_value ff_vertex(const ff_pair *pr);
ff_value ff_centroid(const ff_pair *pr);
rad_status ff_gauss(const ff_pair *pr, int degree, ff_value *v);
rad_status ff_analytic(const ff_pair *pr, int degree, ff_value *v);
rad_status ff_ss(const ff_pair *pr, int n, ff_value *v);
/* int_z0^z1 ln sqrt(z^2 + h^2) dz in closed form (h >= 0), exact's inner integral. */
double ff_log_segment(double z0, double z1, double h);
ff_value ff_exact(const ff_pair *pr, const rad_ff_params *params);
rad_status ff_auto(const ff_pair *pr, const rad_ff_params *params, ff_value *v, rad_ff_rule *used);
/* Points and weights (summing to 1) of the degree-P rule used by gauss:P and
 * analytic:P: symmetric up to degree 10, collapsed Gauss beyond. */
rad_status ff_tri_rule(int degree, double *s, double *t, double *w, int *n);
#define FF_RULE_MAX_POINTS (((RAD_FF_MAX_DEGREE + 3) / 2) * ((RAD_FF_MAX_DEGREE + 3) / 2))

#endif
