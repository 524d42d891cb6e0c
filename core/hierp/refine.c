/* rad_hierp: the oracle and the refinement rounds.
 *
 * eps targets the error of each input triangle's mean radiosity relative to
 * the mean reflected radiosity R, as rad_hier's ERROR oracle: a link's
 * errors on its receivers (hp_link_oracle: the errors of hp_link_errors that
 * reach a receiver's mean, and the receiver's mean departure from its
 * polynomial as far as it reaches means, face_reach), each times the
 * receiver's share of its input triangle's area, are compared with
 * link_share x eps R x the triangle's scale.  A link above is replaced by four, between the children
 * of one element and the other: the element whose split removes more of the
 * errors (a: its own departure as a receiver, f_a, and the detail it hides
 * as a source, k_b dev_a; b alike), the larger one when the integration
 * error dG is the larger part or nothing tells them apart, the other one
 * when the first may not be split.  The new links are estimated in parallel
 * and examined in the same pass.  When a pass refines nothing, the triangles
 * whose estimated error (solve.c) still exceeds eps R have their scale
 * quartered, at most max_tighten times, and refinement goes on: the error
 * goes down where it is largest, and links do not multiply where it is
 * already small.  A link the oracle would refine but whose elements may no
 * longer be split (min_area, max_depth) is counted in links_bound. */
#include "hierp_internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>

#include "rad_sys.h"

/* Which element of link l to split (-1: neither may be). */
static int choose(const rad_hierp *h, const hp_link *l)
{
    const hp_elem *a = &h->el[l->a], *b = &h->el[l->b];
    size_t n = h->nroots;
    double sa = 0.0, sb = 0.0, sg = 0.0;
    for (int c = 0; c < 3; c++) {
        double Ba = a->Bmax[c], Bb = b->Bmax[c];
        double ra = h->rho[(size_t)a->face + (size_t)c * n];
        double rb = h->rho[(size_t)b->face + (size_t)c * n];
        sa = rad_dmax(sa, ra * l->fa * Bb + rb * l->kmb * a->detail[c]);
        sb = rad_dmax(sb, rb * l->fb * Ba + ra * l->kma * b->detail[c]);
        sg = rad_dmax(sg, rad_dmax(ra * l->dG / a->area * Bb, rb * l->dG / b->area * Ba));
    }
    int first = a->area >= b->area ? l->a : l->b;
    if (!l->unknown && sa != sb && rad_dmax(sa, sb) > sg)
        first = sa > sb ? l->a : l->b;
    int second = first == l->a ? l->b : l->a;
    return hp_can_split(h, first) ? first : hp_can_split(h, second) ? second : -1;
}

/* face_reach: in a sealed scene a receiver's mean departure is a local
 * error of its own (solve.c: each leaf is divided by its row), 1.  Elsewhere
 * the departure of a triangle's radiosity from its polynomial leaves every
 * mean on it as it is and reaches the means of the elements it lights
 * through the kernel's departure over it (hp_link_errors: k times the
 * source's departure), so the oracle charges it at the largest k of the
 * links the triangle is the source of, never more than the departure
 * itself. */
static void face_reach(rad_hierp *h)
{
    size_t n = h->nroots;
    for (size_t f = 0; f < n; f++)
        h->face_reach[f] = h->p.sealed ? 1.0 : 0.0;
    if (h->p.sealed)
        return;
    for (size_t k = 0; k < h->nln; k++) {
        const hp_link *l = &h->ln[k];
        size_t fa = (size_t)h->el[l->a].face, fb = (size_t)h->el[l->b].face;
        h->face_reach[fb] = rad_dmax(h->face_reach[fb], l->ka); /* b lights a */
        h->face_reach[fa] = rad_dmax(h->face_reach[fa], l->kb);
    }
    for (size_t f = 0; f < n; f++)
        h->face_reach[f] = rad_dmin(1.0, h->face_reach[f]);
}

