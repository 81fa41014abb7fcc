#!/usr/bin/env bash
# Regenerates docs/RESULTS.md and its figures (and docs/fig_e_fr101.png): the paper's Table A methods on data sets #1..#5 (issue
# "Evaluation"), one `partslam eval` per data set, then scripts/results_table.py turns the JSON into Markdown.
# Usage: scripts/make-results.sh [TASKS=500] [THREADS=2] [RANSAC_TASKS=100]. Needs ../shared/data.
set -euo pipefail
cd "$(dirname "$0")/.."
TASKS=${1:-500}
THREADS=${2:-2}
RANSAC_TASKS=${3:-100}
DATA=../shared/data
BIN=build/partslam
OUT=docs/results
METHODS="dmm,imm:1,imm:2,imm:3,imm:4,imm:5,hmm:1,hmm:2,hmm:3,hmm:4,hmm:5,hmm:3:maxmax,hmm:3:summax,rerank:10:3,rerank:20:3"
[ -d "$DATA" ] || { echo "make-results: $DATA not found (the real data sets are needed)" >&2; exit 1; }
mkdir -p "$OUT"
run() {  # id input dictionary
  echo "== data set #$1: $2 / dictionary $3"
  "$BIN" eval --input "$DATA/$2" --dict "$DATA/$3" --methods "$METHODS" --tasks "$TASKS" --threads "$THREADS" \
    --json "$OUT/set$1.json" --plot "$OUT/fig_d_set$1.png"
  # The paper's RANSAC baseline costs ~40 ms per pair: fewer tasks (same seed, so the same first tasks).
  "$BIN" eval --input "$DATA/$2" --dict "$DATA/$3" --methods dmm-ransac --tasks "$RANSAC_TASKS" \
    --threads "$THREADS" --quiet --json "$OUT/set$1_ransac.json"
}
run 1 fr101/fr101-corrected.log.gz fr079/fr079-corrected.log.gz
run 2 aces/aces-corrected.log.gz fr101/fr101-corrected.log.gz
run 3 intel/intel-corrected.log.gz fr079/fr079-corrected.log.gz
run 4 corrected/freiburg-campus-corrected.log.gz intel/intel-corrected.log.gz
run 5 fr079/fr079-corrected.log.gz fr101/fr101-corrected.log.gz
bash scripts/make-fig-e.sh
/usr/bin/python3 scripts/results_table.py "$OUT" README.md > docs/RESULTS.md.tmp
mv docs/RESULTS.md.tmp docs/RESULTS.md
echo "wrote docs/RESULTS.md and the results table of README.md"
