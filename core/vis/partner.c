/* rad_vis: pairs of triangles that make one convex quadrilateral.
 *
 * Most scenes are built of quadrilaterals cut into two triangles (an OBJ
 * quad, a box's face, a wall).  The exact clipping (visible.c) subtracts
 * each blocker's shadow from the visible part of a triangle; subtracting the
 * two halves of a quad one after the other cuts the visible pieces along
 * their shared diagonal and then again along the second half's edges, where
 * the quad's one shadow needs four cuts at most.  So each triangle may have
 * a partner: another triangle that shares an edge with it (the same two
 * vertex indices), lies in its plane, faces the same way, and forms with it
 * a strictly convex quadrilateral.  Their union casts exactly the union of
 * their shadows, so the clipping subtracts the quad once.  Triangles are
 * paired greedily in index order, each at most once, which makes the
 * pairing depend on the scene only. */
#include "vis_internal.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

static rad_vec3 vertex_at(const rad_vis *vis, int v)
{
    const double *p = vis->xyz + 3 * (size_t)v;
    return rad_vec3_make(p[0], p[1], p[2]);
}

/* The quad u, q, v, p (p the corner of t opposite the shared edge u-v, q
 * that of s): 1 when it is strictly convex and planar, turning the way t's
 * normal says. */
static int convex_quad(const rad_vis *vis, const int quad[4], rad_vec3 n)
{
    rad_vec3 c[4];
    double longest = 0.0;
    for (int k = 0; k < 4; k++)
        c[k] = vertex_at(vis, quad[k]);
    for (int k = 0; k < 4; k++)
        longest = fmax(longest, rad_vec3_norm(rad_vec3_sub(c[(k + 1) % 4], c[k])));
    if (!(longest > 0.0))
        return 0;
    double nn = rad_vec3_norm(n);
    if (!(nn > 0.0))
        return 0;
    n = rad_vec3_scale(n, 1.0 / nn);
    /* the fourth corner within a hair of the first three's plane: the
       union's shadow then differs from the halves' by rounding only */
    if (fabs(rad_vec3_dot(n, rad_vec3_sub(c[1], c[0]))) > 1e-12 * longest)
        return 0;
    for (int k = 0; k < 4; k++) {
        rad_vec3 e1 = rad_vec3_sub(c[(k + 1) % 4], c[k]), e2 = rad_vec3_sub(c[(k + 2) % 4], c[(k + 1) % 4]);
        if (!(rad_vec3_dot(rad_vec3_cross(e1, e2), n) > 1e-9 * longest * longest))
            return 0;
    }
    return 1;
}

static uint64_t edge_key(int u, int v)
{
    if (u > v) {
        int t = u;
        u = v;
        v = t;
    }
    return ((uint64_t)(uint32_t)u << 32) | (uint32_t)v;
}

int vis_partners_build(rad_vis *vis)
{
    size_t n = vis->ntris;
    vis->partner = NULL;
    vis->quad = NULL;
    if (n < 2)
        return 1;
    size_t cap = 8;
    while (cap < 2 * 3 * n) /* 3 n edges at most: the table at most half full */
        cap *= 2;
    uint64_t *keys = malloc(cap * sizeof *keys);
    int *owner = malloc(cap * sizeof *owner);
    vis->partner = malloc(n * sizeof *vis->partner);
    vis->quad = malloc(n * sizeof *vis->quad);
    if (!keys || !owner || !vis->partner || !vis->quad) {
        free(keys);
        free(owner);
        return 0;
    }
    for (size_t k = 0; k < cap; k++)
        owner[k] = -1;
    for (size_t t = 0; t < n; t++)
        vis->partner[t] = -1;
    for (size_t t = 0; t < n; t++) {
        const int *v = vis->tri + 3 * t;
        rad_vec3 nt = rad_vec3_cross(rad_vec3_sub(vertex_at(vis, v[1]), vertex_at(vis, v[0])),
                                     rad_vec3_sub(vertex_at(vis, v[2]), vertex_at(vis, v[0])));
        for (int e = 0; e < 3; e++) {
            int u = v[e], w = v[(e + 1) % 3], p = v[(e + 2) % 3];
            uint64_t key = edge_key(u, w);
            size_t slot = (size_t)(rad_sys_mix64(key) & (cap - 1));
            while (owner[slot] >= 0 && keys[slot] != key)
                slot = (slot + 1) & (cap - 1);
            if (owner[slot] < 0) {
                keys[slot] = key;
                owner[slot] = (int)t;
                continue;
            }
            int s = owner[slot];
            if (vis->partner[t] >= 0 || vis->partner[s] >= 0)
                continue;
            /* s's corner opposite the edge; s runs the edge w -> u if it
               faces the same way */
            const int *sv = vis->tri + 3 * (size_t)s;
            int q = -1;
            for (int j = 0; j < 3; j++)
                if (sv[j] == w && sv[(j + 1) % 3] == u)
                    q = sv[(j + 2) % 3];
            if (q < 0 || q == p)
                continue;
            int quad[4] = {u, q, w, p};
            if (!convex_quad(vis, quad, nt))
                continue;
            vis->partner[t] = (int)s;
            vis->partner[s] = (int)t;
            for (int j = 0; j < 4; j++)
                vis->quad[t][j] = vis->quad[s][j] = quad[j];
        }
    }
    free(keys);
    free(owner);
    return 1;
}
