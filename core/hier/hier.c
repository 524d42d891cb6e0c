/* Hierarchical radiosity for P0 elements (Hanrahan, Salzman, Aupperle 1991,
 * refs.bib key hanrahan1991; BF refinement as in its section 4).
 *
 * 1. Roots: one element per input triangle, B = E.  Elements live in one
 *    growing array and refer to each other by index; an element's four
 *    children are contiguous (first_child .. first_child + 3), made by the
 *    midpoint split (corner children a m_ab m_ca, m_ab b m_bc, m_ca m_bc c and
 *    the middle m_ab m_bc m_ca, all with the parent's orientation), and
 *    inherit the parent's face, rho, E and B.
 * 2. Initial linking: for every ordered pair (r, s) of input triangles, one
 *    estimate (estimate(): F_rs from the ERROR oracle's point values while
 *    either element may be split and oracle_F is on, else from rad_ff by rule
 *    or far_rule); a pair facing away or coplanar makes no link, otherwise
 *    the link r <- s carries F_rs and a visible fraction V_rs (step 5).
 * 3. Step (Jacobi): gather Bg_r = sum over links at r of F_rs V_rs B_s (all
 *    levels, old B); push-pull from each root: a leaf takes
 *    B = E + rho (Bg + sum of its ancestors' Bg), an inner element the area-
 *    weighted mean of its children's B.  The test compares the largest change
 *    of a leaf B in the step with tol times the largest leaf B.  Jacobi
 *    converges because the hierarchical operator keeps the norm of rho F below
 *    max rho < 1 (push-pull conserves power; F rows sum to at most 1).
 * 4. Refine: for each link, the oracle's error estimate (link_error: BF's
 *    transported radiosity, or ERROR's kernel variation times it; for a link
 *    not fully visible the unoccluded transport, so that shadows are refined)
 *    is compared with eps * S (reflected_scale).  Above it, one element of the
 *    pair is split (BF: the larger; ERROR: the side whose kernel varies more;
 *    the other one when that may not be: min_area, max_depth); the link is
 *    replaced by links from the receiver to the source's children or from the
 *    receiver's children to the source, each with its own estimate, and those
 *    are examined in the same pass (their B is the parent's, so the recursion
 *    of HSA 1991's Refine happens within one pass).  A link whose elements may
 *    not be split stays.
 * 5. Visibility: none without a rad_vis, or when rad_vis_is_unoccluded, or when
 *    rad_vis_pair_can_block clears the pair of input triangles (a sub-element
 *    pair's shaft lies inside its input pair's).  Otherwise vis_points points
 *    on each element (one jittered point in it, or one in each of its four
 *    midpoint children; hashed, so reproducible) are joined pairwise
 *    (rad_vis_occluded_between, which ignores hits on the two input triangles
 *    the points lie on) and V = sum K v / sum K, the kernel-weighted share
 *    of open segments.
 * 6. Solve: steps until the test passes, refine, repeat until a pass refines
 *    nothing.  The final B is consistent with the final links. */
#include "rad_hier.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rad_geom.h"
#include "rad_sys.h"

typedef struct hier_elem {
    rad_vec3 p[3];
    double area;
    double size; /* longest edge */
    int parent, first_child; /* -1 for none */
    int face;                /* input triangle */
    int depth;
    double B[3], Bg[3];
    double vis[12]; /* its visibility sample points (sample_points), made once */
} hier_elem;

typedef struct hier_link {
    int r, s;     /* receiver, source; r = -1 marks a refined (dead) link */
    double F, V;  /* F_rs from the receiver's view, visible fraction */
    double dFr, dFs; /* ERROR oracle: kernel variation over the receiver and over
                        the source (in the receiver's units); 0 for BF */
    unsigned char unknown; /* the estimate is 0 but the pair is not provably apart */
    unsigned char traced;  /* V came from rays (else nothing could block the pair) */
} hier_link;

struct rad_hier {
    rad_hier_params p;
    const rad_vis *vis;
    int use_vis;
    /* rad_vis_pair_can_block of every pair of input triangles (r * nroots + s),
     * computed once: every link between their elements asks it again.  NULL
     * for scenes beyond HIER_BLOCK_TABLE_MAX triangles (then asked each time). */
    unsigned char *can_block;
    rad_vec3 *normal; /* unit normal per input triangle: every element of it shares it */
    size_t nroots;
    double *rho, *E;  /* per input triangle, ntris x 3 */
    double E_max;
    hier_elem *el;
    size_t nel, capel;
    hier_link *ln;
    size_t nln, capln;
    rad_hier_stats st;
    int stepped;
    double last_change; /* relative */
};

rad_status rad_hier_oracle_parse(const char *text, rad_hier_oracle *oracle)
{
    if (text && strcmp(text, "bf") == 0)
        *oracle = RAD_HIER_ORACLE_BF;
    else if (text && strcmp(text, "error") == 0)
        *oracle = RAD_HIER_ORACLE_ERROR;
    else
        return RAD_ERROR(RAD_EINVAL, "hier: unknown oracle '%s' (use bf or error)",
                         text ? text : "(null)");
    return RAD_OK;
}

const char *rad_hier_oracle_name(rad_hier_oracle oracle)
{
    return oracle == RAD_HIER_ORACLE_ERROR ? "error" : "bf";
}

