/* rad_hier: the refinement oracles.
 *
 * A link's contributions to the error bounds of the leaves under each of its
 * elements are its terms of solve.c's bound (the error of F, the source's
 * variation, and, for an inner element, the linear fit's residual).
 *
 * ERROR (default).  eps targets the error of each input triangle's mean B
 * (a row of the answer), relative to the mean reflected radiosity R.  A
 * link's contribution to that is its contribution to the bounds of the
 * leaves below its receiver times the receiver's share of its input
 * triangle's area; the link is refined when that exceeds link_share x eps R
 * x the triangle's scale.  The scale starts at 1; when a pass refines
 * nothing, rad_hier_solve computes the bound and quarters the scale of every
 * input triangle whose bound still exceeds eps R and, from the second time
 * on, whose mean B the last quartering moved by more than eps R (at most
 * max_tighten times; hier_tighten_failing): refinement goes where the
 * answer still moves, and stops where the minimum area or depth binds.  (A
 * pointwise target, the same for every element, would link each small
 * element to all the small elements around it: links would grow like
 * leaves^2.)
 * BF (HSA 1991).  A link is refined when the radiosity it brings either way,
 * rho F B, exceeds eps R.
 *
 * Either way a link whose point values are all 0 although its elements face
 * each other is refined while it can be.  A link that sampled its view by
 * rays because its shaft held more than clip_blockers blockers is, the
 * first time the oracle would refine it, estimated again clipping up to
 * RAD_HIER_CLIP_BLOCKERS_MAX, it and the links split from it: rays are
 * cheap where their sampling error is within the link's share, clipping
 * where it is not.  A refined link is replaced by four,
 * between one element's children and the other (ERROR: the element whose
 * split reduces the contributions more; BF: the larger; the other one when
 * the first may not be split).  The new links are
 * estimated in parallel and examined in the same pass, generation by
 * generation: the same links in the same order as HSA 1991's recursive
 * Refine.  A link the oracle would refine but whose elements can both no
 * longer be split is counted (links_bound). */
#include "hier_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rad_sys.h"


/* A link's contributions to the error bounds of the input triangles under
 * a (*ca) and under b (*cb) (ERROR: solve.c's terms that do not average out
 * over a triangle: the error of G and the source's variation), or the
 * radiosity it brings each (BF); and how much splitting a, or b, would
 * reduce the bounds (*sa, *sb: the residual of its linear push, its
 * variation as a source). */
static void contributions(const rad_hier *h, const hier_link *l, double *ca, double *cb,
                          double *sa, double *sb)
{
    const hier_elem *a = &h->el[l->a], *b = &h->el[l->b];
    size_t n = h->nroots;
    *ca = *cb = *sa = *sb = 0.0;
    for (int c = 0; c < 3; c++) {
        double ra = h->rho[(size_t)a->face + c * n], rb = h->rho[(size_t)b->face + c * n];
        if (h->p.oracle == RAD_HIER_ORACLE_BF) {
            *ca = rad_dmax(*ca, ra * l->G / a->area * b->B[c]);
            *cb = rad_dmax(*cb, rb * l->G / b->area * a->B[c]);
            continue;
        }
        double wb = hier_weight(h, a, b, c), wa = hier_weight(h, b, a, c);
        double qa = ra * l->dG / a->area * wb, qb = rb * l->dG / b->area * wa;
        double srcb = ra * l->vb * b->var[c], srca = rb * l->va * a->var[c];
        double resa = ra * l->ra * wb, resb = rb * l->rb * wa;
        *ca = rad_dmax(*ca, qa + srcb);
        *cb = rad_dmax(*cb, qb + srca);
        /* splitting a brings the a <- b link below a and shrinks a as a source */
        *sa = rad_dmax(*sa, resa + srca);
        *sb = rad_dmax(*sb, resb + srcb);
    }
}

/* ERROR oracle: tighten the thresholds of the input triangles whose error
 * bound (the area-weighted mean of their leaves', solve.c) exceeds eps R, by
 * 4 each time, at most max_tighten times.  The bound's iteration part is left
 * out: refining does not reduce it, the last solve (to final_share eps R) does.
 * From the second time on, a triangle is tightened again only where its mean
 * B moved by more than eps R (in some channel) since the last time: the move
 * is what the last quartering corrected of the answer before it, which
 * estimates that answer's error where refining converges; the bound sums
 * every link's worst case carried through every bounce and does not single
 * out a triangle (papers/clustering.md §4).  *count: how many were
 * tightened (0: none fails, or none may be tightened further). */
