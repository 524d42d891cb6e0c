#!/bin/sh
# make demo-large: what clustering is for.  A closed 10 m room (the ceiling
# emitting) holding BOXES small cubes (scenes/gen/many_objects.py; 12 BOXES +
# 12 triangles), solved by hierarchical radiosity through the cluster
# hierarchy (--method cluster --eps EPS --max-tighten TIGHTEN), then drawn
# from just inside one wall.  Linking every pair of triangles first, as
# plain hier does, would start from (12 BOXES)^2 / 2 pairs; the cluster
# hierarchy starts from one link per sibling pair of its tree.  The default
# room of 1 000 boxes is scenes/many_objects/many_1000.obj, which has a Monte
# Carlo reference: the run is then measured against it, so the picture comes
# with its error.  About a minute on 2 cores (papers/clustering.md has the
# figures); `make demo` stays quick and does not run it.
set -eu
RADKIT=${1:-build/radkit}
BOXES=${BOXES:-1000}
EPS=${EPS:-0.1}
TIGHTEN=${TIGHTEN:-0}
out=build/demo
mkdir -p "$out"
scene="$out/room_$BOXES.obj"
{
  echo "# radkit camera position 5 4 0.02 look_at 5 5 10 up 0 1 0 fov_y 75"
  python3 scenes/gen/many_objects.py "$BOXES"
} > "$scene"
cp scenes/many_objects/many_objects.mtl "$out/"
echo "radkit demo (large): a room of $BOXES boxes, $((12 * BOXES + 12)) triangles," \
  "--method cluster --eps $EPS --max-tighten $TIGHTEN"
"$RADKIT" solve "$scene" --method cluster --eps "$EPS" --max-tighten "$TIGHTEN" \
  --png "$out/room_$BOXES.png" --stats "$out/room_$BOXES.json" --out "$out/room_$BOXES.tsv"
awk -F' = ' '/^# (faces|elements|clusters|links|links_cluster|rays|error_estimate|error_estimate_l1|time_[a-z]+_s|memory_peak_bytes) = /{
  printf "  %-24s %s\n", substr($1, 3), $2 }' "$out/room_$BOXES.tsv"
ref=experiments/reference/data/many_$BOXES.tsv
if [ -s "$ref" ] && [ -s "scenes/many_objects/many_$BOXES.obj" ]; then
  # the same room (same generator and seed): its error against Monte Carlo
  "$RADKIT" compare "scenes/many_objects/many_$BOXES.obj" "$out/room_$BOXES.tsv" "$ref" |
    awk -F' = ' '/^# (error_l1|error_worst|error_power|reference_se_l1) = /{
      printf "  %-24s %s\n", "mc_" substr($1, 3), $2 }'
fi
echo "  image: $out/room_$BOXES.png   stats: $out/room_$BOXES.json   per-face radiosity: $out/room_$BOXES.tsv"