void rad_hier_params_default(rad_hier_params *params)
{
    memset(params, 0, sizeof *params);
    params->oracle = RAD_HIER_ORACLE_ERROR;
    params->eps = 0.1;
    params->min_area = 0.0;
    params->max_depth = 8;
    /* analytic:6 (closed-form inner integral, 12 outer points): 0.27% low on
     * the 90-degree edge-adjacent pair where gauss:4 is 75% high, and about 12
     * closed-form evaluations where auto at 1e-3 takes ss:13 (19625 kernel
     * evaluations).  A rule that is far off on adjacent elements misleads the
     * oracle (with gauss:4 the unoccluded Cornell box lost 1.9% of its light);
     * on the Cornell box analytic:6 matches auto's error at a third of its
     * time (experiments/hierarchical). */
    params->rule.scheme = RAD_FF_ANALYTIC;
    params->rule.order = 6;
    params->ff = rad_ff_defaults();
    params->ff.tol = 1e-3;
    /* Far pairs (centroids more than 1.5 longest edges apart): gauss:2 and
     * the kernel-sampled point values, 9 and 24 kernel evaluations instead of
     * 12 and 8 closed forms.  Against exact on random pairs that face each
     * other whole, gauss:2 is off by 0.15% on average (95% of pairs within
     * 0.44%) at 1.5-2 edges, 0.06% at 2-3 (test ff_gauss2_far_pairs); the
     * straddling pairs where it fails are refined as `unknown` links.  On
     * the Cornell box, 1.5 instead of 2 edges reaches the same error 5-9%
     * sooner, and 2 instead of 0 was 15-20% faster (experiments/hierarchical). */
    params->far_ratio = 1.5;
    params->far_rule.scheme = RAD_FF_GAUSS;
    params->far_rule.order = 2;
    params->oracle_F = 1;
    params->vis_points = 4;
    params->tol = 1e-10;
    params->max_iterations = 10000;
    params->max_rounds = 64;
    params->max_elements = 4000000;
    params->max_links = 50000000;
}

static rad_status check_params(const rad_hier_params *p)
{
    if (p->oracle != RAD_HIER_ORACLE_BF && p->oracle != RAD_HIER_ORACLE_ERROR)
        return RAD_ERROR(RAD_EINVAL, "hier: unknown oracle %d", (int)p->oracle);
    if (!(p->eps > 0.0) || !isfinite(p->eps))
        return RAD_ERROR(RAD_EINVAL, "hier: eps must be a finite number > 0 (got %g)", p->eps);
    if (!(p->min_area >= 0.0) || !isfinite(p->min_area))
        return RAD_ERROR(RAD_EINVAL, "hier: min_area must be a finite number >= 0 (got %g)",
                         p->min_area);
    if (p->max_depth < 0 || p->max_depth > 30)
        return RAD_ERROR(RAD_EINVAL, "hier: max_depth must lie in 0..30 (got %d)", p->max_depth);
    if (p->vis_points != 1 && p->vis_points != 4)
        return RAD_ERROR(RAD_EINVAL, "hier: vis_points must be 1 or 4 (got %d)", p->vis_points);
    if (!(p->far_ratio >= 0.0) || !isfinite(p->far_ratio))
        return RAD_ERROR(RAD_EINVAL, "hier: far_ratio must be a finite number >= 0 (got %g)",
                         p->far_ratio);
    if (!(p->tol > 0.0) || !isfinite(p->tol))
        return RAD_ERROR(RAD_EINVAL, "hier: tol must be a finite number > 0 (got %g)", p->tol);
    if (p->max_iterations < 1 || p->max_rounds < 0)
        return RAD_ERROR(RAD_EINVAL, "hier: max_iterations must be >= 1 and max_rounds >= 0");
    if (p->max_elements < 1 || p->max_links < 1)
        return RAD_ERROR(RAD_EINVAL, "hier: max_elements and max_links must be >= 1");
    return RAD_OK;
}

/* Make *arr (used items of `item` bytes, capacity *cap) hold at least `need`
 * items: the capacity doubles (from `first`), so appends cost O(1) on
 * average, and the array moves to memory from rad_sys_alloc_huge (huge pages
 * spare hier most of its page faults).  0 when out of memory. */
static int grow_array(void **arr, size_t *cap, size_t used, size_t need, size_t item,
                      size_t first)
{
    if (need <= *cap)
        return 1;
    size_t c = *cap ? *cap : first;
    while (c < need)
        c *= 2;
    if (c > SIZE_MAX / item)
        return 0;
    void *n = rad_sys_alloc_huge(c * item);
    if (!n)
        return 0;
    if (used > 0)
        memcpy(n, *arr, used * item);
    free(*arr);
    *arr = n;
    *cap = c;
    return 1;
}

static rad_status grow_elems(rad_hier *h, size_t extra)
{
    if (h->nel + extra > h->p.max_elements)
        return RAD_ERROR(RAD_ETOOBIG, "hier: more than %zu elements (raise max_elements, eps or "
                                      "min_area)", h->p.max_elements);
    if (!grow_array((void **)&h->el, &h->capel, h->nel, h->nel + extra, sizeof *h->el, 64))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu elements", h->nel + extra);
    return RAD_OK;
}

/* Room for `extra` more links. */
static rad_status reserve_links(rad_hier *h, size_t extra)
{
    if (h->nln + extra > h->p.max_links)
        return RAD_ERROR(RAD_ETOOBIG, "hier: more than %zu links (raise max_links, eps or "
                                      "min_area)", h->p.max_links);
    if (!grow_array((void **)&h->ln, &h->capln, h->nln, h->nln + extra, sizeof *h->ln, 256))
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu links", h->nln + extra);
    return RAD_OK;
}

/* A uniform number in [0,1) from (element, sample, stream): splitmix64, so the
 * points are the same whatever the order of evaluation. */
