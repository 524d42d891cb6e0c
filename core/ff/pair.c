/* Entry point of rad_ff: validation, the normalised pair, the facing test,
 * adjacency, the dispatch to a scheme, and the rule names.
 *
 * 1. Reject non-finite or degenerate triangles (RAD_EINPUT; degeneracy is a
 *    matter of shape, not size), and pairs so small that their areas leave
 *    double precision's normal range (RAD_EINPUT: scale the pair up).
 * 2. Normalise: translate ti[0] to the origin, divide by the longest edge L.
 *    Every decision below is taken on the normalised pair, so it depends on
 *    the pair's shape only: scaling both triangles by 1e-100 changes nothing.
 * 3. Facing test: the clamped kernel vanishes identically when every vertex of
 *    one triangle lies behind or on the other's plane: the pair faces away or
 *    is coplanar, and G = 0 exactly, without integration.  "On" means within
 *    rounding: plane_rel_tol times the larger of the pair's extent and the
 *    coordinates' magnitude (both over L), the error of the plane test and of
 *    the input's own digits.  Any larger gap is real: facing triangles a tiny
 *    gap apart are integrated (F tends to the overlap's share, 1 for
 *    identical triangles, as the gap closes) instead of jumping to 0.
 * 4. A pair that is coplanar within that rounding, with opposite normals and
 *    overlapping interiors, is flagged RAD_FF_FLAG_COINCIDENT: 0 is right for
 *    the two sides of one surface, but the value jumps there.
 * 5. Detect shared vertices (rad_ff_adjacency_detect) and run the scheme.
 * 6. Scale G back by L^2, F12 = G / A1, F21 = G / A2, flag values outside [0,1]. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ff_internal.h"

void rad_ff_params_default(rad_ff_params *params)
{
    *params = (rad_ff_params){.adjacency_rel_tol = 1e-10,
                              .plane_rel_tol = 64 * DBL_EPSILON,
                              .degenerate_rel_tol = 1e-12,
                              .exact_rel_tol = 1e-14,
                              .exact_far_ratio = 5.0,
                              .exact_retry_rel = 1e-12,
                              .exact_flag_rel = 1e-10,
                              .auto_near_ratio = 0.5,
                              .auto_min_ratio = 0.05,
                              .auto_exact_cost = 35000,
                              .auto_safety = 0.1,
                              .tol = 1e-6,
                              .skip_facing_away = 1,
                              .singular_rules = 1};
}

rad_ff_params rad_ff_params_link_exact(const rad_ff_params *params)
{
    rad_ff_params p = *params;
    p.exact_rel_tol = fmax(p.exact_rel_tol, 1e-6);
    p.exact_retry_rel = fmax(p.exact_retry_rel, 1e-3);
    p.exact_flag_rel = fmax(p.exact_flag_rel, 1e-3);
    return p;
}

double rad_ff_kernel(rad_vec3 x, rad_vec3 nx, rad_vec3 y, rad_vec3 ny, long *guarded)
{
    return ff_kernel(x, nx, y, ny, guarded);
}

rad_ff_adjacency rad_ff_adjacency_detect(const rad_vec3 ti[3], const rad_vec3 tj[3],
                                         double rel_tol, int map_i[3])
{
    double tol = rel_tol * rad_dmin(rad_geom_triangle_longest_edge(ti), rad_geom_triangle_longest_edge(tj));
    int shared = 0;
    for (int a = 0; a < 3; a++) {
        map_i[a] = -1;
        double best = tol;
        for (int b = 0; b < 3; b++) {
            double d = rad_vec3_norm(rad_vec3_sub(ti[a], tj[b]));
            if (d <= best) {
                best = d;
                map_i[a] = b;
            }
        }
        shared += map_i[a] >= 0;
    }
    return shared == 0 ? RAD_FF_DISJOINT
           : shared == 1 ? RAD_FF_SHARE_VERTEX
           : shared == 2 ? RAD_FF_SHARE_EDGE
                         : RAD_FF_SHARE_ALL;
}

/* Largest signed distance of t's vertices in front of the plane (o, n). */
static double max_front(const rad_vec3 t[3], rad_vec3 n, rad_vec3 o)
{
    double m = -INFINITY;
    for (int k = 0; k < 3; k++)
        m = rad_dmax(m, rad_vec3_dot(n, rad_vec3_sub(t[k], o)));
    return m;
}

