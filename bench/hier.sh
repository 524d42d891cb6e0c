#!/bin/sh
# bench/hier.sh RADKIT: the hierarchical-radiosity targets of issue 6 on the
# Cornell box, from the runs of experiments/hierarchical/run.sh (which it
# runs): the wall time each method needs for 1% relative L2 error of the face
# radiosity against the common reference (log-log interpolation between the
# two runs that bracket 1%, and the fastest run under 1%), hier's speed-up over
# the faster dense configuration (target: >= 10), and the exponent of links against leaves as eps shrinks
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
  echo "# time_to_1pct_s: wall time (median of 3 runs) to reach 1% error, interpolated between the runs that bracket it"
  echo "# first_run_under_1pct_s: the fastest run that reaches 1% (dense can only refine 1 -> 4)"
  echo "# speedup: the faster dense method's time / this method's time (target for hier: >= 10)"
  printf 'method\ttime_to_1pct_s\tfirst_run_under_1pct_s\tspeedup\tspeedup_first_run\n'
  awk -F'\t' 'NR > 1 { t[$1] = $2; f[$1] = $3; m[++n] = $1
      if ($1 ~ /^dense/ && $2 != "none" && (bd == "" || $2 + 0 < bd)) bd = $2 + 0
      if ($1 ~ /^dense/ && $3 != "none" && (bf == "" || $3 + 0 < bf)) bf = $3 + 0 }
    END { for (i = 1; i <= n; i++) {
            k = m[i]; s = (t[k] != "none" && t[k] > 0) ? bd / t[k] : 0
            sf = (f[k] != "none" && f[k] > 0) ? bf / f[k] : 0
            printf "%s\t%s\t%s\t%.2f\t%.2f\n", k, t[k], f[k], s, sf } }' "$data/target.dat"
  echo "# links ~ leaves^slope as eps shrinks (target <= 1.1)"
  cat "$data/slopes.dat"
} > "$TSV"
cat "$TSV"
