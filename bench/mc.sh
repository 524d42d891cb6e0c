#!/bin/sh
# bench/mc.sh RADKIT: Monte Carlo radiosity's paths per second against
# Embree's bare occlusion and closest-hit throughput on the same scenes, 1 and
# 2 threads.  Builds bench/mc_bench.c against the library next to the radkit
# binary; writes bench/mc.tsv and prints it.  Target (issue: Monte Carlo
# reference): ratio >= 0.5, i.e. paths per second within 2x of Embree's bare
# occlusion throughput divided by the mean path length in rays.
set -eu
RADKIT=${1:?usage: bench/mc.sh path/to/radkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
LIBDIR=$(cd "$(dirname "$RADKIT")" && pwd)
OUT="$LIBDIR/bench"
mkdir -p "$OUT"
INC=$(for d in "$ROOT"/core/*/; do printf ' -I%s' "$d"; done)
g++ -x c -std=c11 -O2 -fopenmp -D_POSIX_C_SOURCE=200809L $INC "$ROOT/bench/mc_bench.c" -x none \
   "$LIBDIR/libradkit.a" -lembree3 -lassimp -lpng -lgmp -lmpfr -llapacke -lopenblas -lm \
   -o "$OUT/mc_bench"
cd "$ROOT"
{
  echo "# radkit mc benchmark: $("$RADKIT" --version), $(sh "$ROOT/scripts/machine.sh")"
  for scene in scenes/cornell/cornell.obj scenes/furnace_room/room_27.obj; do
    OMP_PROC_BIND=false "$OUT/mc_bench" "$scene" "${MC_BENCH_RAYS:-4000000}" "${MC_BENCH_SAMPLES:-16384}"
  done
} > "$ROOT/bench/mc.tsv"
cat "$ROOT/bench/mc.tsv"
