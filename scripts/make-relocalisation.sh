#!/usr/bin/env bash
# Regenerates the relocalisation figures of docs/NOTES.md ("Locate") and docs/USAGE.md: for each corrected log, a
# map_server map of its first visit (scans before the first revisit) and every later 2 m stretch located in it
# with no initial pose (build/relocalisation_check) -> docs/results/relocalisation_LOG.txt, one line per query.
# fr079 and intel are the floor's sets (the defaults were chosen on them); the buildings of corrected/ validate.
# Then the tables (scripts/relocalisation_tables.py): per log, which it also writes into docs/USAGE.md between its
# relocalisation markers, and the in-map queries by true overlap.
# Then the tracking bench (build/tracking_check, core/evaluation/tracking.h): the same first-visit map, runs of the
# tracker from every 10 m after it with a drifted twin's odometry (mild and harsh) and one kidnapping each ->
# docs/results/tracking_LOG_NOISE.txt, and its table (scripts/tracking_table.py) into docs/USAGE.md; also three raw
# logs the tracker was never built on, mapped by `partslam slam` (its corrected poses are their truth):
# tracking_slam-LOG_NOISE.txt. Last, the same run tracked from another file (scripts/track-other-recording.sh).
# Usage: scripts/make-relocalisation.sh. Needs ../shared/data, build/relocalisation_check and build/tracking_check
# (about 6 min for relocalisation, 20 min for tracking, 2 min for the slam- rows).
set -euo pipefail
cd "$(dirname "$0")/.."
DATA=../shared/data
OUT=docs/results
[ -d "$DATA" ] || { echo "make-relocalisation: $DATA not found (the real data sets are needed)" >&2; exit 1; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
logs=("$DATA/fr079/fr079-corrected.log.gz" "$DATA/intel/intel-corrected.log.gz")
for b in acapulco belgioioso edmonton fhw freiburg-campus infinite-corridor orebro seattle; do
  logs+=("$DATA/corrected/$b-corrected.log.gz")
done
reports=()
for log in "${logs[@]}"; do
  name=$(basename "$log" -corrected.log.gz)
  build/relocalisation_check "$log" "$TMP" | sed "s|$DATA/||" > "$OUT/relocalisation_$name.txt"
  reports+=("$OUT/relocalisation_$name.txt")
done
/usr/bin/python3 scripts/relocalisation_tables.py --readme docs/USAGE.md "${reports[@]}"
tracking=()
for log in "${logs[@]}"; do
  name=$(basename "$log" -corrected.log.gz)
  for noise in mild harsh; do
    build/tracking_check "$log" "$TMP" noise=$noise | sed "s|$DATA/||" > "$OUT/tracking_${name}_$noise.txt"
    tracking+=("$OUT/tracking_${name}_$noise.txt")
  done
done
# Logs the tracker was never built on, with no corrected twin here: slam's map of the raw log is the truth
# (docs/NOTES.md, "A declaration waits for a later search"); rows slam-NAME.
for name in mit-csail aces fr101; do
  raw=$(ls "$DATA"/*/"$name.clf.gz")
  build/partslam slam "$raw" --out "$TMP/slam-$name" --threads 2 --quiet > "$TMP/slam-$name.txt" 2>&1 || {
    status=$?; [ $status -eq 3 ] || { cat "$TMP/slam-$name.txt" >&2; exit $status; }; }
  for noise in mild harsh; do
    build/tracking_check "$TMP/slam-$name/corrected.log" "$TMP" noise=$noise |
      sed "s|$TMP/slam-$name/corrected.log|slam of ${raw#"$DATA"/}|" > "$OUT/tracking_slam-${name}_$noise.txt"
    tracking+=("$OUT/tracking_slam-${name}_$noise.txt")
  done
done
/usr/bin/python3 scripts/tracking_table.py --readme docs/USAGE.md "${tracking[@]}"
bash scripts/track-other-recording.sh "$TMP"  # reuses aces's slam run above
