/* rad_hier: refusing a hierarchy the machine cannot hold (exit status 2)
 * before the kernel kills it (rad_sys_memory_allows).  Before links are
 * added, the process's resident memory plus the new links and the gather's
 * ends they will have (two per link: solve.c's inc, cluster.c's cinc, built
 * after the refinement) is held against RAD_SYS_MEMORY_SHARE of the
 * machine's memory; elements are checked when their array grows.  The message says
 * what the hierarchy holds and what would make it smaller.  Shared among
 * processes (rad_hier_exchange) the check is left out: each process would
 * decide from its own memory, and one that stopped alone would leave the
 * others waiting in the exchange. */
#include "hier_internal.h"

#include "rad_sys.h"

static double pending_ends(size_t links, size_t cap, size_t item)
{
    return 2 * links > cap ? (double)(2 * links - cap) * (double)item : 0.0;
}

rad_status hier_memory_check(const rad_hier *h, size_t links, size_t clinks, size_t elems)
{
    if (hier_shared(h))
        return RAD_OK;
    double add = (double)links * sizeof(hier_link) + (double)clinks * sizeof(hier_clink) +
                 (double)elems * sizeof(hier_elem) +
                 pending_ends(h->nln + links, h->inc_cap, sizeof(hier_end));
    if (h->ncl)
        add += pending_ends(h->ncln + clinks, h->cinc_cap, sizeof(hier_cinc));
    double would, have;
    if (rad_sys_memory_allows(add, &would, &have))
        return RAD_OK;
    const double gib = 1024.0 * 1024.0 * 1024.0;
    size_t more = links ? links : clinks ? clinks : elems;
    const char *kind = links ? "links" : clinks ? "cluster links" : "elements";
    return RAD_ERROR(RAD_ETOOBIG,
                     "hier: %zu more %s would take the process to %.3g GiB, more than %.0f%% "
                     "of this machine's %.3g GiB (RADKIT_MEMORY_LIMIT sets it), with %zu links, "
                     "%zu cluster links and %zu elements made so far; raise --eps or lower "
                     "--max-tighten%s, or use fewer triangles",
                     more, kind, would / gib, 100.0 * RAD_SYS_MEMORY_SHARE, have / gib, h->nln,
                     h->ncln, h->nel, h->ncl ? "" : ", or link through clusters (--method cluster)");
}
