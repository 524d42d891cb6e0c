/* The tone map and per-vertex radiosity shared by the PLY writer and rad_render.
 * 1. Vertex value = sum over faces using the vertex of A_f B_f, divided by the
 *    sum of those A_f: the area-weighted average, which is what a P0 solution
 *    (constant per face) offers at a vertex; smooth shading then interpolates
 *    it linearly over each face (Gouraud).
 * 2. Tone map: clamp(exposure * B, 0, 1)^(1/gamma) scaled to 0..255, rounded.
 * \cite{cohen1993} (chapter 10, rendering radiosity solutions). */
#include "rad_io.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "rad_geom.h"

void rad_io_tonemap_default(rad_io_tonemap *tm)
{
    tm->exposure = 1.0;
    tm->gamma = 2.2;
}

unsigned char rad_io_tonemap_apply(const rad_io_tonemap *tm, double value)
{
    double x = tm->exposure * value;
    if (!(x > 0.0)) /* also NaN */
        return 0;
    if (x >= 1.0)
        return 255;
    double g = tm->gamma > 0.0 ? tm->gamma : 1.0;
    return (unsigned char)lround(255.0 * pow(x, 1.0 / g));
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

double rad_io_tonemap_auto_exposure(size_t n, const double *values, double percentile)
{
    double *pos = malloc((n ? n : 1) * sizeof *pos);
    if (!pos)
        return 1.0;
    size_t m = 0;
    for (size_t k = 0; k < n; k++)
        if (values[k] > 0.0 && isfinite(values[k]))
            pos[m++] = values[k];
    double exposure = 1.0;
    if (m > 0) {
        qsort(pos, m, sizeof *pos, cmp_double);
        double p = percentile < 0.0 ? 0.0 : percentile > 1.0 ? 1.0 : percentile;
        exposure = 1.0 / pos[(size_t)floor(p * (double)(m - 1))];
    }
    free(pos);
    return exposure;
}

rad_status rad_io_vertex_values(size_t nverts, const double *xyz, size_t ntris, const int *tri,
                                const double *B, double *vb)
{
    if ((nverts && (!xyz || !vb)) || (ntris && (!tri || !B)))
        return RAD_ERROR(RAD_EINVAL, "vertex values: NULL argument");
    double *wsum = calloc(nverts ? nverts : 1, sizeof *wsum);
    if (!wsum)
        return RAD_ERROR(RAD_ENOMEM, "vertex values: no memory for %zu vertices", nverts);
    memset(vb, 0, 3 * nverts * sizeof *vb);
    for (size_t t = 0; t < ntris; t++) {
        rad_vec3 p[3];
        for (int k = 0; k < 3; k++) {
            int v = tri[3 * t + k];
            if (v < 0 || (size_t)v >= nverts) {
                free(wsum);
                return RAD_ERROR(RAD_EINPUT, "vertex values: triangle %zu refers to vertex %d", t, v);
            }
            p[k] = rad_vec3_make(xyz[3 * v], xyz[3 * v + 1], xyz[3 * v + 2]);
        }
        double a = rad_geom_triangle_area(p[0], p[1], p[2]);
        for (int k = 0; k < 3; k++) {
            size_t v = (size_t)tri[3 * t + k];
            wsum[v] += a;
            for (int c = 0; c < 3; c++)
                vb[3 * v + c] += a * B[t + (size_t)c * ntris];
        }
    }
    for (size_t v = 0; v < nverts; v++)
        for (int c = 0; c < 3; c++)
            vb[3 * v + c] = wsum[v] > 0.0 ? vb[3 * v + c] / wsum[v] : 0.0;
    free(wsum);
    return RAD_OK;
}
