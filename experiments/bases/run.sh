#!/bin/sh
# Higher-order Galerkin bases (papers/bases.md): dense radiosity with p0, p1
# and p2 elements.
#
# 1. The Cornell box against the committed Monte Carlo reference
#    (experiments/reference): for each basis and uniform refinement, the
#    unknowns (elements x functions), the wall time and radkit compare's
#    error_l1 and error_worst.
# 2. The manufactured case (experiments/bases/manufactured.c, built here
#    against the library beside the radkit binary): the L2 error against the
#    exact B* at each refinement, and the fitted orders of the last two;
#    then hier p1 and p2 on the same case, eps swept.
# 3. Hierarchical p0, p1, p2 on the Cornell box, eps swept: leaves, links,
#    the median wall time of REPEAT runs, the error against the reference and
#    the run's own error_estimate (worst face) beside the true worst face;
#    and the time each basis needs for 0.25% and 0.1% (log-log interpolation
#    between the neighbours on the basis's frontier of error against time
#    that bracket the target: scripts/time_to_target.awk).
# Tables in data/, figures in figures/ (gnuplot).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
RADKIT=${RADKIT:-$root/build/radkit}
case "$RADKIT" in /*) ;; *) RADKIT=$(pwd)/$RADKIT;; esac
libdir=$(cd "$(dirname "$RADKIT")" && pwd)
MAX_P0=${MAX_P0:-3}
MAX_P1=${MAX_P1:-2}
MAX_P2=${MAX_P2:-2}
REPEAT=${REPEAT:-5}
# twelve steps a decade (the E12 series): the error falls in steps, not
# smoothly, as eps shrinks, so a coarser sweep brackets a target loosely
HIER_EPS=${HIER_EPS:-"0.33 0.27 0.22 0.18 0.15 0.12 0.1 0.082 0.068 0.056 0.047 0.039 0.033 0.027 0.022 0.018 0.015 0.012 0.01"}
scene=scenes/cornell/cornell.obj
ref=experiments/reference/data/cornell.tsv
cd "$root"
[ -s "$ref" ] || RADKIT=$RADKIT sh experiments/reference/run.sh
mkdir -p "$here/data" "$here/figures"
version=$("$RADKIT" --version)

# ---- 1. the Cornell box -----------------------------------------------------
dat=$here/data/cornell.dat
{
  echo "# experiment = bases: dense p0, p1, p2 on $scene against $ref"
  echo "# generator = $version; machine = $(sh "$root/scripts/machine.sh")"
  echo "# error_l1, error_worst: radkit compare (over the mean reflected radiosity); time_s: time_total_s"
  printf "basis\trefine\telements\tunknowns\ttime_s\terror_l1\terror_worst\n"
} > "$dat"
for basis in p0 p1 p2; do
  case $basis in p0) max=$MAX_P0; m=1;; p1) max=$MAX_P1; m=3;; p2) max=$MAX_P2; m=6;; esac
  r=0
  while [ "$r" -le "$max" ]; do
    out=$here/data/cornell_${basis}_$r.tsv
    "$RADKIT" solve "$scene" --refine "$r" --basis "$basis" --quiet --out "$out"
    el=$(sed -n 's/^# elements = //p' "$out")
    t=$(sed -n 's/^# time_total_s = //p' "$out")
    cmp=$("$RADKIT" compare "$scene" "$out" "$ref")
    l1=$(echo "$cmp" | sed -n 's/^# error_l1 = //p')
    worst=$(echo "$cmp" | sed -n 's/^# error_worst = //p')
    printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\n" "$basis" "$r" "$el" $((el * m)) "$t" "$l1" "$worst" >> "$dat"
    echo "cornell $basis refine $r: $((el * m)) unknowns, ${t} s, L1 $l1"
    r=$((r + 1))
  done
done

# ---- 2. the manufactured case ------------------------------------------------
inc=$(for d in "$root"/core/*/; do printf ' -I%s' "$d"; done)
g++ -x c -std=c11 -O2 -fopenmp -D_POSIX_C_SOURCE=200809L $inc "$here/manufactured.c" -x none \
   "$libdir/libradkit.a" -lembree3 -lassimp -lpng -lgmp -lmpfr -llapacke -lopenblas -lm \
   -o "$libdir/manufactured"
