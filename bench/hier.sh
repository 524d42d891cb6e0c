#!/bin/sh
# bench/hier.sh RADKIT: the hierarchical-radiosity targets of issue 6 on the
# Cornell box, from the runs of experiments/hierarchical/run.sh (which it
# runs): the wall time each method needs for 1% relative L2 error of the face
# radiosity against the common reference (log-log interpolation between the
# two runs that bracket 1%), hier's speed-up over each dense configuration
# (target: >= 10), and the exponent of links against leaves as eps shrinks
# (target: <= 1.1), for eps >= 0.01 (before the leaves saturate at the minimum
# area) and over all runs.  Writes bench/hier.tsv and prints it.
set -eu
RADKIT=${1:?usage: bench/hier.sh path/to/radkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
TSV="$ROOT/bench/hier.tsv"
RADKIT="$RADKIT" sh "$ROOT/experiments/hierarchical/run.sh" >/dev/null
data="$ROOT/experiments/hierarchical/data"
{
  echo "# hier bench: $("$RADKIT" --version), Cornell box (occluded), $(nproc) cores; from experiments/hierarchical"
  echo "# time_to_1pct_s: wall time to reach 1% error (interpolated); speedup = dense time / hier time"
  printf 'method\ttime_to_1pct_s\tspeedup_of_hier_error\tspeedup_of_hier_bf\n'
  awk -F'\t' 'NR > 1 { t[$1] = $2; m[++n] = $1 }
    END { for (i = 1; i <= n; i++) {
            k = m[i]; se = (t["hier-error"] > 0 && t[k] != "none") ? t[k] / t["hier-error"] : 0
            sb = (t["hier-bf"] > 0 && t[k] != "none") ? t[k] / t["hier-bf"] : 0
            printf "%s\t%s\t%.2f\t%.2f\n", k, t[k], se, sb } }' "$data/target.dat"
  echo "# links ~ leaves^slope as eps shrinks (target <= 1.1)"
  cat "$data/slopes.dat"
} > "$TSV"
cat "$TSV"