static double hash_uniform(unsigned long long key)
{
    unsigned long long z = key + 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

/* n = 1: one point in the element; n = 4: one point in each of its four
 * midpoint children.  Each point is uniform within its triangle (jittered, from
 * a hash of the element index), not at its centroid: centroids of a regular
 * split line up with edges of geometry built on the same grid and bias the
 * visible fraction (the occluder scene came out 3.5% dark with centroids). */
static void sample_points(const hier_elem *e, int idx, int n, double *pts)
{
    /* corners of the four midpoint children in barycentric coordinates */
    static const double child[4][3][3] = {
        {{1, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}},
        {{0, 1, 0}, {0, 0.5, 0.5}, {0.5, 0.5, 0}},
        {{0, 0, 1}, {0.5, 0, 0.5}, {0, 0.5, 0.5}},
        {{0.5, 0.5, 0}, {0, 0.5, 0.5}, {0.5, 0, 0.5}}};
    static const double whole[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 0; k < n; k++) {
        const double (*c)[3] = n == 1 ? whole : child[k];
        unsigned long long key = 8ull * (unsigned long long)idx + 2ull * (unsigned long long)k;
        double a = sqrt(hash_uniform(key)), r2 = hash_uniform(key + 1);
        double t0 = 1.0 - a, t1 = a * (1.0 - r2), t2 = a * r2; /* uniform in the triangle */
        double w[3];
        for (int j = 0; j < 3; j++)
            w[j] = t0 * c[0][j] + t1 * c[1][j] + t2 * c[2][j];
        rad_vec3 q = rad_vec3_add(rad_vec3_add(rad_vec3_scale(e->p[0], w[0]),
                                               rad_vec3_scale(e->p[1], w[1])),
                                  rad_vec3_scale(e->p[2], w[2]));
        pts[3 * k] = q.x;
        pts[3 * k + 1] = q.y;
        pts[3 * k + 2] = q.z;
    }
}

/* The ERROR oracle's point values: the point-to-element form factor F(x, t)
 * (closed form, cosines clamped) at the centroids x of e's four midpoint
 * children, the points where a split of e would put its new receivers.  Their
 * largest deviation from the element average is the change a split can make
 * (Bekaert & Willems 1996 compare the point values with the Galerkin
 * projection the same way). */
static void point_values(const rad_hier *h, const hier_elem *e, const hier_elem *t, double Fx[4],
                         long long *evals)
{
    rad_vec3 n = h->normal[e->face];
    rad_vec3 a = e->p[0], b = e->p[1], c = e->p[2];
    /* child centroids in barycentric form: corners (4,1,1)/6 ..., middle (1,1,1)/3 */
    static const double w[4][3] = {{4.0 / 6, 1.0 / 6, 1.0 / 6}, {1.0 / 6, 4.0 / 6, 1.0 / 6},
                                   {1.0 / 6, 1.0 / 6, 4.0 / 6}, {1.0 / 3, 1.0 / 3, 1.0 / 3}};
    for (int k = 0; k < 4; k++) {
        rad_vec3 x = rad_vec3_add(rad_vec3_add(rad_vec3_scale(a, w[k][0]), rad_vec3_scale(b, w[k][1])),
                                  rad_vec3_scale(c, w[k][2]));
        Fx[k] = rad_ff_point_polygon(x, n, t->p, 3);
    }
    *evals += 4;
}

/* The largest deviation of the four point values from the average Fbar. */
static double deviation(const double Fx[4], double Fbar)
{
    double dev = 0.0;
    for (int k = 0; k < 4; k++)
        dev = rad_dmax(dev, fabs(Fx[k] - Fbar));
    return dev;
}

#define HIER_BLOCK_TABLE_MAX 8192 /* input triangles: a table of at most 64 MB */

static int pair_can_block(const rad_hier *h, int r, int s)
{
    if (h->can_block)
        return h->can_block[(size_t)r * h->nroots + (size_t)s];
    return rad_vis_pair_can_block(h->vis, (size_t)r, (size_t)s);
}

static int can_split(const rad_hier *h, int e);

/* Work counters of estimates made on one thread. */
typedef struct work_count {
    long long evals;
    unsigned long long rays;
} work_count;

/* point_values for a far pair: F(x, t) from the kernel at the three points of
 * the degree-2 rule on t (the kernel is smooth there), no closed form. */
static void point_values_far(const rad_hier *h, const hier_elem *e, const hier_elem *t,
                             double Fx[4], long long *evals)
{
    rad_vec3 ne = h->normal[e->face], nt = h->normal[t->face];
    static const double w[4][3] = {{4.0 / 6, 1.0 / 6, 1.0 / 6}, {1.0 / 6, 4.0 / 6, 1.0 / 6},
                                   {1.0 / 6, 1.0 / 6, 4.0 / 6}, {1.0 / 3, 1.0 / 3, 1.0 / 3}};
    rad_vec3 y[3];
    for (int j = 0; j < 3; j++)
        y[j] = rad_vec3_add(rad_vec3_add(rad_vec3_scale(t->p[0], w[j][0]),
                                         rad_vec3_scale(t->p[1], w[j][1])),
                            rad_vec3_scale(t->p[2], w[j][2]));
    for (int k = 0; k < 4; k++) {
        rad_vec3 x = rad_vec3_add(rad_vec3_add(rad_vec3_scale(e->p[0], w[k][0]),
                                               rad_vec3_scale(e->p[1], w[k][1])),
                                  rad_vec3_scale(e->p[2], w[k][2]));
        double f = 0.0;
        for (int j = 0; j < 3; j++)
            f += rad_ff_kernel(x, ne, y[j], nt, NULL);
        Fx[k] = t->area * f / 3.0;
    }
    *evals += 12;
}

/* Estimate the link r <- s; *facing = 0 when there is nothing to link.
 * Reads h only (re-entrant: called from several threads at once); its work
 * goes to *wc. */
static rad_status estimate(const rad_hier *h, int r, int s, int *facing, hier_link *out,
                           work_count *wc)
{
    const hier_elem *er = &h->el[r], *es = &h->el[s];
    /* a far pair (centroids more than far_ratio longest edges apart) takes
       far_rule and the oracle's kernel-sampled variation */
    rad_ff_rule rule = h->p.rule;
    int far = 0;
    if (h->p.far_ratio > 0.0) {
        rad_vec3 cr = rad_geom_triangle_centroid(er->p[0], er->p[1], er->p[2]);
        rad_vec3 cs = rad_geom_triangle_centroid(es->p[0], es->p[1], es->p[2]);
        double d = rad_vec3_norm(rad_vec3_sub(cr, cs));
        if (d > h->p.far_ratio * rad_dmax(er->size, es->size)) {
            far = 1;
            rule = h->p.far_rule;
        }
    }
    /* The ERROR oracle needs the point values of a link that may still be
     * split; with oracle_F they also give its F (below), without the rule. */
    int varied = h->p.oracle == RAD_HIER_ORACLE_ERROR && (can_split(h, r) || can_split(h, s));
    double Fr[4], Fs[4], scale = er->area > 0.0 ? es->area / er->area : 0.0;
    int from_points = varied && h->p.oracle_F;
    double F12 = 0.0, F21 = 0.0;
    rad_status st;
    if (from_points) {
        if (!rad_ff_facing(er->p, es->p, &h->p.ff)) {
            *facing = 0;
            return RAD_OK;
        }
    } else {
        rad_ff_result res;
        st = rad_ff_compute(er->p, es->p, rule, &h->p.ff, &res);
        if (st != RAD_OK)
            return st;
        wc->evals += res.evals;
        if (res.flags & RAD_FF_FLAG_NOT_FACING) {
            *facing = 0;
            return RAD_OK;
        }
        F12 = res.F12;
        F21 = res.F21;
    }
    if (varied) {
        if (far) {
            point_values_far(h, er, es, Fr, &wc->evals);
            point_values_far(h, es, er, Fs, &wc->evals);
        } else {
            point_values(h, er, es, Fr, &wc->evals);
            point_values(h, es, er, Fs, &wc->evals);
        }
    }
    if (from_points) {
        /* Each side's four values average to a one-sided estimate (the
         * centroid rule of its four children, exact for a kernel linear over
         * them); A_r F_rs = A_s F_sr puts the source's in the receiver's
         * units, and their mean is F_rs.  A link keeps this F only while the
         * oracle finds the values within eps of it, i.e. where the rule's error
         * is below what the oracle accepts anyway; a link between elements
         * that may no longer be split takes the rule. */
        F12 = 0.5 * ((Fr[0] + Fr[1] + Fr[2] + Fr[3]) * 0.25 +
                     scale * (Fs[0] + Fs[1] + Fs[2] + Fs[3]) * 0.25);
        F21 = scale > 0.0 ? F12 / scale : 0.0;
    }
    if (!isfinite(F12) || !(F12 >= 0.0))
        return RAD_ERROR(RAD_ENUMERIC, "hier: form factor of elements %d <- %d is not finite", r,
                         s);
    *facing = 1;
    out->r = r;
    out->s = s;
    out->F = F12;
    out->V = 1.0;
    out->dFr = out->dFs = 0.0;
    out->traced = 0;
    /* A pair that is not provably apart but whose estimate is 0 straddles a
       plane: every quadrature point fell where a cosine is clamped, yet part
       of one element faces the other.  Its BF is unknown, so it is refined
       while it can be (found on the Cornell box: without this, 12 facing leaf
       pairs were lost under parents estimated at 0). */
    out->unknown = !(F12 > 0.0);
    if (out->unknown)
        return RAD_OK;
    /* the oracle's variation matters only for a link that may still be refined;
       F(y, r) over s deviates from F_sr = F21, and A_s / A_r puts that in the
       receiver's units */
    if (varied) {
        out->dFr = deviation(Fr, F12);
        out->dFs = deviation(Fs, F21) * scale;
    }
    if (h->use_vis && pair_can_block(h, er->face, es->face)) {
        int m = h->p.vis_points, n = m * m;
        const double *a = er->vis, *b = es->vis;
        double from[48], to[48];
        unsigned char blocked[16];
        for (int i = 0; i < m; i++)
            for (int j = 0; j < m; j++)
                for (int c = 0; c < 3; c++) {
                    from[3 * (i * m + j) + c] = a[3 * i + c];
                    to[3 * (i * m + j) + c] = b[3 * j + c];
                }
        rad_vis_stats vs = {0, 0, 0};
        /* the end points lie on the two input triangles: ignore hits on them,
           so float rounding of the vertices can never block a segment at its
           own end (rad_vis.h recommends this call for such end points) */
        st = rad_vis_occluded_between(h->vis, (size_t)er->face, (size_t)es->face, (size_t)n, from,
                                      to, blocked, &vs);
        if (st != RAD_OK)
            return st;
        wc->rays += vs.rays;
        out->traced = 1;
        /* V = sum K v / sum K over the sample pairs: the kernel-weighted
         * visible fraction estimates (int int K v) / (int int K), the factor
         * the link's F needs.  The plain share of open rays does not: where K
         * is large (near a shared edge or corner) rays are short and rarely
         * blocked, and pairs where K = 0 (a point behind the other element's
         * plane) may be blocked without mattering; on the Cornell box the
         * plain share left coarse solutions 13% dark. */
        rad_vec3 nr = h->normal[er->face], ns = h->normal[es->face];
        double wsum = 0.0, wopen = 0.0;
        int open = 0;
        for (int k = 0; k < n; k++) {
            rad_vec3 x = rad_vec3_make(from[3 * k], from[3 * k + 1], from[3 * k + 2]);
            rad_vec3 y = rad_vec3_make(to[3 * k], to[3 * k + 1], to[3 * k + 2]);
            double w = rad_ff_kernel(x, nr, y, ns, NULL);
            wc->evals++;
            wsum += w;
            wopen += blocked[k] ? 0.0 : w;
            open += !blocked[k];
        }
        /* all sample pairs clamped (K = 0): fall back to the share of open rays */
        out->V = wsum > 0.0 ? fmin(1.0, wopen / wsum) : (double)open / n;
    }
    return RAD_OK;
}

/* A link to be estimated. */
typedef struct link_job {
    int r, s;
} link_job;

/* Estimate jobs[0..n) in parallel (OpenMP; each job writes its own slot, so
 * the result does not depend on the thread count) and append the facing
 * ones to the links in job order.  The estimates go straight into the link
 * array's free tail, which is then closed up: a copy through a separate
 * buffer, and the page faults of growing the array one link at a time, cost
 * a fifth of the refinement's wall time on two threads.  On failure the first
 * failing job is estimated again on this thread, so that its message
 * (thread-local) is the one the caller sees. */
static rad_status estimate_batch(rad_hier *h, const link_job *jobs, size_t n)
{
    if (n == 0)
        return RAD_OK;
    rad_status st = reserve_links(h, n);
    unsigned char *ok = st == RAD_OK ? malloc(n) : NULL;
    if (!ok)
        return st != RAD_OK ? st
                            : RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu link estimates", n);
    long long evals = 0, failed = -1;
    unsigned long long rays = 0;
    const rad_hier *hc = h;
    hier_link *out = h->ln + h->nln;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : evals, rays) if (n > 64)
    for (long long k = 0; k < (long long)n; k++) {
        work_count wc = {0, 0};
        int facing = 0;
        rad_status est = estimate(hc, jobs[k].r, jobs[k].s, &facing, &out[k], &wc);
        evals += wc.evals;
        rays += wc.rays;
        ok[k] = est == RAD_OK ? (unsigned char)(facing ? 1 : 0) : 2;
    }
    h->st.kernel_evals += evals;
    h->st.rays += rays;
    size_t w = h->nln;
    for (size_t k = 0; k < n; k++) {
        if (ok[k] == 2) {
            failed = (long long)k;
            break;
        }
        if (ok[k] == 1)
            h->ln[w++] = out[k]; /* w <= nln + k: never overwrites an unread slot */
    }
    free(ok);
    if (failed >= 0) {
        work_count wc = {0, 0};
        int facing = 0;
        hier_link l;
        st = estimate(h, jobs[failed].r, jobs[failed].s, &facing, &l, &wc);
        if (st == RAD_OK) /* cannot happen: estimate is deterministic */
            st = RAD_ERROR(RAD_ENUMERIC, "hier: link %d <- %d failed on a worker thread",
                           jobs[failed].r, jobs[failed].s);
        return st;
    }
    h->nln = w;
    return RAD_OK;
}

