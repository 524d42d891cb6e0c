#!/bin/sh
# radkit over MPI ranks on this machine (papers/scaling.md), OMP_NUM_THREADS=1
# so that a rank is a core; this machine has 2, so 4 ranks oversubscribe it.
#  dense: the Cornell box at refinements 2 and 3 on 1, 2 and 4 ranks, wall
#    time per phase and peak memory per rank (data/scaling.dat);
#  hier: strong scaling of hierarchical runs (data/hier_scaling.dat): the
#    Cornell box with hier at eps 0.01 and 0.002 and the room of 64 cubes
#    with cluster at eps 0.1, on 1, 2 and 4 ranks, the gather shared (the
#    default) and, on 2 and 4 ranks, replicated; each run REPEAT times (default 3), the
#    fastest kept, with the machine's load average beside it (other work on
#    the machine slows a run down, never speeds it up) and the processor
#    time of each rank's work outside the exchanges, which that other work
#    does not inflate.  Every table must equal the 1-rank table (the script
#    stops otherwise).
#  weak: weak scaling, the problem grown with the ranks so that each rank's
#    share of the work stays about the same (data/weak_scaling.dat): dense
#    on rooms of 16, 24, 33 boxes (204, 300, 408 triangles: n^2 pairs in
#    the ratios 1 : 2.2 : 4.0) on 1, 2, 4 ranks, and hier on the Cornell box
#    at eps 0.03, 0.01, 0.004 (48.7k, 101k, 189k links: 1 : 2.1 : 3.9); the
#    efficiency is the 1-rank processor time per unit of work over the
#    busiest rank's time per unit of its share (pairs or links / ranks).
# PARTS="dense hier weak" (default) selects the parts.  Builds radkit-mpi with
# `make mpi` (Open MPI and ScaLAPACK from Debian) when it is missing.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
RADKIT=${RADKIT:-$root/build/radkit}
case "$RADKIT" in /*) ;; *) RADKIT=$(pwd)/$RADKIT;; esac
MPI=$(dirname "$RADKIT")/radkit-mpi
PARTS=${PARTS:-dense hier weak}
REPEAT=${REPEAT:-3}
cd "$root"
[ -x "$MPI" ] || make --no-print-directory mpi BUILD="$(dirname "$RADKIT")" >/dev/null
mkdir -p "$here/data"
field() { sed -n "s/^# $1 = //p" "$2"; }
case " $PARTS " in *" dense "*)
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
;; esac

case " $PARTS " in *" hier "*)
dat=$here/data/hier_scaling.dat
{
  echo "# experiment = scaling: radkit-mpi --method hier|cluster, 1-4 ranks on one $(nproc)-core machine"
  echo "# generator = $("$RADKIT" --version); OMP_NUM_THREADS=1 per rank; the fastest of $REPEAT runs"
  echo "# link_s, refine_s, solve_s: phases (the slowest rank's view is rank 0's: every phase ends in a collective);"
  echo "# comm_s: the exchanges, a part of them; speedup: the 1-rank total over this total;"
  echo "# load: the 1-minute load average before the run (other work on the machine)"
  echo "# work_max_s, work_sum_s: processor time of the solve outside the exchanges, the largest rank's and"
  echo "# the sum over ranks (other work on the machine does not inflate it); work_speedup: the 1-rank work"
  echo "# over work_max_s"
  printf "scene\tmethod\teps\telements\tlinks\tranks\tgather\tlink_s\trefine_s\tsolve_s\tcomm_s\ttotal_s\tspeedup\twork_max_s\twork_sum_s\twork_speedup\tmemory_peak_bytes_per_rank\tload\n"
} > "$dat"
for case in "cornell hier 0.01 scenes/cornell/cornell.obj" "cornell hier 0.002 scenes/cornell/cornell.obj" \
            "many_64 cluster 0.1 scenes/many_objects/many_64.obj"; do
  set -- $case
  name=$1 method=$2 eps=$3 scene=$4
  base= base_work=
  for run in "1 shared" "2 shared" "2 replicated" "4 shared" "4 replicated"; do
    np=${run% *} gather=${run#* }
    out=$here/data/${name}_${method}_eps${eps}_np${np}_$gather.tsv
    best=
    for k in $(seq "$REPEAT"); do
      load=$(cut -d' ' -f1 /proc/loadavg)
      OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np "$np" "$MPI" solve "$scene" \
        --method "$method" --eps "$eps" --gather "$gather" --quiet --out "$out.tmp"
      t=$(field time_total_s "$out.tmp")
      if [ -z "$best" ] || awk -v a="$t" -v b="$best" 'BEGIN { exit !(a < b) }'; then
        best=$t; bestload=$load; mv "$out.tmp" "$out"
      else rm -f "$out.tmp"; fi
    done
    [ -n "$base" ] || base=$best
    work=$(field cpu_work_max_rank_s "$out")
    [ -n "$base_work" ] || base_work=$work
    comm=$(field time_comm_s "$out")
    ref=$here/data/${name}_${method}_eps${eps}_np1_shared.tsv
    grep -v '^#' "$ref" > "$out.a"
    grep -v '^#' "$out" > "$out.b"
    cmp -s "$out.a" "$out.b" || { echo "scaling: $out differs from the 1-rank table" >&2; exit 1; }
    rm -f "$out.a" "$out.b"
    printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%.2f\t%s\t%s\t%.2f\t%s\t%s\n" "$name" "$method" \
      "$eps" "$(field elements "$out")" "$(field links "$out")" "$np" "$gather" \
      "$(field time_link_s "$out")" "$(field time_refine_s "$out")" "$(field time_solve_s "$out")" \
      "${comm:-0}" "$best" "$(echo "$base $best" | awk '{print $1 / $2}')" "$work" \
      "$(field cpu_work_sum_s "$out")" "$(echo "$base_work $work" | awk '{print $1 / $2}')" \
      "$(field memory_peak_bytes_per_rank "$out")" "$bestload" >> "$dat"
    echo "$name $method eps $eps, $np ranks, gather $gather: total $best s (load $bestload)"
  done
done
echo "scaling: $dat written"
;; esac

case " $PARTS " in *" weak "*)
dat=$here/data/weak_scaling.dat
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp scenes/many_objects/many_objects.mtl "$tmp/"
{
  echo "# experiment = weak scaling: radkit-mpi, the problem grown with the ranks, 1-4 ranks on one $(nproc)-core machine"
  echo "# generator = $("$RADKIT" --version); OMP_NUM_THREADS=1 per rank; the fastest of $REPEAT runs"
  echo "# work: pairs n (n - 1) / 2 (dense) or links (hier); work_max_s: the busiest rank's processor time"
  echo "# outside the exchanges (hier) or its total time (dense, whose ranks run no other work);"
  echo "# efficiency: (1-rank time per unit of work) / (busiest rank's time per unit of its share);"
  echo "# dense on 4 ranks: wall time of 4 processes on $(nproc) cores, so at most $(nproc)/4 of the ideal"
  printf "method	case	ranks	elements	work	work_per_rank	total_s	work_max_s	efficiency	memory_peak_bytes_per_rank	load
"
} > "$dat"
base_rate=
for run in "dense 16 1" "dense 24 2" "dense 33 4" "hier 0.01 1" "hier 0.006 2" "hier 0.003 4"; do
  set -- $run
  method=$1 size=$2 np=$3
  if [ "$method" = dense ]; then
    [ "$np" = 1 ] && base_rate=
    python3 scenes/gen/many_objects.py "$size" > "$tmp/boxes_$size.obj"
    args="$tmp/boxes_$size.obj"
  else
    [ "$np" = 1 ] && base_rate=
    args="scenes/cornell/cornell.obj --method hier --eps $size"
  fi
  best=
  for k in $(seq "$REPEAT"); do
    load=$(cut -d' ' -f1 /proc/loadavg)
    # shellcheck disable=SC2086
    OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -np "$np" "$MPI" solve $args \
      --quiet --out "$tmp/t.tsv"
    t=$(field time_total_s "$tmp/t.tsv")
    if [ -z "$best" ] || awk -v a="$t" -v b="$best" 'BEGIN { exit !(a < b) }'; then
      best=$t; bestload=$load; mv "$tmp/t.tsv" "$tmp/best.tsv"
    fi
  done
  n=$(field elements "$tmp/best.tsv")
  if [ "$method" = dense ]; then
    work=$(echo "$n" | awk '{printf "%.0f", $1 * ($1 - 1) / 2}')
    busy=$best
  else
    work=$(field links "$tmp/best.tsv")
    busy=$(field cpu_work_max_rank_s "$tmp/best.tsv")
  fi
  rate=$(echo "$busy $work $np" | awk '{print $1 / ($2 / $3)}')
  [ -n "$base_rate" ] || base_rate=$rate
  printf "%s\t%s\t%s\t%s\t%s\t%.0f\t%s\t%s\t%.2f\t%s\t%s\n" "$method" "$size" "$np" "$n" "$work" \
    "$(echo "$work $np" | awk '{print $1 / $2}')" "$best" "$busy" \
    "$(echo "$base_rate $rate" | awk '{print $1 / $2}')" \
    "$(field memory_peak_bytes_per_rank "$tmp/best.tsv")" "$bestload" >> "$dat"
  echo "weak: $method $size on $np ranks: total $best s (load $bestload)"
done
echo "scaling: $dat written"
;; esac
