#!/usr/bin/env bash
# Issue 21's locate check: for each corrected log in ../shared, the building map (partslam export-map), its
# stored maps (partslam submaps), and N of them (evenly spaced ids) exported in the world frame (partslam export
# --frame world) and located in the building map (partslam locate --query-points). The truth is the identity
# (the world frame is the map's), so the pose error is the located frame itself: its rotation, and how far it
# moves the stored map's points (their centre). The world origin's move is printed too ("at origin"): it adds the
# rotation times the distance to the origin (tens of metres), which says nothing about where the map was placed.
# Writes docs/results/locate_stored.txt: one line per located map, then the share within 0.1 m / 1 degree.
# Usage: scripts/check-locate-stored.sh [N=8]. Needs ../shared/data and build/partslam (about 4 min).
set -euo pipefail
cd "$(dirname "$0")/.."
N=${1:-8}
DATA=../shared/data
BIN=build/partslam
OUT=docs/results/locate_stored.txt
[ -d "$DATA" ] || { echo "check-locate-stored: $DATA not found (the real data sets are needed)" >&2; exit 1; }
[ -x "$BIN" ] || { echo "check-locate-stored: $BIN not built (make build)" >&2; exit 1; }
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
logs=()
for b in fr079 fr101 intel aces; do logs+=("$DATA/$b/$b-corrected.log.gz"); done
for f in "$DATA"/corrected/*-corrected.log.gz; do logs+=("$f"); done
for log in "${logs[@]}"; do
  b=$(basename "$log" -corrected.log.gz)
  "$BIN" export-map "$log" --out "$TMP/$b.yaml" > /dev/null
  "$BIN" submaps "$log" --db "$TMP/$b.db" --quiet > /dev/null
  n=$("$BIN" info "$TMP/$b.db" --json | /usr/bin/python3 -c "import json, sys; print(json.load(sys.stdin)['datasets'][0]['submaps'])")
  for k in $(seq 0 $((N - 1))); do
    id=$(((2 * k + 1) * n / (2 * N) + 1))
    "$BIN" export "$TMP/$b.db" --map "$id" --format csv --frame world --out "$TMP/q.csv" > /dev/null
    "$BIN" locate --map "$TMP/$b.yaml" --query-points "$TMP/q.csv" --json "$TMP/l.json" --quiet > /dev/null
    /usr/bin/python3 - "$b" "$id" "$TMP/l.json" "$TMP/q.csv" <<'PY'
import csv, json, math, sys
l = json.load(open(sys.argv[3]))["located"][0]
p = l["T_map_source"]  # the point file's frame (the world) in the map: the identity when located right
xy = [(float(r[0]), float(r[1])) for r in csv.reader(l for l in open(sys.argv[4]) if l[:1] not in "#xX")]
cx, cy = sum(x for x, _ in xy) / len(xy), sum(y for _, y in xy) / len(xy)
c, s = math.cos(p["theta"]), math.sin(p["theta"])
e = math.hypot(c * cx - s * cy + p["x"] - cx, s * cx + c * cy + p["y"] - cy)  # the points' centre moved by it
e0, a = math.hypot(p["x"], p["y"]), abs(math.degrees(p["theta"]))
verdict = "within" if e < 0.1 and a < 1.0 else "off"
print(f"{sys.argv[1]:18s} map {sys.argv[2]:5s} err {e:7.3f} m {a:6.2f} deg  at origin {e0:7.3f} m  inliers "
      f"{l['inlier_fraction']:.3f}  confidence {l['confidence']:.2f} {'(confident)' if l['confident'] else '           '}"
      f"  p {l['probability']:.3f}  {verdict}")
PY
  done
done > "$TMP/lines.txt"
{
  cat "$TMP/lines.txt"
  /usr/bin/python3 - "$TMP/lines.txt" <<'PY'
import re, sys
rows = [re.search(r"err +([\d.]+) m +([\d.]+) deg +at origin +([\d.]+) m.*confidence ([\d.]+) (\(confident\))?", l)
        for l in open(sys.argv[1])]
origin = sum(float(m.group(3)) < 0.1 and float(m.group(2)) < 1.0 for m in rows if m)
rows = [(float(m.group(1)), float(m.group(2)), m.group(5) is not None) for m in rows if m]
within = sum(e < 0.1 and a < 1.0 for e, a, c in rows)
far = [(e, a, c) for e, a, c in rows if e > 2.0 or a > 5.0]
near = [(e, a, c) for e, a, c in rows if not (e < 0.1 and a < 1.0) and (e, a, c) not in far]
print(f"within 0.1 m / 1 deg: {within} of {len(rows)} ({origin} at the world origin); more than 2 m / 5 deg off: {len(far)} "
      f"({sum(c for *_, c in far)} confident); between: {len(near)} ({sum(c for *_, c in near)} confident)")
PY
} > "$OUT"
tail -1 "$OUT"
