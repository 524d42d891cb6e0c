#include "squares.h"

#include "harness.h"

rad_hier *test_hier_of(const double *xyz, size_t nv, const int *tri, size_t nt, const double *rho,
                       const double *E, const rad_hier_params *p, rad_vis **vis)
{
    rad_vis_params vp;
    rad_vis_params_default(&vp);
    *vis = NULL;
    CHECK(rad_vis_create(xyz, nv, tri, nt, &vp, vis) == RAD_OK);
    rad_hier *h = NULL;
    CHECK(*vis && rad_hier_create(xyz, nv, tri, nt, rho, E, *vis, p, &h) == RAD_OK);
    return h;
}

rad_hier *facing_squares(const rad_hier_params *p, rad_vis **vis)
{
    static const double xyz[24] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0,
                                   0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1};
    static const int tri[12] = {0, 1, 2, 0, 2, 3, 4, 6, 5, 4, 7, 6};
    double rho[12], E[12];
    for (int k = 0; k < 12; k++) {
        rho[k] = 0.5;
        E[k] = k % 4 >= 2 ? 1.0 : 0.0;
    }
    return test_hier_of(xyz, 8, tri, 4, rho, E, p, vis);
}
