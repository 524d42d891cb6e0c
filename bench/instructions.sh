#!/bin/sh
# bench/instructions.sh RADKIT: the instructions hier p0 and p1 spend to
# reach 0.25% L1 on the Cornell box (issue 16's race), counted by callgrind
# on one thread.  Wall time on a shared machine swings by 20-50% from hour to
# hour; the count repeats to 0.1%, so it compares builds and bases where the
# timings cannot.  For each basis, the runs at the eps that bracket 0.25%
# (p0: 0.039 .. 0.022, p1: 0.27 .. 0.15, the E12 steps of experiments/bases;
# BENCH_P0_EPS, BENCH_P1_EPS), their L1
# against the Monte Carlo reference, and the count at 0.25% interpolated
# log-log as experiments/bases does for time (scripts/time_to_target.awk).  Valgrind is installed when
# missing (scripts/deps.sh); CGAL's check of the rounding mode fails under
# valgrind, so a build with that check off is made beside RADKIT's
# (build/vg).  Writes bench/instructions.tsv and prints it.
set -eu
RADKIT=${1:?usage: bench/instructions.sh path/to/radkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
TSV="$ROOT/bench/instructions.tsv"
P0_EPS=${BENCH_P0_EPS:-"0.039 0.033 0.027 0.022"}
P1_EPS=${BENCH_P1_EPS:-"0.27 0.22 0.18 0.15"}
GOAL=0.0025
sh "$ROOT/scripts/deps.sh" valgrind
(cd "$ROOT" && CXXFLAGS=-DCGAL_DISABLE_ROUNDING_MATH_CHECK make -s BUILD=build/vg build/vg/radkit)
VG="$ROOT/build/vg/radkit"
scene="$ROOT/scenes/cornell/cornell.obj"
ref="$ROOT/experiments/reference/data/cornell.tsv"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
runs="$tmp/runs"
: > "$runs"
for basis in p0 p1; do
  if [ "$basis" = p0 ]; then list=$P0_EPS; else list=$P1_EPS; fi
  for eps in $list; do
    valgrind --tool=callgrind --callgrind-out-file="$tmp/cg.out" "$VG" solve "$scene" \
      --method hier --basis "$basis" --eps "$eps" --threads 1 --quiet --out "$tmp/out.tsv" \
      2> "$tmp/vg.log"
    ir=$(sed -n 's/.*Collected : //p' "$tmp/vg.log")
    [ -n "$ir" ] || { cat "$tmp/vg.log" >&2; echo "instructions: no count for $basis eps $eps" >&2; exit 1; }
    l1=$("$RADKIT" compare "$scene" "$tmp/out.tsv" "$ref" | sed -n 's/^# error_l1 = //p')
    printf "%s\t%s\t%s\t%s\n" "$basis" "$eps" "$l1" "$ir" >> "$runs"
  done
done
{
  echo "# instructions bench: $("$RADKIT" --version), Cornell box, hier, callgrind (one thread, --threads 1)"
  echo "# per run: L1 against the Monte Carlo reference and the instructions; at_0.25pct: log-log interpolated between the neighbours on the frontier of error against instructions that bracket it (scripts/time_to_target.awk)"
  printf "basis\teps\terror_l1\tinstructions\n"
  cat "$runs"
  printf "basis\tinstructions_at_0.25pct\n"
  for basis in p0 p1; do
    awk -F'\t' -v m="$basis" -v mc=1 -v ec=3 -v tc=4 -v kc=2 -v g="$GOAL" \
      -f "$ROOT/scripts/time_to_target.awk" "$runs" |
      awk -F'\t' -v m="$basis" '{ printf "%s\t%s\n", m, $1 == "none" ? "none" : sprintf("%.4g", $1) }'
  done
} > "$TSV"
cat "$TSV"
