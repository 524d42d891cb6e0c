/* Closed forms of the seed kernel's Galerkin matrices (derivation:
 * papers/galerkin-1d.md, section 2; every formula is checked against adaptive
 * quadrature of its defining integral in tests/test_galerkin1d.c).
 *
 * With h = 1/n, cell c = [c h, (c+1) h] (0-based) and local u = (x - c h)/h:
 *
 *   P0, cells lo < hi:  A = h^4 (2 lo + 1)(2 (n - hi) - 1) / 4
 *   P0, diagonal c:     A = h^4 [ c (n - c - 1) + n/3 - 1/4 ]
 *
 * The notes write the diagonal as (4j-2) h^3/4 - (2j-1)^2 h^4/4 (1-based j):
 * its h^3 term is j - 1/2 where the integral gives j - 2/3 (n = 1: 1/4 instead
 * of 1/12).  The forms here are written with integers so that no digits cancel
 * near x = 1, which 2 - (2j-1) h would do.
 *
 * P1 off-diagonal pairs are separable because k = t (1-x) when t < x:
 *   int psi_a (1-x) dx = h^2 ((n-c)/2 - 1/6, (n-c)/2 - 1/3)   (psi_0 = 1-u, psi_1 = u)
 *   int psi_a  t    dt = h^2 (c/2 + 1/6,     c/2 + 1/3)
 * P1 diagonal cell c: with x = (c+u) h, t = (c+v) h, m = min(u,v), M = max(u,v),
 *   k = (c h + h m)(1 - c h - h M) = h^2 [ c (n-c) - c M + (n-c) m - m M ],
 * and m M = u v, so the local entry is
 *   h^4 [ c (n-c) S0 - c SM + (n-c) Sm - SmM ]
 * with S0 = int psi_a psi_b = 1/4 and the moments SM = int psi_a psi_b M,
 * Sm = int psi_a psi_b m, SmM = int psi_a psi_b u v over the unit square: the
 * rationals in the tables below (each integral split along u = v). */
#include "rad_galerkin1d.h"

static int imin(int a, int b) { return a < b ? a : b; }
static int imax(int a, int b) { return a > b ? a : b; }

double rad_galerkin1d_green_p0(int n, int i, int j)
{
    double h = 1.0 / n, h4 = h * h * h * h;
    if (i == j)
        return h4 * ((double)i * (double)(n - i - 1) + n / 3.0 - 0.25);
    int lo = imin(i, j), hi = imax(i, j);
    return h4 * (2.0 * lo + 1.0) * (2.0 * (n - hi) - 1.0) / 4.0;
}

/* Moments over the unit square of psi_alpha(u) psi_beta(v) times M, m and u v. */
static const double moment_max[2][2] = {{7.0 / 60.0, 7.0 / 40.0}, {7.0 / 40.0, 1.0 / 5.0}};
static const double moment_min[2][2] = {{1.0 / 20.0, 3.0 / 40.0}, {3.0 / 40.0, 2.0 / 15.0}};
static const double moment_uv[2][2] = {{1.0 / 36.0, 1.0 / 18.0}, {1.0 / 18.0, 1.0 / 9.0}};

void rad_galerkin1d_green_p1_local(int n, int a, int c, double out[2][2])
{
    double h = 1.0 / n, h2 = h * h, h4 = h2 * h2;
    if (a == c) {
        double left = (double)c, right = (double)(n - c);
        for (int al = 0; al < 2; al++)
            for (int be = 0; be < 2; be++)
                out[al][be] = h4 * (left * right * 0.25 - left * moment_max[al][be] +
                                    right * moment_min[al][be] - moment_uv[al][be]);
        return;
    }
    /* The left cell carries the factor t (or x), the right one (1 - x) (or 1 - t). */
    int left = imin(a, c), right = imax(a, c);
    double mt[2] = {h2 * (left / 2.0 + 1.0 / 6.0), h2 * (left / 2.0 + 1.0 / 3.0)};
    double m1[2] = {h2 * ((n - right) / 2.0 - 1.0 / 6.0), h2 * ((n - right) / 2.0 - 1.0 / 3.0)};
    for (int al = 0; al < 2; al++)
        for (int be = 0; be < 2; be++)
            out[al][be] = (c < a) ? m1[al] * mt[be] : mt[al] * m1[be];
}
