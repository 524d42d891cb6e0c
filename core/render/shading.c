/* The shading mesh: which vertices the display may smooth across.
 * Vertex colours are area averages of the faces around a vertex.  Across a
 * crease (a wall meeting the floor) or a material boundary (the lamp in the
 * ceiling) that average mixes surfaces that do not share light, so for
 * display every vertex is split by the plane and material of the faces using
 * it: faces share a shading vertex only when they share the vertex, the unit
 * normal (to 1e-6) and the material. */
#include "rad_render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rad_geom.h"

typedef struct corner_key {
    int vertex, material;
    long long nq[3];
    int slot; /* element * 3 + corner */
} corner_key;

/* Order by surface (vertex, material, normal), then by slot. */
static int compare_surface(const corner_key *a, const corner_key *b)
{
    if (a->vertex != b->vertex)
        return a->vertex < b->vertex ? -1 : 1;
    if (a->material != b->material)
        return a->material < b->material ? -1 : 1;
    for (int k = 0; k < 3; k++)
        if (a->nq[k] != b->nq[k])
            return a->nq[k] < b->nq[k] ? -1 : 1;
    return 0;
}

static int compare_corners(const void *pa, const void *pb)
{
    const corner_key *a = pa, *b = pb;
    int c = compare_surface(a, b);
    return c ? c : (a->slot > b->slot) - (a->slot < b->slot);
}

rad_status rad_render_shading_mesh(const double *xyz, const int *tri, size_t ntris,
                                   const int *material, double **xyz_out, size_t *nv_out,
                                   int **tri_out)
{
    size_t n = ntris;
    corner_key *keys = malloc(3 * (size_t)n * sizeof *keys);
    int *tri2 = malloc(3 * (size_t)n * sizeof *tri2);
    double *xyz2 = malloc(9 * (size_t)n * sizeof *xyz2);
    if (!keys || !tri2 || !xyz2) {
        free(keys);
        free(tri2);
        free(xyz2);
        return RAD_ERROR(RAD_ENOMEM, "render: no memory for the shading mesh of %zu triangles", n);
    }
    for (size_t i = 0; i < n; i++) {
        const int *t = tri + 3 * (size_t)i;
        rad_vec3 v[3];
        for (int c = 0; c < 3; c++)
            v[c] = rad_vec3_make(xyz[3 * t[c]], xyz[3 * t[c] + 1], xyz[3 * t[c] + 2]);
        rad_vec3 nrm = rad_geom_triangle_normal(v[0], v[1], v[2]);
        for (int c = 0; c < 3; c++) {
            corner_key *k = &keys[3 * i + (size_t)c];
            k->vertex = t[c];
            k->material = material ? material[i] : 0;
            k->nq[0] = llround(nrm.x * 1e6);
            k->nq[1] = llround(nrm.y * 1e6);
            k->nq[2] = llround(nrm.z * 1e6);
            k->slot = (int)(3 * i) + c;
        }
    }
    qsort(keys, 3 * (size_t)n, sizeof *keys, compare_corners);
    size_t nv = 0;
    for (size_t k = 0; k < 3 * (size_t)n; k++) {
        int fresh = k == 0 || compare_surface(&keys[k - 1], &keys[k]) != 0;
        if (fresh) {
            memcpy(xyz2 + 3 * nv, xyz + 3 * (size_t)keys[k].vertex, 3 * sizeof *xyz2);
            nv++;
        }
        tri2[keys[k].slot] = (int)nv - 1;
    }
    free(keys);
    *xyz_out = xyz2;
    *nv_out = nv;
    *tri_out = tri2;
    return RAD_OK;
}

