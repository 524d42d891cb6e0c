#!/bin/sh
# What the accuracy radkit reports is worth (papers/accuracy.md).
#
# 1. Furnaces: closed scenes where every face emits E = 2.385 and reflects rho,
#    so B = E / (1 - rho) exactly on every face, whatever blocks what.  Two
#    convex enclosures, a room with a box, with a box 1 mm from a wall
#    (room_hair), with 27 boxes; rho 0.5, 0.9, 0.99; dense with default
#    settings (no refinement), hier with its defaults and with --eps 0.01.
#    Per run: the largest face error and the area-weighted mean error,
#    relative to E / (1 - rho), hier's own error_estimate on the same scale,
#    and the time.
# 2. Requested eps against achieved error on the Cornell box, against the
#    Monte Carlo reference (radkit compare): hier with the error oracle and
#    with BF over EPS, with its estimate (worst face, L1) beside the error
#    (worst face, L1), all relative to the mean reflected radiosity; dense at
#    refinements 0..2 for scale.
# Then figures/accuracy.{png,pdf}.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
RADKIT=${RADKIT:-$root/build/radkit}
case "$RADKIT" in /*) ;; *) RADKIT=$(pwd)/$RADKIT;; esac
EPS=${EPS:-"0.3 0.1 0.03 0.01 0.003"}
EPS_BF=${EPS_BF:-"0.3 0.1 0.03"}
cornell=scenes/cornell/cornell.obj
ref=experiments/reference/data/cornell.tsv
cd "$root"
[ -s "$ref" ] || RADKIT=$RADKIT sh experiments/reference/run.sh
cd "$here"
mkdir -p data figures
version=$("$RADKIT" --version)
hdr() { sed -n "s/^# $2 = //p" "$1" | head -1; }

# ---- 1. furnaces ----
fur=data/furnaces.dat
{
  echo "# experiment = accuracy: furnaces, B = E / (1 - rho) on every face"
  echo "# generator = $version; machine = $(sh "$root/scripts/machine.sh")"
  echo "# max_err, mean_err: largest face error and area-weighted mean error over E / (1 - rho);"
  echo "# estimate: hier's error_estimate (worst face) on the same scale (- for dense)"
  printf 'scene\trho\tmethod\tmax_err\tmean_err\testimate\ttime_s\telements\n'
} > "$fur"
for scene in furnace_cube/cube sphere/sphere_2 furnace_room/room_box furnace_room/room_hair \
             furnace_room/room_27; do
  for rho in 0.5 0.9 0.99; do
    for method in dense hier hier-eps0.01; do
      case $method in
        dense) args="" ;;
        hier) args="--method hier" ;;
        hier-eps0.01) args="--method hier --eps 0.01" ;;
      esac
      t=data/furnace.tsv
      echo "accuracy: $scene rho $rho $method" >&2
      (cd "$root" && "$RADKIT" solve "scenes/$scene.obj" --rho "$rho" $args --quiet --out "$here/$t")
      awk -F'\t' -v s="$(basename "$scene")" -v rho="$rho" -v m="$method" \
          -v est="$(hdr $t error_estimate)" -v time="$(hdr $t time_total_s)" \
          -v el="$(hdr $t elements)" '
        BEGIN { exact = 2.385 / (1 - rho) }
        /^#/ || $1 == "face" { next }
        { for (c = 3; c <= 5; c++) { d = ($c - exact) / exact; if (d < 0) d = -d; if (d > worst) worst = d }
          sum += $2 * ($3 - exact) / exact; area += $2 }
        END { mean = sum / area; if (mean < 0) mean = -mean
          # hier reports relative to the mean reflected radiosity, exact - E = rho exact
          e = est == "" ? "-" : sprintf("%.3e", est * rho)
          printf "%s\t%s\t%s\t%.3e\t%.3e\t%s\t%s\t%s\n", s, rho, m, worst, mean, e, time, el }' \
        "$t" >> "$fur"
    done
  done
done
rm -f data/furnace.tsv

# ---- 2. Cornell box: requested eps against achieved error ----
cor=data/cornell.dat
compare() { (cd "$root" && "$RADKIT" compare "$cornell" "$here/$1" "$ref") | sed -n "s/^# $2 = //p"; }
{
  echo "# experiment = accuracy: Cornell box against the Monte Carlo reference ($ref)"
  echo "# generator = $version; machine = $(sh "$root/scripts/machine.sh")"
  echo "# error_worst, error_l1: radkit compare (worst face and channel; area-weighted), over the"
  echo "# mean reflected radiosity; estimate, estimate_l1: the run's error_estimate and _l1"
  printf 'method\tparam\terror_worst\terror_l1\testimate\testimate_l1\ttime_s\telements\tlinks\n'
} > "$cor"
runrow() { # method param table
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$1" "$2" "$(compare "$3" error_worst)" \
    "$(compare "$3" error_l1)" "$(hdr "$3" error_estimate)" "$(hdr "$3" error_estimate_l1)" \
    "$(hdr "$3" time_total_s)" "$(hdr "$3" elements)" "$(hdr "$3" links)" >> "$cor"
}
t=data/cornell_run.tsv
for e in $EPS; do
  echo "accuracy: Cornell hier --eps $e" >&2
  (cd "$root" && "$RADKIT" solve "$cornell" --method hier --eps "$e" --quiet --out "$here/$t")
  runrow hier-error "$e" "$t"
done
for e in $EPS_BF; do
  echo "accuracy: Cornell hier --oracle bf --eps $e" >&2
  (cd "$root" && "$RADKIT" solve "$cornell" --method hier --oracle bf --eps "$e" --quiet --out "$here/$t")
  runrow hier-bf "$e" "$t"
done
for k in 0 1 2; do
  echo "accuracy: Cornell dense --refine $k" >&2
  (cd "$root" && "$RADKIT" solve "$cornell" --refine "$k" --quiet --out "$here/$t")
  runrow dense "$k" "$t"
done
rm -f "$t"

if command -v gnuplot >/dev/null 2>&1; then gnuplot plot.gp; else echo "accuracy: no gnuplot, no plots" >&2; fi
# gnuplot's PDFs carry their creation time: a fixed one, so that a re-run
# changes only what it measured.
find . -name '*.pdf' -exec perl -pi -e 's/(CreationDate \(D:)\d{14}/${1}20000101000000/' {} +
cat "$fur" "$cor"
