#!/usr/bin/env bash
# Test-time only (make test, the ctest ResultMcap.ReadByFoxglove): `partslam slam` on fr079's raw log, then its
# result.mcap read by Foxglove's readers (read-result.js, with the npm packages the ctest fixture Ros2Bags
# installed), and what they decoded compared with the files slam wrote beside it: the map cell for cell in its
# counts (map.pgm: 0 occupied, 254 free, 205 unknown), one pose per corrected scan, the used closures. Then
# `locate --every 20 --mcap` in that map along fr079's corrected log: one pose and one coloured marker per answer.
#   tests/ros2/check-result-mcap.sh BIN SHARED_DATA ROS2_BAGS_DIR
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
bin="$1" data="$2" npm="$3/npm"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
"$bin" slam "$data/fr079/fr079.clf.gz" --out "$out/fr079" --quiet > "$out/slam.txt" || {
  rc=$?; [ "$rc" = 3 ] || { cat "$out/slam.txt"; exit "$rc"; }  # 3: written, but doubtful
}
cp "$here/read-result.js" "$npm/read-result.js"  # beside node_modules, where node resolves its requires
node "$npm/read-result.js" "$out/fr079/result.mcap" > "$out/summary.json"
/usr/bin/python3 - "$out/fr079" "$out/summary.json" <<'PY'
import json, sys, pathlib
folder, summary = pathlib.Path(sys.argv[1]), json.loads(pathlib.Path(sys.argv[2]).read_text())
pgm = (folder / "map.pgm").read_bytes()
fields, at = [], 0
while len(fields) < 4:  # P5, width, height, maxval; comments skipped
    while pgm[at:at + 1].isspace(): at += 1
    if pgm[at:at + 1] == b"#":
        at = pgm.index(b"\n", at); continue
    end = at
    while not pgm[end:end + 1].isspace(): end += 1
    fields.append(pgm[at:end]); at = end
width, height, pixels = int(fields[1]), int(fields[2]), pgm[at + 1:]
m = summary["map"]
checks = {
    "map size": (m["width"], m["height"]) == (width, height),
    "occupied cells": m["occupied"] == pixels.count(0),
    "free cells": m["free"] == pixels.count(254),
    "unknown cells": m["unknown"] == pixels.count(205),
    "one pose per corrected scan": summary["slam_path"] == sum(1 for l in open(folder / "corrected.log") if l.startswith("FLASER")),
    "one transform and cloud per scan": summary["tf"] == summary["slam_path"] == summary["topics"]["/scan"]["messages"],
    "the used closures": summary["closure_points"] == 2 * sum(1 for c in json.load(open(folder / "loops.json"))["accepted"] if c["used"]),
}
for name, ok in checks.items():
    print(("ok   " if ok else "FAIL ") + name)
print(json.dumps(summary["map"]))
sys.exit(0 if all(checks.values()) else 1)
PY
"$bin" locate --map "$out/fr079/map.yaml" --query-log "$data/fr079/fr079-corrected.log.gz" --every 20 --quiet \
  --json "$out/located.json" --mcap "$out/located.mcap" > /dev/null
node "$npm/read-result.js" "$out/located.mcap" > "$out/located_summary.json"
/usr/bin/python3 - "$out/located.json" "$out/located_summary.json" <<'PY'
import json, sys
answers, summary = len(json.load(open(sys.argv[1]))["located"]), json.load(open(sys.argv[2]))
ok = answers > 5 and summary["located_path"] == summary["located_points"] == summary["located_colours"] == answers
print(("ok   " if ok else "FAIL ") + f"locate --mcap: {answers} answers, {summary['located_path']} poses")
sys.exit(0 if ok else 1)
PY
