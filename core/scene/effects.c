/* The effects plan: decide, from the scene alone, which effects a radiosity
 * run must simulate (DESIGN.md, "Effects"), each with its reason.
 *
 *  1. Occlusion.  If every vertex lies on the front side of (or on) every
 *     face's plane (rad_mesh_info.convex_inside; e.g. a convex closed
 *     enclosure seen from inside, two facing plates), no face can block a pair:
 *     a blocker k would need the two end points on opposite sides of k's
 *     plane, but every point is on its front side, and a segment lying in the
 *     plane contributes nothing (both cosines vanish).  Off then; otherwise
 *     visibility is decided per pair.
 *  2. Colour.  When every reflectance is grey (channels within grey_tol), the
 *     matrix I - rho F is the same for the three channels: one scalar system
 *     (with three right-hand sides if the emission is coloured).
 *  3. Facing-away pairs.  The kernel is zero unless both cosines are positive;
 *     for flat triangles, if all of j's corners are behind or on i's plane
 *     (or vice versa) F_ij = 0 exactly: skip such pairs.  Always on; the pairs
 *     are counted when the scene has at most pair_scan_max_faces faces.
 *  4. Singular quadrature.  Only pairs that touch (shared edge or vertex) and
 *     are not coplanar have an integrable singularity of the kernel; coplanar
 *     touching pairs have a zero kernel.  On when such pairs exist.
 *  5. Reflectance near 1.  An error d in a row of form factors (energy lost
 *     or gained per bounce) changes B by up to d / (1 - rho) after all
 *     bounces, and a solver stopped at a step change c is up to
 *     c rho / (1 - rho) from its fixed point.  The defaults are set for
 *     rho_max <= near_one; above it every such tolerance is multiplied by
 *     tighten = (1 - rho_max) / (1 - near_one).  Beyond an amplification of
 *     max_amplification no tolerance double precision can deliver would do:
 *     the plan refuses (refusal), and the solvers exit with its reason.
 *  6. Clustering.  Hierarchical radiosity links every pair of input
 *     triangles that face each other before it refines; with clustering,
 *     links start from the n - 1 sibling pairs of a cluster hierarchy
 *     instead.  That pays where those first links are many against what
 *     refinement keeps.  Where nothing can block (a convex enclosure) a
 *     cluster link's rays always agree and its terms stay small, so the
 *     layer pays from a few ten thousand facing pairs.  Among occluders the
 *     cluster links' errors refine many pairs down to elements, so the
 *     layer pays later, once hier's first links are some hundred thousand
 *     (papers/clustering.md, "when the layer pays", has the measurements).
 *     So clustering is on from cluster_min_pairs (2.5e5) facing pairs where
 *     faces can block each other, from cluster_min_pairs_clear (2e4) where
 *     nothing can block, and always above the scan limit (pairs not
 *     counted).  The solve pipeline
 *     settles it for the method (only hier with constant elements acts on
 *     it; --method cluster forces it on).
 *  7. Contact.  Where a triangle stands on another's inside (a box on a
 *     floor) the floor's radiosity jumps along the line of contact: under
 *     the box it is dark and unseen.  Hierarchical radiosity cuts such
 *     triangles along the line (rad_mesh_split_contacts) and solves on the
 *     pieces, each input triangle's row the area-weighted mean of its
 *     pieces; dense and Monte Carlo solve on the input triangles.
 * Every decision can be forced on or off; the reason then says so.  Each one
 * changes what the solvers run (rad_solve.h says how).
 * The kernel, its support and its singularities: [cohen1993], chapters 3-4. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rad_geom.h"
#include "scene_internal.h"

void rad_scene_effects_params_default(rad_effects_params *p)
{
    memset(p, 0, sizeof *p);
    p->pair_scan_max_faces = 20000;
    p->cluster_min_pairs = 2.5e5;
    p->cluster_min_pairs_clear = 2e4;
    p->grey_tol = 1e-12;
    p->plane_rel_tol = 1e-12;
    p->near_one = 0.5;
    p->max_amplification = 1e6;
    p->contact_rel_tol = 1e-6;
    p->contact_near_rel = 0.1;
    p->contact_near_rel_large = 0.25;
}

void rad_scene_effects_list(const rad_effects_plan *plan,
                            const rad_effect_decision *dec[RAD_EFFECT_COUNT],
                            const char *names[RAD_EFFECT_COUNT])
{
    static const char *const all[RAD_EFFECT_COUNT] = {"occlusion", "colour", "facing_away",
                                                      "singular", "reflectance", "clustering",
                                                      "contact"};
    const rad_effect_decision *d[RAD_EFFECT_COUNT] = {&plan->occlusion, &plan->colour,
                                                      &plan->facing_away, &plan->singular,
                                                      &plan->reflectance, &plan->clustering,
                                                      &plan->contact};
    for (int k = 0; k < RAD_EFFECT_COUNT; k++) {
        if (dec)
            dec[k] = d[k];
        if (names)
            names[k] = all[k];
    }
}

rad_status rad_scene_effect_mode_parse(const char *what, const char *text, rad_effect_mode *out)
{
    if (text && strcmp(text, "auto") == 0)
        *out = RAD_EFFECT_AUTO;
    else if (text && strcmp(text, "on") == 0)
        *out = RAD_EFFECT_ON;
    else if (text && strcmp(text, "off") == 0)
        *out = RAD_EFFECT_OFF;
    else
        return RAD_ERROR(RAD_EINVAL, "%s must be auto, on or off, got '%s'", what, text ? text : "");
    return RAD_OK;
}

/* Apply the user's mode to an automatic decision. */
static void settle(rad_effect_decision *d, rad_effect_mode mode, int automatic, const char *reason)
{
    d->on = automatic;
    d->forced = 0;
    snprintf(d->reason, sizeof d->reason, "%s", reason);
    if (mode == RAD_EFFECT_AUTO)
        return;
    d->on = mode == RAD_EFFECT_ON;
    d->forced = 1;
    char buf[sizeof d->reason];
    snprintf(buf, sizeof buf, "forced %s by the user (automatic: %s, %s)", d->on ? "on" : "off",
             automatic ? "on" : "off", reason);
    memcpy(d->reason, buf, sizeof buf);
}

