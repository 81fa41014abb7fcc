#!/usr/bin/env bash
# Regenerates the raw-log figures of docs/NOTES.md ("Front end", "Loop closures"): for fr079, intel and aces,
# the raw log scan-matched into submaps (partslam submaps --scan-match), loop closures among them checked
# against the corrected twin (partslam loops --truth), written to docs/results/loops_LOG.{json,png}.
# Usage: scripts/make-loops.sh [THREADS=2]. Needs ../shared/data and build/partslam.
set -euo pipefail
cd "$(dirname "$0")/.."
THREADS=${1:-2}
DATA=../shared/data
OUT=docs/results
[ -d "$DATA" ] || { echo "make-loops: $DATA not found (the real data sets are needed)" >&2; exit 1; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
for log in fr079 intel aces; do
  echo "== $log"
  build/partslam submaps "$DATA/$log/$log.clf.gz" --scan-match --quiet --db "$TMP/$log.db"
  build/partslam loops "$TMP/$log.db" --truth "$DATA/$log/$log-corrected.log.gz" --threads "$THREADS" --quiet \
    --json "$OUT/loops_$log.json" --plot "$OUT/loops_$log.png"
done
