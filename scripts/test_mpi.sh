#!/bin/sh
# make test-mpi: radkit-mpi on 1, 2 and 4 ranks of this machine against the
# serial program's tables (every face and channel within 1e-9 relative), on
# a convex furnace (no visibility), the occluder and the Cornell box (exact
# visibility), with the default block and a small one (many blocks per
# rank); the per-rank peak memory of a larger run falling with the ranks; and
# bad input refused once, with exit 2, by every rank.
# usage: scripts/test_mpi.sh RADKIT RADKIT_MPI
set -u
RADKIT=${1:?usage: test_mpi.sh RADKIT RADKIT_MPI}
MPI=${2:?usage: test_mpi.sh RADKIT RADKIT_MPI}
cd "$(dirname "$0")/.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() { # ranks args...
  np=$1; shift
  OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np "$np" "$MPI" solve "$@"
}
fails=0
check() { # name serial mpi
  grep -v '^#' "$2" > "$tmp/a.rows"
  grep -v '^#' "$3" > "$tmp/b.rows"
  worst=$(paste "$tmp/a.rows" "$tmp/b.rows" | awk -F'\t' '$1 != "face" {
      for (c = 3; c <= 5; c++) { d = $c - $(c + 5); if (d < 0) d = -d;
        r = ($c > 0) ? d / $c : d; if (r > m) m = r } n++ }
      END { if (n == 0) print "none"; else printf "%.3g", m }' )
  ok=$(echo "$worst" | awk '$1 != "none" && $1 + 0 <= 1e-9 { print "ok" }')
  [ "$ok" = ok ] || fails=$((fails + 1))
  printf '%-50s max relative difference %s %s\n' "$1" "$worst" "${ok:-FAIL}"
}
for case in "scenes/furnace_cube/cube.obj --rho 0.9 --emission 1" "scenes/occluder/occluder.obj" \
            "scenes/cornell/cornell.obj --refine 1"; do
  # shellcheck disable=SC2086
  "$RADKIT" solve $case --quiet --out "$tmp/serial.tsv" || { echo "serial run failed: $case"; exit 1; }
  for np in 1 2 4; do
    for block in 64 8; do
      # shellcheck disable=SC2086
      if run "$np" $case --block "$block" --quiet --out "$tmp/mpi.tsv"; then
        check "$case, $np ranks, block $block" "$tmp/serial.tsv" "$tmp/mpi.tsv"
      else
        echo "FAIL: $case, $np ranks, block $block: exit $?"; fails=$((fails + 1))
      fi
    done
  done
done
# memory: the Cornell box at refine 3 (2432 elements, a 47 MB matrix)
for np in 1 4; do
  run "$np" scenes/cornell/cornell.obj --refine 3 --quiet --out "$tmp/mem$np.tsv" || fails=$((fails + 1))
done
m1=$(sed -n 's/^# memory_peak_bytes_per_rank = //p' "$tmp/mem1.tsv")
m4=$(sed -n 's/^# memory_peak_bytes_per_rank = //p' "$tmp/mem4.tsv")
echo "peak memory per rank, Cornell refine 3: 1 rank $m1 bytes, 4 ranks $m4 bytes"
awk -v a="$m1" -v b="$m4" 'BEGIN { exit !(a > 0 && b > 0 && a - b > 0.6 * 2 * 8 * 2432 * 2432 * 0.75) }' ||
  { echo "FAIL: 4 ranks should hold about a quarter of the matrices each"; fails=$((fails + 1)); }
check "cornell refine 3, 4 ranks against 1" "$tmp/mem1.tsv" "$tmp/mem4.tsv"
# the stats: top-level ranks and the largest rank's memory
run 4 scenes/occluder/occluder.obj --quiet --out "$tmp/s.tsv" --stats "$tmp/s.json" || fails=$((fails + 1))
if grep -q '"ranks": 4' "$tmp/s.json" && grep -q '"memory_peak_bytes_per_rank"' "$tmp/s.json"; then
  echo "stats: ranks and memory per rank: ok"
else echo "FAIL: stats lack ranks or memory_peak_bytes_per_rank"; fails=$((fails + 1)); fi
# bad input: one message, exit 2
out=$(run 2 "$tmp/missing.obj" 2>&1); code=$?
lines=$(printf '%s\n' "$out" | grep -c '^radkit: ')
if [ "$code" -eq 2 ] && [ "$lines" -eq 1 ]; then echo "missing scene: exit 2, one message: ok"
else echo "FAIL: missing scene: exit $code, $lines messages"; fails=$((fails + 1)); fi
echo "test-mpi: $fails failed"
[ "$fails" -eq 0 ]
