#!/usr/bin/env bash
# The SLAM generalisation bench (docs/NOTES.md "SLAM bench"; build/slam_bench runs one input): `slam` with its
# defaults on
#   - the raw fr079, intel and aces logs against their relations files, and fr101's raw log against relations
#     built from its corrected twin (the twins also judge the accepted closures); then fr079, intel and aces read
#     from their ROS 1 bags (BAGS), judged by the same relations;
#   - drifted twins of every corrected log in ../shared (the eight of data/corrected and fr079, fr101, intel,
#     aces): the real scans with synthetic odometry, at each LEVEL and SEED;
#   - simulated buildings that stress the front end (SIMS: long bare corridors, a large open hall, a 60 m laser),
#     exact poses as the truth, odometry drifted as the twins' (first SEED);
#   - the same with INJECT wrong closures added (fractions of the accepted ones) on the raw logs and the first
#     seed of the harsh twins and simulations.
# Writes docs/results/slam_bench.jsonl (one line per run) and docs/results/slam_bench.md (the table).
#   - the same with FORCE wrong closures forced in (the back end sets none aside: maps made wrong on purpose, which
#     the verdict must not trust).
# The raw logs come first: mit-csail (a building nothing here was tuned on, judged by its relations alone: its
# twin is kept elsewhere), fr079, intel, aces, fr101.
# Usage: scripts/slam-bench.sh; LEVELS="mild harsh" SEEDS="1 2 3" INJECT="0.1 0.3 0.5" FORCE="0.3f" LOGS="..." RAW="..."
# BAGS="..."
# SIMS="..." PEERS="rbpf-slam icp-slam" (or "" to skip MRPT) narrow it
# (LOGS: names of corrected logs, e.g. "orebro fr079"). Needs ../shared/data and build/slam_bench.
set -euo pipefail
cd "$(dirname "$0")/.."
DATA=../shared/data
OUT=${OUT:-docs/results}
LEVELS=${LEVELS-mild harsh}
SEEDS=${SEEDS-1 2 3}
INJECT=${INJECT-0.1 0.3 0.5}
FORCE=${FORCE-0.3f}
[ -d "$DATA" ] || { echo "slam-bench: $DATA not found (the real data sets are needed)" >&2; exit 1; }
BIN=${BIN:-build/slam_bench}
[ -x "$BIN" ] || { echo "slam-bench: $BIN not built (make build)" >&2; exit 1; }
corrected() {  # name -> corrected log
  case "$1" in
    fr079|fr101|intel|aces) echo "$DATA/$1/$1-corrected.log.gz" ;;
    *) echo "$DATA/corrected/$1-corrected.log.gz" ;;
  esac
}
ALL_LOGS="acapulco belgioioso edmonton fhw freiburg-campus infinite-corridor orebro seattle fr079 fr101 intel aces"
LOGS=${LOGS-$ALL_LOGS}
RAW=${RAW-mit-csail fr079 intel aces fr101}
BAGS=${BAGS-fr079 intel aces}
SIMS=${SIMS-corridors hall long-range}
mkdir -p "$OUT"
TMP=$(mktemp)
trap 'rm -f "$TMP" "$TMP.peers"' EXIT
run() {
  echo "== slam_bench $*" >&2
  local status=0
  "$BIN" "$@" >> "$TMP" || status=$?
  if [ "$status" -ne 0 ]; then  # keep what the runs before it measured, and say which run failed and how
    cp "$TMP" "$OUT/slam_bench.partial.jsonl"
    echo "slam-bench: slam_bench $* failed with exit status $status (a signal when above 128); the runs before" \
      "it are in $OUT/slam_bench.partial.jsonl" >&2
    exit "$status"
  fi
}
raw_runs() {  # RAW_LOG TWIN [RELATIONS]: the clean run, then each INJECT and FORCE
  run raw "$@"
  for f in $INJECT $FORCE; do run raw "$@" "$f"; done
}
for log in $RAW; do
  dir=$DATA/$log twin=$(corrected "$log")
  [ "$log" = mit-csail ] && dir=$DATA/csail twin=-
  rel=""
  [ -f "$dir/$log.relations" ] && rel="$dir/$log.relations"
  raw_runs "$dir/$log.clf.gz" "$twin" $rel
done
# The same runs read from their ROS bags (BAGS): re-timed, their odometry one message per scan; judged by the
# logs' relations carried onto the bags' clock (scripts/bag_relations.py pairs each bag scan with the log's scan of the
# same ranges).
for log in $BAGS; do
  bag=$DATA/bags/$log.clf2bag.bag rel=$TMP.$log.relations
  /usr/bin/python3 scripts/bag_relations.py "$DATA/$log/$log.clf.gz" "$bag" "$DATA/$log/$log.relations" "$rel"
  raw_runs "$bag" - "$rel"
  rm -f "$rel"
done
for log in $LOGS; do
  for level in $LEVELS; do
    for seed in $SEEDS; do run twin "$(corrected "$log")" "$level" "$seed"; done
  done
  first=${SEEDS%% *}
  for f in $INJECT $FORCE; do run twin "$(corrected "$log")" harsh "$first" "$f"; done
done
for sim in $SIMS; do
  first=${SEEDS%% *}
  for level in $LEVELS; do run sim "$sim" "$level" "${first:-1}"; done
  for f in $INJECT $FORCE; do run sim "$sim" harsh "${first:-1}" "$f"; done
done
# MRPT's peers on the raw logs (rbpf-slam with its ICP configuration, icp-slam; scripts/mrpt-peers.sh), PEERS=""
# skips them (the committed mrpt_peers.jsonl is then kept).
PEERS=${PEERS-rbpf-slam icp-slam}
if [ -n "$PEERS" ]; then
  PEERS="$PEERS" bash scripts/mrpt-peers.sh $RAW > "$TMP.peers"
  mv "$TMP.peers" "$OUT/mrpt_peers.jsonl"
fi
mv "$TMP" "$OUT/slam_bench.jsonl"
trap - EXIT
/usr/bin/python3 scripts/slam_bench_table.py "$OUT/slam_bench.jsonl" > "$OUT/slam_bench.md"
cat "$OUT/slam_bench.md"
