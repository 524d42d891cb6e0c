/* CIE 1931 chromaticity of a spectrum, for MGF's `cspec` and `cct`.
 *
 * The colour-matching functions are Wyman, Sloan and Shirley's multi-lobe
 * fit (JCGT 2(2), 2013, "Simple analytic approximations to the CIE XYZ
 * colour matching functions"), within about 1% of the tabulated CIE 1931 2°
 * observer's peak: radkit carries no table.  Its far red tail is weak (light
 * at 700 nm alone comes out at x = 0.57, 0.73 tabulated); broad spectra,
 * which is what MGF's `cspec` and `cct` describe, do not notice.  A spectrum is integrated over 360 ..
 * 830 nm at 1 nm by the midpoint rule; chromaticities come out within a few
 * thousandths of the tabulated observer's (tests/test_mgf.c checks
 * illuminant A and the equal-energy white). */
#include "scene_internal.h"

#include <math.h>

static double lobe(double l, double mu, double s1, double s2)
{
    double t = (l - mu) / (l < mu ? s1 : s2);
    return exp(-0.5 * t * t);
}

static void cmf(double l, double *x, double *y, double *z)
{
    *x = 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) -
         0.065 * lobe(l, 501.1, 20.4, 26.2);
    *y = 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1);
    *z = 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8);
}

int scene_cie_xy(double (*spectrum)(double nm, void *ctx), void *ctx, double *x, double *y)
{
    double X = 0.0, Y = 0.0, Z = 0.0;
    for (int i = 0; i < 470; i++) {
        double l = 360.5 + i, s = spectrum(l, ctx), cx, cy, cz;
        if (!(s >= 0.0) || !isfinite(s))
            return 0;
        cmf(l, &cx, &cy, &cz);
        X += s * cx;
        Y += s * cy;
        Z += s * cz;
    }
    double sum = X + Y + Z;
    if (!(Y > 0.0) || !(sum > 0.0) || !isfinite(sum))
        return 0;
    *x = X / sum;
    *y = Y / sum;
    return 1;
}

/* Planck's law up to a constant: lambda^-5 / (exp(c2 / (lambda T)) - 1). */
static double planck(double nm, void *ctx)
{
    double T = *(const double *)ctx, l = nm * 1e-9, c2 = 1.438777e-2;
    double e = expm1(c2 / (l * T));
    return isfinite(e) && e > 0.0 ? 1e-30 / (l * l * l * l * l * e) : 0.0;
}

int scene_cie_xy_blackbody(double kelvin, double *x, double *y)
{
    if (!(kelvin > 0.0) || !isfinite(kelvin))
        return 0;
    return scene_cie_xy(planck, &kelvin, x, y);
}