rad_status rad_hier_create(const double *xyz, size_t nverts, const int *tri, size_t ntris,
                           const double *rho, const double *E, const rad_vis *vis,
                           const rad_hier_params *params, rad_hier **out)
{
    rad_hier_params p;
    if (params)
        p = *params;
    else
        rad_hier_params_default(&p);
    if (!out)
        return RAD_ERROR(RAD_EINVAL, "hier: no output handle");
    *out = NULL;
    rad_status st = check_params(&p);
    if (st != RAD_OK)
        return st;
    if (!xyz || !tri || !rho || !E || ntris < 1 || ntris > (size_t)1 << 30)
        return RAD_ERROR(RAD_EINVAL, "hier: bad arguments (%zu triangles)", ntris);
    rad_hier *h = calloc(1, sizeof *h);
    if (!h)
        return RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
    h->p = p;
    h->vis = vis;
    h->use_vis = vis && !rad_vis_is_unoccluded(vis);
    h->nroots = ntris;
    h->rho = malloc(3 * ntris * sizeof *h->rho);
    h->E = malloc(3 * ntris * sizeof *h->E);
    h->normal = malloc(ntris * sizeof *h->normal);
    if (!h->rho || !h->E || !h->normal) {
        st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory");
        goto fail;
    }
    memcpy(h->rho, rho, 3 * ntris * sizeof *rho);
    memcpy(h->E, E, 3 * ntris * sizeof *E);
    st = grow_elems(h, ntris);
    if (st != RAD_OK)
        goto fail;
    for (size_t t = 0; t < ntris; t++) {
        hier_elem *e = &h->el[t];
        memset(e, 0, sizeof *e);
        for (int v = 0; v < 3; v++) {
            int k = tri[3 * t + (size_t)v];
            if (k < 0 || (size_t)k >= nverts) {
                st = RAD_ERROR(RAD_EINPUT, "hier: triangle %zu: vertex index %d out of range", t,
                               k);
                goto fail;
            }
            e->p[v] = rad_vec3_make(xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]);
            if (!rad_vec3_is_finite(e->p[v])) {
                st = RAD_ERROR(RAD_EINPUT, "hier: triangle %zu: non-finite vertex", t);
                goto fail;
            }
        }
        if (rad_geom_triangle_is_degenerate(e->p[0], e->p[1], e->p[2], p.ff.degenerate_rel_tol)) {
            st = RAD_ERROR(RAD_EINPUT, "hier: triangle %zu is degenerate", t);
            goto fail;
        }
        e->area = rad_geom_triangle_area(e->p[0], e->p[1], e->p[2]);
        e->size = rad_geom_triangle_longest_edge(e->p);
        h->normal[t] = rad_geom_triangle_normal(e->p[0], e->p[1], e->p[2]);
        e->parent = e->first_child = -1;
        e->face = (int)t;
        sample_points(e, (int)t, p.vis_points, e->vis);
        for (int c = 0; c < 3; c++) {
            double r = rho[t + c * ntris], em = E[t + c * ntris];
            if (!(r >= 0.0 && r < 1.0) || !(em >= 0.0) || !isfinite(em)) {
                st = RAD_ERROR(RAD_EINPUT, "hier: triangle %zu: reflectance must lie in [0,1) "
                                           "and emission be finite and >= 0 (channel %d)", t, c);
                goto fail;
            }
            e->B[c] = em;
            h->E_max = fmax(h->E_max, em);
        }
    }
    h->nel = ntris;
    /* Every ordered pair of input triangles is estimated: refuse before the
       work when even half of them could not be held as links (clustering,
       which would link groups of triangles, is not implemented). */
    if ((double)ntris * (double)(ntris - 1) > 2.0 * (double)p.max_links) {
        st = RAD_ERROR(RAD_ETOOBIG, "hier: %zu input triangles make %.3g ordered pairs to link, "
                                    "beyond twice max_links (%zu); use fewer triangles",
                       ntris, (double)ntris * (double)(ntris - 1), p.max_links);
        goto fail;
    }
    double t0 = rad_sys_seconds();
    if (h->use_vis && ntris <= HIER_BLOCK_TABLE_MAX) {
        h->can_block = malloc(ntris * ntris);
        if (!h->can_block) {
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the blocker table of %zu "
                                       "triangles", ntris);
            goto fail;
        }
        const rad_vis *v = vis;
        unsigned char *tab = h->can_block;
