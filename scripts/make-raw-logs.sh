#!/usr/bin/env bash
# Regenerates the raw-log figures of docs/NOTES.md ("Front end for raw logs", "Loop closures", "SLAM"): for
# mit-csail, fr079, intel and aces, the raw log scan-matched into submaps (partslam submaps --scan-match), loop closures
# among them checked against the corrected twin (partslam loops --truth) -> docs/results/loops_LOG.{json,png}
# (the JSON without the hypothesis list, the curve thinned to 200 points);
# and the whole chain (partslam slam --relations) -> docs/results/slam_LOG.json (its slam.json: relation errors of
# the corrected and the odometry's trajectories, closures, verdict, seconds) and slam_LOG.png (the corrected map).
# Then docs/USAGE.md's raw-log table from them (scripts/raw_logs_table.py).
# Usage: scripts/make-raw-logs.sh [THREADS=2]. Needs ../shared/data and build/partslam (about 2 min).
set -euo pipefail
cd "$(dirname "$0")/.."
THREADS=${1:-2}
DATA=../shared/data
OUT=docs/results
[ -d "$DATA" ] || { echo "make-raw-logs: $DATA not found (the real data sets are needed)" >&2; exit 1; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
for log in mit-csail fr079 intel aces; do
  echo "== $log"
  dir=$DATA/$log truth=$DATA/$log/$log-corrected.log.gz
  # mit-csail: a building nothing here was tuned on; its corrected twin is kept elsewhere, so its loops are judged
  # against a reference solved from its relations (loops --truth F.relations).
  [ "$log" = mit-csail ] && dir=$DATA/csail truth=$DATA/csail/$log.relations
  build/partslam submaps "$dir/$log.clf.gz" --scan-match --quiet --db "$TMP/$log.db"
  build/partslam loops "$TMP/$log.db" --truth "$truth" --threads "$THREADS" --quiet \
    --json "$TMP/loops_$log.json" --plot "$OUT/loops_$log.png"
  # The full JSON lists every hypothesis (megabytes); docs keep the figures and the curve at <= 200 points.
  /usr/bin/python3 - "$TMP/loops_$log.json" "$OUT/loops_$log.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
e = j.get("evaluation", {})
curve = e.get("curve", [])
step = max(1, -(-len(curve) // 200))
e["curve"] = curve[::step] + ([curve[-1]] if curve and (len(curve) - 1) % step else [])
out = {k: v for k, v in j.items() if k != "closures"}
out["hypotheses_listed"] = len(j.get("closures", []))
json.dump(out, open(sys.argv[2], "w"), indent=2)
PY
  # Exit status 3: written but not trusted (the verdict, in the table); anything else non-zero is an error.
  status=0
  build/partslam slam "$dir/$log.clf.gz" --out "$TMP/slam_$log" --relations "$dir/$log.relations" \
    --threads "$THREADS" --quiet || status=$?
  [ "$status" -eq 0 ] || [ "$status" -eq 3 ] || exit "$status"
  cp "$TMP/slam_$log/slam.json" "$OUT/slam_$log.json"
  cp "$TMP/slam_$log/map.png" "$OUT/slam_$log.png"
done
/usr/bin/python3 scripts/raw_logs_table.py --readme docs/USAGE.md "$OUT"
