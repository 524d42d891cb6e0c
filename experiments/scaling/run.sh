#!/bin/sh
# Dense radiosity over MPI ranks on this machine (papers/scaling.md): the
# Cornell box at refinements 2 and 3 on 1, 2 and 4 ranks (OMP_NUM_THREADS=1,
# so a rank is a core; this machine has 2, so 4 ranks oversubscribe it),
# wall time per phase and peak memory per rank.  Builds radkit-mpi with
# `make mpi` (Open MPI and ScaLAPACK from Debian) when it is missing.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
RADKIT=${RADKIT:-$root/build/radkit}
case "$RADKIT" in /*) ;; *) RADKIT=$(pwd)/$RADKIT;; esac
MPI=$(dirname "$RADKIT")/radkit-mpi
cd "$root"
[ -x "$MPI" ] || make --no-print-directory mpi BUILD="$(dirname "$RADKIT")" >/dev/null
mkdir -p "$here/data"
dat=$here/data/scaling.dat
{
  echo "# experiment = scaling: radkit-mpi on the Cornell box, 1-4 ranks on one $(nproc)-core machine"
  echo "# generator = $("$RADKIT" --version); OMP_NUM_THREADS=1 per rank"
  echo "# matrix_bytes_per_rank: 8 n^2 / ranks (one of the two n x n arrays each rank holds)"
  printf "refine\telements\tranks\tassemble_s\tsolve_s\ttotal_s\tmemory_peak_bytes_per_rank\tmatrix_bytes_per_rank\n"
} > "$dat"
for r in 2 3; do
  for np in 1 2 4; do
    out=$here/data/cornell_r${r}_np$np.tsv
    OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np "$np" "$MPI" solve \
      scenes/cornell/cornell.obj --refine "$r" --quiet --out "$out"
    el=$(sed -n 's/^# elements = //p' "$out")
    a=$(sed -n 's/^# time_assemble_s = //p' "$out")
    s=$(sed -n 's/^# time_solve_s = //p' "$out")
    t=$(sed -n 's/^# time_total_s = //p' "$out")
    m=$(sed -n 's/^# memory_peak_bytes_per_rank = //p' "$out")
    printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%.0f\n" "$r" "$el" "$np" "$a" "$s" "$t" "$m" \
      "$(echo "$el $np" | awk '{print 8 * $1 * $1 / $2}')" >> "$dat"
    echo "refine $r, $np ranks: total $t s, peak $m bytes per rank"
  done
done
echo "scaling: $dat written"
