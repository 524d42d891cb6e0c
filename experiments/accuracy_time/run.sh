#!/bin/sh
# Accuracy against time for dense radiosity on the Cornell box
# (papers/dense-radiosity.md).
#
# For each form-factor rule and uniform refinement 0..MAX_REFINE, solve the
# Cornell box and compare the radiosity of every input face (the area average
# over its elements) with the Monte Carlo reference of experiments/reference
# (`radkit compare`): error_l1 (area-weighted mean |B - B_ref| over the
# reference's mean reflected radiosity) and error_worst (the worst face and
# channel on the same scale).  The reference's own standard error in the same
# measure is written to the header of errors.dat.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
RADKIT=${RADKIT:-$root/build/radkit}
case "$RADKIT" in /*) ;; *) RADKIT=$(pwd)/$RADKIT;; esac
MAX_REFINE=${MAX_REFINE:-3}
RULES=${RULES:-"vertex centroid gauss:2 auto:1e-3 auto:1e-6"}
scene=scenes/cornell/cornell.obj
ref=experiments/reference/data/cornell.tsv
cd "$root"
[ -s "$ref" ] || RADKIT=$RADKIT sh experiments/reference/run.sh
cd "$here"
mkdir -p data figures
version=$("$RADKIT" --version)

# (sh variables are global: run's own names must not be the loop's.)
run() { # rule[:tol] refine outfile
  run_rule=$1; run_tol=""
  case "$1" in auto:*) run_rule=auto; run_tol="--tol ${1#auto:}";; esac
  (cd "$root" && "$RADKIT" solve "$scene" --refine "$2" --rule "$run_rule" $run_tol --solver lu \
     --quiet --out "$here/$3")
}

# compare TABLE KEY: one figure of `radkit compare` against the reference
compare() {
  (cd "$root" && "$RADKIT" compare "$scene" "$here/$1" "$ref") | sed -n "s/^# $2 = //p"
}

dat=data/errors.dat
{
  echo "# experiment = accuracy_time: dense radiosity on the Cornell box"
  echo "# generator = $version solve --solver lu; machine = $(sh "$root/scripts/machine.sh")"
  echo "# reference = $ref ($(sed -n 's/^# command = //p' "$root/$ref"))"
  echo "# error = error_l1 of radkit compare: area-weighted mean |B - B_ref| over the mean reflected radiosity; worst: the largest face and channel"
  echo "# reference_se_l1 = $(compare "../../$ref" reference_se_l1)"
  printf 'rule\trefine\telements\terror\ttime_s\tassemble_s\tsolve_s\tkernel_evals\trays\tworst\n'
} > "$dat"
for rule in $RULES; do
  r=0
  while [ "$r" -le "$MAX_REFINE" ]; do
    printf '\r  %-10s refine %d' "$rule" "$r" >&2
    out=data/run_$(echo "$rule" | tr ':' '_')_$r.tsv
    run "$rule" "$r" "$out"
    awk -F' = ' -v rule="$rule" -v r="$r" -v e="$(compare "$out" error_l1)" \
        -v w="$(compare "$out" error_worst)" '
      /^# /{ v[substr($1, 3)] = $2 }
      END { printf "%s\t%d\t%d\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n", rule, r, v["elements"], e,
            v["time_total_s"], v["time_assemble_s"], v["time_solve_s"], v["kernel_evals"], v["rays"], w }' \
      "$out" >> "$dat"
    r=$((r + 1))
  done
done
printf '\n' >&2
gnuplot plot.gp
# gnuplot's PDFs carry their creation time: a fixed one, so that a re-run
# changes only what it measured.
find . -name '*.pdf' -exec perl -pi -e 's/(CreationDate \(D:)\d{14}/${1}20000101000000/' {} +
grep -v '^#' "$dat" | column -t
grep '^# reference_se' "$dat"
echo "accuracy_time: figures in $here/figures/"
