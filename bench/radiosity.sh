#!/bin/sh
# bench/radiosity.sh RADKIT: dense radiosity end to end on the Cornell box at
# uniform refinements 1..MAX_REFINE (152 .. 9728 elements), OpenMP/OpenBLAS
# threads 1 and 2, in two configurations:
#   default  radkit's defaults: --rule auto --tol 1e-6 --solver lu
#   fast     --tol 1e-3 --solver cholesky (per-face radiosity within 1e-8 of
#            default on the 9728-element box; Cholesky does half LU's flops)
# Columns: assembly pairs/s, rays/s, solve GFLOP/s (3 channels x 2/3 n^3 for LU,
# x 1/3 n^3 for Cholesky; Cornell's reflectance is coloured) and wall time.
# Writes bench/radiosity.tsv and prints it.
set -eu
RADKIT=${1:?usage: bench/radiosity.sh path/to/radkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
MAX_REFINE=${MAX_REFINE:-4}
TSV="$ROOT/bench/radiosity.tsv"
tmp=$(mktemp)
case "$RADKIT" in /*) ;; *) RADKIT=$(pwd)/$RADKIT;; esac
cd "$ROOT" # scenes are named relative to the repository
{
  echo "# radiosity bench: $("$RADKIT" --version), Cornell box, $(sh "$ROOT/scripts/machine.sh")"
  echo "# pairs_per_s = unordered pairs / assembly seconds (rays included)"
  printf 'config\trefine\telements\tthreads\tpairs\tassemble_s\tpairs_per_s\trays\tMrays_per_s\tsolve_s\tsolve_GFLOP_per_s\ttotal_s\n'
} > "$TSV"
run() { # config refine threads options...
  config=$1 r=$2 t=$3; shift 3
  OMP_NUM_THREADS=$t OPENBLAS_NUM_THREADS=$t "$RADKIT" solve scenes/cornell/cornell.obj \
    --refine "$r" --threads "$t" --quiet --out "$tmp" "$@"
  awk -F' = ' -v c="$config" -v r="$r" -v t="$t" '/^# /{ v[substr($1, 3)] = $2 }
    END { n = v["elements"]; a = v["time_assemble_s"]; s = v["time_solve_s"]
          f = (v["solver"] == "cholesky") ? 1.0 / 3.0 : 2.0 / 3.0
          printf "%s\t%d\t%d\t%d\t%d\t%.3f\t%.3g\t%d\t%.2f\t%.3f\t%.1f\t%.3f\n", c, r, n, t, v["pairs"], a,
                 (a > 0 ? v["pairs"] / a : 0), v["rays"], (a > 0 ? v["rays"] / a / 1e6 : 0), s,
                 (s > 0 ? 3 * f * n * n * n / s / 1e9 : 0), v["time_total_s"] }' "$tmp" >> "$TSV"
}
for t in 1 2; do
  r=1
  while [ "$r" -le "$MAX_REFINE" ]; do
    run default "$r" "$t"
    run fast "$r" "$t" --tol 1e-3 --solver cholesky
    r=$((r + 1))
  done
done
rm -f "$tmp"
grep -v '^#' "$TSV" | column -t
