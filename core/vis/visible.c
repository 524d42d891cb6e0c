/* rad_vis: the visible part of the kernel integral, with visibility computed
 * exactly at every outer point.
 *
 *   G_vis(a, b) = int_a F_vis(x, b) dA_x,
 *   F_vis(x, b) = int_{part of b visible from x} K(x, y) dA_y.
 *
 * 1. Blockers: the triangles the shaft of the pair does not dismiss
 *    (rad_vis_blockers), the pair's own input faces excluded.
 * 2. The visible part of b from a point x (visible_pieces): in b's plane, b
 *    minus the shadow of every blocker (of the convex quad a blocker makes
 *    with its partner, partner.c, once for both).  A blocker's shadow is its part
 *    strictly between b's plane and x (clipped to the slab 0 < h < d, h the
 *    height above b's plane, d that of x) and inside the cone from x over b
 *    (clipped by the three planes through x and an edge of b), projected from
 *    x onto b's plane: a convex polygon inside b.  Subtracting a convex
 *    polygon from a convex piece cuts the piece along each edge line of the
 *    polygon; the parts outside are kept, the part inside dropped.  The
 *    visible part is thus a list of convex pieces.  A closed convex solid
 *    (solid.c) casts one shadow for all its listed faces, the hull of its
 *    clipped part's projected corners; a blocker wholly behind x's own plane
 *    casts none that matters (it would fall where x's cosine is <= 0).
 * 3. F_vis(x, b) = sum over the pieces of the closed-form point-to-polygon
 *    form factor (rad_ff_point_polygon: contour integral, x's cosine clamped).
 *    In a closed scene the visible pieces of all triangles from x tile x's
 *    hemisphere, so sum_b F_vis(x, b) = 1 at every x: whatever outer rule is
 *    used, a row of form factors sums to 1 up to the outer rule's error.
 *    A cell of the outer integral (below) keeps only the blockers its own
 *    shaft with b does not dismiss, filtered from its parent's list.
 * 4. The outer integral (rad_vis_pair_visible) over whichever triangle lies
 *    wholly in front of the other's plane (a when both or neither do): a
 *    symmetric rule of the given degree on it, compared with the same rule on
 *    its four midpoint children; where the visible or the open value differs
 *    by more than the cell's share of tol times the pair's unoccluded G (which
 *    the caller knows from rad_ff), the children are refined in turn (to
 *    max_depth), as is a cell across the other's plane whose nodes all see
 *    nothing of it.  F_vis is continuous in x (a penumbra is continuous), so
 *    the rule converges; the reported error is the sum of the accepted cells'
 *    differences.
 * 5. Where the shaft holds more than max_blockers triangles, or a visible part
 *    would need more pieces than the workspace holds, the pair falls back to
 *    rays: the kernel-weighted share of open segments between stratified
 *    points of a and b, times the unoccluded G (sampled()).
 * Degenerate cases: a point behind b's plane sees nothing of it; a blocker in
 * b's plane casts no shadow (it cannot cross a segment to b's interior). */
#include "vis_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rad_ff.h"
#include "rad_quad.h"

enum { POLY_MAX = 20, PIECES_SMALL = 96, PIECES_MAX = 8192, PARTNER_SCAN = 64 };

typedef struct v2 {
    double x, y;
} v2;

typedef struct poly2 {
    int n;
    double lo[2], hi[2]; /* its bounding box (set by bbox2) */
    v2 p[POLY_MAX];
} poly2;

void rad_vis_visible_params_default(rad_vis_visible_params *p)
{
    memset(p, 0, sizeof *p); /* every field a later one adds starts at 0 */
    p->degree = 2;
    p->tol = 5e-3;
    p->max_depth = 0;
    p->max_blockers = 1024;
    p->sample_strata = 8;
}