#pragma omp parallel for schedule(dynamic, 16) if (ntris > 64)
        for (long long r = 0; r < (long long)ntris; r++)
            for (size_t s = 0; s < ntris; s++)
                tab[(size_t)r * ntris + s] =
                    (size_t)r != s && rad_vis_pair_can_block(v, (size_t)r, s) ? 1 : 0;
    }
    {
        link_job *jobs = malloc(ntris * (ntris - 1 > 0 ? ntris - 1 : 1) * sizeof *jobs + 1);
        if (!jobs) {
            st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for the initial links of %zu "
                                       "triangles", ntris);
            goto fail;
        }
        size_t nj = 0;
        for (size_t r = 0; r < ntris; r++)
            for (size_t s = 0; s < ntris; s++)
                if (r != s)
                    jobs[nj++] = (link_job){(int)r, (int)s};
        st = estimate_batch(h, jobs, nj);
        free(jobs);
        if (st != RAD_OK)
            goto fail;
    }
    h->st.time_link_s = rad_sys_seconds() - t0;
    *out = h;
    return RAD_OK;
fail:
    rad_hier_destroy(h);
    return st;
}

void rad_hier_destroy(rad_hier *h)
{
    if (!h)
        return;
    free(h->rho);
    free(h->E);
    free(h->can_block);
    free(h->normal);
    free(h->el);
    free(h->ln);
    free(h);
}