static const char *scheme_name[] = {"vertex", "centroid", "gauss", "analytic", "ss", "exact", "auto"};

void rad_ff_rule_format(rad_ff_rule rule, char *buf, size_t size)
{
    if (rule.scheme == RAD_FF_GAUSS || rule.scheme == RAD_FF_ANALYTIC || rule.scheme == RAD_FF_SS)
        snprintf(buf, size, "%s:%d", scheme_name[rule.scheme], rule.order);
    else
        snprintf(buf, size, "%s", scheme_name[rule.scheme]);
}

rad_status rad_ff_rule_parse(const char *text, rad_ff_rule *rule)
{
    if (!text || !*text)
        return RAD_ERROR(RAD_EINVAL, "empty rule (expected vertex, centroid, gauss:P, analytic:P, ss:N, exact or auto)");
    const char *colon = strchr(text, ':');
    size_t len = colon ? (size_t)(colon - text) : strlen(text);
    for (int s = 0; s <= RAD_FF_AUTO; s++) {
        if (strlen(scheme_name[s]) != len || strncmp(scheme_name[s], text, len) != 0)
            continue;
        int needs_order = s == RAD_FF_GAUSS || s == RAD_FF_ANALYTIC || s == RAD_FF_SS;
        rule->scheme = (rad_ff_scheme)s;
        rule->order = 0;
        if (!needs_order) {
            if (colon)
                return RAD_ERROR(RAD_EINVAL, "rule '%s' takes no order (got '%s')", scheme_name[s], text);
            return RAD_OK;
        }
        const char *what = s == RAD_FF_SS ? "N" : "P";
        if (!colon || !colon[1])
            return RAD_ERROR(RAD_EINVAL, "rule '%s' needs an order: %s:%s", text, scheme_name[s], what);
        char *end = NULL;
        long v = strtol(colon + 1, &end, 10);
        if (*end != '\0')
            return RAD_ERROR(RAD_EINVAL, "rule '%s': order '%s' is not a whole number", text, colon + 1);
        long lo = s == RAD_FF_SS ? 1 : 0, hi = s == RAD_FF_SS ? RAD_FF_SS_MAX : RAD_FF_MAX_DEGREE;
        if (v < lo || v > hi)
            return RAD_ERROR(RAD_EINVAL, "rule '%s': unsupported order %ld (%s:%s takes %ld to %ld)", text,
                             v, scheme_name[s], what, lo, hi);
        rule->order = (int)v;
        return RAD_OK;
    }
    return RAD_ERROR(RAD_EINVAL,
                     "unknown rule '%s' (expected vertex, centroid, gauss:P, analytic:P, ss:N, exact or auto)",
                     text);
}

/* Step 2: the pair translated by -ti[0] and divided by the longest edge L
 * (returned), with unit normals and areas; *round gets the rounding scale of
 * the plane test in normalised units: the larger of the pair's extent and
 * its coordinates' magnitude over L (at least 1). */
static double normalise_pair(const rad_vec3 ti[3], const rad_vec3 tj[3], ff_pair *pr,
                             double *round)
{
    const rad_vec3 *t[2] = {ti, tj};
    double L = rad_dmax(rad_geom_triangle_longest_edge(ti), rad_geom_triangle_longest_edge(tj));
    rad_vec3 o = ti[0];
    double extent = 1.0, magnitude = 0.0;
    for (int k = 0; k < 2; k++) {
        for (int v = 0; v < 3; v++) {
            rad_vec3 q = t[k][v];
            pr->p[k][v] = rad_vec3_scale(rad_vec3_sub(q, o), 1.0 / L);
            extent = rad_dmax(extent, rad_dmax(rad_dmax(fabs(pr->p[k][v].x), fabs(pr->p[k][v].y)),
                                               fabs(pr->p[k][v].z)));
            magnitude = rad_dmax(magnitude, rad_dmax(rad_dmax(fabs(q.x), fabs(q.y)), fabs(q.z)));
        }
        pr->n[k] = rad_geom_triangle_normal(pr->p[k][0], pr->p[k][1], pr->p[k][2]);
        pr->A[k] = rad_geom_triangle_area(pr->p[k][0], pr->p[k][1], pr->p[k][2]);
    }
    *round = rad_dmax(extent, magnitude / L);
    return L;
}

