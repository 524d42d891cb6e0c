# time_to_target.awk: what a method needs to reach an error target, from a
# table of runs (experiments/hierarchical, experiments/bases,
# bench/instructions.sh).
#
#   awk -F'\t' -v m=METHOD -v mc=C -v ec=C -v tc=C -v kc=C -v g=GOAL \
#       -f scripts/time_to_target.awk TABLE
#
# The rows whose column mc is m give an error (column ec) and a cost (column
# tc: seconds or instructions).  Sorted by cost, the runs that lower the
# error below every cheaper run's make the method's frontier: the best error
# each cost buys.  Printed, tab-separated: the cost at which the frontier
# crosses g, log-log interpolated between the frontier runs on either side
# ("none" when no run reaches g; the first run's cost when it is already
# below), the cost of the cheapest run that reaches g, and that run's
# column kc ("-" when none).  Interpolating only between neighbours on the
# frontier keeps a slow, less accurate run in between from being skipped.
$mc == m { n++; e[n] = $ec + 0; t[n] = $tc + 0; k[n] = $kc }
END {
    for (i = 2; i <= n; i++) { # insertion sort by cost, stable
        te = e[i]; tt = t[i]; tk = k[i]
        for (j = i - 1; j >= 1 && t[j] > tt; j--) { e[j + 1] = e[j]; t[j + 1] = t[j]; k[j + 1] = k[j] }
        e[j + 1] = te; t[j + 1] = tt; k[j + 1] = tk
    }
    best = "none"; first = "none"; key = "-"; have = 0
    for (i = 1; i <= n; i++) {
        if (have && e[i] >= emin)
            continue
        if (e[i] <= g) {
            first = t[i]; key = k[i]
            if (!have)
                best = t[i]
            else if (e[i] > 0 && t[i] > 0 && tprev > 0) {
                f = log(emin / g) / log(emin / e[i])
                best = exp(log(tprev) + f * log(t[i] / tprev))
            } else
                best = t[i]
            break
        }
        have = 1; emin = e[i]; tprev = t[i]
    }
    printf "%s\t%s\t%s\n", best, first, key
}
