/* rad_cluster: what a group of triangles can turn towards a cone of
 * directions (rad_cluster_projected_upper), the bound a cluster link's
 * form factor rests on (hier/cluster.c). */
#include "rad_cluster.h"

#include <math.h>

#include "rad_geom.h"

double rad_cluster_projected_upper(double area, const double N[3], const double axis[3],
                                   double alpha, const double w[3], double beta, double *cosmax)
{
    /* a normal within alpha of axis and a direction within beta of w make
       an angle of at least theta - alpha - beta, theta the axis's to w */
    double c = 1.0;
    if (alpha <= RAD_PI) {
        double d = axis[0] * w[0] + axis[1] * w[1] + axis[2] * w[2];
        double theta = acos(d < -1.0 ? -1.0 : d > 1.0 ? 1.0 : d);
        double gap = theta - alpha - beta;
        c = gap > 0.0 ? cos(gap) : 1.0;
    }
    c = c > 0.0 ? c : 0.0;
    if (cosmax)
        *cosmax = c;
    /* for one direction u, sum a_i max(n_i.u, 0) = (sum a_i |n_i.u| + N.u) / 2
       <= (area + |N|) / 2; turning u to a triangle's own u_i raises its
       cosine by at most |u_i - u| <= 2 sin(beta / 2) */
    double len = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
    double spread = 0.5 * (area + len) + 2.0 * sin(0.5 * beta) * area;
    double by_cone = area * c;
    return by_cone < spread ? by_cone : spread;
}