man=$here/data/manufactured.dat
{
  echo "# experiment = bases: the manufactured case (experiments/bases/manufactured.c) on scenes/plates_parallel"
  echo "# generator = $version; machine = $(sh "$root/scripts/machine.sh")"
  "$libdir/manufactured" scenes/plates_parallel/plates.obj "${MAN_P0:-5}" "${MAN_P1:-4}" "${MAN_P2:-3}"
} > "$man"
# fitted order between the last two refinements of each basis
awk -F'\t' '!/^#/ && $1 ~ /^p/ { if ($1 == b) { o = log(e / $5) / log(2) } else { o = "" }
                               b = $1; e = $5; last[b] = o }
            END { for (k in last) printf "%s\t%.3f\n", k, last[k] }' "$man" | sort > "$here/data/orders.dat"
cat "$here/data/orders.dat"
# the same case by hier (p1, p2; eps targets the input triangles' means,
# not the L2 error: papers/bases.md §4)
{
  echo "# experiment = bases: the manufactured case by hier --basis p1, p2, eps swept"
  echo "# generator = $version; machine = $(sh "$root/scripts/machine.sh")"
  "$libdir/manufactured" --hier scenes/plates_parallel/plates.obj ${MAN_HIER_EPS:-0.1 0.03 0.01 0.003 0.001 3e-4 1e-4 3e-5 1e-5}
} > "$here/data/manufactured_hier.dat"
cat "$here/data/manufactured_hier.dat"

# ---- 3. hierarchical p0, p1, p2 ------------------------------------------------
hier=$here/data/hier.dat
{
  echo "# experiment = bases: hier --basis p0, p1, p2 on $scene against $ref, eps swept"
  echo "# generator = $version; machine = $(sh "$root/scripts/machine.sh"); time_s: median time_total_s of $REPEAT runs"
  echo "# error_l1, error_worst: radkit compare; estimate: the run's error_estimate (worst face)"
  printf "basis\teps\telements\tlinks\ttime_s\terror_l1\terror_worst\testimate\n"
} > "$hier"
# the three bases run in turn at each eps, REPEAT rounds: a drift of the
# machine's speed during the sweep falls on all three alike
rm -f "$here"/data/hier_*.times "$hier.unsorted"
for eps in $HIER_EPS; do
  i=0
  while [ "$i" -lt "$REPEAT" ]; do
    for basis in p0 p1 p2; do
      out=$here/data/hier_${basis}_$eps.tsv
      "$RADKIT" solve "$scene" --method hier --basis "$basis" --eps "$eps" --quiet --out "$out"
      sed -n 's/^# time_total_s = //p' "$out" >> "$here/data/hier_${basis}_$eps.times"
    done
    i=$((i + 1))
  done
  for basis in p0 p1 p2; do
    out=$here/data/hier_${basis}_$eps.tsv
    t=$(sort -g "$here/data/hier_${basis}_$eps.times" | awk '{ t[NR] = $1 } END { print t[int((NR + 1) / 2)] }')
    cmp=$("$RADKIT" compare "$scene" "$out" "$ref")
    printf "%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n" "$basis" "$eps" \
      "$(sed -n 's/^# elements = //p' "$out")" "$(sed -n 's/^# links = //p' "$out")" "$t" \
      "$(echo "$cmp" | sed -n 's/^# error_l1 = //p')" "$(echo "$cmp" | sed -n 's/^# error_worst = //p')" \
      "$(sed -n 's/^# error_estimate = //p' "$out")" >> "$hier.unsorted"
    rm -f "$out" "$here/data/hier_${basis}_$eps.times"
    echo "hier $basis eps $eps: ${t} s"
  done
done
# rows by basis, then eps as swept
for basis in p0 p1 p2; do awk -F'\t' -v b="$basis" '$1 == b' "$hier.unsorted"; done >> "$hier"
rm -f "$hier.unsorted"
target=$here/data/hier_target.dat
printf "basis\ttarget\ttime_s\tfirst_run_s\tfirst_run_eps\n" > "$target"
for basis in p0 p1 p2; do
  for goal in 0.0025 0.001; do
    printf "%s\t%s\t%s\n" "$basis" "$goal" "$(awk -F'\t' -v m="$basis" -v mc=1 -v ec=6 -v tc=5 \
      -v kc=2 -v g="$goal" -f "$root/scripts/time_to_target.awk" "$hier")" >> "$target"
  done
done
cat "$hier" "$target"

(cd "$here" && gnuplot plot.gp)
echo "bases: data/ and figures/ written"
