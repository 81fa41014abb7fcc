#!/usr/bin/env bash
# The hostile inputs of issue "reliability", each beside the same input without the bad line: exit code, peak
# memory (max RSS, /usr/bin/time) and wall time of the command, and the first line of its error. Fails when a
# hostile run crashes (exit code other than 0 or 1), prints no error when it fails, or takes more than twice the
# memory of its clean run (the issue's floor). The gzip bomb has no clean twin: its memory is printed as it is.
# Usage: scripts/check-hostile-inputs.sh PARTSLAM_BINARY [CORRECTED_LOG]   (default: fr079 from ../shared/data)
set -euo pipefail
BIN=$(realpath "$1")
LOG=$(realpath "${2:-$(dirname "$0")/../../shared/data/fr079/fr079-corrected.log.gz}")
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
cd "$TMP"

zcat -f "$LOG" > clean.log
# The FLASER line half-way through; x is the field after the ranges (FLASER n r1..rn x y theta ...).
half=$(( $(grep -c '^FLASER' clean.log) / 2 ))
edit() {  # edit EXPR OUT: apply EXPR to x (as awk's x) on that one line
  awk -v half="$half" -v expr="$1" '$1 == "FLASER" && ++c == half { n = $2; x = $(3 + n);
    if (expr == "huge") $(3 + n) = "1e300"; else if (expr == "far") $(3 + n) = x + 3000 } { print }' clean.log > "$2"
}
edit huge huge.log
edit far far.log
# A 1000-line gzip of 100000 beams each (~0.4 MB compressed, 1e8 beams).
/usr/bin/python3 - <<'PY'
import gzip
beams = " ".join(["1.0"] * 100000)
with gzip.open("bomb.log.gz", "wt") as f:
    for i in range(1000):
        f.write(f"FLASER 100000 {beams} 0 0 0 0 0 0 {i} host {i}\n")
PY

failed=0
printf '%-44s %4s %10s %8s  %s\n' run exit "RSS [MB]" "time [s]" "error (first line)"
declare -A RSS
run() {  # run NAME ARGS...: records RSS[NAME]
  local name=$1
  shift
  local t0 rc=0
  t0=$(date +%s.%N)
  /usr/bin/time -f %M -o rss.txt "$BIN" "$@" > out.txt 2> err.txt || rc=$?
  local seconds rss
  seconds=$(awk -v a="$(date +%s.%N)" -v b="$t0" 'BEGIN { print a - b }')
  rss=$(tail -1 rss.txt)
  RSS[$name]=$rss
  printf '%-44s %4s %10.1f %8.2f  %s\n' "$name" "$rc" "$(awk -v r="$rss" 'BEGIN { print r / 1024 }')" "$seconds" \
    "$(grep -m1 . err.txt | cut -c1-110)"
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 1 ]; then echo "  ^ crashed (exit $rc)"; failed=1; fi
  if [ "$rc" -eq 1 ] && ! grep -q 'error' err.txt; then echo "  ^ failed without an error message"; failed=1; fi
}
compare() {  # compare HOSTILE CLEAN
  local ratio
  ratio=$(awk -v a="${RSS[$1]}" -v b="${RSS[$2]}" 'BEGIN { print a / b }')
  if awk -v r="$ratio" 'BEGIN { exit !(r > 2) }'; then
    printf '  ^ %s took %.1fx the memory of %s\n' "$1" "$ratio" "$2"
    failed=1
  fi
}

run "submaps clean" submaps clean.log --db clean.db
run "submaps, one pose 1e300" submaps huge.log --db huge.db
compare "submaps, one pose 1e300" "submaps clean"
run "submaps, one scan 3 km away" submaps far.log --db far.db
compare "submaps, one scan 3 km away" "submaps clean"
run "dictionary clean" dictionary clean.log --db clean.db --name dict
run "dictionary, one scan 3 km away" dictionary far.log --db clean.db --name far-dict
compare "dictionary, one scan 3 km away" "dictionary clean"
run "describe (dictionary clean)" describe clean.db --dict dict --k 3 --parts 20 --quiet
run "describe (dictionary with a scan 3 km away)" describe clean.db --dict far-dict --k 3 --parts 20 --quiet
compare "describe (dictionary with a scan 3 km away)" "describe (dictionary clean)"
run "submaps, gzip bomb (1e8 beams)" submaps bomb.log.gz --db bomb.db

# Stored values: a map's first point set to FLT_MAX, or two points 131 km apart (a valid float32 each).
cp clean.db flt.db
cp clean.db wide.db
/usr/bin/python3 - <<'PY'
import sqlite3, struct
for path, first in (("flt.db", (3.4028234663852886e38, 0.0)), ("wide.db", (-65500.0, 0.0))):
    db = sqlite3.connect(path)
    (blob,) = db.execute("SELECT points FROM submaps WHERE id = 1").fetchone()
    blob = struct.pack("<ff", *first) + blob[8:]
    if path == "wide.db":
        blob = blob[:-8] + struct.pack("<ff", 65500.0, 0.0)
    db.execute("UPDATE submaps SET points = ? WHERE id = 1", (blob,))
    db.commit()
PY
run "match dmm, query clean" match clean.db --query 1 --method dmm --top 3
run "match dmm, stored point at FLT_MAX" match flt.db --query 1 --method dmm --top 3
compare "match dmm, stored point at FLT_MAX" "match dmm, query clean"
run "match dmm, a stored map 131 km wide" match wide.db --query 2 --method dmm --top 3
compare "match dmm, a stored map 131 km wide" "match dmm, query clean"
run "match dmm, the query map 131 km wide" match wide.db --query 1 --method dmm --top 3
compare "match dmm, the query map 131 km wide" "match dmm, query clean"
exit $failed
