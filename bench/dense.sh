#!/bin/sh
# bench/dense.sh RADKIT: LU GFLOP/s of rad_dense_lu_solve vs LAPACKE_dgesv on the
# same matrix, n = 1000, 2000, 4000 (DENSE_BENCH_SIZES overrides), OpenBLAS
# threads 1 and 2.  Writes bench/dense.tsv and prints it.
set -eu
RADKIT=${1:?usage: bench/dense.sh path/to/radkit}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
LIBDIR=$(cd "$(dirname "$RADKIT")" && pwd)
OUT="$LIBDIR/bench"
mkdir -p "$OUT"
INC=$(for d in "$ROOT"/core/*/; do printf ' -I%s' "$d"; done)
cc -std=c11 -O2 -fopenmp -D_POSIX_C_SOURCE=200809L $INC "$ROOT/bench/dense_bench.c" \
   "$LIBDIR/libradkit.a" -lembree3 -lpng -llapacke -lopenblas -lm -o "$OUT/dense_bench"
SIZES=${DENSE_BENCH_SIZES:-1000 2000 4000}
LARGE=${DENSE_BENCH_LARGE:-10000 20000}   # one run each: a 20000 solve takes minutes
TSV="$ROOT/bench/dense.tsv"
echo "# dense bench: LU solve (2/3 n^3 + 2 n^2 flops), best of 3 ($LARGE: one run), rad_dense_lu_solve vs LAPACKE_dgesv; $(sh "$ROOT/scripts/machine.sh")" > "$TSV"
first=1
for t in 1 2; do
  if [ $first = 1 ]; then
    OPENBLAS_NUM_THREADS=$t OMP_NUM_THREADS=$t "$OUT/dense_bench" $SIZES >> "$TSV"
    first=0
  else
    OPENBLAS_NUM_THREADS=$t OMP_NUM_THREADS=$t "$OUT/dense_bench" $SIZES | tail -n +2 >> "$TSV"
  fi
done
if [ -n "$LARGE" ]; then
  for t in 1 2; do
    DENSE_BENCH_REPS=1 OPENBLAS_NUM_THREADS=$t OMP_NUM_THREADS=$t "$OUT/dense_bench" $LARGE | tail -n +2 >> "$TSV"
  done
fi
cat "$TSV"