/* Step 3: 0 when every vertex of one triangle lies behind or on the other's
 * plane (within tol of the normalised pair). */
static int pair_faces(const ff_pair *pr, double tol)
{
    return !(max_front(pr->p[1], pr->n[0], pr->p[0][0]) <= tol ||
             max_front(pr->p[0], pr->n[1], pr->p[1][0]) <= tol);
}

/* Whether every vertex of t lies within tol of the plane (o, n). */
static int on_plane(const rad_vec3 t[3], rad_vec3 n, rad_vec3 o, double tol)
{
    for (int k = 0; k < 3; k++)
        if (!(fabs(rad_vec3_dot(n, rad_vec3_sub(t[k], o))) <= tol))
            return 0;
    return 1;
}

/* Step 4, for a pair in one plane (normal n): whether the interiors overlap,
 * i.e. no edge of either triangle separates them (separating axes; touching
 * within tol does not count as overlap). */
static int coplanar_overlap(const ff_pair *pr, rad_vec3 n, double tol)
{
    for (int k = 0; k < 2; k++)
        for (int e = 0; e < 3; e++) {
            rad_vec3 a = pr->p[k][e], b = pr->p[k][(e + 1) % 3], c = pr->p[k][(e + 2) % 3];
            rad_vec3 m = rad_vec3_cross(rad_vec3_sub(b, a), n); /* in the plane, across the edge */
            if (rad_vec3_dot(m, rad_vec3_sub(c, a)) > 0.0)
                m = rad_vec3_scale(m, -1.0); /* pointing away from the triangle */
            double lo = INFINITY;
            for (int v = 0; v < 3; v++)
                lo = rad_dmin(lo, rad_vec3_dot(m, rad_vec3_sub(pr->p[1 - k][v], a)));
            if (lo >= -tol * rad_vec3_norm(m))
                return 0;
        }
    return 1;
}

int rad_ff_facing(const rad_vec3 ti[3], const rad_vec3 tj[3], const rad_ff_params *params)
{
    ff_pair pr;
    double round;
    normalise_pair(ti, tj, &pr, &round);
    rad_ff_params defaults;
    if (!params) {
        rad_ff_params_default(&defaults);
        params = &defaults;
    }
    return pair_faces(&pr, round * params->plane_rel_tol);
}

