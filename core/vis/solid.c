/* rad_vis: the small closed convex solids of the scene (a box, a prism, a
 * coarse sphere).
 *
 * A segment that enters a closed convex solid leaves it through its surface,
 * so it meets two of its faces, and a shaft that holds the segment cannot
 * dismiss either of them: the solid's faces that a pair's shaft keeps cast,
 * together, the shadow of the whole solid, which from a point is one convex
 * polygon (the hull of its corners' projections, visible.c).  The exact
 * clipping subtracts that polygon once instead of the shadows of every face
 * it lists, which overlap and cut the visible pieces into slivers along each
 * other's edges.
 *
 * Solids are found from the triangles alone: corners are the same point when
 * their coordinates are equal (files often repeat a box's corners per face),
 * triangles sharing an edge belong together, a group is closed when each of
 * its edges is used exactly twice, and convex when every corner lies on one
 * side of every face's plane (within 1e-9 of the group's size).  Groups of
 * more than VIS_SOLID_MAX_TRIS triangles, and flat ones, are left as
 * triangles.  Each solid keeps its triangles, its distinct corners and its
 * face planes, oriented so that the solid lies on their negative side. */
#include "vis_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct corner {
    double x, y, z;
    int v;
} corner;

typedef struct edge {
    int u, w, t;
} edge;

static int corner_cmp(const void *pa, const void *pb)
{
    const corner *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    if (a->z != b->z)
        return a->z < b->z ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

static int edge_cmp(const void *pa, const void *pb)
{
    const edge *a = pa, *b = pb;
    if (a->u != b->u)
        return a->u < b->u ? -1 : 1;
    if (a->w != b->w)
        return a->w < b->w ? -1 : 1;
    return (a->t > b->t) - (a->t < b->t);
}

static int find(int *up, int t)
{
    while (up[t] != t) {
        up[t] = up[up[t]];
        t = up[t];
    }
    return t;
}

/* Whether group g (its triangles tris[0..n), its corners' point ids) is
 * convex and not flat; its outward planes into m, c. */
static int convex_group(const rad_vis *vis, const int *tris, int n, const int *pts, int np,
                        rad_vec3 *m, double *c)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < np; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], vis->xyz[3 * (size_t)pts[i] + (size_t)k]);
            hi[k] = fmax(hi[k], vis->xyz[3 * (size_t)pts[i] + (size_t)k]);
        }
    double size = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double tol = 1e-9 * size;
    int solid = 0;
    for (int i = 0; i < n; i++) {
        rad_vec3 p0 = vis_vertex(vis, (size_t)tris[i], 0);
        rad_vec3 nn = rad_vec3_cross(rad_vec3_sub(vis_vertex(vis, (size_t)tris[i], 1), p0),
                                     rad_vec3_sub(vis_vertex(vis, (size_t)tris[i], 2), p0));
        double len = rad_vec3_norm(nn);
        if (!(len > 0.0))
            return 0;
        nn = rad_vec3_scale(nn, 1.0 / len);
        int above = 0, below = 0;
        for (int j = 0; j < np; j++) {
            const double *q = vis->xyz + 3 * (size_t)pts[j];
            double s = rad_vec3_dot(nn, rad_vec3_sub(rad_vec3_make(q[0], q[1], q[2]), p0));
            above += s > tol;
            below += s < -tol;
        }
        if (above && below)
            return 0;
        if (above)
            nn = rad_vec3_scale(nn, -1.0);
        solid |= above || below;
        m[i] = nn;
        c[i] = rad_vec3_dot(nn, p0);
    }
    return solid;
}

