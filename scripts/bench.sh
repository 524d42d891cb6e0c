#!/bin/sh
# make bench: run every bench/*.sh with the radkit binary; each writes its own
# table bench/<name>.tsv and prints it.
set -eu
RADKIT=$(cd "$(dirname "${1:-build/radkit}")" && pwd)/$(basename "${1:-build/radkit}")
for b in bench/*.sh; do
  echo "== $b"
  sh "$b" "$RADKIT"
done