static rad_vec3 vertex(const double *xyz, int v)
{
    return rad_vec3_make(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
}

/* All corners of j on or behind the plane of i (a relative tolerance keeps a
 * shared plane from counting as "in front"). */
static int behind(const double *xyz, const int *ti, const int *tj, double rel_tol)
{
    rad_vec3 a = vertex(xyz, ti[0]), b = vertex(xyz, ti[1]), c = vertex(xyz, ti[2]);
    rad_vec3 n = rad_vec3_cross(rad_vec3_sub(b, a), rad_vec3_sub(c, a));
    double scale = rad_vec3_norm(n) * (rad_vec3_norm(rad_vec3_sub(b, a)) + rad_vec3_norm(rad_vec3_sub(c, a)));
    for (int k = 0; k < 3; k++) {
        double h = rad_vec3_dot(n, rad_vec3_sub(vertex(xyz, tj[k]), a));
        if (h > rel_tol * scale)
            return 0;
    }
    return 1;
}

rad_status rad_scene_effects_plan(const rad_scene *s, const rad_mesh *mesh,
                                  const rad_effects_params *params, rad_effects_plan *plan)
{
    rad_mesh_contacts cut;
    rad_status st = rad_scene_effects_plan_cut(s, mesh, params, plan, &cut);
    rad_mesh_contacts_free(&cut);
    return st;
}

rad_status rad_scene_effects_plan_cut(const rad_scene *s, const rad_mesh *mesh,
                                      const rad_effects_params *params, rad_effects_plan *plan,
                                      rad_mesh_contacts *cut)
{
    if (cut)
        memset(cut, 0, sizeof *cut);
    rad_effects_params defaults;
    if (!params) {
        rad_scene_effects_params_default(&defaults);
        params = &defaults;
    }
    if (!s || !mesh || !plan || !cut)
        return RAD_ERROR(RAD_EINVAL, "rad_scene_effects_plan: NULL argument");
    if (rad_mesh_face_count(mesh) != s->nt)
        return RAD_ERROR(RAD_EINVAL, "rad_scene_effects_plan: the mesh has %d faces, the scene %d",
                         rad_mesh_face_count(mesh), s->nt);
    memset(plan, 0, sizeof *plan);
    rad_mesh_info info;
    rad_mesh_get_info(mesh, &info);
    char why[256];
    long long n = s->nt;
    plan->pairs_total = n * (n - 1) / 2;

    /* 1. occlusion */
    if (info.convex_inside == 1)
        snprintf(why, sizeof why, "every vertex is in front of every face's plane (%s), so no face "
                 "can block another pair", info.closed ? "a closed convex enclosure" : "an open convex arrangement");
    else
        snprintf(why, sizeof why, "%s; visibility is decided per pair (rays only where a shaft test "
                 "cannot rule out blockers)", info.convex_inside == 0 ? "some faces lie behind others' planes"
                                                                     : "convexity unknown");
    settle(&plan->occlusion, params->occlusion, info.convex_inside != 1, why);

    /* 2. colour */
    int grey = 1, grey_e = 1;
    for (int t = 0; t < s->nt; t++) {
        const rad_scene_material *m = &s->mats[s->tri_mat[t]];
        if (fabs(m->rho[0] - m->rho[1]) > params->grey_tol || fabs(m->rho[1] - m->rho[2]) > params->grey_tol)
            grey = 0;
        if (fabs(m->emission[0] - m->emission[1]) > params->grey_tol ||
            fabs(m->emission[1] - m->emission[2]) > params->grey_tol)
            grey_e = 0;
    }
    if (grey)
        snprintf(why, sizeof why, "every reflectance is grey, so one scalar system serves the three "
                 "channels%s", grey_e ? " (emission grey too: one right-hand side)"
                                      : " (coloured emission: three right-hand sides)");
    else
        snprintf(why, sizeof why, "some reflectance differs between channels: three systems");
    settle(&plan->colour, params->colour, !grey, why);

    /* 3. facing-away pairs */
    plan->pairs_facing_away = -1;
    if (s->nt <= params->pair_scan_max_faces) {
        long long away = 0;
        for (int i = 0; i < s->nt; i++)
            for (int j = i + 1; j < s->nt; j++) {
                const int *ti = s->tri + 3 * (size_t)i, *tj = s->tri + 3 * (size_t)j;
                away += behind(s->xyz, ti, tj, params->plane_rel_tol) ||
                        behind(s->xyz, tj, ti, params->plane_rel_tol);
            }
        plan->pairs_facing_away = away;
        snprintf(why, sizeof why, "the kernel vanishes unless both cosines are positive: %lld of %lld "
                 "pairs face away and are zero without integration", away, plan->pairs_total);
    } else {
        snprintf(why, sizeof why, "the kernel vanishes unless both cosines are positive: pairs facing "
                 "away are zero without integration (not counted above %d faces)",
                 params->pair_scan_max_faces);
    }
    settle(&plan->facing_away, params->facing_away, 1, why);

    /* 4. singular pairs */
    plan->pairs_singular = info.pairs_edge - info.pairs_edge_coplanar + info.pairs_vertex -
                           info.pairs_vertex_coplanar;
    plan->pairs_adjacent_coplanar = info.pairs_edge_coplanar + info.pairs_vertex_coplanar;
    snprintf(why, sizeof why, "%d edge- and %d vertex-adjacent non-coplanar pairs have a singular "
             "kernel; %d coplanar adjacent pairs have a zero kernel",
             info.pairs_edge - info.pairs_edge_coplanar, info.pairs_vertex - info.pairs_vertex_coplanar,
             plan->pairs_adjacent_coplanar);
    settle(&plan->singular, params->singular, plan->pairs_singular > 0, why);

    /* sealed: closed components, the largest-volume one facing inward (a
       negative signed volume), every other one outward */
    {
        int nc = info.components, ok = nc > 0 && info.closed;
        double *vol = ok ? calloc((size_t)nc, sizeof *vol) : NULL;
        const int *comp = rad_mesh_face_components(mesh);
        if (vol && comp) {
            for (int t = 0; t < s->nt; t++) {
                const int *v = s->tri + 3 * (size_t)t;
                rad_vec3 a = vertex(s->xyz, v[0]), b = vertex(s->xyz, v[1]), c = vertex(s->xyz, v[2]);
                vol[comp[t]] += rad_vec3_dot(a, rad_vec3_cross(b, c)) / 6.0;
            }
            int big = 0;
            for (int k = 1; k < nc; k++)
                if (fabs(vol[k]) > fabs(vol[big]))
                    big = k;
            ok = vol[big] < 0.0;
            for (int k = 0; k < nc && ok; k++)
                ok = k == big || vol[k] > 0.0;
        } else {
            ok = 0;
        }
        free(vol);
        plan->sealed = ok;
    }

    /* 5. reflectance near 1 */
    double rho_max = 0.0;
    for (int t = 0; t < s->nt; t++)
        for (int c = 0; c < 3; c++)
            rho_max = fmax(rho_max, s->mats[s->tri_mat[t]].rho[c]);
    plan->rho_max = rho_max;
    double amp = rho_max < 1.0 ? 1.0 / (1.0 - rho_max) : INFINITY;
    int near = rho_max > params->near_one;
    snprintf(why, sizeof why, "the largest reflectance is %.10g: errors are amplified up to %.3g "
             "times%s", rho_max, amp,
             near ? ", so form-factor and solver tolerances are tightened by that factor over "
                    "the defaults'"
                  : "");
    settle(&plan->reflectance, params->reflectance, near, why);
    plan->tighten = 1.0;
    if (plan->reflectance.on && params->near_one < 1.0)
        plan->tighten = fmin(1.0, (1.0 - rho_max) / (1.0 - params->near_one));
    /* 6. clustering */
    int clear = !plan->occlusion.on;
    double from = clear ? params->cluster_min_pairs_clear : params->cluster_min_pairs;
    if (plan->pairs_facing_away >= 0) {
        double facing = (double)(plan->pairs_total - plan->pairs_facing_away);
        int many = facing >= from;
        snprintf(why, sizeof why, "%.3g pairs of input triangles face each other: %s (on from "
                 "%.3g such pairs %s; see papers/clustering.md)", facing,
                 many ? "links start from a cluster hierarchy instead of linking them all first"
                      : "hierarchical radiosity links them all first",
                 from, clear ? "where nothing can block" : "where faces can block each other");
        settle(&plan->clustering, params->clustering, many, why);
    } else {
        snprintf(why, sizeof why, "%d input triangles, more than the %d up to which facing pairs "
                 "are counted: links start from a cluster hierarchy instead of linking up to "
                 "%.3g pairs first", s->nt, params->pair_scan_max_faces,
                 (double)plan->pairs_total);
        settle(&plan->clustering, params->clustering, 1, why);
    }
    /* 7. contact */
    rad_status st = rad_mesh_split_contacts(s->xyz, (size_t)s->nv, s->tri, (size_t)s->nt,
                                            params->contact_rel_tol, params->contact_near_rel,
                                            params->contact_near_rel_large, params->threads,
                                            cut);
    if (st != RAD_OK)
        return st;
    const rad_mesh_contacts ct = *cut;
    plan->contact_faces = (int)ct.faces_split;
    plan->contact_pieces = (int)(ct.nt - ((size_t)s->nt - ct.faces_split));
    if (ct.faces_split > 0)
        snprintf(why, sizeof why, "%d input triangles have others standing on them, or "
                 "within %.3g%% of their size above (%.3g%% over one %d times larger), "
                 "along %zu segments: hier cuts them into %d pieces%s so that no element "
                 "straddles a radiosity jump",
                 plan->contact_faces, 100.0 * params->contact_near_rel,
                 100.0 * params->contact_near_rel_large, (int)RAD_MESH_HOVER_LARGE, ct.segments,
                 plan->contact_pieces, ct.slivers ? " (hair-angle slivers dropped)" : "");
    else
        snprintf(why, sizeof why, "no triangle stands on (or just above) another's inside: "
                 "nothing to cut");
    settle(&plan->contact, params->contact, plan->contact_faces > 0, why);
    if (amp > params->max_amplification)
        snprintf(plan->refusal, sizeof plan->refusal, "the largest reflectance %.10g is within "
                 "%.3g of 1: errors would be amplified %.3g times, beyond the %.3g that radkit's "
                 "tolerances can hold; use a reflectance of at most %.10g", rho_max,
                 1.0 - rho_max, amp, params->max_amplification,
                 1.0 - 1.0 / params->max_amplification);
    return RAD_OK;
}
