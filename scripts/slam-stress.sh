#!/usr/bin/env bash
# The SLAM stress bench (make slam-stress; docs/NOTES.md "Real logs degraded"): `slam` with its defaults on the raw
# logs that have a relations file (mit-csail, fr079, intel, aces), each as recorded and degraded as another robot's
# sensors would be (scripts/log_variants.py: every second beam, every second scan, miscalibrated wheel odometry, an
# 8 m laser, half of the returns lost, odometry that turns as it drives straight, scans posed 0.1 s late, 3 cm of
# range noise), judged by
# the log's relations. Real scans and real odometry errors, unlike
# the drifted twins: where a variant breaks the map, the verdict must say so.
# Writes docs/results/slam_stress.jsonl (one build/slam_bench line per run) and docs/results/slam_stress.md.
# Usage: scripts/slam-stress.sh; RAW="aces fr079" VARIANTS="short-range" OUT=DIR narrow it. Needs ../shared/data.
set -euo pipefail
cd "$(dirname "$0")/.."
DATA=../shared/data
OUT=${OUT:-docs/results}
RAW=${RAW-mit-csail fr079 intel aces}
VARIANTS=${VARIANTS-as-recorded half-beams half-rate odometry-scale short-range sparse odometry-curve laser-lag range-noise}
BIN=${BIN:-build/slam_bench}
[ -d "$DATA" ] || { echo "slam-stress: $DATA not found (the real data sets are needed)" >&2; exit 1; }
[ -x "$BIN" ] || { echo "slam-stress: $BIN not built (make build)" >&2; exit 1; }
mkdir -p "$OUT"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
for log in $RAW; do
  dir=$DATA/$log
  [ "$log" = mit-csail ] && dir=$DATA/csail
  for variant in $VARIANTS; do
    input=$dir/$log.clf.gz
    if [ "$variant" != as-recorded ]; then
      input=$WORK/$log.$variant.clf.gz
      /usr/bin/python3 scripts/log_variants.py "$dir/$log.clf.gz" "$input" "$variant"
    fi
    echo "== slam_bench raw $log $variant" >&2
    "$BIN" raw "$input" - "$dir/$log.relations" >> "$WORK/runs.jsonl"
    rm -f "$WORK/$log.$variant.clf.gz"
  done
done
mv "$WORK/runs.jsonl" "$OUT/slam_stress.jsonl"
/usr/bin/python3 scripts/slam_stress_table.py "$OUT/slam_stress.jsonl" > "$OUT/slam_stress.md"
cat "$OUT/slam_stress.md"