int vis_solids_build(rad_vis *vis)
{
    size_t nv = vis->nverts, nt = vis->ntris;
    vis->solid = NULL;
    if (nt == 0)
        return 1;
    corner *cs = malloc((nv + 1) * sizeof *cs);
    int *point = malloc((nv + 1) * sizeof *point);
    edge *es = malloc((3 * nt + 1) * sizeof *es);
    int *up = malloc(nt * sizeof *up), *closed = malloc(nt * sizeof *closed);
    int *count = calloc(nt + 1, sizeof *count), *members = malloc(nt * sizeof *members);
    int ok = cs && point && es && up && closed && count && members;
    if (!ok)
        goto done;
    /* corners that are the same point */
    for (size_t v = 0; v < nv; v++)
        cs[v] = (corner){vis->xyz[3 * v], vis->xyz[3 * v + 1], vis->xyz[3 * v + 2], (int)v};
    qsort(cs, nv, sizeof *cs, corner_cmp);
    for (size_t i = 0; i < nv; i++)
        point[cs[i].v] = i > 0 && cs[i].x == cs[i - 1].x && cs[i].y == cs[i - 1].y &&
                                 cs[i].z == cs[i - 1].z
                             ? point[cs[i - 1].v]
                             : cs[i].v;
    /* triangles joined through shared edges; a group is closed when every
       edge it uses is used exactly twice */
    for (size_t t = 0; t < nt; t++) {
        up[t] = (int)t;
        closed[t] = 1;
        for (int k = 0; k < 3; k++) {
            int a = point[vis->tri[3 * t + (size_t)k]], b = point[vis->tri[3 * t + (size_t)(k + 1) % 3]];
            es[3 * t + (size_t)k] = (edge){a < b ? a : b, a < b ? b : a, (int)t};
        }
    }
    qsort(es, 3 * nt, sizeof *es, edge_cmp);
    for (size_t i = 0; i < 3 * nt;) {
        size_t j = i + 1;
        while (j < 3 * nt && es[j].u == es[i].u && es[j].w == es[i].w)
            j++;
        for (size_t k = i + 1; k < j; k++) {
            int ra = find(up, es[i].t), rb = find(up, es[k].t);
            if (ra != rb)
                up[ra] = rb;
        }
        if (j - i != 2 || es[i].u == es[i].w)
            for (size_t k = i; k < j; k++)
                closed[es[k].t] = 0;
        i = j;
    }
    for (size_t t = 0; t < nt; t++) {
        int r = find(up, (int)t);
        closed[r] &= closed[t];
        count[r]++;
    }
    /* members grouped by root: start[r] from the counts */
    int *start = count; /* reused: count[r] becomes the group's first slot */
    {
        int sum = 0;
        for (size_t t = 0; t <= nt; t++) {
            int c = count[t];
            count[t] = sum;
            sum += c;
        }
    }
    for (size_t t = 0; t < nt; t++)
        members[start[find(up, (int)t)]++] = (int)t;
    for (size_t t = nt; t > 0; t--)
        start[t] = start[t - 1];
    start[0] = 0;
    if (!(vis->solid = malloc(nt * sizeof *vis->solid))) {
        ok = 0;
        goto done;
    }
    for (size_t t = 0; t < nt; t++)
        vis->solid[t] = -1;
    /* the solids: closed, small, convex, not flat (room for every triangle) */
    vis->solids = malloc((nt / 4 + 1) * sizeof *vis->solids);
    vis->solid_tri = malloc(nt * sizeof *vis->solid_tri);
    vis->solid_pt = malloc(3 * nt * sizeof *vis->solid_pt);
    vis->solid_plane = malloc(4 * nt * sizeof *vis->solid_plane);
    if (!vis->solids || !vis->solid_tri || !vis->solid_pt || !vis->solid_plane) {
        ok = 0;
        goto done;
    }
    size_t used_tri = 0, used_pt = 0;
    int nsol = 0;
    for (size_t r = 0; r < nt; r++) {
        int n = start[r + 1] - start[r];
        if (n < 4 || n > VIS_SOLID_MAX_TRIS || find(up, (int)r) != (int)r || !closed[r])
            continue;
        const int *tris = members + start[r];
        int pts[3 * VIS_SOLID_MAX_TRIS], np = 0;
        for (int i = 0; i < n; i++)
            for (int k = 0; k < 3; k++) {
                int p = point[vis->tri[3 * (size_t)tris[i] + (size_t)k]], seen = 0;
                for (int j = 0; j < np && !seen; j++)
                    seen = pts[j] == p;
                if (!seen)
                    pts[np++] = p;
            }
        rad_vec3 m[VIS_SOLID_MAX_TRIS];
        double c[VIS_SOLID_MAX_TRIS];
        if (!convex_group(vis, tris, n, pts, np, m, c))
            continue;
        vis_solid *so = &vis->solids[nsol];
        *so = (vis_solid){(int)used_tri, n, (int)used_pt, np, {0.0, 0.0, 0.0}, 0.0};
        for (int i = 0; i < np; i++)
            for (int k = 0; k < 3; k++)
                so->centre[k] += vis->xyz[3 * (size_t)pts[i] + (size_t)k] / np;
        for (int i = 0; i < np; i++) {
            const double *q = vis->xyz + 3 * (size_t)pts[i];
            double dx = q[0] - so->centre[0], dy = q[1] - so->centre[1], dz = q[2] - so->centre[2];
            so->radius = fmax(so->radius, sqrt(dx * dx + dy * dy + dz * dz));
        }
        so->radius *= 1.0 + 1e-12;
        for (int i = 0; i < n; i++) {
            vis->solid_tri[used_tri + (size_t)i] = tris[i];
            vis->solid[tris[i]] = nsol;
            double *pl = vis->solid_plane + 4 * (used_tri + (size_t)i);
            pl[0] = m[i].x;
            pl[1] = m[i].y;
            pl[2] = m[i].z;
            pl[3] = c[i];
        }
        memcpy(vis->solid_pt + used_pt, pts, (size_t)np * sizeof *pts);
        used_tri += (size_t)n;
        used_pt += (size_t)np;
        nsol++;
    }
    if (nsol == 0) { /* none: the clipping need not look */
        free(vis->solid);
        free(vis->solids);
        free(vis->solid_tri);
        free(vis->solid_pt);
        free(vis->solid_plane);
        vis->solid = NULL;
        vis->solids = NULL;
        vis->solid_tri = vis->solid_pt = NULL;
        vis->solid_plane = NULL;
    } else { /* keep what is used (shrinking cannot fail to keep the data) */
        void *q;
        if ((q = realloc(vis->solids, (size_t)nsol * sizeof *vis->solids)))
            vis->solids = q;
        if ((q = realloc(vis->solid_tri, used_tri * sizeof *vis->solid_tri)))
            vis->solid_tri = q;
        if ((q = realloc(vis->solid_pt, used_pt * sizeof *vis->solid_pt)))
            vis->solid_pt = q;
        if ((q = realloc(vis->solid_plane, 4 * used_tri * sizeof *vis->solid_plane)))
            vis->solid_plane = q;
    }
done:
    free(cs);
    free(point);
    free(es);
    free(up);
    free(closed);
    free(count);
    free(members);
    return ok;
}
