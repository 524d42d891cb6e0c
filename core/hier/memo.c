/* rad_hier: touching pairs' singular integrals, remembered.
 *
 * Elements that touch get their unoccluded G from a singular rule (ss:5 and
 * ss:4, or the contour-integral reference), tens of thousands of kernel
 * evaluations each.  Midpoint subdivision makes the same shapes again and
 * again: along an edge two input triangles share, the children that meet it
 * are translates of each other, and every level repeats the one above at
 * half the size.  So a pair is brought to a canonical frame: moved by its
 * first triangle's first corner, scaled by a power of two (exact) to a size
 * in [1/2, 1), and its coordinates rounded to multiples of 2^-40 (a shift of
 * about 1e-12 of its size, far inside the rules' 1e-4 to 1e-6).  The rule
 * runs on that canonical pair, never on the given one, so a value is a
 * function of its key alone: remembered or computed, on any thread or
 * process, a link gets the same bits.  G scales with the square of the
 * size; the form factors and the relative error do not scale.  The evals
 * returned are those the value took, remembered or not, so that work
 * counters do not depend on which thread computed a key first.
 *
 * The table is shared by the threads of an estimate batch (one lock; a
 * lookup is a few hundred instructions against the rule's tens of
 * thousands) and stops growing at MEMO_MAX entries (32 MB of slots). */
#include "rad_hier.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

enum { MEMO_KEY = 18, MEMO_MAX = 1 << 16 }; /* about 250 B each, at most half the slots used */

typedef struct memo_entry {
    double key[MEMO_KEY];
    int scheme, order, used;
    rad_ff_result res; /* in the canonical frame */
} memo_entry;

struct rad_hier_memo {
    rad_ff_params params;
    memo_entry *slot;
    size_t cap, n; /* cap a power of two, or 0 */
};

rad_hier_memo *rad_hier_memo_create(const rad_ff_params *params)
{
    rad_hier_memo *m = calloc(1, sizeof *m);
    if (m)
        m->params = *params;
    return m;
}

void rad_hier_memo_destroy(rad_hier_memo *m)
{
    if (!m)
        return;
    free(m->slot);
    free(m);
}

size_t rad_hier_memo_count(const rad_hier_memo *m) { return m ? m->n : 0; }

/* The canonical pair (key: ti then tj, corner by corner) and the scale s. */
static double canonical(const rad_vec3 ti[3], const rad_vec3 tj[3], double key[MEMO_KEY])
{
    rad_vec3 o = ti[0];
    double big = 0.0;
    for (int v = 1; v < 3; v++) {
        rad_vec3 d = rad_vec3_sub(ti[v], o);
        big = fmax(big, fmax(fabs(d.x), fmax(fabs(d.y), fabs(d.z))));
    }
    int e;
    frexp(big, &e); /* big = f 2^e, f in [1/2, 1) */
    const rad_vec3 *t[2] = {ti, tj};
    for (int k = 0; k < 2; k++)
        for (int v = 0; v < 3; v++) {
            rad_vec3 d = rad_vec3_sub(t[k][v], o);
            double c[3] = {d.x, d.y, d.z};
            for (int i = 0; i < 3; i++)
                key[9 * k + 3 * v + i] = ldexp(nearbyint(ldexp(c[i], 40 - e)), -40);
        }
    return ldexp(1.0, e);
}

static uint64_t hash(const double key[MEMO_KEY], int scheme, int order)
{
    uint64_t h = 1469598103934665603ull;
    for (int i = 0; i < MEMO_KEY; i++) {
        uint64_t b;
        memcpy(&b, &key[i], sizeof b);
        h = (h ^ b) * 1099511628211ull;
        h ^= h >> 29;
    }
    h = (h ^ (uint64_t)(unsigned)scheme) * 1099511628211ull;
    return ((h ^ (uint64_t)(unsigned)order) * 1099511628211ull) ^ (h >> 31);
}

/* The slot of the key, or the empty slot where it would go (cap > 0). */
static memo_entry *find(const rad_hier_memo *m, const double key[MEMO_KEY], int scheme,
                        int order)
{
    size_t i = (size_t)hash(key, scheme, order) & (m->cap - 1);
    for (;; i = (i + 1) & (m->cap - 1)) {
        memo_entry *s = &m->slot[i];
        if (!s->used || (s->scheme == scheme && s->order == order &&
                         memcmp(s->key, key, sizeof s->key) == 0))
            return s;
    }
}

static int grow(rad_hier_memo *m)
{
    size_t cap = m->cap ? 2 * m->cap : 1024;
    memo_entry *old = m->slot, *slot = calloc(cap, sizeof *slot);
    if (!slot)
        return 0;
    size_t oc = m->cap;
    m->slot = slot;
    m->cap = cap;
    for (size_t i = 0; i < oc; i++)
        if (old[i].used)
            *find(m, old[i].key, old[i].scheme, old[i].order) = old[i];
    free(old);
    return 1;
}

rad_status rad_hier_memo_compute(rad_hier_memo *m, const rad_vec3 ti[3], const rad_vec3 tj[3],
                                 rad_ff_rule rule, rad_ff_result *out)
{
    double key[MEMO_KEY];
    double s = canonical(ti, tj, key);
    int found = 0;
#pragma omp critical(rad_hier_memo)
    {
        if (m->cap) {
            const memo_entry *e = find(m, key, (int)rule.scheme, rule.order);
            if (e->used) {
                *out = e->res;
                found = 1;
            }
        }
    }
    if (!found) {
        rad_vec3 c[2][3];
        for (int k = 0; k < 2; k++)
            for (int v = 0; v < 3; v++)
                c[k][v] = rad_vec3_make(key[9 * k + 3 * v], key[9 * k + 3 * v + 1],
                                        key[9 * k + 3 * v + 2]);
        rad_status st = rad_ff_compute(c[0], c[1], rule, &m->params, out);
        if (st != RAD_OK)
            return st;
#pragma omp critical(rad_hier_memo)
        {
            if (m->n < MEMO_MAX && (2 * (m->n + 1) <= m->cap || grow(m))) {
                memo_entry *e = find(m, key, (int)rule.scheme, rule.order);
                if (!e->used) {
                    memcpy(e->key, key, sizeof e->key);
                    e->scheme = (int)rule.scheme;
                    e->order = rule.order;
                    e->res = *out;
                    e->used = 1;
                    m->n++;
                }
            }
        }
    }
    double s2 = s * s;
    out->G *= s2;
    out->A1 *= s2;
    out->A2 *= s2;
    return RAD_OK;
}