rad_status hier_tighten_failing(rad_hier *h, int *count)
{
    size_t n = h->nroots;
    *count = 0;
    if (!h->tight_B && !(h->tight_B = calloc(3 * n, sizeof *h->tight_B)))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the tightening of %zu triangles", n);
    double *area = calloc(7 * n, sizeof *area);
    if (!area)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the tightening of %zu triangles", n);
    double *bound = area + n, *B = area + 4 * n, target = h->p.eps * hier_reflected_scale(h);
    for (size_t e = 0; e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        area[x->face] += x->area;
        for (int c = 0; c < 3; c++) {
            bound[3 * (size_t)x->face + (size_t)c] += x->area * hier_face_part(h, x, c);
            B[3 * (size_t)x->face + (size_t)c] += x->area * x->B[c];
        }
    }
    int first = h->st.tightenings == 0, tightened = 0;
    double total = 0.0, quartered = 0.0, finest = pow(0.25, h->p.max_tighten) * 1.0001;
    for (size_t f = 0; f < n; f++) {
        double b = 0.0, moved = 0.0;
        for (int c = 0; c < 3; c++) {
            size_t i = 3 * f + (size_t)c;
            B[i] = area[f] > 0.0 ? B[i] / area[f] : 0.0;
            b = rad_dmax(b, area[f] > 0.0 ? bound[i] / area[f] : 0.0);
            moved = rad_dmax(moved, fabs(B[i] - h->tight_B[i]));
        }
        total += area[f];
        if (b - h->iter_err > target && (first || moved > target) && h->face_scale[f] > finest) {
            h->face_scale[f] *= 0.25;
            quartered += area[f];
            tightened++;
        }
    }
    memcpy(h->tight_B, B, 3 * n * sizeof *B);
    free(area);
    h->st.tightenings += tightened > 0;
    h->st.tightened_share += total > 0.0 ? quartered / total : 0.0;
    *count = tightened;
    return RAD_OK;
}

/* Drop the replaced links from links[from ..) keeping their order (so
 * results do not depend on when this runs); returns where the survivors of
 * links[from .. end) now end. */
static size_t drop_replaced(rad_hier *h, size_t from, size_t end)
{
    size_t kept = from, w = from;
    for (size_t k = from; k < h->nln; k++)
        if (h->ln[k].a >= 0) {
            kept += k < end;
            h->ln[w++] = h->ln[k];
        }
    h->nln = w;
    return kept;
}

/* The oracle's decision on element link l at target: keep it, or split
 * (or first estimate again, rad_hier_refine decides) with the end to split
 * first, a or b. */
enum { DECIDE_KEEP, DECIDE_SPLIT_A, DECIDE_SPLIT_B };
static signed char decide(const rad_hier *h, const hier_link *l, double target)
{
    if (l->a < 0)
        return DECIDE_KEEP;
    const hier_elem *ea = &h->el[l->a], *eb = &h->el[l->b];
    double ca, cb, sa, sb;
    contributions(h, l, &ca, &cb, &sa, &sb);
    double la = target, lb = target;
    if (h->p.oracle == RAD_HIER_ORACLE_ERROR) {
        /* the share of its input triangle's mean error */
        ca *= ea->area / h->el[ea->face].area;
        cb *= eb->area / h->el[eb->face].area;
        la *= h->p.link_share * h->face_scale[ea->face];
        lb *= h->p.link_share * h->face_scale[eb->face];
    }
    if (!(ca > la) && !(cb > lb) && !l->unknown)
        return DECIDE_KEEP;
    int split_a;
    if (h->p.oracle == RAD_HIER_ORACLE_ERROR && !l->unknown && sa != sb)
        split_a = sa > sb;
    else
        split_a = ea->area >= eb->area;
    return split_a ? DECIDE_SPLIT_A : DECIDE_SPLIT_B;
}

/* Queue link l's pair to be estimated again clipping every blocker it may. */
static rad_status push_upgrade(hier_job **up, size_t *n, size_t *cap, hier_link l)
{
    if (!rad_sys_grow((void **)up, cap, *n, *n + 1, sizeof **up, 256))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu link estimates", *n + 1);
    (*up)[(*n)++] = (hier_job){l.a, l.b, 1};
    return RAD_OK;
}

