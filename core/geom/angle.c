/* rad_geom_angle: the angle between two vectors from the norm of their cross
 * product s >= 0 and their dot product c, atan2(s, c) in [0, pi].
 *
 * The point-to-polygon form factor takes one such angle per edge of every
 * visible piece, from a norm (s >= 0), so only the upper half-plane
 * occurs, and libm's atan2 (correctly rounded, every quadrant and special
 * value) does more than it needs.  The arctangent is fdlibm's (Sun Microsystems, 1993: the
 * argument reduced to |t| < 7/16 about atan(1/2), atan(1), atan(3/2) or
 * infinity, then an odd polynomial of degree 23 in t), within 1 ulp; the
 * half-plane c < 0 is pi minus the angle of (s, -c).  Checked against libm's
 * atan2 (tests/test_geom.c). */
#include "rad_geom.h"

static const double atan_hi[4] = {4.63647609000806093515e-01, 7.85398163397448278999e-01,
                                  9.82793723247329054082e-01, 1.57079632679489655800e+00};
static const double atan_lo[4] = {2.26987774529616870924e-17, 3.06161699786838301793e-17,
                                  1.39033110312309984516e-17, 6.12323399573676603587e-17};
static const double aT[11] = {
    3.33333333333329318027e-01,  -1.99999999998764832476e-01, 1.42857142725034663711e-01,
    -1.11111104054623557880e-01, 9.09088713343650656196e-02,  -7.69187620504482999495e-02,
    6.66107313738753120669e-02,  -5.83357013379057348645e-02, 4.97687799461593236017e-02,
    -3.65315727442169155270e-02, 1.62858201153657823623e-02};

/* atan(t) for t >= 0 (t may be +inf). */
static double atan_nonneg(double t)
{
    int id;
    if (t < 0.4375) {
        id = -1;
    } else if (t < 1.1875) {
        if (t < 0.6875) {
            id = 0;
            t = (2.0 * t - 1.0) / (2.0 + t);
        } else {
            id = 1;
            t = (t - 1.0) / (t + 1.0);
        }
    } else if (t < 2.4375) {
        id = 2;
        t = (t - 1.5) / (1.0 + 1.5 * t);
    } else {
        id = 3;
        t = -1.0 / t;
    }
    double z = t * t, w = z * z;
    double s1 = z * (aT[0] + w * (aT[2] + w * (aT[4] + w * (aT[6] + w * (aT[8] + w * aT[10])))));
    double s2 = w * (aT[1] + w * (aT[3] + w * (aT[5] + w * (aT[7] + w * aT[9]))));
    if (id < 0)
        return t - t * (s1 + s2);
    return atan_hi[id] - ((t * (s1 + s2) - atan_lo[id]) - t);
}

double rad_geom_angle(double s, double c)
{
    if (c > 0.0)
        return atan_nonneg(s / c);
    if (c < 0.0)
        return RAD_PI - atan_nonneg(s / -c);
    if (c == 0.0 && s >= 0.0)
        return s > 0.0 ? 0.5 * RAD_PI : 0.0;
    return s + c; /* a NaN stays one */
}
