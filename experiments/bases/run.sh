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
#    exact B* at each refinement, and the fitted orders of the last two.
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
  echo "# generator = $version; machine = $(nproc) cores"
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
  echo "# generator = $version; machine = $(nproc) cores"
  "$libdir/manufactured" scenes/plates_parallel/plates.obj "${MAN_P0:-5}" "${MAN_P1:-4}" "${MAN_P2:-3}"
} > "$man"
# fitted order between the last two refinements of each basis
awk -F'\t' '!/^#/ && $1 ~ /^p/ { if ($1 == b) { o = log(e / $5) / log(2) } else { o = "" }
                               b = $1; e = $5; last[b] = o }
            END { for (k in last) printf "%s\t%.3f\n", k, last[k] }' "$man" | sort > "$here/data/orders.dat"
cat "$here/data/orders.dat"

(cd "$here" && gnuplot plot.gp)
echo "bases: data/ and figures/ written"
