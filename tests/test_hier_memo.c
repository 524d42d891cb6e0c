/* rad_hier_memo: the remembered singular integrals of touching pairs equal
 * rad_ff_compute of the pair itself (within the rules' accuracy, far below
 * it in fact), pairs equal up to translation and power-of-two scale share one
 * value, and that value's bits do not depend on which pair computed it. */
#include <math.h>
#include <string.h>

#include "harness.h"
#include "rad_ff.h"
#include "rad_hier.h"

static rad_vec3 V(double x, double y, double z) { return rad_vec3_make(x, y, z); }

static void move(const rad_vec3 in[3], double s, rad_vec3 d, rad_vec3 out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = rad_vec3_add(rad_vec3_scale(in[i], s), d);
}

/* The pairs hier meets (corners in eighths and sixteenths, so that moving
 * them by the tests' steps rounds nothing): an edge-adjacent pair at a right angle (two walls),
 * a vertex-adjacent pair, and a contact (a box's face standing on a floor
 * triangle, touching it along a segment without sharing a corner). */
static void pairs(rad_vec3 a[3][3], rad_vec3 b[3][3], rad_ff_rule rule[3])
{
    rad_vec3 ea[3] = {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)};
    rad_vec3 eb[3] = {V(1, 0, 0), V(0, 0, 0), V(0.375, 0, 0.8125)};
    rad_vec3 va[3] = {V(0, 0, 0), V(1, 0, 0), V(0.25, 0.875, 0)};
    rad_vec3 vb[3] = {V(0, 0, 0), V(-0.6875, 0.125, 0.4375), V(-0.125, -0.5, 0.625)};
    rad_vec3 ca[3] = {V(0, 0, 0), V(2, 0, 0), V(0, 2, 0)};
    rad_vec3 cb[3] = {V(0.25, 0.5, 0), V(0.875, 0.5, 0), V(0.5625, 0.5, 0.6875)};
    memcpy(a[0], ea, sizeof ea);
    memcpy(b[0], eb, sizeof eb);
    memcpy(a[1], va, sizeof va);
    memcpy(b[1], vb, sizeof vb);
    memcpy(a[2], ca, sizeof ca);
    memcpy(b[2], cb, sizeof cb);
    rule[0] = rule[1] = (rad_ff_rule){RAD_FF_SS, 5};
    rule[2] = (rad_ff_rule){RAD_FF_EXACT, 0};
}

TEST(hier_memo_equals_the_rule_and_shares_congruent_pairs)
{
    rad_ff_params p;
    rad_ff_params_default(&p);
    p = rad_ff_params_link_exact(&p);
    rad_hier_memo *m = rad_hier_memo_create(&p);
    CHECK(m != NULL && rad_hier_memo_count(m) == 0);
    rad_vec3 a[3][3], b[3][3];
    rad_ff_rule rule[3];
    pairs(a, b, rule);
    rad_vec3 shift = V(3.25, -17.5, 101.125);
    size_t expected = 0;
    for (int k = 0; k < 3; k++) {
        rad_ff_result direct, first;
        CHECK(rad_ff_compute(a[k], b[k], rule[k], &p, &direct) == RAD_OK);
        CHECK(direct.G > 0.0 && !(direct.flags & RAD_FF_FLAG_NOT_FACING));
        CHECK(rad_hier_memo_compute(m, a[k], b[k], rule[k], &first) == RAD_OK);
        CHECK_MSG(fabs(first.G - direct.G) <= 1e-12 * direct.G, "pair %d: memo G %.17g, rule %.17g",
                  k, first.G, direct.G);
        CHECK(first.evals == direct.evals || rule[k].scheme == RAD_FF_EXACT);
        size_t n = rad_hier_memo_count(m);
        CHECK(n == ++expected);
        /* moved, and scaled by powers of two: the same value, bit for bit,
           with G times the square of the scale, and nothing new remembered */
        for (int e = -3; e <= 3; e++) {
            double s = ldexp(1.0, e);
            rad_vec3 a2[3], b2[3];
            move(a[k], s, shift, a2);
            move(b[k], s, shift, b2);
            rad_ff_result again;
            CHECK(rad_hier_memo_compute(m, a2, b2, rule[k], &again) == RAD_OK);
            int same_error = again.rel_error == first.rel_error ||
                             (isnan(again.rel_error) && isnan(first.rel_error));
            CHECK_MSG(again.G == first.G * s * s && again.F12 == first.F12 && same_error,
                      "pair %d scaled by 2^%d: G %.17g, expected %.17g", k, e, again.G,
                      first.G * s * s);
            CHECK(again.evals == first.evals);
        }
        CHECK_MSG(rad_hier_memo_count(m) == n, "pair %d: %zu values remembered, expected %zu", k,
                  rad_hier_memo_count(m), n);
        /* another scale is another key, computed in its own frame: the
           same integral within the rule's accuracy */
        rad_vec3 a3[3], b3[3];
        move(a[k], 0.3, shift, a3);
        move(b[k], 0.3, shift, b3);
        rad_ff_result other;
        CHECK(rad_hier_memo_compute(m, a3, b3, rule[k], &other) == RAD_OK);
        CHECK_MSG(fabs(other.G - 0.09 * direct.G) <= 1e-9 * direct.G, "pair %d scaled by 0.3: %.17g",
                  k, other.G / 0.09);
        CHECK(rad_hier_memo_count(m) == ++expected);
    }
    /* another order of the same pair is another key */
    rad_ff_result low;
    rad_ff_rule ss4 = {RAD_FF_SS, 4};
    size_t n = rad_hier_memo_count(m);
    CHECK(rad_hier_memo_compute(m, a[0], b[0], ss4, &low) == RAD_OK);
    CHECK(rad_hier_memo_count(m) == n + 1);
    /* and a bad pair is the rule's error, not remembered */
    rad_vec3 flat[3] = {V(0, 0, 0), V(1, 0, 0), V(2, 0, 0)};
    rad_ff_result bad;
    CHECK(rad_hier_memo_compute(m, flat, b[0], rule[0], &bad) == RAD_EINPUT);
    CHECK(rad_hier_memo_count(m) == n + 1);
    rad_hier_memo_destroy(m);
    rad_hier_memo_destroy(NULL);
}

/* Many threads asking for the same few keys at once get the same bits. */
TEST(hier_memo_is_thread_safe)
{
    rad_ff_params p;
    rad_ff_params_default(&p);
    p = rad_ff_params_link_exact(&p);
    rad_hier_memo *m = rad_hier_memo_create(&p);
    rad_vec3 a[3][3], b[3][3];
    rad_ff_rule rule[3];
    pairs(a, b, rule);
    enum { N = 96 };
    double G[N];
    int bad = 0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(4) reduction(+ : bad)
    for (int i = 0; i < N; i++) {
        int k = i % 3;
        rad_vec3 a2[3], b2[3];
        double s = ldexp(1.0, i % 5 - 2);
        move(a[k], s, V(i, 0.5 * i, -i), a2);
        move(b[k], s, V(i, 0.5 * i, -i), b2);
        rad_ff_result r;
        bad += rad_hier_memo_compute(m, a2, b2, rule[k], &r) != RAD_OK;
        G[i] = r.G / (s * s);
    }
    CHECK(bad == 0);
    for (int i = 3; i < N; i++)
        CHECK_MSG(G[i] == G[i % 3], "call %d: %.17g, call %d: %.17g", i, G[i], i % 3, G[i % 3]);
    CHECK(rad_hier_memo_count(m) == 3);
    rad_hier_memo_destroy(m);
}
