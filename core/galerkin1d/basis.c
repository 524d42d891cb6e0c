/* Bases: dimensions, mass matrices, evaluation, and the option parsers. */
#include "rad_galerkin1d.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

size_t rad_galerkin1d_dim(rad_galerkin1d_basis basis, int n)
{
    if (n < 1)
        return 0;
    return basis == RAD_GALERKIN1D_P1 ? (size_t)n + 1 : (size_t)n;
}

/* P0: M = h I.  P1: the hat functions' mass matrix h/6 [1 4 1] in the interior,
 * h/3 on the two boundary half-hats. */
void rad_galerkin1d_mass(rad_galerkin1d_basis basis, int n, double *diag, double *off)
{
    double h = 1.0 / n;
    size_t dim = rad_galerkin1d_dim(basis, n);
    for (size_t i = 0; i < dim; i++)
        diag[i] = h;
    for (size_t i = 0; i + 1 < dim; i++)
        off[i] = 0.0;
    if (basis == RAD_GALERKIN1D_P1) {
        for (size_t i = 0; i < dim; i++)
            diag[i] = (i == 0 || i == dim - 1) ? h / 3.0 : 2.0 * h / 3.0;
        for (size_t i = 0; i + 1 < dim; i++)
            off[i] = h / 6.0;
    }
}

double rad_galerkin1d_eval(rad_galerkin1d_basis basis, int n, const double *y, double x)
{
    int c = (int)(x * n);
    if (c < 0)
        c = 0;
    if (c > n - 1)
        c = n - 1;
    if (basis == RAD_GALERKIN1D_P0)
        return y[c];
    double u = x * n - c;
    return y[c] * (1.0 - u) + y[c + 1] * u;
}

rad_status rad_galerkin1d_basis_parse(const char *text, rad_galerkin1d_basis *out)
{
    if (text && strcmp(text, "p0") == 0)
        *out = RAD_GALERKIN1D_P0;
    else if (text && strcmp(text, "p1") == 0)
        *out = RAD_GALERKIN1D_P1;
    else
        return RAD_ERROR(RAD_EINVAL, "unknown basis '%s' (expected p0 or p1)", text ? text : "");
    return RAD_OK;
}

const char *rad_galerkin1d_basis_name(rad_galerkin1d_basis basis)
{
    return basis == RAD_GALERKIN1D_P1 ? "p1" : "p0";
}

/* Largest K accepted: the nodes are computed in O(K^2), the assembly costs K^2
 * kernel evaluations per cell pair; beyond this nothing is gained in double. */
#define RAD_GALERKIN1D_MAX_POINTS 256

static rad_status parse_points(const char *text, const char *digits, int *points)
{
    char *end = NULL;
    errno = 0;
    long k = strtol(digits, &end, 10);
    if (*digits == '\0' || *end != '\0' || errno || k < 1 || k > RAD_GALERKIN1D_MAX_POINTS)
        return RAD_ERROR(RAD_EINVAL,
                         "assembly '%s': the number of Gauss points must be an integer "
                         "from 1 to %d", text, RAD_GALERKIN1D_MAX_POINTS);
    *points = (int)k;
    return RAD_OK;
}

rad_status rad_galerkin1d_assembly_parse(const char *text, rad_galerkin1d_assembly *out)
{
    if (!text)
        text = "";
    if (strcmp(text, "exact") == 0) {
        out->kind = RAD_GALERKIN1D_EXACT;
        out->points = 0;
        return RAD_OK;
    }
    if (strcmp(text, "midpoint") == 0) {
        out->kind = RAD_GALERKIN1D_GAUSS;
        out->points = 1;
        return RAD_OK;
    }
    if (strncmp(text, "gauss:", 6) == 0) {
        out->kind = RAD_GALERKIN1D_GAUSS;
        return parse_points(text, text + 6, &out->points);
    }
    if (strncmp(text, "gauss-split:", 12) == 0) {
        out->kind = RAD_GALERKIN1D_GAUSS_SPLIT;
        return parse_points(text, text + 12, &out->points);
    }
    return RAD_ERROR(RAD_EINVAL,
                     "unknown assembly '%s' (expected exact, midpoint, gauss:K or gauss-split:K)",
                     text);
}

void rad_galerkin1d_assembly_format(rad_galerkin1d_assembly assembly, char *buf, size_t size)
{
    if (assembly.kind == RAD_GALERKIN1D_EXACT)
        snprintf(buf, size, "exact");
    else if (assembly.kind == RAD_GALERKIN1D_GAUSS && assembly.points == 1)
        snprintf(buf, size, "midpoint");
    else
        snprintf(buf, size, "%s:%d",
                 assembly.kind == RAD_GALERKIN1D_GAUSS ? "gauss" : "gauss-split", assembly.points);
}
