#!/usr/bin/env bash
# slam's resolution on the raw logs (make slam-resolution; docs/NOTES.md "The bench's resolution"): `slam` with its
# defaults on each raw log that has a relations file as recorded and moved rigidly as a whole
# (scripts/log_variants.py moved-1 .. moved-4: every pose turned and shifted, so nothing a relation measures
# changes). The spread of the relation errors is what a change of a few tenths of a millimetre on one log is
# worth: the grids' cells fall elsewhere on the same scans.
# Writes docs/results/slam_resolution.jsonl (one build/slam_bench line per run) and docs/results/slam_resolution.md.
# Usage: scripts/slam-resolution.sh; RAW="aces" MOVES="1 2" OUT=DIR narrow it. Needs ../shared/data.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${OUT:-docs/results}
MOVES=${MOVES-1 2 3 4}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
VARIANTS=as-recorded
for k in $MOVES; do VARIANTS+=" moved-$k"; done
VARIANTS="$VARIANTS" OUT="$WORK" bash scripts/slam-stress.sh > /dev/null
mkdir -p "$OUT"
mv "$WORK/slam_stress.jsonl" "$OUT/slam_resolution.jsonl"
/usr/bin/python3 scripts/slam_resolution_table.py "$OUT/slam_resolution.jsonl" > "$OUT/slam_resolution.md"
cat "$OUT/slam_resolution.md"
