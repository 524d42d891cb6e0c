/* A small cluster emits through rows of cemit (core/hier/cluster.c): its
 * triangles' own, or, where some of them share a unit normal, one row per
 * group of equal normals holding the sum of area x B over the group.  Here
 * three boxes (a box's cluster turns its twelve triangles into six rows,
 * one a face) and a tilted one: for every small cluster and many
 * directions u, sum over its rows of max(n . u, 0) x the row's sum must be
 * the intensity sum_j A_j B_j max(n_j . u, 0) summed triangle by
 * triangle. */
#include <math.h>
#include <stdio.h>

#include "harness.h"
#include "hier_internal.h"
#include "rad_hier.h"
#include "rad_vis.h"
#include "squares.h"

enum { BOXES = 4 };

/* Box b's corners (8) and its twelve triangles wound outwards: the first
 * three axis-aligned along x, the last turned about z and y. */
static void box(int b, double *xyz, int *tri)
{
    static const int quad[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                   {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    double c = 0.3, s = 0.95393920141694566; /* cos and sin of the tilt */
    for (int v = 0; v < 8; v++) {
        double p[3] = {(v & 1) * 0.8, ((v >> 1) & 1) * 0.6, ((v >> 2) & 1) * 0.5};
        if (b == BOXES - 1) { /* turned about z, then about y */
            double x = c * p[0] - s * p[1], y = s * p[0] + c * p[1];
            p[0] = c * x + s * p[2];
            p[1] = y;
            p[2] = -s * x + c * p[2];
        }
        xyz[3 * (8 * b + v)] = p[0] + 2.0 * b;
        xyz[3 * (8 * b + v) + 1] = p[1];
        xyz[3 * (8 * b + v) + 2] = p[2] + 1.0;
    }
    double centre[3] = {0, 0, 0};
    for (int v = 0; v < 8; v++)
        for (int a = 0; a < 3; a++)
            centre[a] += xyz[3 * (8 * b + v) + a] / 8.0;
    for (int f = 0; f < 6; f++) {
        const int *q = quad[f];
        int t[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
        for (int k = 0; k < 2; k++) {
            const double *p0 = xyz + 3 * (8 * b + t[k][0]), *p1 = xyz + 3 * (8 * b + t[k][1]),
                         *p2 = xyz + 3 * (8 * b + t[k][2]);
            rad_vec3 n = rad_vec3_cross(rad_vec3_make(p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]),
                                        rad_vec3_make(p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]));
            double in = n.x * (centre[0] - p0[0]) + n.y * (centre[1] - p0[1]) +
                        n.z * (centre[2] - p0[2]);
            int *out = tri + 3 * (12 * b + 2 * f + k);
            out[0] = 8 * b + t[k][0];
            out[1] = 8 * b + (in > 0.0 ? t[k][2] : t[k][1]);
            out[2] = 8 * b + (in > 0.0 ? t[k][1] : t[k][2]);
        }
    }
}

TEST(cluster_small_clusters_emit_by_groups_of_equal_normals)
{
    enum { NT = 12 * BOXES };
    double xyz[3 * 8 * BOXES], rho[3 * NT], E[3 * NT];
    int tri[3 * NT];
    for (int b = 0; b < BOXES; b++)
        box(b, xyz, tri);
    for (int k = 0; k < 3 * NT; k++) {
        rho[k] = 0.5;
        E[k] = k % NT == 0 ? 1.0 : 0.0;
    }
    rad_hier_params p;
    rad_hier_params_default(&p);
    p.cluster = 1;
    rad_vis *vis = NULL;
    rad_hier *h = test_hier_of(xyz, 8 * BOXES, tri, NT, rho, E, &p, &vis);
    if (!h) {
        rad_vis_destroy(vis);
        return;
    }
    /* what each triangle carries: a B of its own in each channel */
    for (size_t t = 0; t < h->nroots; t++)
        for (int c = 0; c < 3; c++)
            h->el[t].B[c] = 0.1 + 0.37 * (double)((t * 7 + (size_t)c * 5) % 11);
    CHECK(hier_fill_sources(h, CLUSTER_B) == RAD_OK);
    int boxes_grouped = 0, checked = 0;
    double worst = 0.0;
    for (size_t i = 0; i < h->ncl; i++) {
        const hier_clus *x = &h->cl[i];
        if (x->root >= 0 || x->count > 16)
            continue;
        CHECK(x->ngrp >= 1 && x->ngrp <= x->count);
        boxes_grouped += x->count == 12 && x->ngrp == 6;
        for (int d = 0; d < 64; d++) {
            /* directions spread over the sphere */
            double z = 1.0 - (2.0 * d + 1.0) / 64.0, r = sqrt(1.0 - z * z), a = 2.399963 * d;
            rad_vec3 u = rad_vec3_make(r * cos(a), r * sin(a), z);
            for (int c = 0; c < 3; c++) {
                double rows = 0.0, direct = 0.0, scale = 0.0;
                for (int g = 0; g < x->ngrp; g++) {
                    const double *m = h->cemit + 6 * ((size_t)x->grp + (size_t)g);
                    rows += fmax(0.0, m[0] * u.x + m[1] * u.y + m[2] * u.z) * m[3 + c];
                }
                for (int k = x->first; k < x->first + x->count; k++) {
                    const hier_elem *e = &h->el[h->corder[k]];
                    double a_j = e->area * e->B[c];
                    direct += a_j * fmax(0.0, rad_vec3_dot(h->normal[e->face], u));
                    scale += a_j;
                }
                worst = fmax(worst, fabs(rows - direct) / scale);
                checked++;
            }
        }
    }
    printf("# %d small clusters x directions x channels checked, %d boxes read as six rows, "
           "largest difference %.2e of the cluster's A B\n",
           checked, boxes_grouped, worst);
    /* the three axis-aligned boxes at least; the tilted one's two triangles
       of a face may differ in their normals' last bits, and then stay apart */
    CHECK_MSG(boxes_grouped >= BOXES - 1, "%d boxes grouped into their six faces", boxes_grouped);
    CHECK(checked > 0);
    CHECK_MSG(worst < 1e-14, "grouped rows differ from the triangles by %.3e", worst);
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
}
