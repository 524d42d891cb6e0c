/* Internal to rad_mc: the per-triangle tables a path reads, the random number
 * generator, and the one-path estimator (path.c). */
#ifndef MC_INTERNAL_H
#define MC_INTERNAL_H

#include <stdint.h>

#include "rad_geom.h"
#include "rad_mc.h"
#include "rad_sys.h"

/* A counter-based generator: splitmix64 over a 64-bit state, seeded per
 * sample from (seed, triangle, sample) so that results do not depend on which
 * thread draws them \cite{steele2014splitmix}. */
typedef struct mc_rng {
    uint64_t state;
} mc_rng;

/* Uniform on [0, 1) with 53 random bits: the stream of rad_sys_hash64. */
static inline double mc_uniform(mc_rng *r)
{
    uint64_t bits = rad_sys_hash64(r->state);
    r->state += RAD_SYS_GOLDEN;
    return rad_sys_unit(bits);
}

static inline void mc_rng_seed(mc_rng *r, uint64_t seed, uint64_t tri, uint64_t sample)
{
    r->state = rad_sys_mix64(seed ^ rad_sys_mix64(tri * RAD_SYS_GOLDEN ^ rad_sys_mix64(sample + 1)));
}

/* What a path needs of one triangle. */
typedef struct mc_tri {
    rad_vec3 a, ab, ac;   /* corner and edges: x = a + s ab + t ac */
    rad_vec3 n, t1, t2;   /* unit normal and a tangent frame */
    double area;
    double rho[3], E[3];
    double light_pdf;     /* area density of next-event points on it (0: not an emitter) */
} mc_tri;

typedef struct mc_scene {
    const mc_tri *tris;
    size_t ntris;
    const int *emitters;      /* triangles with some emission */
    const double *emit_prob;  /* alias table over the emitters, in proportion to */
    const int *emit_alias;    /* area x summed emission (mc_pick_emitter) */
    size_t nemitters;
    const rad_vis *vis;
    int occlusion, next_event, max_depth;
    double rr_weight;
    /* Continuation rays start this far out: the ray epsilon of the
     * visibility, beyond float rounding of the origin, so that the filter
     * that rejects the path vertex's own triangle runs only on the rare
     * grazing ray. */
    double tnear;
} mc_scene;

/* An emitter index in proportion to area x power, from one uniform number:
 * Walker's alias method \cite{walker1977alias} with Vose's construction
 * \cite{vose1991alias}, constant time where a binary search of a cumulative
 * table mispredicts a branch per level. */
static inline size_t mc_pick_emitter(const mc_scene *s, double u)
{
    double x = u * (double)s->nemitters;
    size_t k = (size_t)x;
    if (k >= s->nemitters)
        k = s->nemitters - 1;
    return x - (double)k < s->emit_prob[k] ? k : (size_t)s->emit_alias[k];
}

/* Work of one path. */
typedef struct mc_counts {
    long long rays, bounces, too_long;
} mc_counts;

/* H(x) at the point x of triangle t (irradiance, W/m^2 per channel) by one
 * path: next-event estimation and cosine continuation combined by MIS,
 * Russian roulette on the throughput.  first (or NULL) gives the first
 * vertex's uniform numbers: [0..1] the direction, [2..3] the emitter point. */
void mc_path_irradiance(const mc_scene *s, int t, rad_vec3 x, mc_rng *rng, const double *first,
                        double H[3], mc_counts *counts);

#endif
