#!/bin/sh
# Clustering (papers/clustering.md): hierarchical radiosity with and without
# the cluster layer.
#
# 1. Scaling: rooms of N boxes (scenes/gen/many_objects.py N: a closed 10 m
#    room, the ceiling emitting, N cubes on a grid, 12 N + 12 triangles),
#    solved by hier without clusters (--clustering off, up to HIER_MAX
#    boxes: its initial linking couples every pair of triangles) and by
#    cluster with each model (oriented, iso) at
#    eps EPS: links (pairs coupled, cluster links among them), leaves, wall
#    time, peak memory and the run's error estimate; then the log-log slope
#    of links and of time against triangles per method.
#    A second, cheaper table at a preview setting (eps LOOSE_EPS,
#    --max-tighten LOOSE_TIGHTEN) runs cluster on LOOSE_SIZES boxes, up to
#    3 000 (36 012 triangles, the top of issue 17's slope range), with the
#    room of 343 boxes's errors against its Monte Carlo reference (part
#    "loose", data/scaling_loose.dat and its slopes in data/slopes.dat;
#    each size run LOOSE_REPEAT times, the fastest kept: this machine's
#    times move by up to a fifth from run to run).
#    Part "range": cluster (oriented) at the defaults (eps EPS, the default
#    --max-tighten) on RANGE_SIZES boxes (300, 1 000 and 3 000: 3 612,
#    12 012 and 36 012 triangles, issue 17's slope range), one run each, the
#    log-log slope of links and time over them (data/scaling_range.dat,
#    method cluster-defaults in data/slopes.dat; about 5 minutes, 4 GB); and
#    the same eps without tightening (--max-tighten 0) on RANGE_SIZES_K0
#    boxes (the same sizes; method cluster-eps-K0, about a minute, 1.3 GB).
# 2. Accuracy against the Monte Carlo references of experiments/reference:
#    the Cornell box and many_64 (64 coloured boxes in a lit room), hier and
#    cluster (both models) at each of EPS_ACC: error_l1, error_worst and
#    error_power of radkit compare, the error estimate, links, time; and
#    many_64 with cluster (oriented) at EPS_FINE (about a minute), and the
#    room of 343 boxes (4 128 triangles, about 2.5 minutes) with cluster
#    (oriented) at each of EPS_ROOM, and the room of 1 000 boxes (12 012
#    triangles) with cluster (oriented) at each eps:K of EPS_LARGE (eps and
#    --max-tighten).
# 3. What the tightening buys: the room of 343 boxes with cluster at eps
#    EPS_TIGHTEN and --max-tighten K for each K of TIGHTEN (links, time,
#    the errors against the Monte Carlo reference, the estimate, and the
#    table's tightenings and tightened_share).
# 4. Furnaces of FURNACE_BOXES boxes (below).
# 6. The target size and beyond: cluster at the preview setting on each of
#    TARGET_BOXES boxes (10 000: 120 012 triangles, issue 17's "120k
#    triangles in under 2 minutes and 6 GB"; 30 000: 360 012 triangles, the
#    largest this 24 GB machine runs on the way to the goal's 1.2M), part
#    "target", data/target.dat (about 4 minutes, 4 GB at the largest), with
#    --max-links TARGET_MAX_LINKS (past the default cap, so that the
#    machine's memory decides).  A size radkit refuses (exit 2: the links'
#    cap or the machine's memory) is a comment row with its time and
#    message; TARGET_BOXES="10000 30000 100000" adds the goal's 1.2M
#    triangles at the preview (not run since the tree splits between
#    objects; refused on 24 GB after about 12 minutes before).
#    Then cluster-coarse: COARSE_BOXES (100 000 boxes, the goal's 1.2M
#    triangles) at eps COARSE_EPS (3), --max-tighten 0, the coarsest
#    setting with a usable answer (16% L1 on 1 000 boxes; about 5
#    minutes, 8.4 GB).  data/target_time.dat: where each row's time goes
#    (the solve's phases, link estimates, the error transport, steps) and
#    the cluster links' share of the error estimate.
# 7. When the layer pays (the effects plan's choice for --method hier):
#    hier without and with clusters on the spheres of 320 and 1 280
#    triangles and rooms of PAYS_BOXES boxes at eps 0.1 (the defaults) and,
#    for PAYS_LOOSE_BOXES, at the preview setting: wall time, peak memory,
#    links and the pairs hier links first (part "pays", data/pays.dat,
#    about 12 minutes).
# 5. The picture of a large scene: make demo-large's room of 1 000 boxes
#    (figures/room_1000.png, its figures and its error against the Monte
#    Carlo reference in data/room_1000.txt).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
RADKIT=${RADKIT:-$root/build/radkit}
case "$RADKIT" in /*) ;; *) RADKIT=$(pwd)/$RADKIT;; esac
SIZES=${SIZES:-"8 27 64 125 216 343"}
HIER_MAX=${HIER_MAX:-125}
EPS=${EPS:-0.1}
EPS_ACC=${EPS_ACC:-"0.1 0.03"}
EPS_FINE=${EPS_FINE:-0.01} # many_64 with cluster (oriented) only: the issue's target
EPS_ROOM=${EPS_ROOM:-"1 0.3 0.1"} # many_343 (4 128 triangles) with cluster (oriented) only
EPS_LARGE=${EPS_LARGE:-"1000:0 10:0 3:0 1:0 0.3:0 0.1:0"} # many_1000 (12 012 triangles): eps:K, cluster (oriented) only
TIGHTEN=${TIGHTEN:-"0 1 2 3"}   # --max-tighten values on many_343 (3 is the default)
EPS_TIGHTEN=${EPS_TIGHTEN:-0.1}
RANGE_SIZES=${RANGE_SIZES:-"300 1000 3000"}
RANGE_SIZES_K0=${RANGE_SIZES_K0:-"300 1000 3000"}
LOOSE_SIZES=${LOOSE_SIZES:-"343 1000 3000"}
LOOSE_EPS=${LOOSE_EPS:-1}
LOOSE_TIGHTEN=${LOOSE_TIGHTEN:-0}
LOOSE_REPEAT=${LOOSE_REPEAT:-3} # the preview's runs per size: the fastest is kept
TARGET_BOXES=${TARGET_BOXES:-"10000 30000"}
TARGET_MAX_LINKS=${TARGET_MAX_LINKS:-200000000} # past the default cap: the machine's memory decides
COARSE_BOXES=${COARSE_BOXES:-100000} # the goal's 1.2M triangles at a coarse setting
COARSE_EPS=${COARSE_EPS:-3}
PAYS_BOXES=${PAYS_BOXES:-"125 216 343 512"}
PAYS_LOOSE_BOXES=${PAYS_LOOSE_BOXES:-"125 343"}
FURNACE_BOXES=${FURNACE_BOXES:-"125 1000"}
FURNACE_RHO=${FURNACE_RHO:-0.9}
FURNACE_EPS=${FURNACE_EPS:-0.01}
PARTS=${PARTS:-"scaling range loose target pays accuracy tighten furnace picture"} # any of them, e.g. PARTS=furnace
want() { case " $PARTS " in *" $1 "*) return 0;; esac; return 1; }
cd "$root"
for r in cornell many_64 many_343 many_1000; do
  [ -s "experiments/reference/data/$r.tsv" ] || RADKIT=$RADKIT sh experiments/reference/run.sh
done
cd "$here"
mkdir -p data figures
version=$("$RADKIT" --version)
# the commit whose tree ran the part (a "-dirty" suffix: with changes not
# committed), so that tables made by different builds say so
commit=$(git -C "$root" describe --always --dirty 2>/dev/null || echo unknown)
tmp=$(mktemp -d "${TMPDIR:-/tmp}/radkit-clustering.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
cp "$root/scenes/many_objects/many_objects.mtl" "$tmp/"
hdr() { sed -n "s/^# $2 = //p" "$1" | head -1; }

# slopes: least squares of log(links) and log(time) against log(faces)
slopes() {
awk -F'\t' '!/^#/ && $1 != "method" {
  m = $1; x = log($3); n[m]++; sx[m] += x; sxx[m] += x * x
  y = log($4); sy[m] += y; sxy[m] += x * y
  t = log($7); st[m] += t; sxt[m] += x * t
} END {
  printf "method\tpoints\tlinks_slope\ttime_slope\n"
  for (m in n) {
    d = n[m] * sxx[m] - sx[m] * sx[m]
    if (n[m] < 2 || d <= 0) continue
    printf "%s\t%d\t%.3f\t%.3f\n", m, n[m], (n[m] * sxy[m] - sx[m] * sy[m]) / d, (n[m] * sxt[m] - sx[m] * st[m]) / d
  }
}' "$@"
}

# table_head FILE EXPERIMENT NOTE COLUMNS: a data table's header lines (the
# columns tab-separated in COLUMNS)
table_head() {
  {
    echo "# experiment = $2"
    echo "# generator = $version, commit $commit; machine = $(sh "$root/scripts/machine.sh")"
    echo "# $3"
    printf '%s\n' "$4"
  } > "$1"
}

# scaling_row LABEL BOXES: the scaling tables' columns of the run in $tmp/t.tsv
scaling_row() {
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s' "$1" "$2" "$(hdr $tmp/t.tsv faces)" \
    "$(hdr $tmp/t.tsv links)" "$(hdr $tmp/t.tsv links_cluster)" "$(hdr $tmp/t.tsv elements)" \
    "$(hdr $tmp/t.tsv time_total_s)" "$(hdr $tmp/t.tsv memory_peak_bytes)" \
    "$(hdr $tmp/t.tsv error_estimate)"
}

# method_args METHOD: the solve options of a method label
method_args() {
  case "$1" in
    hier) echo "--method hier --clustering off" ;;
    cluster) echo "--method cluster" ;;
    cluster-iso) echo "--method cluster --cluster-model iso" ;;
    cluster-defaults) echo "--method cluster" ;;
    cluster-eps-K0) echo "--method cluster --max-tighten 0" ;;
  esac
}

# The scaling tables' header lines after the experiment's, and a row:
# scaling_run LABEL BOXES TABLE solves the room of BOXES boxes
# ($tmp/boxes_BOXES.obj, made on first use) with LABEL's options at eps EPS
# and appends its row (none where the solve fails).
scaling_note="links: pairs coupled (links_cluster of them with a cluster at one end); time: time_total_s; memory: memory_peak_bytes"
scaling_cols="method	boxes	faces	links	links_cluster	elements	time_s	memory_bytes	estimate"
scaling_run() {
  [ -s "$tmp/boxes_$2.obj" ] || python3 "$root/scenes/gen/many_objects.py" "$2" > "$tmp/boxes_$2.obj"
  echo "clustering: $1, $2 boxes" >&2
  # shellcheck disable=SC2046
  "$RADKIT" solve "$tmp/boxes_$2.obj" $(method_args "$1") --eps "$EPS" --quiet \
    --out "$tmp/t.tsv" 2>/dev/null || true
  [ -s "$tmp/t.tsv" ] || return 0
  { scaling_row "$1" "$2"; echo; } >> "$3"
  rm -f "$tmp/t.tsv"
}

if want scaling; then
dat=data/scaling.dat
table_head "$dat" "clustering: rooms of N boxes (scenes/gen/many_objects.py), eps $EPS" \
  "$scaling_note" "$scaling_cols"
for n in $SIZES; do
  for m in hier cluster cluster-iso; do
    if [ "$m" = hier ] && [ "$n" -gt "$HIER_MAX" ]; then continue; fi
    scaling_run "$m" "$n" "$dat"
  done
done
slopes "$dat" > data/slopes.dat
for f in data/scaling_range.dat data/scaling_loose.dat; do
  [ -s "$f" ] && slopes "$f" | sed 1d >> data/slopes.dat
done
fi
if want range; then
dat=data/scaling_range.dat
table_head "$dat" "clustering in issue 17's slope range: rooms of N boxes, cluster (oriented) at eps $EPS, the defaults (cluster-defaults) and without tightening (cluster-eps-K0: --max-tighten 0)" \
  "$scaling_note" "$scaling_cols"
for n in $RANGE_SIZES; do scaling_run cluster-defaults "$n" "$dat"; done
for n in $RANGE_SIZES_K0; do scaling_run cluster-eps-K0 "$n" "$dat"; done
sed -i '/^cluster-defaults/d; /^cluster-eps-K0/d' data/slopes.dat 2>/dev/null || true
slopes "$dat" | sed 1d >> data/slopes.dat
fi
if want loose; then
dat=data/scaling_loose.dat
table_head "$dat" "clustering at a preview setting: rooms of N boxes, cluster (oriented) at eps $LOOSE_EPS, --max-tighten $LOOSE_TIGHTEN" \
  "$scaling_note; error, worst, power: radkit compare against experiments/reference/data/many_343.tsv (343 boxes only)" \
  "$scaling_cols	error	worst	power"
for n in $LOOSE_SIZES; do
  python3 "$root/scenes/gen/many_objects.py" "$n" > "$tmp/boxes_$n.obj"
  # the fastest of LOOSE_REPEAT runs (the answer is the same each time;
  # other work on the machine slows a run down, never speeds it up)
  best=
  r=0
  while [ "$r" -lt "$LOOSE_REPEAT" ]; do
    r=$((r + 1))
    echo "clustering: preview setting, $n boxes, run $r of $LOOSE_REPEAT" >&2
    "$RADKIT" solve "$tmp/boxes_$n.obj" --method cluster --eps "$LOOSE_EPS" \
      --max-tighten "$LOOSE_TIGHTEN" --quiet --out "$tmp/r.tsv" 2>/dev/null || true
    [ -s "$tmp/r.tsv" ] || continue
    t=$(hdr $tmp/r.tsv time_total_s)
    if [ -z "$best" ] || awk -v a="$t" -v b="$best" 'BEGIN { exit !(a < b) }'; then
      best=$t
      mv "$tmp/r.tsv" "$tmp/t.tsv"
    fi
  done
  [ -s "$tmp/t.tsv" ] || continue
  err="-\t-\t-"
  if [ "$n" = 343 ]; then
    (cd "$root" && "$RADKIT" compare scenes/many_objects/many_343.obj "$tmp/t.tsv" \
      experiments/reference/data/many_343.tsv) > "$tmp/c.txt"
    err="$(hdr $tmp/c.txt error_l1)\t$(hdr $tmp/c.txt error_worst)\t$(hdr $tmp/c.txt error_power)"
  fi
  { scaling_row cluster-preview "$n"; printf "\t$err\n"; } >> "$dat"
  rm -f "$tmp/t.tsv"
done
sed -i '/^cluster-preview/d' data/slopes.dat 2>/dev/null || true
slopes "$dat" | sed 1d >> data/slopes.dat
fi
if want target; then
dat=data/target.dat
tdat=data/target_time.dat
table_head "$tdat" "where the target part's time goes (the rows of data/target.dat)" \
  "seconds from the solve's # lines: link, refine, solve (its phases); estimate_cluster and estimate_element: estimating links with a cluster at one end and between elements (inside link and refine); bound: the error transport (inside solve); steps: gather/push-pull steps of the solves and of the transport; local_cluster: the share of the leaves' local errors of F that cluster links bring (error_local_cluster)" \
  "method	boxes	time_s	link_s	refine_s	solve_s	estimate_cluster_s	estimate_element_s	bound_s	steps	steps_bound	rays	local_cluster"
table_head "$dat" "clustering at the target size and beyond: rooms of $TARGET_BOXES boxes, cluster (oriented) at eps $LOOSE_EPS, --max-tighten $LOOSE_TIGHTEN (cluster-preview), and of $COARSE_BOXES boxes at eps $COARSE_EPS, --max-tighten 0 (cluster-coarse) (issue 17: 120k triangles in under 120 s and 6 GB; the goal 1.2M in 60 s and 8 GB)" \
  "$scaling_note" "$scaling_cols"
target_row() { # LABEL BOXES EPS MAX_TIGHTEN
  label=$1 n=$2 eps=$3 tighten=$4
  python3 "$root/scenes/gen/many_objects.py" "$n" > "$tmp/boxes_target.obj"
  echo "clustering: $label, $n boxes" >&2
  start=$(date +%s)
  code=0
  set --
  [ -x /usr/bin/time ] && set -- /usr/bin/time -f %M -o "$tmp/rss"
  "$@" "$RADKIT" solve "$tmp/boxes_target.obj" --method cluster --eps "$eps" --max-tighten "$tighten" \
    --max-links "$TARGET_MAX_LINKS" --quiet --out "$tmp/t.tsv" 2>"$tmp/err" || code=$?
  if [ "$code" -eq 0 ] && [ -s "$tmp/t.tsv" ]; then
    { scaling_row "$label" "$n"; echo; } >> "$dat"
    printf '%s\t%s' "$label" "$n" >> "$tdat"
    for k in time_total_s time_link_s time_refine_s time_solve_s time_estimate_cluster_s \
      time_estimate_element_s time_bound_s iterations iterations_bound rays error_local_cluster; do
      printf '\t%s' "$(hdr $tmp/t.tsv $k)" >> "$tdat"
    done
    echo >> "$tdat"
  else
    rss=$(tail -n 1 "$tmp/rss" 2>/dev/null || echo "?")
    echo "# refused ($label): $n boxes, exit $code after $(($(date +%s) - start)) s, max RSS $rss kB: $(grep '^radkit' "$tmp/err" | head -c 400)" >> "$dat"
  fi
  rm -f "$tmp/t.tsv" "$tmp/err" "$tmp/rss" "$tmp/boxes_target.obj"
}
for n in $TARGET_BOXES; do target_row cluster-preview "$n" "$LOOSE_EPS" "$LOOSE_TIGHTEN"; done
for n in $COARSE_BOXES; do target_row cluster-coarse "$n" "$COARSE_EPS" 0; done
fi
if want pays; then
dat=data/pays.dat
table_head "$dat" "clustering: when the layer pays, --method hier with --clustering off and on" \
  "pairs: the facing pairs of input triangles hier links first (radkit info); setting: default (eps 0.1) or preview (eps $LOOSE_EPS, --max-tighten $LOOSE_TIGHTEN); time: time_total_s; memory: memory_peak_bytes" \
  "scene	faces	pairs	setting	clustering	links	time_s	memory_bytes"
pays_row() { # SCENE_FILE NAME SETTING CLUSTERING [solve options]
  f=$1 name=$2 setting=$3 c=$4
  shift 4
  echo "clustering: when it pays, $name, $setting, clustering $c" >&2
  "$RADKIT" solve "$f" --method hier --clustering "$c" "$@" --quiet --out "$tmp/t.tsv" 2>/dev/null || true
  [ -s "$tmp/t.tsv" ] || return 0
  "$RADKIT" info "$f" > "$tmp/info.txt" 2>/dev/null || true
  total=$(hdr $tmp/info.txt pairs_total) away=$(hdr $tmp/info.txt pairs_facing_away)
  facing=-
  [ -n "$total" ] && [ -n "$away" ] && facing=$((total - away))
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$(hdr $tmp/t.tsv faces)" "$facing" "$setting" "$c" \
    "$(hdr $tmp/t.tsv links)" "$(hdr $tmp/t.tsv time_total_s)" "$(hdr $tmp/t.tsv memory_peak_bytes)" >> "$dat"
  rm -f "$tmp/t.tsv"
}
for s in 2 3; do
  for c in off on; do pays_row "$root/scenes/sphere/sphere_$s.obj" "sphere_$s" default "$c"; done
done
for n in $PAYS_BOXES; do
  python3 "$root/scenes/gen/many_objects.py" "$n" > "$tmp/boxes_$n.obj"
  for c in off on; do pays_row "$tmp/boxes_$n.obj" "boxes_$n" default "$c"; done
done
for n in $PAYS_LOOSE_BOXES; do
  python3 "$root/scenes/gen/many_objects.py" "$n" > "$tmp/boxes_$n.obj"
  for c in off on; do
    pays_row "$tmp/boxes_$n.obj" "boxes_$n" preview "$c" --eps "$LOOSE_EPS" --max-tighten "$LOOSE_TIGHTEN"
  done
done
fi
if want accuracy; then
acc=data/accuracy.dat
{
  echo "# experiment = clustering accuracy against the Monte Carlo references (experiments/reference)"
  echo "# generator = $version, commit $commit; machine = $(sh "$root/scripts/machine.sh")"
  echo "# error, worst, power: error_l1, error_worst, error_power of radkit compare; estimate: the run's error_estimate"
  printf 'scene\tmethod\teps\tlinks\tlinks_cluster\terror\tworst\tpower\testimate\ttime_s\tmax_tighten\n'
} > "$acc"
for scene in cornell/cornell many_objects/many_64 many_objects/many_343 many_objects/many_1000; do
  name=$(basename "$scene")
  list=$EPS_ACC
  [ "$name" = many_64 ] && list="$EPS_ACC $EPS_FINE"
  [ "$name" = many_343 ] && list=$EPS_ROOM
  [ "$name" = many_1000 ] && list=$EPS_LARGE
  for item in $list; do
    e=${item%%:*}
    k=3
    case "$item" in *:*) k=${item#*:} ;; esac
    methods="hier cluster cluster-iso"
    [ "$e" = "$EPS_FINE" ] || [ "$name" = many_343 ] || [ "$name" = many_1000 ] && methods=cluster
    for m in $methods; do
      echo "clustering: $name, $m, eps $e, --max-tighten $k" >&2
      # shellcheck disable=SC2046
      (cd "$root" && "$RADKIT" solve "scenes/$scene.obj" $(method_args "$m") --eps "$e" \
        --max-tighten "$k" --quiet --out "$tmp/t.tsv" 2>/dev/null) || true
      [ -s "$tmp/t.tsv" ] || continue
      (cd "$root" && "$RADKIT" compare "scenes/$scene.obj" "$tmp/t.tsv" \
        "experiments/reference/data/$name.tsv") > "$tmp/c.txt"
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$name" "$m" "$e" \
        "$(hdr $tmp/t.tsv links)" "$(hdr $tmp/t.tsv links_cluster)" "$(hdr $tmp/c.txt error_l1)" \
        "$(hdr $tmp/c.txt error_worst)" "$(hdr $tmp/c.txt error_power)" \
        "$(hdr $tmp/t.tsv error_estimate)" "$(hdr $tmp/t.tsv time_total_s)" "$k" >> "$acc"
      rm -f "$tmp/t.tsv"
    done
  done
done
fi

if want tighten; then
tig=data/tighten.dat
table_head "$tig" "clustering: what the oracle's tightening buys on many_343 (cluster, eps $EPS_TIGHTEN, --max-tighten K)" \
  "error, worst, power: error_l1, error_worst, error_power of radkit compare against experiments/reference/data/many_343.tsv; estimate: the run's error_estimate (worst face), estimate_l1 its area-weighted mean; tightenings, tightened_share: how often the oracle quartered thresholds and over what share of the area, summed" \
  "max_tighten	links	links_cluster	error	worst	power	estimate	estimate_l1	time_s	tightenings	tightened_share"
for k in $TIGHTEN; do
  echo "clustering: many_343, cluster, eps $EPS_TIGHTEN, --max-tighten $k" >&2
  (cd "$root" && "$RADKIT" solve scenes/many_objects/many_343.obj --method cluster \
    --eps "$EPS_TIGHTEN" --max-tighten "$k" --quiet --out "$tmp/t.tsv" 2>/dev/null) || true
  [ -s "$tmp/t.tsv" ] || continue
  (cd "$root" && "$RADKIT" compare scenes/many_objects/many_343.obj "$tmp/t.tsv" \
    experiments/reference/data/many_343.tsv) > "$tmp/c.txt"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$k" "$(hdr $tmp/t.tsv links)" \
    "$(hdr $tmp/t.tsv links_cluster)" "$(hdr $tmp/c.txt error_l1)" "$(hdr $tmp/c.txt error_worst)" \
    "$(hdr $tmp/c.txt error_power)" "$(hdr $tmp/t.tsv error_estimate)" \
    "$(hdr $tmp/t.tsv error_estimate_l1)" "$(hdr $tmp/t.tsv time_total_s)" \
    "$(hdr $tmp/t.tsv tightenings)" "$(hdr $tmp/t.tsv tightened_share)" >> "$tig"
  rm -f "$tmp/t.tsv"
done
fi

# 4. Furnaces: a room of FURNACE_BOXES boxes where every surface emits 1 and
#    reflects FURNACE_RHO (B = 1 / (1 - rho) everywhere), cluster at eps
#    FURNACE_EPS: the largest and the area-weighted mean relative error of
#    the faces, links and time.
if want furnace; then
  fur=data/furnace.dat
  {
    echo "# experiment = clustering furnaces: rooms of boxes, every surface E = 1, rho = $FURNACE_RHO (exact B = 1 / (1 - rho))"
    echo "# generator = $version, commit $commit; machine = $(sh "$root/scripts/machine.sh")"
    printf 'boxes\tfaces\teps\tlinks\tlinks_cluster\ttime_s\tmemory_bytes\tmax_error\tmean_error\n'
  } > "$fur"
  mkdir -p "$tmp/furnace"
  printf 'newmtl %s\nKd %s %s %s\nKe 1 1 1\n' wall $FURNACE_RHO $FURNACE_RHO $FURNACE_RHO \
    ceiling $FURNACE_RHO $FURNACE_RHO $FURNACE_RHO object $FURNACE_RHO $FURNACE_RHO $FURNACE_RHO \
    > "$tmp/furnace/many_objects.mtl"
  for n in $FURNACE_BOXES; do
    echo "clustering: furnace of $n boxes, eps $FURNACE_EPS" >&2
    python3 "$root/scenes/gen/many_objects.py" "$n" > "$tmp/furnace/f.obj"
    "$RADKIT" solve "$tmp/furnace/f.obj" --method cluster --eps "$FURNACE_EPS" --quiet \
      --out "$tmp/t.tsv" 2>/dev/null || true
    [ -s "$tmp/t.tsv" ] || continue
    errs=$(awk -v rho="$FURNACE_RHO" '!/^#/ && $1 != "face" {
        b = 1 / (1 - rho); for (c = 3; c <= 5; c++) { d = ($c - b) / b; if (d < 0) d = -d
        if (d > m) m = d; s += $2 * d; a += $2 } }
      END { printf "%.3e\t%.3e", m, s / a }' "$tmp/t.tsv")
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$n" "$(hdr $tmp/t.tsv faces)" "$FURNACE_EPS" \
      "$(hdr $tmp/t.tsv links)" "$(hdr $tmp/t.tsv links_cluster)" "$(hdr $tmp/t.tsv time_total_s)" \
      "$(hdr $tmp/t.tsv memory_peak_bytes)" "$errs" >> "$fur"
    rm -f "$tmp/t.tsv"
  done
fi
if want picture; then
  echo "clustering: the room of 1 000 boxes (scripts/demo_large.sh)" >&2
  (cd "$root" && BOXES=1000 sh scripts/demo_large.sh "$RADKIT") | grep '^ ' > data/room_1000.txt
  cp "$root/build/demo/room_1000.png" figures/room_1000.png
fi
if command -v gnuplot > /dev/null; then gnuplot plot.gp; fi
# gnuplot's PDFs carry their creation time: a fixed one, so that a re-run
# changes only what it measured.
find figures -name '*.pdf' -exec perl -pi -e 's/(CreationDate \(D:)\d{14}/${1}20000101000000/' {} +
echo "clustering: data/scaling.dat, data/scaling_loose.dat, data/target.dat, data/target_time.dat, data/pays.dat, data/slopes.dat, data/accuracy.dat, data/tighten.dat, data/furnace.dat, data/room_1000.txt, figures/scaling.png, figures/room_1000.png" >&2
