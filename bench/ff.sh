#!/bin/sh
# Form-factor throughput: pairs per second per scheme, one thread, on three
# pairs (disjoint near, edge-adjacent at 90 degrees, disjoint far).
# Usage: sh bench/ff.sh path/to/radkit   (writes bench/ff.tsv and prints it)
set -eu
RADKIT=${1:?usage: bench/ff.sh path/to/radkit}
here=$(cd "$(dirname "$0")" && pwd)
out=$here/ff.tsv
export OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1

pairs='far|0 0 0 1 0.1 0 0.2 0.9 0.05|0.3 0.2 4.1 0.5 1.2 4.3 1.5 0.1 4.0
near|0 0 0 1 0.1 0 0.2 0.9 0.05|0.1 0.2 0.31 0.3 1.2 0.5 1.3 0.1 0.22
edge90|0 0 0 1 0 0 0.35 0.85 0|0 0 0 0.55 0 0.8 1 0 0'
rules="vertex centroid gauss:2 gauss:5 gauss:10 gauss:20 analytic:5 analytic:10 analytic:20 ss:4 ss:8 ss:14 exact auto"

{
    echo "# radkit form-factor benchmark: $("$RADKIT" --version), $(uname -m), $(sh "$here/../scripts/machine.sh")"
    echo "# one thread; each entry repeats the pair for about 0.3 s (radkit ff --repeat); auto at tol 1e-6"
    printf 'pair\trule\tused\tevals\tseconds_per_pair\tpairs_per_second\tns_per_eval\n'
    echo "$pairs" | while IFS='|' read -r name t1 t2; do
        for r in $rules; do
            one=$("$RADKIT" ff --tri "$t1" --tri "$t2" --rule "$r" --repeat 3 | tail -n 1)
            sec=$(echo "$one" | cut -f5)
            rep=$(awk -v s="$sec" 'BEGIN { r = int(0.3 / (s + 1e-9)); if (r < 1) r = 1; print r }')
            "$RADKIT" ff --tri "$t1" --tri "$t2" --rule "$r" --repeat "$rep" | tail -n 1 |
                awk -F '\t' -v p="$name" '{ printf "%s\t%s\t%s\t%s\t%.3e\t%.0f\t%.1f\n", p, $1, $8, $4, $5, 1 / $5, 1e9 * $5 / ($4 > 0 ? $4 : 1) }'
        done
    done
} > "$out"
cat "$out"