rad_status rad_hier_refine(rad_hier *h, long long *refined)
{
    double t0 = rad_sys_seconds();
    if (refined)
        *refined = 0;
    if (!h)
        return RAD_ERROR(RAD_EINVAL, "hier: no handle");
    rad_status st = RAD_OK;
    long long count = 0;
    hier_job *jobs = NULL, *up = NULL;
    size_t capj = 0, nup = 0, capup = 0, capdec = 0;
    signed char *dec = NULL;
    double target = h->p.eps * hier_reflected_scale(h);
    h->st.links_bound = 0;
    /* the source variation of an inner element, in its links' terms, is
       that of the B the last solve left below it */
    if ((st = hier_inner_spread(h, 0)) != RAD_OK)
        goto done;
    /* the cluster links first: the root links they end in are examined below */
    if (h->E_max > 0.0 && (st = hier_cluster_refine(h, target, &count)) != RAD_OK)
        goto done;
    size_t begin = 0, end = h->E_max > 0.0 ? h->nln : 0;
    while (begin < end) {
        size_t nj = 0;
        /* the decisions read only the ends' values, which splitting leaves
           as they are: made in parallel, then carried out in link order */
        if (!rad_sys_grow((void **)&dec, &capdec, 0, end - begin, 1, 4096)) {
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu link decisions", end - begin);
            goto done;
        }
        const rad_hier *hc = h;
#pragma omp parallel for schedule(static) num_threads(hier_threads(h)) if (end - begin > 4096)
        for (long long k = (long long)begin; k < (long long)end; k++)
            dec[k - (long long)begin] = decide(hc, &hc->ln[k], target);
        for (size_t k = begin; k < end; k++) {
            hier_link l = h->ln[k];
            signed char d = dec[k - begin];
            if (d == DECIDE_KEEP)
                continue;
            if (l.sampled && !l.clip && h->p.clip_blockers > 0) {
                /* its rays' sampling error may be what the oracle sees: the
                   pair is estimated again clipping every blocker it may, at
                   the same level, before it is split */
                if ((st = push_upgrade(&up, &nup, &capup, l)) != RAD_OK)
                    goto done;
                h->ln[k].a = -1;
                count++;
                continue;
            }
            int first_choice = d == DECIDE_SPLIT_A ? l.a : l.b;
            int second = first_choice == l.a ? l.b : l.a;
            int target_elem = hier_can_split(h, first_choice) ? first_choice
                              : hier_can_split(h, second)     ? second
                                                              : -1;
            if (target_elem < 0) {
                h->st.links_bound += !l.unknown;
                continue;
            }
            if ((st = hier_split(h, target_elem)) != RAD_OK)
                goto done;
            if (nj + 4 > capj) {
                size_t cap = capj ? 2 * capj : 1024;
                hier_job *grown = realloc(jobs, cap * sizeof *jobs);
                if (!grown) {
                    st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu new links", cap);
                    goto done;
                }
                jobs = grown;
                capj = cap;
            }
            h->ln[k].a = -1; /* the link is replaced */
            int first = h->el[target_elem].first_child, other = target_elem == l.a ? l.b : l.a;
            for (int c4 = 0; c4 < 4; c4++)
                jobs[nj++] = (hier_job){first + c4, other, l.clip};
            count++;
        }
        st = hier_estimate_batch(h, jobs, nj, 1);
        if (st == RAD_OK)
            st = hier_estimate_batch(h, up, nup, 0);
        nup = 0;
        /* the generation's replaced links go before the next is examined, so
           the array holds the live links and one generation's new ones, not
           every link made */
        begin = drop_replaced(h, begin, end);
        end = h->nln;
        if (st != RAD_OK)
            goto done;
        hier_working(h, "linking", h->nln + h->ncln);
    }
done:
    free(jobs);
    free(up);
    free(dec);
    if (st != RAD_OK)
        drop_replaced(h, 0, 0); /* what an error left among the links */
    h->version++; /* the gather's incidence and the shared gather's plan are rebuilt */
    if (count > 0) {
        rad_status caps = hier_row_caps(h);
        if (st == RAD_OK)
            st = caps;
    }
    h->st.refinements += count;
    h->st.time_refine_s += rad_sys_seconds() - t0;
    if (count > 0) {
        h->st.rounds++;
        h->stepped = 0; /* the system changed: the last test no longer holds */
    }
    if (refined)
        *refined = count;
    return st;
}
