/* Globally adaptive Gauss-Kronrod (7,15) quadrature (QUADPACK QAG/QAGP).
 *
 * 1. Split [a,b] at the breakpoints; apply the 15-point Kronrod rule and its
 *    embedded 7-point Gauss rule to each piece.  Interval error = |K15 - G7|.
 * 2. While the summed error exceeds max(abs_tol, rel_tol |sum|), bisect the
 *    interval with the largest error.
 * 3. Stop with RAD_ENUMERIC when the interval cap is reached.
 * Nodes and weights [piessens1983]: Piessens, de Doncker-Kapenga, Ueberhuber, Kahaner,
 * QUADPACK (1983), routine QK15 (public domain), to 33 digits. */
#include "rad_quad.h"

#include <math.h>

static const double xgk[8] = {
    0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
    0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
    0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
    0.207784955007898467600689403773245, 0.000000000000000000000000000000000};
static const double wgk[8] = {
    0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
    0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
    0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
    0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
/* Gauss weights for the nodes xgk[1], xgk[3], xgk[5], xgk[7]. */
static const double wg[4] = {
    0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

typedef struct interval {
    double a, b, value, error;
} interval;

static int qk15(rad_quad_fn f, void *ctx, double a, double b, interval *iv)
{
    double c = 0.5 * (a + b), hl = 0.5 * (b - a);
    double fc = f(c, ctx);
    double resk = fc * wgk[7], resg = fc * wg[3];
    int finite = isfinite(fc);
    for (int j = 0; j < 7; j++) {
        double dx = hl * xgk[j];
        double f1 = f(c - dx, ctx), f2 = f(c + dx, ctx);
        finite = finite && isfinite(f1) && isfinite(f2);
        resk += wgk[j] * (f1 + f2);
        if (j % 2 == 1)
            resg += wg[j / 2] * (f1 + f2);
    }
    iv->a = a;
    iv->b = b;
    iv->value = resk * hl;
    iv->error = fabs((resk - resg) * hl);
    return finite;
}

void rad_quad_adapt_params_default(rad_quad_adapt_params *params)
{
    *params = (rad_quad_adapt_params){.abs_tol = 0.0, .rel_tol = 1e-13, .max_intervals = 1000};
}

rad_status rad_quad_adapt(rad_quad_fn f, void *ctx, double a, double b,
                          const double *breaks, int nbreaks,
                          const rad_quad_adapt_params *params, rad_quad_result *out)
{
    rad_quad_adapt_params p;
    if (params)
        p = *params;
    else
        rad_quad_adapt_params_default(&p);
    if (!f || !out || !(a <= b) || !isfinite(a) || !isfinite(b) || nbreaks < 0)
        return RAD_ERROR(RAD_EINVAL, "adaptive quadrature: bad interval [%g, %g]", a, b);
    if (p.max_intervals < 1 || p.max_intervals > RAD_QUAD_ADAPT_MAX_INTERVALS)
        p.max_intervals = RAD_QUAD_ADAPT_MAX_INTERVALS;
    if (p.abs_tol < 0 || p.rel_tol < 0)
        return RAD_ERROR(RAD_EINVAL, "adaptive quadrature: negative tolerance");

    interval iv[RAD_QUAD_ADAPT_MAX_INTERVALS];
    int count = 0, finite = 1;
    long evals = 0;

    /* Initial pieces: [a,b] cut at the sorted breakpoints that lie inside it. */
    double lo = a;
    for (;;) {
        double next = b;
        for (int i = 0; i < nbreaks; i++)
            if (breaks[i] > lo && breaks[i] < next)
                next = breaks[i];
        if (count >= p.max_intervals)
            return RAD_ERROR(RAD_EINVAL, "adaptive quadrature: more breakpoints than intervals");
        finite &= qk15(f, ctx, lo, next, &iv[count++]);
        evals += 15;
        if (next >= b)
            break;
        lo = next;
    }

    rad_status status = RAD_OK;
    for (;;) {
        double sum = 0.0, err = 0.0;
        int worst = 0;
        for (int i = 0; i < count; i++) {
            sum += iv[i].value;
            err += iv[i].error;
            if (iv[i].error > iv[worst].error)
                worst = i;
        }
        out->value = sum;
        out->error = err;
        out->evals = evals;
        if (!finite) {
            status = RAD_ERROR(RAD_ENUMERIC, "adaptive quadrature: integrand not finite on [%g, %g]", a, b);
            break;
        }
        if (err <= fmax(p.abs_tol, p.rel_tol * fabs(sum)))
            break;
        /* Stop when the worst interval cannot be split any more in floating point. */
        double m = 0.5 * (iv[worst].a + iv[worst].b);
        if (count >= p.max_intervals || !(m > iv[worst].a && m < iv[worst].b)) {
            status = RAD_ERROR(RAD_ENUMERIC,
                               "adaptive quadrature: tolerance not reached on [%g, %g] "
                               "(estimated error %.3g after %d intervals)", a, b, err, count);
            break;
        }
        double wb = iv[worst].b;
        finite &= qk15(f, ctx, iv[worst].a, m, &iv[worst]);
        finite &= qk15(f, ctx, m, wb, &iv[count++]);
        evals += 30;
    }
    return status;
}
