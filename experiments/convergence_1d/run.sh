#!/bin/sh
# Convergence study of the 1D model problem (papers/galerkin-1d.md).
#
# For every problem x basis x assembly it solves n = 2, 4, ..., NMAX with
# `radkit galerkin1d` and writes one .dat file per combination (data/), then
# fits the observed order on the finest points (rates.dat, slopes.gp) and draws
# the figures with gnuplot (figures/).  NMAX=512 sh run.sh gives a quick run;
# REPLOT=1 sh run.sh refits and redraws from the data already there.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
RADKIT=${RADKIT:-$here/../../build/radkit}
NMAX=${NMAX:-4096}
FIT_POINTS=${FIT_POINTS:-6}   # the finest points used for the slope fit
FLOOR=${FLOOR:-1e-12}         # errors below this are round-off, not discretisation
cd "$here"
mkdir -p data figures
version=$("$RADKIT" --version)

[ "${REPLOT:-0}" = 1 ] ||
for problem in seed exp; do
  for basis in p0 p1; do
    for assembly in exact midpoint gauss:2 gauss:4 gauss-split:2; do
      tag=$(echo "$assembly" | tr -d ':-')
      file="data/${problem}_${basis}_${tag}.dat"
      {
        echo "# experiment = convergence_1d"
        echo "# generator = $version galerkin1d"
        echo "# problem = $problem"
        echo "# basis = $basis"
        echo "# assembly = $assembly"
        echo "# errors: l2, linf against the exact solution; nodal at midpoints (p0) or nodes (p1);"
        echo "#         coef = max |y - y_exact_assembly|; residual = independent Galerkin residual"
        echo "# time_s = assemble_s + solve_s (one thread of OpenBLAS unless OPENBLAS_NUM_THREADS says otherwise)"
        printf 'n\th\terr_l2\terr_linf\terr_nodal\terr_coef\tresidual\tcond1\tassemble_s\tsolve_s\ttime_s\n'
      } > "$file"
      n=2
      while [ "$n" -le "$NMAX" ]; do
        printf '\r  %-5s %-3s %-14s n = %-5d' "$problem" "$basis" "$assembly" "$n" >&2
        "$RADKIT" galerkin1d --n "$n" --problem "$problem" --basis "$basis" --assembly "$assembly" |
          awk -F' = ' -v n="$n" '
            /^# /{ v[substr($1, 3)] = $2 }
            END { printf "%d\t%.17g\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%.6f\n", n, 1.0 / n,
                  v["err_l2"], v["err_linf"], v["err_nodal"], v["err_coef"], v["galerkin_residual"],
                  v["cond1_estimate"], v["assemble_s"], v["solve_s"], v["assemble_s"] + v["solve_s"] }' >> "$file"
        n=$((n * 2))
      done
    done
  done
done
printf '\n' >&2

# Theory (papers/galerkin-1d.md, section 5).  The order seen is the smaller of the
# discretisation order and the assembly (quadrature) order; "none" where the
# computed answer is exact up to round-off (seed: y = x lies in P1, its P0
# coefficients are exactly the cell means, and gauss-split:2 integrates every
# seed P0 integrand exactly).  P1 with midpoint or gauss-split:2 errs only in
# the two boundary rows; the mass matrix spreads that over O(1) nodes, so the
# L2 norm gains half an order over the maximum norm.
theory() { # problem basis assembly quantity
  awk -v pr="$1" -v b="$2" -v a="$3" -v q="$4" 'BEGIN {
    inf = 99
    if (q == "l2" || q == "linf") d = (b == "p0") ? 1 : 2
    else if (q == "nodal") d = 2
    else d = inf
    if (pr == "seed" && (b == "p1" || q == "nodal")) d = inf
    layer = 0
    if (a == "exact") qa = inf
    else if (a == "gauss-split:2") { qa = (b == "p0") ? ((pr == "seed") ? inf : 4) : 3; layer = (b == "p1") }
    else if (a == "midpoint") { qa = (b == "p0") ? 2 : 1; layer = (b == "p1") }
    else qa = 2
    if (q == "l2" && layer) qa += 0.5
    t = (d < qa) ? d : qa
    if (t == inf) print "none"; else print t }'
}

rates=rates.dat
{
  echo "# experiment = convergence_1d: observed orders (least-squares slope of log err vs log h"
  echo "# over the $FIT_POINTS finest n with err > $FLOOR) and theory; generator = $version"
  printf 'problem\tbasis\tassembly\tquantity\tslope\tslope_err\ttheory\tverdict\n'
} > "$rates"
: > slopes.gp
for file in data/*.dat; do
  set -- $(basename "$file" .dat | tr '_' ' ')
  problem=$1 basis=$2 assembly=$(grep '^# assembly = ' "$file" | sed 's/^# assembly = //')
  for col in 3:l2 4:linf 5:nodal 6:coef; do
    c=${col%%:*} q=${col#*:}
    th=$(theory "$problem" "$basis" "$assembly" "$q")
    awk -F'\t' -v c="$c" -v m="$FIT_POINTS" -v floor="$FLOOR" -v th="$th" \
        -v id="$problem	$basis	$assembly	$q" '
      !/^#/ && $1 != "n" && $c + 0 > floor { k++; x[k] = log($2); y[k] = log($c) }
      END {
        if (k < 4) { slope = "-"; se = "-"; verdict = (th == "none") ? "ok (round-off)" : "FAIL (no data)" }
        else {
          lo = (k > m) ? k - m + 1 : 1; N = k - lo + 1
          for (i = lo; i <= k; i++) { sx += x[i]; sy += y[i] }
          mx = sx / N; my = sy / N
          for (i = lo; i <= k; i++) { sxx += (x[i]-mx)^2; sxy += (x[i]-mx)*(y[i]-my) }
          b = sxy / sxx; a = my - b * mx
          for (i = lo; i <= k; i++) ss += (y[i] - a - b*x[i])^2
          se = (N > 2) ? sqrt(ss / (N - 2) / sxx) : 0
          slope = sprintf("%.3f", b); se = sprintf("%.2g", se)
          if (th == "none") verdict = "FAIL (expected round-off)"
          else verdict = (b - th < 0.1 && th - b < 0.1) ? "ok" : "FAIL"
        }
        printf "%s\t%s\t%s\t%s\t%s\n", id, slope, se, th, verdict }' "$file" >> "$rates"
  done
done
# Legend strings for the figures: one gnuplot variable per file and quantity.
awk -F'\t' '!/^#/ && $1 != "problem" {
  a = $3; gsub(/[:-]/, "", a)
  s = ($5 == "-") ? "round-off" : sprintf("slope %s ± %.1g", $5, $6)
  printf "s_%s_%s_%s_%s = \"%s\"\n", $1, $2, a, $4, s }' "$rates" >> slopes.gp

gnuplot plot.gp
# gnuplot's PDFs carry their creation time: a fixed one, so that a re-run
# changes only what it measured.
find . -name '*.pdf' -exec perl -pi -e 's/(CreationDate \(D:)\d{14}/${1}20000101000000/' {} +
column -t -s "$(printf '\t')" "$rates" | sed -n '1,200p' | grep -v '^#'
if grep -q 'FAIL' "$rates"; then
  echo "convergence_1d: some observed orders differ from theory by 0.1 or more (see $here/$rates)" >&2
  exit 1
fi
echo "convergence_1d: every observed order within 0.1 of theory; figures in $here/figures/"
