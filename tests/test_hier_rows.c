/* The rows' caps (core/hier/solve.c, push_rows): in a sealed scene a leaf's
 * row is scaled up to the ceiling, 1, but not a row that is no more than
 * what rounding leaves of cancelling terms (1e-20 at some leaves of a large
 * room's first hierarchy, where every link at them comes from clusters they
 * turn away from): scaled by 1e20, that noise would be a whole irradiance
 * and flip the leaf's B from step to step.  Here the facing squares'
 * links are scaled so that one leaf's row is 1e-20 and another's 1e-6: the
 * first keeps a cap of 1, the second is scaled to the ceiling. */
#include <math.h>

#include "harness.h"
#include "hier_internal.h"
#include "rad_hier.h"
#include "rad_vis.h"
#include "squares.h"

TEST(hier_sealed_row_of_rounding_noise_is_not_scaled_up)
{
    rad_hier_params p;
    rad_hier_params_default(&p);
    rad_vis *vis = NULL;
    rad_hier *h = facing_squares(&p, &vis);
    if (!h)
        return;
    CHECK(rad_hier_leaf_count(h) == 4 && h->nln > 0);
    h->p.sealed = 1; /* rows normalized as in a closed scene */
    CHECK(hier_row_caps(h) == RAD_OK);
    double want[2] = {1e-20, 1e-6}, scale[2];
    for (int e = 0; e < 2; e++) {
        CHECK(h->el[e].row0 > 0.1);
        scale[e] = want[e] / h->el[e].row0;
    }
    /* each link joins a leaf of the lower square (0, 1) to one of the upper */
    for (size_t k = 0; k < h->nln; k++) {
        hier_link *l = &h->ln[k];
        int low = l->a < 2 ? l->a : l->b;
        CHECK(low >= 0 && low < 2 && (l->a < 2) != (l->b < 2));
        l->G *= scale[low];
        l->ga = rad_vec3_scale(l->ga, scale[low]);
        l->gb = rad_vec3_scale(l->gb, scale[low]);
    }
    h->version++; /* the links changed: the gather's ends are rebuilt */
    CHECK(hier_row_caps(h) == RAD_OK);
    double top = rad_hier_row_ceiling(1, h->rho_max);
    CHECK_MSG(fabs(h->el[0].row0 / 1e-20 - 1.0) < 1e-9, "row %.3e", h->el[0].row0);
    CHECK_MSG(h->el[0].cap == 1.0, "a row of 1e-20 capped by %.3e", h->el[0].cap);
    CHECK_MSG(fabs(h->el[1].cap * h->el[1].row0 - top) < 1e-12 * top,
              "a row of %.3e capped by %.3e", h->el[1].row0, h->el[1].cap);
    rad_hier_destroy(h);
    rad_vis_destroy(vis);
}
