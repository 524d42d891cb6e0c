#!/bin/sh
# make test-mpi: radkit-mpi on 1, 2 and 4 ranks of this machine against the
# serial program's tables (every face and channel within 1e-9 relative), on
# a convex furnace (no visibility), the occluder and the Cornell box (exact
# visibility): dense with the default block and a small one (many blocks per
# rank), and the per-rank peak memory of a larger run falling with the ranks;
# hier on the same scenes and cluster on a room of 8 cubes, with the gather
# shared and replicated, one case on 2 threads per rank, every header figure
# but the times equal to the serial run's, and a failure on one rank alone
# agreed; bad input refused once, with exit 2, by every rank.
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
# compare serial mpi: the largest relative difference of a B column over the
# rows (faces) of two tables, "none" when there are no rows or their counts or
# face numbers differ; exit 0 when it is within 1e-9.
compare() {
  grep -v '^#' "$1" > "$tmp/a.rows"
  grep -v '^#' "$2" > "$tmp/b.rows"
  worst=$(paste "$tmp/a.rows" "$tmp/b.rows" | awk -F'\t' '
      NF != 10 || $1 != $6 { bad = 1 }
      $1 != "face" { for (c = 3; c <= 5; c++) { d = $c - $(c + 5); if (d < 0) d = -d;
        r = ($c > 0) ? d / $c : d; if (r > m) m = r } n++ }
      END { if (n == 0 || bad) print "none"; else printf "%.3g", m }' )
  echo "$worst" | awk '$1 != "none" && $1 + 0 <= 1e-9 { ok = 1 } END { exit !ok }'
}
check() { # name serial mpi
  if compare "$2" "$3"; then ok=ok; else ok=FAIL; fails=$((fails + 1)); fi
  printf '%-50s max relative difference %s %s\n' "$1" "$worst" "$ok"
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
# ---- hierarchical runs (hier_mpi.c): link estimates dealt among the ranks,
# the gather shared by input triangles (the default) or replicated; every
# rank holds the whole hierarchy, so the tables must be the serial ones.
# Beyond the faces, every '#' line of the table but the times (wall and
# processor), memory and ranks (elements, links, rays, kernel_evals,
# iterations, the error estimates) must be the serial one: the work counters
# are summed over ranks.
headers() { grep '^#' "$1" | grep -v -e '^# time_' -e '^# memory_peak' -e '^# ranks' -e '^# gather' -e '^# cpu_work'; }
check_all() { # name serial mpi
  check "$1" "$2" "$3"
  if headers "$2" > "$tmp/h1" && headers "$3" > "$tmp/h2" && [ -s "$tmp/h1" ] && cmp -s "$tmp/h1" "$tmp/h2"
  then echo "$1: header lines (links, work, estimates) equal: ok"
  else echo "FAIL: $1: header lines differ:"; diff "$tmp/h1" "$tmp/h2" | head -5; fails=$((fails + 1)); fi
}
# the comparison itself must be able to fail: one face changed by 1e-6
"$RADKIT" solve scenes/cornell/cornell.obj --method hier --eps 0.1 --quiet --out "$tmp/h.tsv" ||
  { echo "serial hier run failed"; exit 1; }
awk -F'\t' 'BEGIN { OFS = "\t" } !/^#/ && $1 == "7" { $4 = $4 * (1 + 1e-6) } { print }' \
  "$tmp/h.tsv" > "$tmp/h_off.tsv"
if compare "$tmp/h.tsv" "$tmp/h_off.tsv"; then echo "FAIL: a face off by 1e-6 passes the comparison"
  fails=$((fails + 1)); else echo "the comparison catches a face off by 1e-6 ($worst): ok"; fi
if compare "$tmp/h.tsv" /dev/null; then echo "FAIL: an empty table passes the comparison"
  fails=$((fails + 1)); else echo "the comparison refuses an empty table: ok"; fi
python3 scenes/gen/many_objects.py 8 > "$tmp/many_8.obj"
cp scenes/many_objects/many_objects.mtl "$tmp/"
for case in "scenes/furnace_cube/cube.obj --rho 0.9 --emission 1 --method hier --eps 0.1" \
            "scenes/occluder/occluder.obj --method hier --eps 0.1" \
            "scenes/cornell/cornell.obj --method hier --eps 0.1" \
            "$tmp/many_8.obj --method cluster --eps 0.1"; do
  name=$(echo "$case" | sed "s|$tmp/||")
  # shellcheck disable=SC2086
  "$RADKIT" solve $case --quiet --out "$tmp/serial.tsv" || { echo "serial run failed: $case"; exit 1; }
  for np in 1 2 4; do
    # shellcheck disable=SC2086
    if run "$np" $case --quiet --out "$tmp/mpi.tsv"; then
      check_all "$name, $np ranks" "$tmp/serial.tsv" "$tmp/mpi.tsv"
    else
      echo "FAIL: $name, $np ranks: exit $?"; fails=$((fails + 1))
    fi
  done
  # shellcheck disable=SC2086
  if run 2 $case --gather replicated --quiet --out "$tmp/mpi.tsv"; then
    check_all "$name, 2 ranks, gather replicated" "$tmp/serial.tsv" "$tmp/mpi.tsv"
  else echo "FAIL: $name, gather replicated: exit $?"; fails=$((fails + 1)); fi
done
# two OpenMP threads per rank: the Cornell box at eps 0.03 (several
# refinement generations) against the serial run on one thread
"$RADKIT" solve scenes/cornell/cornell.obj --method hier --eps 0.03 --threads 1 --quiet \
  --out "$tmp/serial.tsv" || { echo "serial run failed"; exit 1; }
if OMP_NUM_THREADS=2 mpirun --allow-run-as-root --oversubscribe -np 2 "$MPI" solve \
     scenes/cornell/cornell.obj --method hier --eps 0.03 --quiet --out "$tmp/mpi.tsv" \
     --stats "$tmp/h.json"; then
  check_all "cornell hier eps 0.03, 2 ranks x 2 threads" "$tmp/serial.tsv" "$tmp/mpi.tsv"
else echo "FAIL: cornell hier eps 0.03, 2 ranks x 2 threads: exit $?"; fails=$((fails + 1)); fi
if grep -q '"ranks": 2' "$tmp/h.json" && grep -q '"memory_peak_bytes_per_rank"' "$tmp/h.json" &&
   grep -q '"comm"' "$tmp/h.json" && grep -q '"method": "hier"' "$tmp/h.json"; then
  echo "hier stats: ranks, memory per rank, comm time: ok"
else echo "FAIL: hier stats lack ranks, memory_peak_bytes_per_rank or the comm time"; fails=$((fails + 1)); fi
# a failure on rank 0 alone (its output path; the other ranks go on into
# the solve): agreed, one message, exit 2, no rank left waiting
out=$(timeout 300 mpirun --allow-run-as-root --oversubscribe -np 2 "$MPI" solve \
        scenes/cornell/cornell.obj --method hier --out "$tmp/no/such/dir/t.tsv" 2>&1); code=$?
lines=$(printf '%s\n' "$out" | grep -c '^radkit: ')
if [ "$code" -eq 2 ] && [ "$lines" -eq 1 ]; then echo "hier, rank 0 fails alone: exit 2, one message: ok"
else echo "FAIL: hier, rank 0 fails alone: exit $code, $lines messages"; printf '%s\n' "$out" | head -5
  fails=$((fails + 1)); fi
# bad input: one message, exit 2
out=$(run 2 "$tmp/missing.obj" 2>&1); code=$?
lines=$(printf '%s\n' "$out" | grep -c '^radkit: ')
if [ "$code" -eq 2 ] && [ "$lines" -eq 1 ]; then echo "missing scene: exit 2, one message: ok"
else echo "FAIL: missing scene: exit $code, $lines messages"; fails=$((fails + 1)); fi
echo "test-mpi: $fails failed"
[ "$fails" -eq 0 ]
