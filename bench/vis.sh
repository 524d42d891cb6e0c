#!/bin/sh
# bench/vis.sh RADKIT: rays/s of rad_vis vs Embree's own rtcOccluded1 on the
# same rays, 1 and 2 threads.  Builds bench/vis_bench.c against the library
# next to the radkit binary; writes bench/vis.tsv and prints it.
set -eu
RADKIT=${1:?usage: bench/vis.sh path/to/radkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
LIBDIR=$(cd "$(dirname "$RADKIT")" && pwd)
OUT="$LIBDIR/bench"
mkdir -p "$OUT"
INC=$(for d in "$ROOT"/core/*/; do printf ' -I%s' "$d"; done)
cc -std=c11 -O2 -fopenmp -D_POSIX_C_SOURCE=200809L $INC "$ROOT/bench/vis_bench.c" \
   "$LIBDIR/libradkit.a" -lembree3 -lpng -llapacke -lopenblas -lm -o "$OUT/vis_bench"
RAYS=${VIS_BENCH_RAYS:-2000000}
{ echo "# machine: $(sh "$ROOT/scripts/machine.sh")"; OMP_PROC_BIND=false "$OUT/vis_bench" "$RAYS"; } > "$ROOT/bench/vis.tsv"
cat "$ROOT/bench/vis.tsv"
