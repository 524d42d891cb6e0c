/* radkit solve: the options as pipeline parameters (rad_solve_params).  Each
 * method takes its own options; another method's option is a usage error
 * naming it, so that a typo in a method never silently does nothing. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "rad_basis.h"
#include "rad_ff.h"
#include "solve.h"

/* A whole number in [lo, hi] (unsigned 64-bit range); RAD_EINVAL names the option. */
static rad_status parse_count(const char *option, const char *text, unsigned long long lo,
                              unsigned long long hi, unsigned long long *out)
{
    char *end = NULL;
    errno = 0;
    const char *p = text;
    while (*p == ' ')
        p++;
    unsigned long long v = *p == '-' ? 0 : strtoull(p, &end, 10);
    if (*p == '-' || end == p || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        return RAD_ERROR(RAD_EINVAL, "solve: %s must be a whole number in [%llu, %llu], got '%s'",
                         option, lo, hi, text);
    *out = v;
    return RAD_OK;
}

/* The first option given that `method` does not take. */
static rad_status refuse_others(const solve_options *o, rad_solve_method method)
{
    /* which methods take each option: d(ense), h(ier), c(luster), m(c) */
    const struct {
        const char *name, *value, *methods;
    } table[] = {
        {"--rule", o->rule, "dh"},          {"--tol", o->tol, "dhc"},
        {"--solver", o->solver, "d"},       {"--solver-tol", o->solver_tol, "dhc"},
        {"--max-iter", o->max_iter, "dhc"}, {"--refine", o->refine, "d"},
        {"--vis-strata", o->strata, "d"},   {"--eps", o->eps, "hc"},
        {"--min-area", o->min_area, "hc"},  {"--oracle", o->oracle, "h"},
        {"--max-tighten", o->max_tighten, "hc"}, {"--max-links", o->max_links, "hc"},
        {"--clip-blockers", o->clip_blockers, "hc"}, {"--anderson", o->anderson, "hc"},
        {"--samples", o->samples, "m"},     {"--seed", o->seed, "m"},
        {"--basis", o->basis, "dh"},        {"--cluster-model", o->cluster_model, "c"},
    };
    const char code = method == RAD_SOLVE_HIER      ? 'h'
                      : method == RAD_SOLVE_CLUSTER ? 'c'
                      : method == RAD_SOLVE_MC      ? 'm'
                                                    : 'd';
    for (size_t k = 0; k < sizeof table / sizeof table[0]; k++) {
        if (!table[k].value || strchr(table[k].methods, code))
            continue;
        const char *m = table[k].methods;
        const char *who = strcmp(m, "d") == 0    ? "--method dense"
                          : strcmp(m, "h") == 0  ? "--method hier"
                          : strcmp(m, "c") == 0  ? "--method cluster"
                          : strcmp(m, "hc") == 0 ? "--method hier or cluster"
                          : strcmp(m, "m") == 0  ? "--method mc"
                          : strcmp(m, "dh") == 0 ? "--method dense or hier"
                                                 : "--method dense, hier or cluster";
        return RAD_ERROR(RAD_EINVAL, "solve: %s applies to %s only, not --method %s",
                         table[k].name, who, rad_solve_method_name(method));
    }
    return RAD_OK;
}

static rad_status parse_dense(const solve_options *o, rad_solve_params *p)
{
    rad_status st = RAD_OK;
    if (o->rule && (st = rad_ff_rule_parse(o->rule, &p->assembly.rule)) != RAD_OK)
        return st;
    if (o->tol && (st = solve_parse_double("--tol", o->tol, 0.0, &p->assembly.ff.tol)) != RAD_OK)
        return st;
    p->keep_tol = o->tol != NULL;
    if (o->solver && (st = rad_dense_method_parse(o->solver, &p->dense.method)) != RAD_OK)
        return st;
    if (o->solver_tol &&
        (st = solve_parse_double("--solver-tol", o->solver_tol, 0.0, &p->dense.tol)) != RAD_OK)
        return st;
    p->keep_solver_tol = o->solver_tol != NULL;
    if (o->max_iter && (st = cli_parse_positive_int("solve: --max-iter", o->max_iter, 100000000,
                                                    &p->dense.max_iter)) != RAD_OK)
        return st;
    if (o->refine && strcmp(o->refine, "0") != 0 &&
        (st = cli_parse_positive_int("solve: --refine", o->refine, 12, &p->refine)) != RAD_OK)
        return st;
    int strata = 8;
    if (o->strata &&
        (st = cli_parse_positive_int("solve: --vis-strata", o->strata, 16, &strata)) != RAD_OK)
        return st;
    p->assembly.visible.sample_strata = strata;
    return RAD_OK;
}

static rad_status parse_hier(const solve_options *o, rad_solve_params *p)
{
    rad_status st = RAD_OK;
    rad_hier_params *hp = &p->hier;
    if (o->rule && (st = rad_ff_rule_parse(o->rule, &hp->rule)) != RAD_OK)
        return st;
    if (o->rule) { /* an explicit rule gives every link's unoccluded F */
        hp->use_rule = 1;
        hp->far_ratio = 0.0;
    }
    if (o->tol && (st = solve_parse_double("--tol", o->tol, 0.0, &hp->ff.tol)) != RAD_OK)
        return st;
    if (o->eps && (st = solve_parse_double("--eps", o->eps, 0.0, &hp->eps)) != RAD_OK)
        return st;
    if (o->oracle && (st = rad_hier_oracle_parse(o->oracle, &hp->oracle)) != RAD_OK)
        return st;
    if (o->cluster_model &&
        (st = rad_hier_cluster_model_parse(o->cluster_model, &hp->cluster_model)) != RAD_OK)
        return st;
    if (o->min_area) {
        char *end = NULL;
        double v = strtod(o->min_area, &end);
        if (end == o->min_area || *end != '\0' || !isfinite(v) || v < 0.0)
            return RAD_ERROR(RAD_EINVAL, "solve: --min-area must be a number >= 0, got '%s'",
                             o->min_area);
        hp->min_area = v;
    }
    if (o->max_tighten) {
        unsigned long long v;
        if ((st = parse_count("--max-tighten", o->max_tighten, 0, 30, &v)) != RAD_OK)
            return st;
        if (hp->oracle != RAD_HIER_ORACLE_ERROR) /* BF compares no bound with eps */
            return RAD_ERROR(RAD_EINVAL, "solve: --max-tighten applies to --oracle error only");
        hp->max_tighten = (int)v;
    }
    if (o->clip_blockers) {
        unsigned long long v;
        if ((st = parse_count("--clip-blockers", o->clip_blockers, 0, RAD_HIER_CLIP_BLOCKERS_MAX,
                              &v)) != RAD_OK)
            return st;
        hp->clip_blockers = (int)v;
    }
    if (o->anderson) {
        unsigned long long v;
        if ((st = parse_count("--anderson", o->anderson, 0, RAD_HIER_ANDERSON_MAX, &v)) != RAD_OK)
            return st;
        hp->anderson = (int)v;
    }
    if (o->max_links) {
        unsigned long long v;
        if ((st = parse_count("--max-links", o->max_links, 1, 1ull << 40, &v)) != RAD_OK)
            return st;
        hp->max_links = (size_t)v;
    }
    if (o->solver_tol &&
        (st = solve_parse_double("--solver-tol", o->solver_tol, 0.0, &hp->tol)) != RAD_OK)
        return st;
    if (o->solver_tol) /* the user's tolerance, not a share of eps */
        hp->final_share = 0.0;
    if (o->max_iter && (st = cli_parse_positive_int("solve: --max-iter", o->max_iter, 100000000,
                                                    &hp->max_iterations)) != RAD_OK)
        return st;
    return RAD_OK;
}

static rad_status parse_mc(const solve_options *o, rad_solve_params *p)
{
    rad_status st = RAD_OK;
    unsigned long long v;
    if (o->samples) {
        if ((st = parse_count("--samples", o->samples, 2, 1ull << 40, &v)) != RAD_OK)
            return st;
        p->mc.samples = (long long)v;
    }
    if (o->seed) {
        if ((st = parse_count("--seed", o->seed, 0, ~0ull, &v)) != RAD_OK)
            return st;
        p->mc.seed = v;
    }
    return RAD_OK;
}

rad_status solve_parse_params(const solve_options *o, const rad_effects_params *ep,
                              rad_solve_params *p)
{
    rad_solve_params_default(p);
    p->effects = *ep;
    rad_status st = RAD_OK;
    if (o->method && (st = rad_solve_method_parse(o->method, &p->method)) != RAD_OK)
        return st;
    if ((st = refuse_others(o, p->method)) != RAD_OK)
        return st;
    if (o->threads &&
        (st = cli_parse_positive_int("solve: --threads", o->threads, 1024, &p->threads)) != RAD_OK)
        return st;
    st = p->method == RAD_SOLVE_HIER || p->method == RAD_SOLVE_CLUSTER ? parse_hier(o, p)
         : p->method == RAD_SOLVE_MC ? parse_mc(o, p)
                                     : parse_dense(o, p);
    if (st != RAD_OK)
        return st;
    if (o->basis && rad_basis_parse(o->basis, &p->basis) != RAD_OK)
        return RAD_ERROR(RAD_EINVAL, "solve: --basis must be p0, p1 or p2, got '%s'", o->basis);
    /* hierp's steps stay plain: a mixed solve could settle on the fixed
       point of a mode its quadrature leaves non-contracting, which its
       solve finds by the change that stalls (hierp/solve.c) */
    if (o->anderson && p->basis > 0)
        return RAD_ERROR(RAD_EINVAL, "solve: --anderson applies to --basis p0 only (p%d's "
                                     "steps are plain Jacobi)", p->basis);
    p->display = o->ply || o->png;
    p->edges = o->edges;
    return RAD_OK;
}
