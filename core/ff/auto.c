#include <math.h>
#include "ff_internal.h"
rad_status ff_auto(const ff_pair *pr, const rad_ff_params *params, ff_value *v, rad_ff_rule *used)
{
    used->scheme = RAD_FF_EXACT;
    *v = ff_exact(pr, params);
    return RAD_OK;
}
