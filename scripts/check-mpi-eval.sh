#!/usr/bin/env bash
# ctest mpi.eval_two_ranks: `mpirun -n 2 partslam eval` gives the JSON of a serial run, timings apart (issue
# "scale": byte-identical results over MPI ranks). Usage: scripts/check-mpi-eval.sh PARTSLAM_BINARY
set -euo pipefail
BIN=$1
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
ARGS=(eval --input sim:1 --dict sim:2 --tasks 30 --db-size 25 --methods dmm,hmm:3,succinct --quiet)
"$BIN" "${ARGS[@]}" --json "$TMP/serial.json" > /dev/null
# Root in containers and CI needs --allow-run-as-root; two ranks on a one-core machine need --oversubscribe.
mpirun --allow-run-as-root --oversubscribe -n 2 "$BIN" "${ARGS[@]}" --json "$TMP/ranks.json" > "$TMP/out.txt"
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