/* Push down[] (the ancestors' gathered radiosity) to the leaves under e and
 * pull the area-weighted mean back up; accumulates the largest leaf change. */
static void push_pull(rad_hier *h, int e, const double down[3], double *change, double *bmax)
{
    hier_elem *x = &h->el[e];
    double tot[3];
    for (int c = 0; c < 3; c++)
        tot[c] = down[c] + x->Bg[c];
    if (x->first_child < 0) {
        const double *rho = h->rho, *E = h->E;
        size_t n = h->nroots, f = (size_t)x->face;
        for (int c = 0; c < 3; c++) {
            double b = E[f + c * n] + rho[f + c * n] * tot[c];
            /* a non-finite b makes the change infinite, which the caller reports */
            *change = isfinite(b) ? rad_dmax(*change, fabs(b - x->B[c])) : INFINITY;
            *bmax = rad_dmax(*bmax, fabs(b));
            x->B[c] = b;
        }
        return;
    }
    double sum[3] = {0, 0, 0}, area = 0.0;
    for (int k = 0; k < 4; k++) {
        int ch = h->el[e].first_child + k;
        push_pull(h, ch, tot, change, bmax);
        const hier_elem *y = &h->el[ch];
        area += y->area;
        for (int c = 0; c < 3; c++)
            sum[c] += y->area * y->B[c];
    }
    x = &h->el[e];
    for (int c = 0; c < 3; c++)
        x->B[c] = area > 0.0 ? sum[c] / area : 0.0;
}

rad_status rad_hier_step(rad_hier *h)
{
    if (!h)
        return RAD_ERROR(RAD_EINVAL, "hier: no handle");
    for (size_t e = 0; e < h->nel; e++)
        h->el[e].Bg[0] = h->el[e].Bg[1] = h->el[e].Bg[2] = 0.0;
    for (size_t k = 0; k < h->nln; k++) {
        const hier_link *l = &h->ln[k];
        if (l->r < 0)
            continue;
        double fv = l->F * l->V;
        hier_elem *r = &h->el[l->r];
        const hier_elem *s = &h->el[l->s];
        for (int c = 0; c < 3; c++)
            r->Bg[c] += fv * s->B[c];
    }
    double change = 0.0, bmax = 0.0, zero[3] = {0, 0, 0};
    for (size_t t = 0; t < h->nroots; t++)
        push_pull(h, (int)t, zero, &change, &bmax);
    if (!isfinite(change) || !isfinite(bmax))
        return RAD_ERROR(RAD_ENUMERIC, "hier: a radiosity is not finite after step %lld",
                         h->st.iterations + 1);
    h->last_change = bmax > 0.0 ? change / bmax : change;
    h->st.residual = h->last_change;
    h->st.iterations++;
    h->stepped = 1;
    return RAD_OK;
}