rad_status hp_refine(rad_hierp *h, long long *refined)
{
    double t0 = rad_sys_seconds();
    *refined = 0;
    rad_status st = RAD_OK;
    long long count = 0;
    hp_job *jobs = NULL;
    size_t capj = 0;
    if ((st = hp_incidence(h)) != RAD_OK)
        return st;
    hp_bound_B(h);
    hp_pull_dev(h);
    face_reach(h);
    double target = h->p.eps * hp_reflected(h) * h->p.link_share;
    h->st.links_bound = 0;
    size_t begin = 0, end = h->E_max > 0.0 ? h->nln : 0;
    double *oracle = NULL;
    size_t cap_oracle = 0;
    int threads = h->p.threads > 0 ? h->p.threads : omp_get_max_threads();
    while (begin < end) {
        size_t nj = 0;
        /* the oracle of this generation's links, in parallel (splitting below
           adds children only: it changes no element a link here reads) */
        if (end - begin > cap_oracle) {
            double *grown = realloc(oracle, 2 * (end - begin) * sizeof *grown);
            if (!grown) {
                st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu links", end - begin);
                goto done;
            }
            oracle = grown;
            cap_oracle = end - begin;
        }
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) if (end - begin > 1024)
        for (long long k = (long long)begin; k < (long long)end; k++) {
            const hp_link *l = &h->ln[k];
            double *o = oracle + 2 * ((size_t)k - begin);
            if (l->a < 0)
                continue;
            const hp_elem *ea = &h->el[l->a], *eb = &h->el[l->b];
            hp_link_oracle(h, l, &o[0], &o[1]);
            o[0] *= ea->area / h->el[ea->face].area;
            o[1] *= eb->area / h->el[eb->face].area;
        }
        for (size_t k = begin; k < end; k++) {
            hp_link l = h->ln[k];
            if (l.a < 0)
                continue;
            const hp_elem *ea = &h->el[l.a], *eb = &h->el[l.b];
            double ca = oracle[2 * (k - begin)], cb = oracle[2 * (k - begin) + 1];
            if (!(ca > target * h->face_scale[ea->face]) &&
                !(cb > target * h->face_scale[eb->face]) && !l.unknown)
                continue;
            int split = choose(h, &l);
            if (split < 0) {
                h->st.links_bound += !l.unknown;
                continue;
            }
            if ((st = hp_split(h, split)) != RAD_OK)
                goto done;
            if (nj + 4 > capj) {
                size_t cap = capj ? 2 * capj : 1024;
                hp_job *grown = realloc(jobs, cap * sizeof *jobs);
                if (!grown) {
                    st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu new links", cap);
                    goto done;
                }
                jobs = grown;
                capj = cap;
            }
            h->ln[k].a = -1;
            int first = h->el[split].first_child, other = split == l.a ? l.b : l.a;
            for (int c4 = 0; c4 < 4; c4++)
                jobs[nj++] = (hp_job){first + c4, other};
            count++;
        }
        if ((st = hp_estimate_batch(h, jobs, nj, 1)) != RAD_OK)
            goto done;
        begin = end;
        end = h->nln;
    }
done:
    free(jobs);
    free(oracle);
    {
        /* drop the replaced links, keeping the order */
        size_t w = 0, mm = (size_t)(h->m * h->m);
        for (size_t k = 0; k < h->nln; k++)
            if (h->ln[k].a >= 0) {
                if (w != k) {
                    h->ln[w] = h->ln[k];
                    for (size_t i = 0; i < mm; i++)
                        h->K[w * mm + i] = h->K[k * mm + i];
                }
                w++;
            }
        h->nln = w;
    }
    if (count > 0)
        h->inc_valid = 0; /* the links changed */
    h->st.refinements += count;
    if (count > 0)
        h->st.rounds++;
    h->st.time_refine_s += rad_sys_seconds() - t0;
    *refined = count;
    return st;
}

int hp_tighten_failing(rad_hierp *h)
{
    size_t n = h->nroots;
    double *sum = calloc(2 * n, sizeof *sum);
    if (!sum)
        return 0;
    double target = h->p.eps * hp_reflected(h);
    for (size_t e = 0; e < h->nel; e++) {
        const hp_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        sum[x->face] += x->area * rad_dmax(x->T[0], rad_dmax(x->T[1], x->T[2]));
        sum[n + (size_t)x->face] += x->area;
    }
    int tightened = 0;
    double total = 0.0, quartered = 0.0;
    for (size_t f = 0; f < n; f++) {
        double b = sum[n + f] > 0.0 ? sum[f] / sum[n + f] : 0.0;
        total += sum[n + f];
        if (b > target && h->face_scale[f] > pow(0.25, h->p.max_tighten) * 1.0001) {
            h->face_scale[f] *= 0.25;
            quartered += sum[n + f];
            tightened++;
        }
    }
    free(sum);
    h->st.tightenings += tightened > 0;
    h->st.tightened_share += total > 0.0 ? quartered / total : 0.0;
    return tightened;
}
