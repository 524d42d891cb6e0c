#!/bin/sh
# Accuracy against time for dense radiosity on the Cornell box
# (papers/dense-radiosity.md).
#
# For each form-factor rule and uniform refinement 0..MAX_REFINE, solve the
# Cornell box and compare the radiosity of every input face (the area average
# over its elements) with a reference: refinement REF_REFINE, auto at 1e-6.
# Error = relative area-weighted L2 norm over the non-emitting faces and the
# three channels.  The reference's own error is estimated from how the auto
# runs converge towards it (written to the header of errors.dat).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
RADKIT=${RADKIT:-$root/build/radkit}
MAX_REFINE=${MAX_REFINE:-3}
REF_REFINE=${REF_REFINE:-4}
RULES=${RULES:-"vertex centroid gauss:2 auto:1e-3 auto:1e-6"}
scene=$root/scenes/cornell/cornell.obj
cd "$here"
mkdir -p data figures
version=$("$RADKIT" --version)

# (sh variables are global: run's own names must not be the loop's.)
run() { # rule[:tol] refine outfile
  run_rule=$1; run_tol=""
  case "$1" in auto:*) run_rule=auto; run_tol="--tol ${1#auto:}";; esac
  "$RADKIT" solve "$scene" --refine "$2" --rule "$run_rule" $run_tol --solver lu --quiet --out "$3"
}

ref=data/reference.tsv
if [ ! -s "$ref" ] || [ "${REDO_REFERENCE:-0}" = 1 ]; then
  echo "accuracy_time: reference (refine $REF_REFINE, auto 1e-6): this takes minutes" >&2
  run auto:1e-6 "$REF_REFINE" "$ref"
fi

errorof() { # table reference (experiments/face_error.awk)
  awk -F'\t' -f "$root/experiments/face_error.awk" "$1" "$2"
}

dat=data/errors.dat
{
  echo "# experiment = accuracy_time: dense radiosity on the Cornell box"
  echo "# generator = $version solve --solver lu; machine = $(nproc) cores"
  echo "# reference = refine $REF_REFINE, rule auto, tol 1e-6 ($(grep '^# elements' "$ref" | sed 's/# //'))"
  echo "# error = relative area-weighted L2 norm of (B - B_ref) over non-emitting input faces, 3 channels"
  printf 'rule\trefine\telements\terror\ttime_s\tassemble_s\tsolve_s\tkernel_evals\trays\n'
} > "$dat"
for rule in $RULES; do
  r=0
  while [ "$r" -le "$MAX_REFINE" ]; do
    printf '\r  %-10s refine %d' "$rule" "$r" >&2
    out=data/run_$(echo "$rule" | tr ':' '_')_$r.tsv
    run "$rule" "$r" "$out"
    awk -F' = ' -v rule="$rule" -v r="$r" -v e="$(errorof "$out" "$ref")" '
      /^# /{ v[substr($1, 3)] = $2 }
      END { printf "%s\t%d\t%d\t%s\t%s\t%s\t%s\t%s\t%s\n", rule, r, v["elements"], e,
            v["time_total_s"], v["time_assemble_s"], v["time_solve_s"], v["kernel_evals"], v["rays"] }' \
      "$out" >> "$dat"
    r=$((r + 1))
  done
done
printf '\n' >&2
# The reference's own error: successive auto:1e-6 differences d_r = |B_r - B_{r+1}|
# shrink by a factor q per level; then |B_ref - B_exact| ~ d_{ref-1} q / (1 - q).
prev=""; for r in $(seq 0 "$MAX_REFINE"); do
  f=data/run_auto_1e-6_$r.tsv; [ -f "$f" ] || continue
  if [ -n "$prev" ]; then echo "$(errorof "$prev" "$f")"; fi; prev=$f
done > data/successive.txt
echo "$(errorof "$prev" "$ref")" >> data/successive.txt
awk 'NR > 1 { q = $1 / last } { last = $1 }
     END { if (q > 0 && q < 1) printf "# reference error estimate = %.3e (successive ratio q = %.3f)\n", last * q / (1 - q), q
           else printf "# reference error estimate = unknown (successive ratio %.3f)\n", q }' \
    data/successive.txt >> "$dat"
gnuplot plot.gp
grep -v '^#' "$dat" | column -t
grep '^# reference error' "$dat"
echo "accuracy_time: figures in $here/figures/"