rad_status rad_hier_test(const rad_hier *h)
{
    if (!h || !h->stepped)
        return RAD_CONTINUE;
    return h->last_change <= h->p.tol ? RAD_OK : RAD_CONTINUE;
}

static double maxc(const double *v, size_t stride)
{
    return rad_dmax(v[0], rad_dmax(v[stride], v[2 * stride]));
}

static int can_split(const rad_hier *h, int e)
{
    const hier_elem *x = &h->el[e];
    /* an element split for another link already has its children */
    return x->first_child >= 0 ||
           (x->depth < h->p.max_depth && x->area / 4.0 >= h->p.min_area);
}

static rad_status split(rad_hier *h, int e)
{
    if (h->el[e].first_child >= 0)
        return RAD_OK;
    rad_status st = grow_elems(h, 4);
    if (st != RAD_OK)
        return st;
    hier_elem par = h->el[e];
    rad_vec3 a = par.p[0], b = par.p[1], c = par.p[2];
    rad_vec3 ab = rad_vec3_scale(rad_vec3_add(a, b), 0.5);
    rad_vec3 bc = rad_vec3_scale(rad_vec3_add(b, c), 0.5);
    rad_vec3 ca = rad_vec3_scale(rad_vec3_add(c, a), 0.5);
    rad_vec3 corners[4][3] = {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}};
    int first = (int)h->nel;
    for (int k = 0; k < 4; k++) {
        hier_elem *x = &h->el[first + k];
        *x = par;
        memcpy(x->p, corners[k], sizeof x->p);
        x->area = rad_geom_triangle_area(x->p[0], x->p[1], x->p[2]);
        x->size = rad_geom_triangle_longest_edge(x->p);
        x->parent = e;
        x->first_child = -1;
        x->depth = par.depth + 1;
        x->Bg[0] = x->Bg[1] = x->Bg[2] = 0.0;
        sample_points(x, first + k, h->p.vis_points, x->vis);
    }
    h->el[e].first_child = first;
    h->nel += 4;
    return RAD_OK;
}


/* The oracle's estimate of the radiosity error a link leaves at its receiver
 * (compared with eps * reflected_scale; see rad_hier.h). */
static double link_error(const rad_hier *h, const hier_link *l)
{
    const hier_elem *r = &h->el[l->r], *s = &h->el[l->s];
    double rho_bs = maxc(h->rho + r->face, h->nroots) * maxc(s->B, 1);
    /* A link not fully visible is judged by its unoccluded transport: its V
     * comes from a few samples (all of them may miss a gap), and only refining
     * it can resolve the shadow it lies in (HSA 1991, sec. 4.2).  With F V
     * here, links sampled at V = 0 were never refined and their light was
     * lost: the occluder scene came out 3.5% dark. */
    if (l->V < 1.0)
        return rho_bs * l->F;
    if (h->p.oracle == RAD_HIER_ORACLE_ERROR)
        return rho_bs * rad_dmax(l->dFr, l->dFs);
    return rho_bs * l->F;
}

/* The radiosity scale the oracles' errors are compared with: the area-
 * weighted mean over the leaves of the reflected radiosity max_c (B - E), i.e.
 * the quantity whose relative error users measure.  E_max before anything has
 * been reflected (no step yet, or no reflectance anywhere). */
static double reflected_scale(const rad_hier *h)
{
    double sum = 0.0, area = 0.0;
    for (size_t e = 0; e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        double m = 0.0;
        for (int c = 0; c < 3; c++)
            m = fmax(m, x->B[c] - h->E[(size_t)x->face + c * h->nroots]);
        sum += x->area * m;
        area += x->area;
    }
    double mean = area > 0.0 ? sum / area : 0.0;
    return mean > 0.0 ? mean : h->E_max;
}

rad_status rad_hier_refine(rad_hier *h, long long *refined)
{
    double t0 = rad_sys_seconds();
    if (refined)
        *refined = 0;
    if (!h)
        return RAD_ERROR(RAD_EINVAL, "hier: no handle");
    long long count = 0;
    rad_status st = RAD_OK;
    double threshold = h->p.eps * reflected_scale(h);
    link_job *jobs = NULL;
    size_t capj = 0;
    /* Generation by generation: decide and split for the links of one
     * generation (in order, on this thread), estimate the links that replace
     * them in parallel, then examine those as the next generation.  The same
     * links in the same order as examining each new link right after the
     * ones before it (HSA 1991's recursive Refine): a decision depends only on
     * its own link and on which elements are split already. */
    size_t begin = 0, end = h->E_max > 0.0 ? h->nln : 0;
    while (begin < end) {
        size_t nj = 0;
        for (size_t k = begin; k < end; k++) {
            hier_link l = h->ln[k];
            if (l.r < 0)
                continue;
            const hier_elem *r = &h->el[l.r], *s = &h->el[l.s];
            double err = link_error(h, &l);
            if (!(err > threshold) && !l.unknown)
                continue;
            /* BF splits the larger element; ERROR the side whose kernel varies
             * more (a split of the other could not reduce the error it found).
             * Either way the other one when the first may not be split. */
            int first_choice;
            if (h->p.oracle == RAD_HIER_ORACLE_ERROR && l.V >= 1.0 && !l.unknown)
                first_choice = l.dFs > l.dFr ? l.s : l.r;
            else
                first_choice = s->area > r->area ? l.s : l.r;
            int second = first_choice == l.s ? l.r : l.s;
            int target = can_split(h, first_choice) ? first_choice
                         : can_split(h, second)     ? second
                                                    : -1;
            if (target < 0)
                continue;
            int split_src = target == l.s;
            if ((st = split(h, target)) != RAD_OK)
                goto done;
            if (nj + 4 > capj) {
                size_t cap = capj ? 2 * capj : 1024;
                link_job *nj_ = realloc(jobs, cap * sizeof *jobs);
                if (!nj_) {
                    st = RAD_ERROR(RAD_ENOMEM, "hier: out of memory for %zu new links", cap);
                    goto done;
                }
                jobs = nj_;
                capj = cap;
            }
            h->ln[k].r = -1; /* the link is replaced */
            int first = h->el[target].first_child;
            for (int c = 0; c < 4; c++)
                jobs[nj++] = (link_job){split_src ? l.r : first + c, split_src ? first + c : l.s};
            count++;
        }
        if ((st = estimate_batch(h, jobs, nj)) != RAD_OK)
            goto done;
        begin = end;
        end = h->nln;
    }
done:
    free(jobs);
    /* drop the replaced links (keeps order, so results do not depend on capacity) */
    {
        size_t w = 0;
        for (size_t k = 0; k < h->nln; k++)
            if (h->ln[k].r >= 0)
                h->ln[w++] = h->ln[k];
        h->nln = w;
    }
    h->st.refinements += count;
    h->st.time_refine_s += rad_sys_seconds() - t0;
    if (count > 0)
        h->st.rounds++;
    if (count > 0)
        h->stepped = 0; /* the system changed: the last test no longer holds */
    if (refined)
        *refined = count;
    return st;
}

