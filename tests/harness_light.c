/* An independent check of radkit's Monte Carlo reference: a light tracer
 * that shares no code with core/ (its own ray-triangle test over every
 * triangle, its own generator and sampling).  Photons leave the emitters
 * (a point uniform on a triangle chosen by its emitted power, a cosine
 * direction), and every hit on a front face adds the photon's flux to that
 * face's incident flux; the photon goes on with probability max rho, its
 * channels scaled by rho / max rho.  Then B = E + rho Phi_in / A.  It
 * estimates the transport adjoint to radkit's path tracer (which gathers
 * from the receivers), so a shared mistake would have to be made twice in
 * opposite directions. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"

typedef struct lt_vec {
    double x, y, z;
} lt_vec;

static lt_vec lt_sub(lt_vec a, lt_vec b) { return (lt_vec){a.x - b.x, a.y - b.y, a.z - b.z}; }
static lt_vec lt_add(lt_vec a, lt_vec b) { return (lt_vec){a.x + b.x, a.y + b.y, a.z + b.z}; }
static lt_vec lt_mul(lt_vec a, double s) { return (lt_vec){a.x * s, a.y * s, a.z * s}; }
static double lt_dot(lt_vec a, lt_vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static lt_vec lt_cross(lt_vec a, lt_vec b)
{
    return (lt_vec){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

static double lt_uniform(uint64_t *s)
{
    /* xorshift64* */
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 0x2545F4914F6CDD1DULL) >> 11) * (1.0 / 9007199254740992.0);
}

typedef struct lt_scene {
    const lt_vec *p; /* 3 corners per triangle */
    const lt_vec *n; /* unit normal per triangle */
    int count;
} lt_scene;

/* The nearest triangle hit by o + t d, t > 0, other than skip; -1 for none. */
static int lt_hit(const lt_scene *s, lt_vec o, lt_vec d, int skip, double *t_hit)
{
    int best = -1;
    double bt = INFINITY;
    for (int i = 0; i < s->count; i++) {
        if (i == skip)
            continue;
        const lt_vec *p = s->p + 3 * i;
        lt_vec e1 = lt_sub(p[1], p[0]), e2 = lt_sub(p[2], p[0]), pv = lt_cross(d, e2);
        double det = lt_dot(e1, pv);
        if (fabs(det) < 1e-300)
            continue;
        lt_vec tv = lt_sub(o, p[0]);
        double u = lt_dot(tv, pv) / det;
        if (u < 0.0 || u > 1.0)
            continue;
        lt_vec qv = lt_cross(tv, e1);
        double v = lt_dot(d, qv) / det;
        if (v < 0.0 || u + v > 1.0)
            continue;
        double t = lt_dot(e2, qv) / det;
        if (t > 1e-12 && t < bt) {
            bt = t;
            best = i;
        }
    }
    *t_hit = bt;
    return best;
}

int harness_light_trace(const double *xyz, const int *tri, int n, const double *rho,
                        const double *E, long photons, int batches, uint64_t seed, double *B,
                        double *se)
{
    lt_vec *p = malloc((size_t)n * 4 * sizeof *p);
    double *area = malloc((size_t)n * 2 * sizeof *area);
    double *tally = calloc((size_t)n * 3 * (size_t)(batches + 2), sizeof *tally);
    if (!p || !area || !tally || batches < 2 || n <= 0) {
        free(p);
        free(area);
        free(tally);
        return -1;
    }
    lt_vec *nrm = p + 3 * (size_t)n;
    double *cdf = area + n, total = 0.0;
    for (int i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            const double *q = xyz + 3 * tri[3 * i + k];
            p[3 * i + k] = (lt_vec){q[0], q[1], q[2]};
        }
        lt_vec c = lt_cross(lt_sub(p[3 * i + 1], p[3 * i]), lt_sub(p[3 * i + 2], p[3 * i]));
        double len = sqrt(lt_dot(c, c));
        area[i] = 0.5 * len;
        nrm[i] = len > 0.0 ? lt_mul(c, 1.0 / len) : (lt_vec){0, 0, 0};
        total += area[i] * (E[i] + E[i + n] + E[i + 2 * n]);
        cdf[i] = total;
    }
    if (!(total > 0.0)) {
        free(p);
        free(area);
        free(tally);
        return -1;
    }
    lt_scene s = {p, nrm, n};
    uint64_t state = seed ? seed : 1;
    long per = photons / batches;
    for (int b = 0; b < batches; b++) {
        double *t = tally + (size_t)b * 3 * (size_t)n;
        for (long k = 0; k < per; k++) {
            double r = lt_uniform(&state) * total;
            int lo = 0, hi = n - 1;
            while (lo < hi) {
                int mid = (lo + hi) / 2;
                if (cdf[mid] < r)
                    lo = mid + 1;
                else
                    hi = mid;
            }
            int from = lo;
            double sum = E[from] + E[from + n] + E[from + 2 * n], w[3];
            for (int c = 0; c < 3; c++)
                w[c] = E[from + c * n] / sum * total / (double)per;
            double u = lt_uniform(&state), v = lt_uniform(&state);
            if (u + v > 1.0) {
                u = 1.0 - u;
                v = 1.0 - v;
            }
            const lt_vec *q = p + 3 * from;
            lt_vec o = lt_add(q[0], lt_add(lt_mul(lt_sub(q[1], q[0]), u), lt_mul(lt_sub(q[2], q[0]), v)));
            for (int depth = 0; depth < 10000; depth++) {
                lt_vec nn = nrm[from];
                lt_vec a = fabs(nn.x) > 0.5 ? (lt_vec){0, 1, 0} : (lt_vec){1, 0, 0};
                lt_vec tu = lt_cross(nn, a);
                tu = lt_mul(tu, 1.0 / sqrt(lt_dot(tu, tu)));
                lt_vec tv = lt_cross(nn, tu);
                double r1 = lt_uniform(&state), r2 = 2.0 * RAD_PI * lt_uniform(&state);
                double sr = sqrt(r1);
                lt_vec d = lt_add(lt_add(lt_mul(tu, sr * cos(r2)), lt_mul(tv, sr * sin(r2))),
                                  lt_mul(nn, sqrt(1.0 - r1)));
                double th;
                int h = lt_hit(&s, o, d, from, &th);
                if (h < 0 || lt_dot(d, nrm[h]) >= 0.0)
                    break; /* escaped, or a back face: absorbed */
                for (int c = 0; c < 3; c++)
                    t[h + c * n] += w[c];
                double pmax = fmax(rho[h], fmax(rho[h + n], rho[h + 2 * n]));
                if (!(pmax > 0.0) || lt_uniform(&state) >= pmax)
                    break;
                for (int c = 0; c < 3; c++)
                    w[c] *= rho[h + c * n] / pmax;
                o = lt_add(o, lt_mul(d, th));
                from = h;
            }
        }
    }
    for (int i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            size_t k = (size_t)i + (size_t)c * (size_t)n;
            double m = 0.0, m2 = 0.0;
            for (int b = 0; b < batches; b++) {
                double x = area[i] > 0.0
                               ? rho[k] * tally[(size_t)b * 3 * (size_t)n + k] / area[i]
                               : 0.0;
                m += x;
                m2 += x * x;
            }
            m /= batches;
            m2 /= batches;
            B[k] = E[k] + m;
            se[k] = sqrt(fmax(0.0, m2 - m * m) / (batches - 1));
        }
    free(p);
    free(area);
    free(tally);
    return 0;
}