static double cross2(v2 o, v2 a, v2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

static double area2(const poly2 *q)
{
    double s = 0.0;
    for (int k = 0; k < q->n; k++) {
        v2 a = q->p[k], b = q->p[k + 1 < q->n ? k + 1 : 0];
        s += a.x * b.y - a.y * b.x;
    }
    return 0.5 * s;
}

/* Split convex q by the line through a, b: left (cross >= 0) and right parts.
 * 0 when a part would have more than POLY_MAX corners. */
static int split_line(const poly2 *q, v2 a, v2 b, poly2 *left, poly2 *right)
{
    left->n = right->n = 0;
    for (int k = 0; k < q->n; k++) {
        v2 p = q->p[k], r = q->p[k + 1 < q->n ? k + 1 : 0];
        double sp = cross2(a, b, p), sr = cross2(a, b, r);
        if (left->n + 2 > POLY_MAX || right->n + 2 > POLY_MAX)
            return 0;
        if (sp >= 0.0)
            left->p[left->n++] = p;
        if (sp <= 0.0)
            right->p[right->n++] = p;
        if ((sp > 0.0 && sr < 0.0) || (sp < 0.0 && sr > 0.0)) {
            double t = sp / (sp - sr);
            v2 m = {p.x + t * (r.x - p.x), p.y + t * (r.y - p.y)};
            left->p[left->n++] = m;
            right->p[right->n++] = m;
        }
    }
    return 1;
}

/* Clip a 3D polygon (n <= 9: a quad cut by at most five planes) to
 * dot(m, p) - c >= 0. */
static int clip3(const rad_vec3 *in, int n, rad_vec3 m, double c, rad_vec3 *out)
{
    int k = 0;
    for (int i = 0; i < n; i++) {
        rad_vec3 p = in[i], q = in[i + 1 < n ? i + 1 : 0];
        double sp = rad_vec3_dot(m, p) - c, sq = rad_vec3_dot(m, q) - c;
        if (sp >= 0.0)
            out[k++] = p;
        if ((sp > 0.0 && sq < 0.0) || (sp < 0.0 && sq > 0.0)) {
            double t = sp / (sp - sq);
            out[k++] = rad_vec3_add(p, rad_vec3_scale(rad_vec3_sub(q, p), t));
        }
    }
    return k;
}

/* The frame of b's plane: origin b0, in-plane axes e1, e2 (counter-clockwise
 * seen from the front), unit normal n. */
typedef struct plane_frame {
    rad_vec3 o, e1, e2, n;
    double area;
} plane_frame;

static int make_frame(const rad_vec3 b[3], plane_frame *f)
{
    rad_vec3 n = rad_vec3_cross(rad_vec3_sub(b[1], b[0]), rad_vec3_sub(b[2], b[0]));
    double len = rad_vec3_norm(n), l1 = rad_vec3_norm(rad_vec3_sub(b[1], b[0]));
    if (!(len > 0.0) || !(l1 > 0.0))
        return 0;
    f->o = b[0];
    f->n = rad_vec3_scale(n, 1.0 / len);
    f->e1 = rad_vec3_scale(rad_vec3_sub(b[1], b[0]), 1.0 / l1);
    f->e2 = rad_vec3_cross(f->n, f->e1);
    f->area = 0.5 * len;
    return 1;
}

static v2 to2(const plane_frame *f, rad_vec3 p)
{
    rad_vec3 d = rad_vec3_sub(p, f->o);
    v2 r = {rad_vec3_dot(d, f->e1), rad_vec3_dot(d, f->e2)};
    return r;
}

static rad_vec3 to3(const plane_frame *f, v2 q)
{
    return rad_vec3_add(f->o, rad_vec3_add(rad_vec3_scale(f->e1, q.x), rad_vec3_scale(f->e2, q.y)));
}

/* The five planes that bound what can shadow b from x: the slab strictly
 * between b's plane and x (heights above b's plane in (0, d)) and the three
 * planes through x and an edge of b, all as dot(m, p) >= c. */
typedef struct shadow_planes {
    rad_vec3 m[5];
    double c[5], len[5]; /* len: |m| */
    double h0, d;
    rad_vec3 nx;  /* x's normal: what lies behind x's plane blocks nothing x sees */
    double front; /* dot(nx, p) > front: p in front of x's plane (by 1e-9 d) */
} shadow_planes;

static void make_shadow_planes(rad_vec3 x, rad_vec3 nx, double d, const rad_vec3 b[3],
                               const plane_frame *f, shadow_planes *sp)
{
    sp->nx = nx;
    sp->front = rad_vec3_dot(nx, x) + 1e-9 * d * rad_vec3_norm(nx);
    double h0 = rad_vec3_dot(f->n, f->o), eps = 1e-12 * (d + fabs(h0)) + 1e-300;
    sp->h0 = h0;
    sp->d = d;
    sp->m[0] = f->n;
    sp->c[0] = h0 + eps;
    sp->m[1] = rad_vec3_scale(f->n, -1.0);
    sp->len[0] = sp->len[1] = 1.0;
    sp->c[1] = -(h0 + d * (1.0 - 1e-9));
    for (int e = 0; e < 3; e++) {
        rad_vec3 p = b[e], q = b[(e + 1) % 3], r = b[(e + 2) % 3];
        rad_vec3 m = rad_vec3_cross(rad_vec3_sub(p, x), rad_vec3_sub(q, x));
        if (rad_vec3_dot(m, rad_vec3_sub(r, x)) < 0.0)
            m = rad_vec3_scale(m, -1.0);
        sp->m[2 + e] = m;
        sp->c[2 + e] = rad_vec3_dot(m, x);
        sp->len[2 + e] = rad_vec3_norm(m);
    }
}

/* The shadow of blocker k (with its partner, the quad they make: partner.c)
 * on b's plane from x, as a counter-clockwise convex polygon in the frame; 0
 * when it casts none.  A blocker wholly outside one plane is dismissed at
 * once, one wholly inside all five is projected without clipping. */
static int shadow(const rad_vis *vis, size_t k, rad_vec3 x, const shadow_planes *sp,
                  const plane_frame *f, poly2 *out)
{
    rad_vec3 buf[2][POLY_MAX];
    int n = 3;
    if (vis->partner && vis->partner[k] >= 0) {
        n = 4;
        for (int v = 0; v < 4; v++) {
            const double *p = vis->xyz + 3 * (size_t)vis->quad[k][v];
            buf[0][v] = rad_vec3_make(p[0], p[1], p[2]);
        }
    } else {
        for (int v = 0; v < 3; v++)
            buf[0][v] = vis_vertex(vis, k, v);
    }
    int clip_mask = 0, front = 0;
    for (int v = 0; v < n; v++) /* behind x's plane: its shadow falls where x sees nothing */
        front += rad_vec3_dot(sp->nx, buf[0][v]) > sp->front;
    if (front == 0)
        return 0;
    for (int q = 0; q < 5; q++) {
        int inside = 0;
        for (int v = 0; v < n; v++)
            inside += rad_vec3_dot(sp->m[q], buf[0][v]) >= sp->c[q];
        if (inside == 0)
            return 0;
        if (inside < n)
            clip_mask |= 1 << q;
    }
    int cur = 0;
    for (int q = 0; q < 5 && n >= 3; q++)
        if (clip_mask & (1 << q)) {
            n = clip3(buf[cur], n, sp->m[q], sp->c[q], buf[1 - cur]);
            cur = 1 - cur;
        }
    if (n < 3)
        return 0;
    out->n = n;
    double d = sp->d;
    for (int v = 0; v < n; v++) {
        rad_vec3 p = buf[cur][v];
        double h = rad_vec3_dot(f->n, p) - sp->h0;
        rad_vec3 y = rad_vec3_add(x, rad_vec3_scale(rad_vec3_sub(p, x), d / (d - h)));
        out->p[v] = to2(f, y);
    }
    double a = area2(out);
    if (!(fabs(a) > 1e-15 * f->area))
        return 0;
    if (a < 0.0) /* keep it counter-clockwise */
        for (int v = 0; v < n / 2; v++) {
            v2 t = out->p[v];
            out->p[v] = out->p[n - 1 - v];
            out->p[n - 1 - v] = t;
        }
    return 1;
}

/* The convex hull of p[0..n) (sorted in place by x, then y), counter-clockwise without
 * collinear corners, into out; 0 when it has more than POLY_MAX corners. */
static int hull2(v2 *p, int n, poly2 *out)
{
    v2 h[9 * VIS_SOLID_MAX_TRIS + 11]; /* n + 1 at most: solid_shadow's PTS */
    for (int i = 1; i < n; i++) { /* insertion sort: a few dozen points */
        v2 t = p[i];
        int j = i;
        while (j > 0 && (p[j - 1].x > t.x || (p[j - 1].x == t.x && p[j - 1].y > t.y))) {
            p[j] = p[j - 1];
            j--;
        }
        p[j] = t;
    }
    int k = 0;
    for (int i = 0; i < n; i++) { /* lower hull */
        while (k >= 2 && cross2(h[k - 2], h[k - 1], p[i]) <= 0.0)
            k--;
        h[k++] = p[i];
    }
    for (int i = n - 2, lo = k + 1; i >= 0; i--) { /* upper hull */
        while (k >= lo && cross2(h[k - 2], h[k - 1], p[i]) <= 0.0)
            k--;
        h[k++] = p[i];
    }
    k = k > 1 ? k - 1 : k; /* the last point repeats the first */
    if (k > POLY_MAX)
        return 0;
    out->n = k;
    memcpy(out->p, h, (size_t)k * sizeof *h);
    return 1;
}

/* The point on the three planes q1, q2, q3 of sp; 0 when they do not meet in
 * one point. */
static int three_planes(const shadow_planes *sp, int q1, int q2, int q3, rad_vec3 *p)
{
    rad_vec3 a = sp->m[q1], b = sp->m[q2], c = sp->m[q3];
    rad_vec3 bc = rad_vec3_cross(b, c), ca = rad_vec3_cross(c, a), ab = rad_vec3_cross(a, b);
    double det = rad_vec3_dot(a, bc);
    double scale = rad_vec3_norm(a) * rad_vec3_norm(b) * rad_vec3_norm(c);
    if (!(fabs(det) > 1e-12 * scale))
        return 0;
    *p = rad_vec3_scale(rad_vec3_add(rad_vec3_add(rad_vec3_scale(bc, sp->c[q1]),
                                                  rad_vec3_scale(ca, sp->c[q2])),
                                     rad_vec3_scale(ab, sp->c[q3])),
                        1.0 / det);
    return 1;
}

/* The shadow of closed convex solid s (solid.c) on b's plane from x: the
 * projection of its part inside the five planes, which is convex, as the
 * hull of the projections of that part's corners: the solid's corners where
 * no plane cuts it, else its faces' corners after clipping and the points
 * where three planes meet inside it.  (Where the solid stays low, the
 * polygon may reach beyond b: see below.)  1 with the polygon in out, 0 when it
 * casts none, -1 when x lies inside the solid or the hull has more corners
 * than a poly2 holds (the caller subtracts the faces one by one). */
static int solid_shadow(const rad_vis *vis, int s, rad_vec3 x, const shadow_planes *sp,
                        const plane_frame *f, poly2 *out)
{
    /* a face (triangle or quad) clipped by five planes keeps at most 9
       corners; ten triple points; b's plane alone: corners and crossings */
    enum { PTS = 9 * VIS_SOLID_MAX_TRIS + 10 };
    const vis_solid *so = &vis->solids[s];
    rad_vec3 p3[PTS];
    double hgt[3 * VIS_SOLID_MAX_TRIS];
    int n = 0, clip_mask = 0, inside_all = 1;
    /* heights above b's plane: the slab's two planes */
    double lo = sp->c[0] - sp->h0, top = -sp->c[1] - sp->h0, hmax = -INFINITY;
    int below = 0, above = 0, behind = 0;
    for (int i = 0; i < so->npt; i++) {
        const double *q = vis->xyz + 3 * (size_t)vis->solid_pt[so->pt + i];
        p3[i] = rad_vec3_make(q[0], q[1], q[2]);
        hgt[i] = rad_vec3_dot(f->n, p3[i]) - sp->h0;
        hmax = rad_dmax(hmax, hgt[i]);
        below += !(hgt[i] >= lo);
        above += !(hgt[i] <= top);
        behind += !(rad_vec3_dot(sp->nx, p3[i]) > sp->front);
    }
    /* below b's plane, above x, or behind x's own plane (x on the solid's
       surface: its shadow falls where x sees nothing) */
    if (below == so->npt || above == so->npt || behind == so->npt)
        return 0;
    clip_mask = (below ? 1 : 0) | (above ? 2 : 0);
    rad_vec3 centre = rad_vec3_make(so->centre[0], so->centre[1], so->centre[2]);
    for (int q = 2; q < 5; q++) {
        /* the bounding sphere first: wholly outside, or wholly inside */
        double sc = rad_vec3_dot(sp->m[q], centre) - sp->c[q], r = so->radius * sp->len[q];
        if (sc < -r)
            return 0;
        if (sc > r)
            continue;
        int inside = 0;
        for (int i = 0; i < so->npt; i++)
            inside += rad_vec3_dot(sp->m[q], p3[i]) >= sp->c[q];
        if (inside == 0)
            return 0;
        if (inside < so->npt)
            clip_mask |= 1 << q;
    }
    /* from inside (a room's walls), segments to other points inside cross
       none of its faces: those are subtracted one by one */
    inside_all = rad_vec3_norm(rad_vec3_sub(x, centre)) < so->radius;
    for (int i = 0; i < so->ntri && inside_all; i++) {
        const double *pl = vis->solid_plane + 4 * (size_t)(so->tri + i);
        inside_all = pl[0] * x.x + pl[1] * x.y + pl[2] * x.z < pl[3];
    }
    if (inside_all)
        return -1;
    /* Within b the projection of the solid's part in the slab is that of its
       part in the cone too, so where the solid stays below 0.99 of x's
       height (the projection at most multiplies distances from x's foot by
       100) the cone planes are left to the subtraction, which keeps what
       lies outside the shadow anyway; nearer x's height they bound the
       projection.  Cut by b's plane alone, the part's corners are the
       solid's above it and where its edges cross it. */
    if (hmax <= 0.99 * sp->d) {
        n = below ? 0 : so->npt;
        if (below) {
            for (int i = 0; i < so->npt; i++)
                if (hgt[i] >= lo)
                    p3[n++] = p3[i];
            for (int i = 0; i < so->ntri; i++) {
                rad_vec3 c[3];
                double hc[3];
                for (int v = 0; v < 3; v++) {
                    c[v] = vis_vertex(vis, (size_t)vis->solid_tri[so->tri + i], v);
                    hc[v] = rad_vec3_dot(f->n, c[v]) - sp->h0 - lo;
                }
                for (int v = 0; v < 3; v++) {
                    int w = v + 1 < 3 ? v + 1 : 0;
                    if ((hc[v] > 0.0 && hc[w] < 0.0) || (hc[v] < 0.0 && hc[w] > 0.0))
                        p3[n++] = rad_vec3_add(c[v], rad_vec3_scale(rad_vec3_sub(c[w], c[v]),
                                                                    hc[v] / (hc[v] - hc[w])));
                }
            }
        }
    } else if (!clip_mask) {
        n = so->npt;
    } else {
        /* each face clipped, a quad (partner.c) as one polygon */
        for (int i = 0; i < so->ntri; i++) {
            int t = vis->solid_tri[so->tri + i], pa = vis->partner ? vis->partner[t] : -1;
            if (pa >= 0 && pa < t)
                continue;
            rad_vec3 buf[2][POLY_MAX];
            int m = pa >= 0 ? 4 : 3, cur = 0;
            for (int v = 0; v < m; v++) {
                const double *q = vis->xyz + 3 * (size_t)(pa >= 0 ? vis->quad[t][v]
                                                                   : vis->tri[3 * (size_t)t + (size_t)v]);
                buf[0][v] = rad_vec3_make(q[0], q[1], q[2]);
            }
            for (int q = 0; q < 5 && m >= 3; q++)
                if (clip_mask & (1 << q)) {
                    m = clip3(buf[cur], m, sp->m[q], sp->c[q], buf[1 - cur]);
                    cur = 1 - cur;
                }
            for (int v = 0; v < m && m >= 3; v++)
                p3[n++] = buf[cur][v];
        }
        /* where three planes that cut the solid meet inside it */
        for (int q1 = 0; q1 < 5; q1++)
            for (int q2 = q1 + 1; q2 < 5; q2++)
                for (int q3 = q2 + 1; q3 < 5; q3++) {
                    rad_vec3 p;
                    if (!(clip_mask >> q1 & clip_mask >> q2 & clip_mask >> q3 & 1) ||
                        !three_planes(sp, q1, q2, q3, &p))
                        continue;
                    int in = 1;
                    for (int q = 0; q < 5 && in; q++)
                        if (q != q1 && q != q2 && q != q3)
                            in = rad_vec3_dot(sp->m[q], p) >= sp->c[q];
                    for (int i = 0; i < so->ntri && in; i++) {
                        const double *pl = vis->solid_plane + 4 * (size_t)(so->tri + i);
                        in = pl[0] * p.x + pl[1] * p.y + pl[2] * p.z <= pl[3];
                    }
                    if (in)
                        p3[n++] = p;
                }
    }
    if (n < 3)
        return 0;
    v2 p2[PTS];
    double d = sp->d;
    for (int i = 0; i < n; i++) {
        double h = rad_vec3_dot(f->n, p3[i]) - sp->h0;
        p2[i] = to2(f, rad_vec3_add(x, rad_vec3_scale(rad_vec3_sub(p3[i], x), d / (d - h))));
    }
    if (!hull2(p2, n, out))
        return -1;
    if (out->n < 3 || !(area2(out) > 1e-15 * f->area))
        return 0;
    return 1;
}

/* 1 when the edge u -> w is shorter than sqrt(min_edge2): a corner repeated
 * to within rounding, whose direction means nothing (every point lies on
 * its line). */
static int short_edge(v2 u, v2 w, double min_edge2)
{
    double ex = w.x - u.x, ey = w.y - u.y;
    return !(ex * ex + ey * ey > min_edge2);
}

/* 1 when the convex polygons p and q (counter-clockwise) are separated by
 * the line of an edge of either (touching counts as separated): then
 * subtracting q leaves p whole instead of cutting it into slivers. */
static int separated(const poly2 *p, const poly2 *q, double min_edge2)
{
    for (int pass = 0; pass < 2; pass++) {
        const poly2 *a = pass ? q : p, *b = pass ? p : q;
        for (int e = 0; e < a->n; e++) {
            v2 u = a->p[e], w = a->p[e + 1 < a->n ? e + 1 : 0];
            if (short_edge(u, w, min_edge2))
                continue;
            int k = 0;
            while (k < b->n && cross2(u, w, b->p[k]) <= 0.0)
                k++;
            if (k == b->n)
                return 1; /* every corner of b on the outer side of this edge */
        }
    }
    return 0;
}

static void bbox2(poly2 *q)
{
    q->lo[0] = q->lo[1] = INFINITY;
    q->hi[0] = q->hi[1] = -INFINITY;
    for (int k = 0; k < q->n; k++) {
        q->lo[0] = rad_dmin(q->lo[0], q->p[k].x);
        q->lo[1] = rad_dmin(q->lo[1], q->p[k].y);
        q->hi[0] = rad_dmax(q->hi[0], q->p[k].x);
        q->hi[1] = rad_dmax(q->hi[1], q->p[k].y);
    }
}

/* dst = src, copying only the corners in use (a poly2 holds room for
 * POLY_MAX; the pieces are copied in the clipping's inner loop). */
static void poly_copy(poly2 *dst, const poly2 *src)
{
    dst->n = src->n;
    dst->lo[0] = src->lo[0];
    dst->lo[1] = src->lo[1];
    dst->hi[0] = src->hi[0];
    dst->hi[1] = src->hi[1];
    memcpy(dst->p, src->p, (size_t)src->n * sizeof src->p[0]);
}

static int boxes_apart(const poly2 *p, const poly2 *q)
{
    return p->lo[0] >= q->hi[0] || p->hi[0] <= q->lo[0] || p->lo[1] >= q->hi[1] ||
           p->hi[1] <= q->lo[1];
}

/* Room for the pieces of a visible part. */
typedef struct pieces_ws {
    poly2 *list;
    int cap;
    poly2 *heap;               /* PIECES_MAX, once a part needs more */
    poly2 small[PIECES_SMALL]; /* the usual case, on the caller's stack */
} pieces_ws;

static void ws_init(pieces_ws *ws)
{
    ws->heap = NULL;
    ws->list = ws->small;
    ws->cap = PIECES_SMALL;
}

/* 0 when the workspace is at its largest already or memory is short. */
static int ws_grow(pieces_ws *ws)
{
    if (ws->heap || !(ws->heap = malloc((size_t)PIECES_MAX * sizeof(poly2))))
        return 0;
    ws->list = ws->heap;
    ws->cap = PIECES_MAX;
    return 1;
}

static void ws_free(pieces_ws *ws) { free(ws->heap); }

/* 1 when blocker k's partner (partner.c) comes earlier in the list, whose
 * entry subtracts the quad they make.  Past PARTNER_SCAN blockers the list
 * is not searched: both halves subtract the quad, the second removing
 * nothing more. */
static int listed_partner(const rad_vis *vis, const int *blockers, int nb, int k)
{
    int p = vis->partner ? vis->partner[blockers[k]] : -1;
    if (p < 0 || nb > PARTNER_SCAN)
        return 0;
    for (int i = 0; i < k; i++)
        if (blockers[i] == p)
            return 1;
    return 0;
}

/* The solids a visible part has met (visible_pieces), each with how its
 * shadow is subtracted: a small open-addressed set; once half full, further
 * solids are not recorded (solid_mark returns NULL) and their faces are
 * subtracted one by one. */
enum { SOLID_SET = 512, SOLID_NEW = 0, SOLID_DONE = 1, SOLID_FACES = 2 };
typedef struct solid_set {
    int n;
    int key[SOLID_SET], mode[SOLID_SET];
    unsigned char used[SOLID_SET];
} solid_set;

/* The mode slot of solid s (SOLID_NEW when it is new to the set), or NULL. */
static int *solid_mark(solid_set *set, int s)
{
    if (set->n == 0)
        memset(set->used, 0, sizeof set->used);
    unsigned h = ((unsigned)s * 2654435761u) % SOLID_SET;
    for (int probe = 0; probe < SOLID_SET; probe++, h = (h + 1) % SOLID_SET) {
        if (!set->used[h]) {
            if (2 * set->n >= SOLID_SET)
                return NULL;
            set->used[h] = 1;
            set->key[h] = s;
            set->mode[h] = SOLID_NEW;
            set->n++;
            return &set->mode[h];
        }
        if (set->key[h] == s)
            return &set->mode[h];
    }
    return NULL;
}

/* The visible part of b from x as convex pieces (*out points into ws); -1
 * when it needs more pieces, or pieces with more corners, than the
 * workspace holds (a larger one may do), -2 when it would take more than
 * max_work piece-against-shadow tests (> 0; the caller falls back), else
 * their count.  The pieces
 * are kept in one list: a piece a shadow misses stays where it is, one it
 * cuts is replaced by its first part outside the shadow and the others are
 * appended, one it covers is dropped. */
static int visible_pieces(const rad_vis *vis, rad_vec3 x, rad_vec3 nx, const rad_vec3 b[3],
                          const plane_frame *f, const int *blockers, int nb, long max_work,
                          pieces_ws *ws, const poly2 **out, int *cut)
{
    *cut = 0;
    double d = rad_vec3_dot(f->n, rad_vec3_sub(x, f->o));
    poly2 *pieces = ws->list;
    *out = pieces;
    if (!(d > 0.0))
        return 0;
    pieces[0].n = 3;
    for (int v = 0; v < 3; v++)
        pieces[0].p[v] = to2(f, b[v]);
    bbox2(&pieces[0]);
    int np = 1;
    long work = 0;
    double min_area = 1e-13 * f->area, sliver = 1e-18 * f->area;
    shadow_planes sp;
    if (nb > 0)
        make_shadow_planes(x, nx, d, b, f, &sp);
    solid_set seen; /* its arrays are read only where set->n says they are filled */
    seen.n = 0;
    for (int k = 0; k < nb && np > 0; k++) {
        poly2 q;
        int s = vis->solid ? vis->solid[blockers[k]] : -1, got = -1;
        int *mode = s >= 0 ? solid_mark(&seen, s) : NULL;
        if (mode && *mode == SOLID_DONE)
            continue; /* the solid's shadow is subtracted already */
        if (mode && *mode == SOLID_NEW) {
            got = solid_shadow(vis, s, x, &sp, f, &q);
            *mode = got < 0 ? SOLID_FACES : SOLID_DONE;
        }
        if (got < 0) /* not a solid's, or the solid's faces one by one */
            got = !listed_partner(vis, blockers, nb, k) &&
                  shadow(vis, (size_t)blockers[k], x, &sp, f, &q);
        if (!got)
            continue;
        bbox2(&q);
        int end = np; /* the pieces before this shadow; those appended lie outside it */
        if (max_work > 0 && (work += end) > max_work)
            return -2;
        for (int i = 0; i < end;) {
            if (boxes_apart(&pieces[i], &q) || separated(&pieces[i], &q, sliver)) {
                i++;
                continue;
            }
            *cut = 1;
            poly2 rest;
            poly_copy(&rest, &pieces[i]);
            int kept = 0;
            for (int e = 0; e < q.n && rest.n >= 3; e++) {
                poly2 in, outside;
                v2 u = q.p[e], w = q.p[e + 1 < q.n ? e + 1 : 0];
                if (short_edge(u, w, sliver))
                    continue; /* both sides of its line would be the whole rest */
                if (!split_line(&rest, u, w, &in, &outside))
                    return -1;
                if (outside.n >= 3 && area2(&outside) > min_area) {
                    bbox2(&outside);
                    if (!kept)
                        poly_copy(&pieces[i], &outside);
                    else if (np < ws->cap)
                        poly_copy(&pieces[np++], &outside);
                    else
                        return -1;
                    kept = 1;
                }
                poly_copy(&rest, &in);
            }
            if (kept) {
                i++;
                continue;
            }
            /* covered: the last piece not yet examined takes its place, the
               last appended one that piece's */
            poly_copy(&pieces[i], &pieces[--end]);
            --np;
            if (end != np)
                poly_copy(&pieces[end], &pieces[np]);
        }
    }
    return np;
}

/* F_vis(x, b) from the pieces (fanned into triangles when a piece has more
 * corners than the closed form takes). */
static double pieces_ff(rad_vec3 x, rad_vec3 nx, const plane_frame *f, const poly2 *pieces, int np,
                        long *evals)
{
    double sum = 0.0;
    for (int i = 0; i < np; i++) {
        const poly2 *q = &pieces[i];
        rad_vec3 pts[POLY_MAX];
        for (int v = 0; v < q->n; v++)
            pts[v] = to3(f, q->p[v]);
        if (q->n <= 8) {
            sum += rad_ff_point_polygon(x, nx, pts, q->n);
            (*evals)++;
        } else {
            for (int v = 1; v + 1 < q->n; v++) {
                rad_vec3 t[3] = {pts[0], pts[v], pts[v + 1]};
                sum += rad_ff_point_polygon(x, nx, t, 3);
                (*evals)++;
            }
        }
    }
    return sum;
}

static int point_visible_ws(const rad_vis *vis, rad_vec3 x, rad_vec3 nx, const rad_vec3 b[3],
                            const int *blockers, int nb, long max_work, pieces_ws *ws, double *F,
                            double *F_open, long *evals)
{
    plane_frame f;
    long ev = 0;
    *F = 0.0;
    if (F_open)
        *F_open = 0.0;
    if (!make_frame(b, &f))
        return 1;
    if (F_open) {
        *F_open = rad_ff_point_polygon(x, nx, b, 3);
        ev++;
    }
    if (nb == 0 && F_open) {
        *F = *F_open;
    } else {
        const poly2 *pieces;
        int cut;
        int np = visible_pieces(vis, x, nx, b, &f, blockers, nb, max_work, ws, &pieces, &cut);
        if (np == -1 && ws_grow(ws))
            np = visible_pieces(vis, x, nx, b, &f, blockers, nb, max_work, ws, &pieces, &cut);
        if (np < 0) {
            if (evals)
                *evals += ev;
            return 0;
        }
        if (!cut && np == 1 && F_open)
            *F = *F_open; /* no shadow reached b: the open value, not the same sum again */
        else /* rounding in slivers can leave a sum a hair below 0 */
            *F = rad_dmax(0.0, pieces_ff(x, nx, &f, pieces, np, &ev));
    }
    if (evals)
        *evals += ev;
    return 1;
}

int rad_vis_point_visible_limited(const rad_vis *vis, rad_vec3 x, rad_vec3 nx,
                                  const rad_vec3 b[3], const int *blockers, int nb, long max_work,
                                  double *F, double *F_open, long *evals)
{
    pieces_ws ws;
    ws_init(&ws);
    int ok = point_visible_ws(vis, x, nx, b, blockers, nb, max_work, &ws, F, F_open, evals);
    ws_free(&ws);
    return ok;
}

int rad_vis_point_visible(const rad_vis *vis, rad_vec3 x, rad_vec3 nx, const rad_vec3 b[3],
                          const int *blockers, int nb, double *F, double *F_open, long *evals)
{
    return rad_vis_point_visible_limited(vis, x, nx, b, blockers, nb, 0, F, F_open, evals);
}

/* Cut convex q to the counter-clockwise triangle t (2D): out->n < 3 when
 * they do not overlap; 0 when a part would have too many corners. */
static int cut_to_triangle(const poly2 *q, const v2 t[3], poly2 *out)
{
    poly2 outside;
    poly_copy(out, q);
    for (int e = 0; e < 3 && out->n >= 3; e++) {
        poly2 in;
        if (!split_line(out, t[e], t[(e + 1) % 3], &in, &outside))
            return 0;
        out->n = in.n;
        memcpy(out->p, in.p, (size_t)in.n * sizeof in.p[0]);
    }
    return 1;
}

int rad_vis_point_visible_parts(const rad_vis *vis, rad_vec3 x, rad_vec3 nx, const rad_vec3 b[3],
                                const rad_vec3 *parts, int nparts, const int *blockers, int nb,
                                long max_work, double *F, double *F_open, long *evals)
{
    plane_frame f;
    long ev = 0;
    int ok = 1, flat = !make_frame(b, &f);
    for (int i = 0; i < nparts; i++) {
        F[i] = 0.0;
        F_open[i] = flat ? 0.0 : rad_ff_point_polygon(x, nx, parts + 3 * i, 3);
        ev += !flat;
    }
    if (!flat) {
        pieces_ws ws;
        ws_init(&ws);
        const poly2 *pieces;
        int cut;
        int np = visible_pieces(vis, x, nx, b, &f, blockers, nb, max_work, &ws, &pieces, &cut);
        if (np == -1 && ws_grow(&ws))
            np = visible_pieces(vis, x, nx, b, &f, blockers, nb, max_work, &ws, &pieces, &cut);
        ok = np >= 0;
        for (int i = 0; ok && i < nparts; i++) {
            if (!cut && np == 1) { /* no shadow reached b */
                F[i] = F_open[i];
                continue;
            }
            v2 t[3];
            for (int v = 0; v < 3; v++)
                t[v] = to2(&f, parts[3 * i + v]);
            poly2 tri = {.n = 3, .p = {t[0], t[1], t[2]}};
            bbox2(&tri);
            double whole = area2(&tri);
            if (whole < 0.0) {
                v2 s = t[1];
                t[1] = t[2];
                t[2] = s;
                whole = -whole;
            }
            double sum = 0.0, seen = 0.0;
            for (int k = 0; k < np && ok; k++) {
                poly2 piece;
                if (boxes_apart(&pieces[k], &tri))
                    continue; /* they can share an edge at most */
                if (!cut_to_triangle(&pieces[k], t, &piece)) {
                    ok = 0;
                    break;
                }
                double a = piece.n >= 3 ? area2(&piece) : 0.0;
                if (!(a > 1e-13 * f.area))
                    continue;
                seen += a;
                sum += pieces_ff(x, nx, &f, &piece, 1, &ev);
            }
            /* rounding in slivers can leave a sum a hair below 0 */
            F[i] = seen >= (1.0 - 1e-12) * whole ? F_open[i] : rad_dmax(0.0, sum);
        }
        ws_free(&ws);
    }
    if (evals)
        *evals += ev;
    return ok;
}

int rad_vis_split_values(const rad_vis *vis, const rad_vec3 o[3], int face_o, const rad_vec3 *y,
                         int n, rad_vec3 no, const rad_vec3 b[3], int face_b,
                         const rad_vec3 *parts, int *blk, int max, int *nb, long max_work,
                         double *F, double *F_open, int stride, long *evals)
{
    *nb = rad_vis_blockers(vis, o, face_o, b, face_b, blk, max);
    if (*nb > max)
        *nb = -1;
    if (*nb <= 0)
        return 0;
    for (int k = 0; k < n; k++) {
        double f4[4], fo4[4];
        if (!rad_vis_point_visible_parts(vis, y[k], no, b, parts, 4, blk, *nb, max_work, f4, fo4,
                                         evals))
            return 0;
        for (int i = 0; i < 4; i++) {
            F[i * stride + k] = f4[i];
            F_open[i * stride + k] = fo4[i];
        }
    }
    return 1;
}

uint64_t rad_vis_pair_key(const rad_vec3 a[3], const rad_vec3 b[3])
{
    uint64_t key = 0;
    for (int v = 0; v < 3; v++) {
        double c[6] = {a[v].x, a[v].y, a[v].z, b[v].x, b[v].y, b[v].z};
        for (int q = 0; q < 6; q++) {
            uint64_t bits;
            memcpy(&bits, &c[q], sizeof bits);
            key = key * 0x100000001b3ull ^ bits;
        }
    }
    return key;
}

/* ---- the outer integral ------------------------------------------------- */

typedef struct outer_ctx {
    const rad_vis *vis;
    const rad_vec3 *b;
    rad_vec3 na;
    const int *blockers;
    int nb;
    double s[RAD_QUAD_TRI_MAX_POINTS], t[RAD_QUAD_TRI_MAX_POINTS], w[RAD_QUAD_TRI_MAX_POINTS];
    int npts;
    int max_depth;
    long evals;
    pieces_ws ws;
    /* per refinement level, room for the four children's blocker lists */
    int *scratch;
    int scratch_per_level;
    int failed; /* too many pieces somewhere */
} outer_ctx;

/* The rule on cell c: the visible and the open integral. */
static void cell_rule(outer_ctx *o, const rad_vec3 c[3], double *vis_sum, double *open_sum)
{
    double area = rad_geom_triangle_area(c[0], c[1], c[2]), sv = 0.0, so = 0.0;
    for (int k = 0; k < o->npts && !o->failed; k++) { /* failed: the pair goes to rays */
        rad_vec3 x = rad_geom_triangle_point(c[0], c[1], c[2], o->s[k], o->t[k]);
        double F = 0.0, Fo = 0.0;
        if (!point_visible_ws(o->vis, x, o->na, o->b, o->blockers, o->nb, 0, &o->ws, &F, &Fo,
                              &o->evals))
            o->failed = 1;
        sv += o->w[k] * F;
        so += o->w[k] * Fo;
    }
    *vis_sum = area * sv;
    *open_sum = area * so;
}

static void children_of(const rad_vec3 c[3], rad_vec3 ch[4][3])
{
    rad_vec3 ab = rad_vec3_scale(rad_vec3_add(c[0], c[1]), 0.5);
    rad_vec3 bc = rad_vec3_scale(rad_vec3_add(c[1], c[2]), 0.5);
    rad_vec3 ca = rad_vec3_scale(rad_vec3_add(c[2], c[0]), 0.5);
    rad_vec3 k[4][3] = {{c[0], ab, ca}, {ab, c[1], bc}, {ca, bc, c[2]}, {ab, bc, ca}};
    memcpy(ch, k, sizeof k);
}

/* 1 when the cell c has corners on both sides of b's plane (part of it may
 * see b although every node of its rule lies behind the plane). */
static int straddles(const rad_vec3 c[3], const rad_vec3 b[3])
{
    rad_vec3 n = rad_vec3_cross(rad_vec3_sub(b[1], b[0]), rad_vec3_sub(b[2], b[0]));
    int front = 0, back = 0;
    for (int k = 0; k < 3; k++) {
        double h = rad_vec3_dot(n, rad_vec3_sub(c[k], b[0]));
        front += h > 0.0;
        back += h < 0.0;
    }
    return front && back;
}

/* Adaptive refinement of one cell whose rule gave (coarse, coarse_open): the
 * cell is accepted when its four children change neither value by more than
 * tol (and a cell across b's plane whose nodes all see nothing is split
 * anyway); returns the accepted value, adds the accepted differences to *err
 * and the open integral to *open. */
static double refine(outer_ctx *o, const rad_vec3 c[3], double coarse, double coarse_open,
                     double tol, int depth, double *err, double *open)
{
    rad_vec3 ch[4][3];
    children_of(c, ch);
    /* each child's own blockers: its shaft lies inside the cell's */
    const int *parent_blk = o->blockers;
    int parent_nb = o->nb, *mine = o->scratch + (size_t)depth * (size_t)o->scratch_per_level;
    int child_nb[4];
    double v[4], vo[4], fine = 0.0, fine_open = 0.0;
    for (int k = 0; k < 4; k++) {
        int *list = mine + (size_t)k * (size_t)parent_nb;
        child_nb[k] = parent_nb ? vis_shaft_filter(o->vis, ch[k], o->b, parent_blk, parent_nb, list) : 0;
        o->blockers = list;
        o->nb = child_nb[k];
        cell_rule(o, ch[k], &v[k], &vo[k]);
        fine += v[k];
        fine_open += vo[k];
    }
    double diff = rad_dmax(fabs(fine - coarse), fabs(fine_open - coarse_open));
    int blind = fine_open == 0.0 && straddles(c, o->b);
    double sum = fine;
    if ((diff <= tol && !blind) || depth >= o->max_depth) {
        *err += diff;
        *open += fine_open;
    } else {
        sum = 0.0;
        for (int k = 0; k < 4; k++) {
            o->blockers = mine + (size_t)k * (size_t)parent_nb;
            o->nb = child_nb[k];
            sum += refine(o, ch[k], v[k], vo[k], tol / 2.0, depth + 1, err, open);
        }
    }
    o->blockers = parent_blk;
    o->nb = parent_nb;
    return sum;
}

/* 1 when every corner of c lies on or in front of b's plane. */
static int in_front(const rad_vec3 c[3], const rad_vec3 b[3])
{
    rad_vec3 n = rad_vec3_cross(rad_vec3_sub(b[1], b[0]), rad_vec3_sub(b[2], b[0]));
    for (int k = 0; k < 3; k++)
        if (rad_vec3_dot(n, rad_vec3_sub(c[k], b[0])) < 0.0)
            return 0;
    return 1;
}

/* The fallback where the clipping would need too many blockers or pieces:
 * G = G_open x (sum K v / sum K) over the segments joining jittered
 * stratified points of a and b (k^2 each, k = sample_strata), the
 * kernel-weighted visible fraction; its error is taken as the binomial
 * standard error of that fraction times G_open. */
static rad_status sampled(const rad_vis *vis, const rad_vec3 a[3], int face_a, const rad_vec3 b[3],
                          int face_b, double G_open, const rad_vis_visible_params *p,
                          rad_vis_visible_result *out)
{
    int k = p->sample_strata, m = k * k;
    rad_vec3 na = rad_geom_triangle_normal(a[0], a[1], a[2]);
    rad_vec3 nb = rad_geom_triangle_normal(b[0], b[1], b[2]);
    enum { BATCH = 256 };
    double from[3 * BATCH], to[3 * BATCH], w[BATCH];
    unsigned char blocked[BATCH];
    double wsum = 0.0, wopen = 0.0;
    long evals = 0;
    int filled = 0;
    rad_status st = rad_vis_prepare_rays(vis);
    if (st != RAD_OK)
        return st;
    vis_context vc;
    vis_context_init(&vc, face_a < 0 ? RTC_INVALID_GEOMETRY_ID : (unsigned)face_a,
                     face_b < 0 ? RTC_INVALID_GEOMETRY_ID : (unsigned)face_b);
    unsigned long long rays = 0;
    uint64_t key = rad_vis_pair_key(a, b);
    for (int i = 0; i < m; i++) {
        double s, t;
        rad_geom_triangle_stratum(k, i, rad_sys_hash_unit(key + 4 * (uint64_t)i),
                                  rad_sys_hash_unit(key + 4 * (uint64_t)i + 1), &s, &t);
        rad_vec3 x = rad_geom_triangle_point(a[0], a[1], a[2], s, t);
        for (int j = 0; j < m; j++) {
            rad_geom_triangle_stratum(k, j, rad_sys_hash_unit(~key + 4 * (uint64_t)j),
                                      rad_sys_hash_unit(~key + 4 * (uint64_t)j + 1), &s, &t);
            rad_vec3 y = rad_geom_triangle_point(b[0], b[1], b[2], s, t);
            w[filled] = rad_ff_kernel(x, na, y, nb, NULL);
            evals++;
            from[3 * filled] = x.x; from[3 * filled + 1] = x.y; from[3 * filled + 2] = x.z;
            to[3 * filled] = y.x; to[3 * filled + 1] = y.y; to[3 * filled + 2] = y.z;
            if (++filled == BATCH || (i == m - 1 && j == m - 1)) {
                vis_occluded_ctx(vis, &vc, (size_t)filled, from, to, blocked, &rays); /* prepared */
                for (int q = 0; q < filled; q++) {
                    wsum += w[q];
                    wopen += blocked[q] ? 0.0 : w[q];
                }
                filled = 0;
            }
        }
    }
    double V = wsum > 0.0 ? rad_dmin(1.0, wopen / wsum) : 1.0;
    out->G = G_open * V;
    out->G_open = G_open;
    out->error = G_open * sqrt(rad_dmax(V * (1.0 - V), 1.0 / m) / (double)(m * m));
    out->evals = evals;
    out->rays = (long)rays;
    out->status = RAD_VIS_VISIBLE_SAMPLED;
    return RAD_OK;
}

rad_status rad_vis_pair_visible(const rad_vis *vis, const rad_vec3 a[3], int face_a,
                                const rad_vec3 b[3], int face_b, double G_open,
                                const rad_vis_visible_params *params,
                                rad_vis_visible_result *out)
{
    if (!vis || !a || !b || !out)
        return RAD_ERROR(RAD_EINVAL, "visibility: NULL argument to the visible integral");
    rad_vis_visible_params p;
    if (params)
        p = *params;
    else
        rad_vis_visible_params_default(&p);
    if (p.max_depth == 0) /* about log4(1 / tol) levels: a kink's cells shrink as tol does */
        p.max_depth = (int)rad_dmin(8.0, rad_dmax(3.0, ceil(log(1.0 / p.tol) / log(4.0)) + 1.0));
    if (p.max_blockers < 0 || p.max_blockers > 65536 || p.max_depth < 0 || p.max_depth > 12 ||
        !(p.tol > 0.0) || p.sample_strata < 1 || p.sample_strata > 64)
        return RAD_ERROR(RAD_EINVAL, "visibility: bad parameters of the visible integral");
    memset(out, 0, sizeof *out);
    if (!(G_open > 0.0))
        return RAD_OK; /* the pair does not interact */
    /* The outer integral runs over a triangle that lies wholly in front of the
     * other's plane when one does: its integrand is then smooth across it,
     * and the other's straddling part is clipped exactly by the closed form. */
    if (!in_front(a, b) && in_front(b, a)) {
        const rad_vec3 *tmp = a;
        a = b;
        b = tmp;
        int f = face_a;
        face_a = face_b;
        face_b = f;
    }
    int stack_blockers[256];
    int *blk = stack_blockers, cap = p.max_blockers;
    if (cap > 256 && !(blk = malloc((size_t)cap * sizeof *blk)))
        return RAD_ERROR(RAD_ENOMEM, "visibility: no memory for %d blockers", cap);
    int nb = rad_vis_blockers(vis, a, face_a, b, face_b, blk, cap);
    out->blockers = nb;
    if (nb > cap) {
        if (blk != stack_blockers)
            free(blk);
        return sampled(vis, a, face_a, b, face_b, G_open, &p, out);
    }
    outer_ctx o;
    memset(&o, 0, sizeof o);
    o.vis = vis;
    o.b = b;
    o.na = rad_geom_triangle_normal(a[0], a[1], a[2]);
    o.blockers = blk;
    o.nb = nb;
    o.max_depth = p.max_depth;
    rad_status st = rad_quad_tri_symmetric(p.degree, o.s, o.t, o.w, &o.npts);
    o.scratch_per_level = 4 * nb;
    if (st == RAD_OK && nb > 0 &&
        !(o.scratch = malloc((size_t)(p.max_depth + 1) * (size_t)o.scratch_per_level * sizeof *o.scratch)))
        st = RAD_ERROR(RAD_ENOMEM, "visibility: no memory for the cells' blockers");
    ws_init(&o.ws);
    if (st != RAD_OK) {
        free(o.scratch);
        if (blk != stack_blockers)
            free(blk);
        return st;
    }
    double wsum = 0.0;
    for (int k = 0; k < o.npts; k++)
        wsum += o.w[k];
    for (int k = 0; k < o.npts; k++)
        o.w[k] /= wsum;
    double coarse, coarse_open, err = 0.0, open = 0.0;
    cell_rule(&o, a, &coarse, &coarse_open);
    out->G = refine(&o, a, coarse, coarse_open, p.tol * G_open, 1, &err, &open);
    ws_free(&o.ws);
    free(o.scratch);
    if (blk != stack_blockers)
        free(blk);
    if (o.failed) /* too many visible pieces somewhere */
        return sampled(vis, a, face_a, b, face_b, G_open, &p, out);
    out->G_open = open;
    out->error = err;
    out->evals = o.evals;
    out->status = RAD_VIS_VISIBLE_EXACT;
    return RAD_OK;
}
