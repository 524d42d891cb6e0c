#!/bin/sh
# bench/hier.sh RADKIT: hierarchical radiosity's speed to accuracy on the
# Cornell box (issue 13's targets), from the runs of
# experiments/hierarchical/run.sh (which it runs), all measured against the
# Monte Carlo reference (area-weighted L1 error of the face radiosity over the
# mean reflected radiosity):
#  - the wall time each method needs for 1%, 0.5% and 0.1% (log-log
#    interpolation between the two runs that bracket it), the fastest run that
#    reaches it and that run's links (pairs; an implementation with one-way
#    links needs two per pair).  Targets for hier: 1% in 0.02 s, 0.5% in
#    0.05 s with under 25k one-way links; the same for the error oracle
#    with --basis p1 and p2 (hier-error-p1, -p2);
#  - the fastest hier run reaching 0.5% against dense at refinement 3 (auto),
#    side by side (target: at most 1/40 of its time);
#  - the exponent of links against leaves as eps goes from 0.1 to 0.003
#    (target: <= 1.25).
# Writes bench/hier.tsv and prints it.  REUSE=1 takes the data of the last
# run of the experiment instead of running it again (same binary assumed).
set -eu
RADKIT=${1:?usage: bench/hier.sh path/to/radkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
TSV="$ROOT/bench/hier.tsv"
[ "${REUSE:-0}" = 1 ] || RADKIT="$RADKIT" sh "$ROOT/experiments/hierarchical/run.sh" >/dev/null
data="$ROOT/experiments/hierarchical/data"
{
  echo "# hier bench: $("$RADKIT" --version), Cornell box against the Monte Carlo reference, $(sh "$ROOT/scripts/machine.sh"); from experiments/hierarchical"
  echo "# time_s: wall time (median of 5 runs) to reach the target L1 error, interpolated between the runs that bracket it"
  echo "# first_run_s, first_run_links: the fastest run that reaches it, and its links (pairs)"
  cat "$data/target.dat"
  echo "# the fastest hier run reaching 0.5% against dense --refine 3 (auto), side by side (target: ratio <= 1/40 = 0.025)"
  printf 'hier_first_run_0.5pct_s\tdense_refine3_s\tratio\n'
  awk -F'\t' '
    FNR == NR { if ($1 == "hier-error" && $2 == 0.005) h = $4; next }
    $1 == "dense-auto" && $2 == 3 { d = $6 }
    END { if (h == "" || h == "none" || d == "") printf "%s\t%s\tnone\n", h, d
          else printf "%s\t%s\t%.4f\n", h, d, h / d }' "$data/target.dat" "$data/runs.dat"
  echo "# links ~ leaves^slope as eps shrinks from 0.1 to 0.003 (target <= 1.25)"
  cat "$data/slopes.dat"
} > "$TSV"
cat "$TSV"
