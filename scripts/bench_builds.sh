#!/bin/sh
# scripts/bench_builds.sh OLD NEW: two builds of radkit side by side on the
# clustering goal's run (1.2M triangles: 100 000 boxes at eps 3, --max-tighten 0), their runs
# alternated RUNS times (default 2), so that both meet the same state of a
# shared host; a table row is one run.  Build OLD from a commit in a scratch
# worktree (git worktree add /tmp/old COMMIT && make -C /tmp/old
# build/radkit).  OLD_LABEL and NEW_LABEL name them (default: the paths);
# BOXES sets the room (default 100000).  Writes bench/builds.tsv and prints
# it (about 4 minutes a pair of runs at the default size).  Not part of
# make bench, which runs one build.
set -eu
OLD=${1:?usage: scripts/bench_builds.sh OLD_RADKIT NEW_RADKIT}
NEW=${2:?usage: scripts/bench_builds.sh OLD_RADKIT NEW_RADKIT}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
RUNS=${RUNS:-2}
BOXES=${BOXES:-100000}
OLD_LABEL=${OLD_LABEL:-$OLD}
NEW_LABEL=${NEW_LABEL:-$NEW}
for b in "$OLD" "$NEW"; do
  [ -x "$b" ] || { echo "scripts/bench_builds.sh: $b is not an executable radkit" >&2; exit 2; }
done
tmp=$(mktemp -d "${TMPDIR:-/tmp}/radkit-builds.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
python3 "$ROOT/scenes/gen/many_objects.py" "$BOXES" > "$tmp/room.obj"
cp "$ROOT/scenes/many_objects/many_objects.mtl" "$tmp/"
out=$ROOT/bench/builds.tsv
{
  echo "# experiment = two builds alternated on $BOXES boxes, --method cluster --eps 3 --max-tighten 0"
  echo "# machine = $(sh "$ROOT/scripts/machine.sh")"
  printf 'build\trun\ttime_s\tsolve_s\trefine_s\tlink_s\tsteps\tlinks\tmemory_bytes\n'
} > "$out"
hdr() { sed -n "s/^# $2 = //p" "$1" | head -1; }
r=1
while [ "$r" -le "$RUNS" ]; do
  for which in old new; do
    if [ "$which" = old ]; then bin=$OLD; label=$OLD_LABEL; else bin=$NEW; label=$NEW_LABEL; fi
    echo "scripts/bench_builds.sh: $label, run $r" >&2
    "$bin" solve "$tmp/room.obj" --method cluster --eps 3 --max-tighten 0 \
      --max-links 200000000 --out "$tmp/t.tsv" --quiet
    t=$tmp/t.tsv
    printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$label" "$r" "$(hdr "$t" time_total_s)" \
      "$(hdr "$t" time_solve_s)" "$(hdr "$t" time_refine_s)" "$(hdr "$t" time_link_s)" \
      "$(hdr "$t" iterations)" "$(hdr "$t" links)" "$(hdr "$t" memory_peak_bytes)" >> "$out"
  done
  r=$((r + 1))
done
cat "$out"