rad_status rad_ff_compute(const rad_vec3 ti[3], const rad_vec3 tj[3], rad_ff_rule rule,
                          const rad_ff_params *params, rad_ff_result *out)
{
    rad_ff_params p;
    if (params)
        p = *params;
    else
        rad_ff_params_default(&p);
    memset(out, 0, sizeof *out);
    out->rel_error = NAN;
    out->used = rule;
    const rad_vec3 *t[2] = {ti, tj};
    for (int k = 0; k < 2; k++) {
        for (int v = 0; v < 3; v++)
            if (!rad_vec3_is_finite(t[k][v]))
                return RAD_ERROR(RAD_EINPUT, "triangle %d, vertex %d: non-finite coordinate", k + 1, v + 1);
            else if (!rad_vec3_in_range(t[k][v]))
                return RAD_ERROR(RAD_EINPUT, "triangle %d, vertex %d: a coordinate beyond %g, where "
                                 "form-factor products overflow; scale the pair down", k + 1, v + 1,
                                 RAD_GEOM_MAX_COORD);
        if (rad_geom_triangle_is_degenerate(t[k][0], t[k][1], t[k][2], p.degenerate_rel_tol))
            return RAD_ERROR(RAD_EINPUT, "triangle %d is degenerate (zero area or collinear vertices)", k + 1);
        /* G = A F scales with the area: below DBL_MIN it loses digits, then vanishes */
        double area = rad_geom_triangle_area(t[k][0], t[k][1], t[k][2]);
        if (!(area >= DBL_MIN))
            return RAD_ERROR(RAD_EINPUT, "triangle %d: its area %.3g is below %.3g, where double "
                             "precision loses digits; scale the pair up", k + 1, area, DBL_MIN);
    }
    if ((rule.scheme == RAD_FF_GAUSS || rule.scheme == RAD_FF_ANALYTIC) &&
        (rule.order < 0 || rule.order > RAD_FF_MAX_DEGREE))
        return RAD_ERROR(RAD_EINVAL, "unsupported degree %d (0 to %d)", rule.order, RAD_FF_MAX_DEGREE);
    if (rule.scheme == RAD_FF_SS && (rule.order < 1 || rule.order > RAD_FF_SS_MAX))
        return RAD_ERROR(RAD_EINVAL, "unsupported ss order %d (1 to %d)", rule.order, RAD_FF_SS_MAX);
    if (rule.scheme == RAD_FF_AUTO && !(p.tol > 0.0 && p.tol < 1.0))
        return RAD_ERROR(RAD_EINVAL, "auto: tolerance must lie in (0, 1), got %g", p.tol);

    ff_pair pr;
    double round;
    double L = normalise_pair(ti, tj, &pr, &round);
    out->A1 = rad_geom_triangle_area(ti[0], ti[1], ti[2]);
    out->A2 = rad_geom_triangle_area(tj[0], tj[1], tj[2]);
    /* on the normalised pair: relative to size, and no squares of tiny lengths */
    pr.adj = rad_ff_adjacency_detect(pr.p[0], pr.p[1], p.adjacency_rel_tol, pr.map);
    out->adjacency = pr.adj;

    /* Facing test (step 3), and the coincident pair (step 4). */
    double plane_tol = round * p.plane_rel_tol;
    if (p.skip_facing_away && !pair_faces(&pr, plane_tol)) {
        out->flags |= RAD_FF_FLAG_NOT_FACING;
        out->rel_error = 0.0;
        if (rad_vec3_dot(pr.n[0], pr.n[1]) < 0.0 &&
            on_plane(pr.p[1], pr.n[0], pr.p[0][0], plane_tol) &&
            on_plane(pr.p[0], pr.n[1], pr.p[1][0], plane_tol) &&
            coplanar_overlap(&pr, pr.n[0], plane_tol))
            out->flags |= RAD_FF_FLAG_COINCIDENT;
        return RAD_OK;
    }

    ff_value v = {0};
    rad_status st = RAD_OK;
    switch (rule.scheme) {
    case RAD_FF_VERTEX: v = ff_vertex(&pr); break;
    case RAD_FF_CENTROID: v = ff_centroid(&pr); break;
    case RAD_FF_GAUSS: st = ff_gauss(&pr, rule.order, &v); break;
    case RAD_FF_ANALYTIC: st = ff_analytic(&pr, rule.order, &v); break;
    case RAD_FF_SS: st = ff_ss(&pr, rule.order, &v); break;
    case RAD_FF_EXACT: v = ff_exact(&pr, &p); break;
    case RAD_FF_AUTO: st = ff_auto(&pr, &p, &v, &out->used); break;
    default: return RAD_ERROR(RAD_EINVAL, "unknown form-factor scheme %d", (int)rule.scheme);
    }
    if (st != RAD_OK)
        return st;
    out->G = v.G * L * L;
    out->F12 = v.G / pr.A[0];
    out->F21 = v.G / pr.A[1];
    out->rel_error = v.rel_error;
    out->evals = v.evals;
    out->guarded = v.guarded;
    out->flags |= v.flags;
    if (v.guarded > 0)
        out->flags |= RAD_FF_FLAG_GUARDED;
    if (!(out->F12 >= 0.0 && out->F12 <= 1.0) || !(out->F21 >= 0.0 && out->F21 <= 1.0))
        out->flags |= RAD_FF_FLAG_OUT_OF_RANGE;
    return RAD_OK;
}
