#!/usr/bin/env bash
# Tracking a run in a map made from another file of the same run (docs/NOTES.md, "Tracking the same run from another
# file"): `partslam slam` of each raw CARMEN log (fr079, intel, aces) makes the map; `partslam locate --track
# --scan-match` follows the same run read from its ROS 1 bag (and fr079's ROS 2 MCAP); scripts/track_other_recording.py
# pairs each step's robot pose with slam's corrected pose of the same scan -> docs/results/track_other_recording.jsonl
# and the table between docs/USAGE.md's other-recording markers.
# Usage: scripts/track-other-recording.sh [SLAM_RUNS] (about 2 minutes on 2 cores). Needs ../shared/data and build/
# (with its Python module). SLAM_RUNS: a folder whose slam-NAME/ holds a `partslam slam` run of NAME's raw log made
# by this build (make-relocalisation.sh's aces), used instead of mapping that log again.
set -euo pipefail
cd "$(dirname "$0")/.."
DATA=../shared/data
OUT=docs/results
[ -d "$DATA" ] || { echo "track-other-recording: $DATA not found (the real data sets are needed)" >&2; exit 1; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
RUNS=${1:-}
specs=()
for name in fr079 intel aces; do
  log=$DATA/$name/$name.clf.gz
  if [ -n "$RUNS" ] && [ -s "$RUNS/slam-$name/corrected.log" ] && [ -s "$RUNS/slam-$name/map.yaml" ]; then
    ln -s "$(realpath "$RUNS/slam-$name")" "$TMP/$name"
  else
    build/partslam slam "$log" --out "$TMP/$name" --threads 2 --quiet > "$TMP/$name.slam.txt" 2>&1 || {
      status=$?; [ $status -eq 3 ] || { cat "$TMP/$name.slam.txt" >&2; exit $status; }; }
  fi
  bags=("$DATA/bags/$name.clf2bag.bag")
  [ -f "$DATA/bags/$name.mcap" ] && bags+=("$DATA/bags/$name.mcap")
  for bag in "${bags[@]}"; do
    json=$TMP/$(basename "$bag").json
    build/partslam locate --map "$TMP/$name/map.yaml" --query-log "$bag" --scan-match --track --quiet --json "$json" \
      > /dev/null
    specs+=("$name:$log:$bag:$TMP/$name:$json")
  done
done
/usr/bin/python3 scripts/track_other_recording.py --readme docs/USAGE.md --out "$OUT/track_other_recording.jsonl" \
  "${specs[@]}" | sed "s|$DATA/||g"
