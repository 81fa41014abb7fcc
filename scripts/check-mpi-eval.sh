#!/usr/bin/env bash
# ctest mpi.eval_two_ranks: `mpirun -n 2 partslam eval`, `loops` and `match` give the JSON of a serial run, timings apart,
# and `mpirun -n 2 partslam describe` stores the same descriptors (issue "scale": identical results over MPI ranks).
# Usage: scripts/check-mpi-eval.sh PARTSLAM_BINARY
set -euo pipefail
BIN=$1
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
# Two ranks. Root in containers and CI needs --allow-run-as-root; two ranks on a one-core machine need
# --oversubscribe. Under `make sanitize` (ASAN_OPTIONS set) LeakSanitizer is off in the processes mpirun starts:
# OpenMPI's runtime leaves allocations of its dlopen()ed components at exit, in frames LSan cannot name a library
# for, so no suppression can single them out. ASan and UBSan stay on there, and every command also runs serially
# here with leak detection on.
mpi2() {
  ASAN_OPTIONS=${ASAN_OPTIONS:+$ASAN_OPTIONS:detect_leaks=0} mpirun --allow-run-as-root --oversubscribe -n 2 "$@"
}
ARGS=(eval --input sim:1 --dict sim:2 --tasks 6 --db-size 20 --methods dmm,hmm:3,succinct --quiet)
"$BIN" "${ARGS[@]}" --json "$TMP/serial.json" > /dev/null
mpi2 "$BIN" "${ARGS[@]}" --json "$TMP/ranks.json" > "$TMP/out.txt"
grep -q "wrote $TMP/ranks.json" "$TMP/out.txt" || { echo "rank 0 did not report"; cat "$TMP/out.txt"; exit 1; }
[ "$(grep -c '^method ' "$TMP/out.txt")" -eq 1 ] || { echo "more than one rank printed the table"; exit 1; }
/usr/bin/python3 - "$TMP/serial.json" "$TMP/ranks.json" <<'PY'
import json, sys
def strip(j):  # timings differ from run to run
    if isinstance(j, dict):
        return {k: strip(v) for k, v in j.items() if not (k.endswith("_ms") or k.startswith("ms_") or "_ms_" in k or k == "seconds")}
    if isinstance(j, list):
        return [strip(x) for x in j]
    return j
a, b = (strip(json.load(open(p))) for p in sys.argv[1:3])
if a != b:
    sys.exit("the 2-rank JSON differs from the serial one")
print("2 ranks: same results as 1")
PY
# loops: the same hypotheses (JSON without timings); a shortlist of 5 instead of 20, as the sanitizer build pays
# each dMM verification and the sharding does not depend on how many there are.
"$BIN" submaps sim:1 --db "$TMP/l.db" > /dev/null
"$BIN" loops "$TMP/l.db" --method rerank:5 --quiet --json "$TMP/l1.json" > /dev/null
mpi2 "$BIN" loops "$TMP/l.db" --method rerank:5 --quiet --json "$TMP/l2.json" > /dev/null
/usr/bin/python3 - "$TMP/l1.json" "$TMP/l2.json" <<'PY'
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
for j in (a, b):
    j.pop("seconds", None)
if not a["closures"] or a != b:
    sys.exit("loops over 2 ranks found other hypotheses than a serial run")
print(f"loops over 2 ranks: the same {len(a['closures'])} hypotheses")
PY
# describe: the stored descriptors, byte for byte.
"$BIN" submaps sim:1 --db "$TMP/a.db" > /dev/null
"$BIN" dictionary sim:2 --db "$TMP/a.db" > /dev/null
cp "$TMP/a.db" "$TMP/b.db"
"$BIN" describe "$TMP/a.db" --dict sim-2 --k 3 --parts 20 --quiet > /dev/null
mpi2 "$BIN" describe "$TMP/b.db" --dict sim-2 --k 3 --parts 20 --quiet \
  --json "$TMP/d.json" > /dev/null
/usr/bin/python3 - "$TMP/a.db" "$TMP/b.db" <<'PY'
import sqlite3, sys
rows = [sqlite3.connect(p).execute("select map_id, dictionary, k, data from descriptors order by 1, 2, 3").fetchall()
        for p in sys.argv[1:3]]
if not rows[0] or rows[0] != rows[1]:
    sys.exit("describe over 2 ranks stored other descriptors than a serial run")
print(f"describe over 2 ranks: the same {len(rows[0])} descriptors")
PY
# match: each rank ranks its slice of the stored maps, the top rows are merged: the same JSON as a serial run
# (dMM with the narrower search loops make: this is about the sharding, and the sanitizer build pays each search).
NARROW=(--dmm-turns 4 --dmm-angular-window 3)
for method in dmm hmm:3 imm:3; do
  "$BIN" match "$TMP/a.db" --query 40 --method "$method" --top 5 "${NARROW[@]}" --json "$TMP/m1.json" > /dev/null
  mpi2 "$BIN" match "$TMP/a.db" --query 40 --method "$method" --top 5 "${NARROW[@]}" \
    --json "$TMP/m2.json" > "$TMP/m2.txt"
  [ "$(grep -c '^confidence\|^ rank' "$TMP/m2.txt")" -le 2 ] || { echo "more than one rank printed the ranking"; exit 1; }
  cmp -s "$TMP/m1.json" "$TMP/m2.json" || { echo "match $method over 2 ranks differs from a serial run"; exit 1; }
  echo "match $method over 2 ranks: the same ranking"
done
# A method that learns from every stored map cannot be sharded: a clear error, not a different ranking.
if mpi2 "$BIN" match "$TMP/a.db" --query 40 --method succinct \
     > "$TMP/s.txt" 2>&1; then
  echo "succinct was sharded"; exit 1
fi
grep -q "cannot be sharded" "$TMP/s.txt" || { echo "no clear error for succinct over 2 ranks"; cat "$TMP/s.txt"; exit 1; }
