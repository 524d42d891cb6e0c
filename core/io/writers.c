/* The file writers: per-face TSV, PLY with vertex colours, experiment .dat.
 * Every writer writes through rad_io_output (output.c): a temporary file
 * renamed onto the target only when every write and the close succeeded, so
 * a failed write (a full disk shows up at the flush) is RAD_EIO with the path
 * and strerror, and leaves the target as it was. */
#include "rad_io.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "rad_version.h"

static void write_header(FILE *f, const rad_io_kv *header, size_t nheader)
{
    for (size_t k = 0; k < nheader; k++)
        fprintf(f, "# %s = %s\n", header[k].key ? header[k].key : "",
                header[k].value ? header[k].value : "");
}

rad_status rad_io_write_faces_tsv(const char *path, size_t n, const double *area, const double *B,
                                  const rad_io_kv *header, size_t nheader)
{
    if (n && (!area || !B))
        return RAD_ERROR(RAD_EINVAL, "faces TSV: NULL argument");
    rad_io_output o;
    rad_status status = rad_io_output_open(path, 0, &o);
    if (status != RAD_OK)
        return status;
    fprintf(o.f, "# radkit %s per-face radiosity (W/m^2)\n", RAD_VERSION);
    write_header(o.f, header, nheader);
    rad_io_print_faces(o.f, n, area, B);
    return rad_io_output_commit(&o);
}

void rad_io_print_faces(FILE *f, size_t n, const double *area, const double *B)
{
    rad_io_print_faces_se(f, n, area, B, NULL);
}

void rad_io_print_faces_se(FILE *f, size_t n, const double *area, const double *B,
                           const double *se)
{
    fprintf(f, se ? "face\tarea\tB_r\tB_g\tB_b\tse_r\tse_g\tse_b\n" : "face\tarea\tB_r\tB_g\tB_b\n");
    for (size_t i = 0; i < n; i++) {
        fprintf(f, "%zu\t%.17g\t%.17g\t%.17g\t%.17g", i, area[i], B[i], B[i + n], B[i + 2 * n]);
        if (se)
            fprintf(f, "\t%.17g\t%.17g\t%.17g", se[i], se[i + n], se[i + 2 * n]);
        fputc('\n', f);
    }
}

rad_status rad_io_face_averages(size_t nelem, const int *face_of, const double *elem_area,
                                const double *elem_B, size_t nfaces, double *face_area,
                                double *face_B)
{
    memset(face_area, 0, nfaces * sizeof *face_area);
    memset(face_B, 0, 3 * nfaces * sizeof *face_B);
    for (size_t i = 0; i < nelem; i++) {
        if (face_of[i] < 0 || (size_t)face_of[i] >= nfaces)
            return RAD_ERROR(RAD_EINPUT, "face averages: element %zu names face %d of %zu", i,
                             face_of[i], nfaces);
        size_t f = (size_t)face_of[i];
        face_area[f] += elem_area[i];
        for (size_t c = 0; c < 3; c++)
            face_B[f + c * nfaces] += elem_area[i] * elem_B[i + c * nelem];
    }
    /* sums of area x value -> averages; an empty face stays 0 */
    for (size_t f = 0; f < nfaces; f++)
        for (size_t c = 0; c < 3; c++)
            face_B[f + c * nfaces] = face_area[f] > 0.0 ? face_B[f + c * nfaces] / face_area[f] : 0.0;
    return RAD_OK;
}

/* Little-endian bytes regardless of the host's order. */
static void put_u32(FILE *f, uint32_t x)
{
    unsigned char b[4] = {(unsigned char)x, (unsigned char)(x >> 8), (unsigned char)(x >> 16),
                          (unsigned char)(x >> 24)};
    fwrite(b, 1, 4, f);
}

static void put_f32(FILE *f, float x)
{
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    put_u32(f, u);
}

rad_status rad_io_write_ply(const char *path, size_t nverts, const double *xyz, size_t ntris,
                            const int *tri, const double *B, const rad_io_tonemap *tm, int binary)
{
    rad_io_tonemap deftm;
    if (!tm) {
        rad_io_tonemap_default(&deftm);
        tm = &deftm;
    }
    double *vb = malloc((3 * nverts + 1) * sizeof *vb);
    if (!vb)
        return RAD_ERROR(RAD_ENOMEM, "PLY: no memory for %zu vertex colours", nverts);
    rad_status status = rad_io_vertex_values(nverts, xyz, ntris, tri, B, vb);
    rad_io_output o;
    if (status == RAD_OK)
        status = rad_io_output_open(path, binary, &o);
    if (status != RAD_OK) {
        free(vb);
        return status;
    }
    FILE *f = o.f;
    fprintf(f, "ply\nformat %s 1.0\n", binary ? "binary_little_endian" : "ascii");
    fprintf(f, "comment radkit %s: vertex colour = tone-mapped area-weighted average of the "
            "adjacent faces' radiosity (exposure %.9g, gamma %.9g)\n", RAD_VERSION, tm->exposure,
            tm->gamma);
    fprintf(f, "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n"
            "property uchar red\nproperty uchar green\nproperty uchar blue\n", nverts);
    fprintf(f, "element face %zu\nproperty list uchar int vertex_indices\nend_header\n", ntris);
    for (size_t v = 0; v < nverts; v++) {
        unsigned char rgb[3];
        for (int c = 0; c < 3; c++)
            rgb[c] = rad_io_tonemap_apply(tm, vb[3 * v + c]);
        if (binary) {
            for (int c = 0; c < 3; c++)
                put_f32(f, (float)xyz[3 * v + c]);
            fwrite(rgb, 1, 3, f);
        } else {
            fprintf(f, "%.9g %.9g %.9g %u %u %u\n", (float)xyz[3 * v], (float)xyz[3 * v + 1],
                    (float)xyz[3 * v + 2], rgb[0], rgb[1], rgb[2]);
        }
    }
    for (size_t t = 0; t < ntris; t++) {
        if (binary) {
            fputc(3, f);
            for (int k = 0; k < 3; k++)
                put_u32(f, (uint32_t)tri[3 * t + k]);
        } else {
            fprintf(f, "3 %d %d %d\n", tri[3 * t], tri[3 * t + 1], tri[3 * t + 2]);
        }
    }
    free(vb);
    return rad_io_output_commit(&o);
}

rad_status rad_io_write_dat(const char *path, const char *title, const rad_io_kv *header,
                            size_t nheader, size_t ncols, const char *const *columns,
                            size_t nrows, const double *data)
{
    if (ncols == 0 || !columns || (nrows && !data))
        return RAD_ERROR(RAD_EINVAL, ".dat: no columns or NULL data");
    rad_io_output o;
    rad_status status = rad_io_output_open(path, 0, &o);
    if (status != RAD_OK)
        return status;
    FILE *f = o.f;
    fprintf(f, "# %s\n# version = radkit %s\n", title ? title : "radkit data", RAD_VERSION);
    write_header(f, header, nheader);
    fprintf(f, "#");
    for (size_t c = 0; c < ncols; c++)
        fprintf(f, "%c%s", c ? '\t' : ' ', columns[c]);
    fprintf(f, "\n");
    for (size_t r = 0; r < nrows; r++)
        for (size_t c = 0; c < ncols; c++)
            fprintf(f, "%.17g%c", data[r * ncols + c], c + 1 < ncols ? '\t' : '\n');
    return rad_io_output_commit(&o);
}