/* Gather/push-pull steps until the step change is at most tol (relative to
 * the largest leaf radiosity). */
static rad_status solve_links(rad_hier *h, double tol)
{
    double t0 = rad_sys_seconds();
    for (int it = 0; it < h->p.max_iterations; it++) {
        rad_status st = rad_hier_step(h);
        if (st != RAD_OK)
            return st;
        if (h->last_change <= tol) {
            h->st.time_solve_s += rad_sys_seconds() - t0;
            return RAD_OK;
        }
    }
    return RAD_ERROR(RAD_ENUMERIC, "hier: gather/push-pull did not converge in %d steps "
                                   "(change %.3g > tol %.3g)", h->p.max_iterations,
                     h->last_change, tol);
}

/* The solves between refinement rounds only feed the oracle, whose decisions
 * compare link errors with eps (>= 1e-3 in practice) times the mean reflected
 * radiosity: a step change of 1e-5 leaves B within about 1e-5 / (1 - rho) of
 * its fixed point, far below that.  The last solve goes to tol.  On the
 * Cornell box this more than halves the steps (88 -> 39 at eps 0.005, min_area total/1280). */
#define HIER_ROUND_TOL 1e-5

rad_status rad_hier_solve(rad_hier *h)
{
    if (!h)
        return RAD_ERROR(RAD_EINVAL, "hier: no handle");
    double round_tol = fmax(h->p.tol, HIER_ROUND_TOL);
    rad_status st = solve_links(h, round_tol);
    for (int round = 0; st == RAD_OK; round++) {
        if (h->p.progress)
            h->p.progress(round, rad_hier_leaf_count(h), h->nln, h->p.progress_ctx);
        if (round >= h->p.max_rounds)
            break;
        long long n = 0;
        st = rad_hier_refine(h, &n);
        if (st != RAD_OK || n == 0)
            break;
        st = solve_links(h, round_tol);
    }
    if (st == RAD_OK)
        st = solve_links(h, h->p.tol);
    return st;
}

void rad_hier_get_stats(const rad_hier *h, rad_hier_stats *stats)
{
    if (!h || !stats)
        return;
    *stats = h->st;
    stats->nodes = h->nel;
    stats->links = h->nln;
    stats->elements = rad_hier_leaf_count(h);
    stats->links_clear = stats->links_visible = stats->links_partial = 0;
    stats->links_blocked = stats->links_unknown = stats->links_leaf = 0;
    for (size_t k = 0; k < h->nln; k++) {
        const hier_link *l = &h->ln[k];
        if (l->unknown)
            stats->links_unknown++;
        else if (!l->traced)
            stats->links_clear++;
        else if (l->V >= 1.0)
            stats->links_visible++;
        else if (l->V > 0.0)
            stats->links_partial++;
        else
            stats->links_blocked++;
        stats->links_leaf += h->el[l->r].first_child < 0 && h->el[l->s].first_child < 0;
    }
    stats->max_depth = 0;
    for (size_t e = 0; e < h->nel; e++)
        if (h->el[e].first_child < 0 && h->el[e].depth > stats->max_depth)
            stats->max_depth = h->el[e].depth;
}

size_t rad_hier_leaf_count(const rad_hier *h)
{
    size_t n = 0;
    if (!h)
        return 0;
    for (size_t e = 0; e < h->nel; e++)
        n += h->el[e].first_child < 0;
    return n;
}

void rad_hier_leaves(const rad_hier *h, int *face, double *area, double *corners, double *B)
{
    if (!h)
        return;
    size_t n = rad_hier_leaf_count(h), k = 0;
    for (size_t e = 0; e < h->nel; e++) {
        const hier_elem *x = &h->el[e];
        if (x->first_child >= 0)
            continue;
        if (face)
            face[k] = x->face;
        if (area)
            area[k] = x->area;
        if (corners)
            for (int v = 0; v < 3; v++) {
                corners[9 * k + 3 * v] = x->p[v].x;
                corners[9 * k + 3 * v + 1] = x->p[v].y;
                corners[9 * k + 3 * v + 2] = x->p[v].z;
            }
        if (B)
            for (int c = 0; c < 3; c++)
                B[k + c * n] = x->B[c];
        k++;
    }
}
