#!/bin/sh
# Benchmark of the 1D model problem: assembly and LU-solve time and rate against
# n, for exact and gauss:4 assembly, P0 and P1, with 1 and 2 OpenBLAS threads.
# Writes bench/galerkin1d.tsv.  The solve's flop count is 2/3 n^3 (dgetrf) +
# 2 n^2 (dgetrs), reported as GFLOP/s.
set -eu
RADKIT=${1:-build/radkit}
out=$(dirname "$0")/galerkin1d.tsv
{
  echo "# bench = galerkin1d; generator = $("$RADKIT" --version); machine = $(sh "$(dirname "$0")/../scripts/machine.sh")"
  echo "# times are the best of 3 runs"
  printf 'basis\tassembly\tn\tthreads\tassemble_s\tsolve_s\tsolve_gflops\tentries_per_s\n'
} > "$out"
for basis in p0 p1; do
  for assembly in exact gauss:4; do
    for n in 512 1024 2048 4096; do
      for threads in 1 2; do
        best=""
        for rep in 1 2 3; do
          line=$(OPENBLAS_NUM_THREADS=$threads "$RADKIT" galerkin1d --n "$n" --basis "$basis" \
                   --assembly "$assembly" --no-check |
                 awk -F' = ' '/^# assemble_s/{a=$2} /^# solve_s/{s=$2} END{print a, s}')
          best=$(printf '%s\n%s\n' "$best" "$line" | awk 'NF==2 && (min=="" || $1+$2 < min) {min=$1+$2; l=$0} END{print l}')
        done
        echo "$best" | awk -v b="$basis" -v a="$assembly" -v n="$n" -v t="$threads" '{
          dim = (b == "p1") ? n + 1 : n
          fl = 2.0 / 3.0 * dim^3 + 2.0 * dim^2
          printf "%s\t%s\t%d\t%d\t%.4f\t%.4f\t%.2f\t%.3g\n", b, a, n, t, $1, $2,
                 ($2 > 0 ? fl / $2 / 1e9 : 0), ($1 > 0 ? dim * dim / $1 : 0) }' >> "$out"
      done
    done
  done
done
grep -v "^#" "$out" | column -t -s "$(printf '\t')"
