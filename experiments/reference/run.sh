#!/bin/sh
# Monte Carlo references for the study scenes (papers/monte-carlo.md): per
# input face, the area-average radiosity and its standard error by
# `radkit solve --method mc`, which shares nothing with the Galerkin solvers
# but the scene loader and Embree.  The other studies measure against these.
#
#   cornell   scenes/cornell/cornell.obj, SAMPLES_CORNELL paths per face: the
#             target is an area-weighted relative standard error (se_rel_l1)
#             of at most 1e-4 (about 12 minutes on 2 cores)
#   occluder  scenes/occluder/occluder.obj with every reflectance 0.5 (as
#             shipped everything is black and B = E)
#   many_64   scenes/many_objects/many_64.obj: 64 boxes in a lit room
#   lamp      scenes/lamp/lamp.obj: a small lamp in a dark open room
#   lamp_closed  scenes/lamp/lamp_closed.obj: a small emitting cube in a dark
#             closed room
#   many_27_rho99  scenes/many_objects/many_27_seed2.obj with every
#             reflectance 0.99: boxes 3 to 8 cm from the ceiling or the floor,
#             narrow gaps (about 12 minutes)
#   many_343  scenes/many_objects/many_343.obj: 343 boxes in a lit room (4 128
#             triangles), the clustering study's mid-size scene (about 6
#             minutes)
#   lattice   scenes/lattice/lattice.obj: a floor lit through an 8 x 8 lattice
#             of black cubes (SAMPLES_LATTICE paths per face, about 35 s)
#   slit      scenes/slit/slit.obj: 16 boxes lit through a slit between two
#             thin slabs (SAMPLES_SLIT paths per face, about 90 s)
#   many_1000 scenes/many_objects/many_1000.obj: 1 000 boxes in a lit room
#             (12 012 triangles), the clustering study's large scene with a
#             reference (SAMPLES_LARGE paths per face, about 5 minutes)
#
# Each table (data/<name>.tsv) starts with '# command = ...', the command that
# made it; a seed makes it reproducible bit for bit on any thread count, so a
# rerun changes only the timing lines.  data/summary.dat lists the figures.
# REFERENCE_SCALE=k divides every sample count by k (quick trial runs write
# to data/trial_*); SKIP_EXISTING=1 keeps tables already made with the same
# command.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
RADKIT=${RADKIT:-$root/build/radkit}
case "$RADKIT" in /*) ;; *) RADKIT=$(pwd)/$RADKIT;; esac
SCALE=${REFERENCE_SCALE:-1}
SAMPLES_CORNELL=${SAMPLES_CORNELL:-52428800}
SAMPLES_OCCLUDER=${SAMPLES_OCCLUDER:-4194304}
SAMPLES_MANY=${SAMPLES_MANY:-262144}
SAMPLES_GAPS=${SAMPLES_GAPS:-65536}
SAMPLES_LAMP=${SAMPLES_LAMP:-4194304}
SAMPLES_ROOM=${SAMPLES_ROOM:-131072}
SAMPLES_LARGE=${SAMPLES_LARGE:-32768}
SAMPLES_LATTICE=${SAMPLES_LATTICE:-400000}
SAMPLES_SLIT=${SAMPLES_SLIT:-1048576}
cd "$root"
mkdir -p "$here/data"
prefix=""
[ "$SCALE" = 1 ] || prefix=trial_

hdr() { sed -n "s/^# $2 = //p" "$1" | head -1; }

# reference NAME SAMPLES SCENE [scene options...]
reference() {
  name=$1; samples=$(( $2 / SCALE )); scene=$3; shift 3
  out=$here/data/$prefix$name.tsv
  cmd="radkit solve $scene --method mc --samples $samples --seed 1 $*"
  if [ "${SKIP_EXISTING:-0}" = 1 ] && [ -s "$out" ] && [ "$(hdr "$out" command)" = "$cmd" ]; then
    echo "reference: $name kept ($out)" >&2
    return
  fi
  echo "reference: $name: $cmd" >&2
  { echo "# command = $cmd"
    "$RADKIT" solve "$scene" --method mc --samples "$samples" --seed 1 "$@"
  } > "$out.part"
  mv "$out.part" "$out"
}

reference cornell "$SAMPLES_CORNELL" scenes/cornell/cornell.obj
reference occluder "$SAMPLES_OCCLUDER" scenes/occluder/occluder.obj --rho 0.5
reference many_64 "$SAMPLES_MANY" scenes/many_objects/many_64.obj
reference lamp "$SAMPLES_LAMP" scenes/lamp/lamp.obj
reference lamp_closed "$SAMPLES_LAMP" scenes/lamp/lamp_closed.obj
reference many_27_rho99 "$SAMPLES_GAPS" scenes/many_objects/many_27_seed2.obj --rho 0.99
reference many_343 "$SAMPLES_ROOM" scenes/many_objects/many_343.obj
reference many_1000 "$SAMPLES_LARGE" scenes/many_objects/many_1000.obj
reference lattice "$SAMPLES_LATTICE" scenes/lattice/lattice.obj
reference slit "$SAMPLES_SLIT" scenes/slit/slit.obj

dat=$here/data/${prefix}summary.dat
{
  echo "# experiment = reference: Monte Carlo references (radkit solve --method mc)"
  echo "# generator = $("$RADKIT" --version); machine = $(sh "$root/scripts/machine.sh")"
  echo "# se_rel_l1 = sum_f A_f sum_c se_fc / sum_f A_f sum_c (B_fc - E_fc): the area-weighted"
  echo "#   standard error relative to the area-weighted mean reflected radiosity"
  echo "# se_rel_max = the largest se_fc over that mean (per channel)"
  printf 'scene\tfaces\tsamples_per_face\tpaths\trays_per_path\tse_rel_l1\tse_rel_max\ttime_s\n'
  for name in cornell occluder many_64 lamp lamp_closed many_27_rho99 many_343 many_1000 lattice slit; do
    f=$here/data/$prefix$name.tsv
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$(hdr "$f" faces)" "$(hdr "$f" samples)" \
      "$(hdr "$f" paths)" "$(hdr "$f" rays_per_path)" "$(hdr "$f" se_rel_l1)" \
      "$(hdr "$f" se_rel_max)" "$(hdr "$f" time_total_s)"
  done
} > "$dat"
grep -v '^#' "$dat" | column -t
