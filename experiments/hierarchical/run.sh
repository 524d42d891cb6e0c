#!/bin/sh
# Hierarchical against dense radiosity on the Cornell box (papers/hierarchical.md,
# papers/accuracy.md).
#
# Error of the per-input-face radiosity against the Monte Carlo reference of
# experiments/reference (made if missing), by `radkit compare`: error_l1, the
# area-weighted mean |B - B_ref| over the mean reflected radiosity, and
# error_worst, the worst face and channel on that scale, for
#  - hier with the error oracle at EPS_ERROR and the BF oracle at EPS_BF (each
#    with its default minimum area, which follows eps), with the error estimate
#    each run reports of itself (error_estimate: worst face; _l1), and the
#    error oracle with --basis p1 and p2 at EPS_BASES,
#  - dense at refinements 0..MAX_REFINE with auto at 1e-3 and with gauss:2 (the
#    fastest rule of experiments/accuracy_time), its default solver,
# with wall time (the median of REPEAT runs: single runs of a tenth of a second
# vary by 20% on a shared machine), elements and links (dense: facing pairs).
# Then links against leaves with the fitted slope per oracle (eps 0.1 to
# 0.003), the time each method needs for 1%, 0.5% and 0.1%, and pictures of
# the adaptive mesh.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
RADKIT=${RADKIT:-$root/build/radkit}
case "$RADKIT" in /*) ;; *) RADKIT=$(pwd)/$RADKIT;; esac # we cd below
# eps of the error oracle: twelve steps a decade (the E12 series) from 0.33 to
# 0.01, where a target falls between runs, then coarser to 0.001
EPS_ERROR=${EPS_ERROR:-"0.33 0.27 0.22 0.18 0.15 0.12 0.1 0.082 0.068 0.056 0.047 0.039 0.033 0.027 0.022 0.018 0.015 0.012 0.01 0.005 0.003 0.002 0.001"}
EPS_BF=${EPS_BF:-"1 0.3 0.1 0.05 0.03"}
# the error oracle with linear and quadratic elements (papers/bases.md), from
# larger eps: a higher order reaches a coarse target with far fewer links
EPS_BASES=${EPS_BASES:-"1 0.82 0.68 0.56 0.47 0.39 0.33 0.27 0.22 0.18 0.15 0.12 0.1 0.082 0.068"}
REPEAT=${REPEAT:-5}
ORACLES="bf error"
MAX_REFINE=${MAX_REFINE:-3}
scene=scenes/cornell/cornell.obj
ref=experiments/reference/data/cornell.tsv
cd "$root"
[ -s "$ref" ] || RADKIT=$RADKIT sh experiments/reference/run.sh
cd "$here"
mkdir -p data figures
version=$("$RADKIT" --version)

# compare TABLE KEY: one figure of `radkit compare` against the reference
compare() {
  (cd "$root" && "$RADKIT" compare "$scene" "$here/$1" "$ref") | sed -n "s/^# $2 = //p"
}
hdr() { sed -n "s/^# $2 = //p" "$1" | head -1; }

# solve OUT ARGS...: radkit solve REPEAT times into OUT; prints the median
# time_total_s (OUT keeps the last run's table: the runs are deterministic)
solve() {
  out=$1; shift
  i=0
  while [ "$i" -lt "$REPEAT" ]; do
    (cd "$root" && "$RADKIT" solve "$scene" "$@" --quiet --out "$here/$out")
    hdr "$out" time_total_s
    i=$((i + 1))
  done | sort -g | awk '{ t[NR] = $1 } END { print t[int((NR + 1) / 2)] }'
}
dat=data/runs.dat
{
  echo "# experiment = hierarchical: hier (bf, error oracles) and dense on the Cornell box"
  echo "# generator = $version; machine = $(sh "$root/scripts/machine.sh")"
  echo "# reference = $ref ($(sed -n 's/^# command = //p' "$root/$ref"))"
  echo "# reference_se_l1 = $(compare "../../$ref" reference_se_l1)"
  echo "# error = error_l1 of radkit compare: area-weighted mean |B - B_ref| over the mean reflected radiosity; worst: the largest face and channel"
  echo "# estimate, estimate_l1: the run's own error_estimate (worst face) and error_estimate_l1 (hier only)"
  printf 'method\tparam\telements\tlinks\terror\ttime_s\trays\tkernel_evals\tlinks_partial\tworst\testimate\testimate_l1\n'
} > "$dat"
rm -f data/hier_*.tsv data/dense-*.tsv
row() { # method param table time
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$1" "$2" "$(hdr $3 elements)" \
    "$(hdr $3 links)" "$(compare $3 error_l1)" "$4" "$(hdr $3 rays)" \
    "$(hdr $3 kernel_evals)" "$(hdr $3 links_partial)" "$(compare $3 error_worst)" \
    "$(hdr $3 error_estimate)" "$(hdr $3 error_estimate_l1)" >> "$dat"
}
# sweep METHOD TAG "EPS..." ARGS...: a row of METHOD per eps, hier with ARGS
sweep() {
  m=$1; tag=$2; list=$3; shift 3
  for e in $list; do
    t=data/hier_${tag}_$e.tsv
    echo "hierarchical: hier $* --eps $e" >&2
    row "$m" "$e" "$t" "$(solve "$t" --method hier "$@" --eps "$e")"
  done
}
sweep hier-bf bf "$EPS_BF" --oracle bf
sweep hier-error error "$EPS_ERROR" --oracle error
sweep hier-error-p1 error_p1 "$EPS_BASES" --basis p1
sweep hier-error-p2 error_p2 "$EPS_BASES" --basis p2
for rule in auto gauss:2; do
  k=0
  name=dense-$(echo "$rule" | tr -d ':')
  while [ "$k" -le "$MAX_REFINE" ]; do
    t=data/${name}_$k.tsv
    echo "hierarchical: dense --refine $k --rule $rule" >&2
    time_s=$(solve "$t" --refine "$k" --rule "$rule" --tol 1e-3)
    links=$(awk '/^# pairs = /{p=$4} /^# pairs_not_facing = /{n=$4} END{print p-n}' "$t")
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t-\t-\n' "$name" "$k" "$(hdr $t elements)" \
      "$links" "$(compare $t error_l1)" "$time_s" "$(hdr $t rays)" "$(hdr $t kernel_evals)" "-" \
      "$(compare $t error_worst)" >> "$dat"
    k=$((k + 1))
  done
done

# links ~ leaves^slope per oracle: least squares in log-log over the runs with
# eps in [SLOPE_MIN_EPS, SLOPE_MAX_EPS] (issue 13 measures 0.1 .. 0.003); the
# slope over all runs beside it.
SLOPE_MIN_EPS=${SLOPE_MIN_EPS:-0.003}
SLOPE_MAX_EPS=${SLOPE_MAX_EPS:-0.1}
slopes=data/slopes.dat
printf 'oracle\tslope_eps_%s_to_%s\tslope_all\n' "$SLOPE_MAX_EPS" "$SLOPE_MIN_EPS" > "$slopes"
for o in $ORACLES; do
  awk -F'\t' -v m="hier-$o" -v lo="$SLOPE_MIN_EPS" -v hi="$SLOPE_MAX_EPS" '
    function fit(a, b, c, d, e) { return e < 2 ? "-" : sprintf("%.3f", (e*d - a*b) / (e*c - a*a)) }
    $1 == m { x = log($3); y = log($4)
      N++; SX += x; SY += y; SXX += x*x; SXY += x*y
      if ($2 + 0 >= lo + 0 && $2 + 0 <= hi + 0) { n++; sx += x; sy += y; sxx += x*x; sxy += x*y } }
    END { printf "%s\t%s\t%s\n", m, fit(sx, sy, sxx, sxy, n), fit(SX, SY, SXX, SXY, N) }' "$dat" >> "$slopes"
done

# Targets: the time each method needs for 1%, 0.5% and 0.1% L1 (log-log
# interpolation between the neighbours on the method's frontier of error
# against time that bracket it, scripts/time_to_target.awk; "none" when no
# run reaches it), the time of its fastest run that reaches it, and that
# run's links.
target=data/target.dat
printf 'method\ttarget\ttime_s\tfirst_run_s\tfirst_run_links\n' > "$target"
for m in dense-auto dense-gauss2 hier-bf hier-error hier-error-p1 hier-error-p2; do
  for goal in 0.01 0.005 0.001; do
    printf '%s\t%s\t%s\n' "$m" "$goal" "$(awk -F'\t' -v m="$m" -v mc=1 -v ec=5 -v tc=6 -v kc=4 \
      -v g="$goal" -f "$root/scripts/time_to_target.awk" "$dat")" >> "$target"
  done
done

# pictures of the adaptive mesh (leaf edges drawn)
for o in $ORACLES; do
  (cd "$root" && "$RADKIT" solve "$scene" --method hier --oracle "$o" --eps 0.1 --quiet \
     --out /dev/null --png "$here/figures/mesh_$o.png" --edges --image-size 512x512)
done
(cd "$root" && "$RADKIT" solve "$scene" --method hier --oracle error --eps 0.01 --quiet \
   --out /dev/null --png "$here/figures/cornell_hier.png" --ply "$here/data/cornell_hier.ply" \
   --image-size 512x512)

if command -v gnuplot >/dev/null 2>&1; then gnuplot plot.gp; else echo "hierarchical: no gnuplot, no plots" >&2; fi
# gnuplot's PDFs carry their creation time: a fixed one, so that a re-run
# changes only what it measured.
find . -name '*.pdf' -exec perl -pi -e 's/(CreationDate \(D:)\d{14}/${1}20000101000000/' {} +
cat "$dat" "$slopes" "$target"
