/* rad_hier: refusing a hierarchy the machine cannot hold (exit status 2)
 * before the kernel kills it (rad_sys_memory_allows).  Before links are
 * added, and when the element array grows, the process's resident memory
 * plus the new items and what the gather's arrays will hold for the larger
 * hierarchy (built at solve time: two ends per link, per element its
 * sources' row and start, a cluster-link build's copy of the
 * clusters' rows, and the oriented model's per-triangle irradiance of small
 * clusters, allocated with the clusters but first written by the solve)
 * beyond what they have touched so far is held against
 * RAD_SYS_MEMORY_SHARE of the machine's memory.  The message says what the
 * hierarchy holds and what would make it smaller.  Shared among processes
 * (rad_hier_exchange) the check is left out: each process would decide
 * from its own memory, and one that stopped alone would leave the others
 * waiting in the exchange. */
#include "hier_internal.h"

#include <stdio.h>

#include "rad_sys.h"

void hier_gather_touch(rad_hier *h, int k, size_t bytes)
{
    h->gather_touched[k] = rad_dmax(h->gather_touched[k], (double)bytes);
}

/* What array k (cap bytes now) will add when it holds `bytes`: rebuilt
   within its capacity it writes over the pages it has touched; past it,
   rad_sys_grow frees the old block and hands its pages back before it
   makes the new one, and rad_sys_grow_mapped moves the pages it has into
   the larger mapping, so again only what goes beyond them. */
static double pending(const rad_hier *h, int k, double bytes)
{
    return rad_dmax(0.0, bytes - h->gather_touched[k]);
}

rad_status hier_memory_check(const rad_hier *h, size_t links, size_t clinks, size_t elems)
{
    if (hier_shared(h))
        return RAD_OK;
    double nl = (double)(h->nln + links), ncl = (double)(h->ncln + clinks);
    double ne = (double)(h->nel + elems), word = sizeof(size_t);
    double add = (double)links * sizeof(hier_link) + (double)clinks * sizeof(hier_clink) +
                 (double)elems * sizeof(hier_elem) +
                 pending(h, HIER_GATHER_INC, 2.0 * nl * sizeof(hier_end)) +
                 pending(h, HIER_GATHER_INC_START, (ne + 1.0) * word) +
                 pending(h, HIER_GATHER_SRC, ne * HIER_SRC * sizeof(double));
    if (h->ncl)
        add += pending(h, HIER_GATHER_CINC, 2.0 * ncl * sizeof(hier_cinc)) +
               pending(h, HIER_GATHER_CINC_START, ((double)h->ncl + ne + 1.0) * word) +
               (double)h->ncl * sizeof(hier_cinc) +
               (h->p.cluster_model == RAD_HIER_CLUSTER_ISO
                    ? 0.0
                    : pending(h, HIER_GATHER_CRECV, 3.0 * (double)h->nroots * sizeof(double)));
    double would, have;
    if (rad_sys_memory_allows(add, &would, &have))
        return RAD_OK;
    const double gib = 1024.0 * 1024.0 * 1024.0;
    size_t more = links ? links : clinks ? clinks : elems;
    const char *kind = links ? "links" : clinks ? "cluster links" : elems ? "elements" : NULL;
    char what[64];
    if (kind)
        snprintf(what, sizeof what, "%zu more %s", more, kind);
    else
        snprintf(what, sizeof what, "the solve's arrays");
    return RAD_ERROR(RAD_ETOOBIG,
                     "hier: %s would take the process to %.3g GiB, more than %.0f%% "
                     "of this machine's %.3g GiB (RADKIT_MEMORY_LIMIT sets it), with %zu links, "
                     "%zu cluster links and %zu elements made so far; raise --eps or lower "
                     "--max-tighten%s, or use fewer triangles",
                     what, would / gib, 100.0 * RAD_SYS_MEMORY_SHARE, have / gib, h->nln,
                     h->ncln, h->nel, h->ncl ? "" : ", or link through clusters (--method cluster)");
}
