#!/usr/bin/env bash
# Regenerates the relocalisation figures of docs/NOTES.md ("Locate") and the README: for each corrected log, a
# map_server map of its first visit (scans before the first revisit) and every later 2 m stretch located in it
# with no initial pose (build/relocalisation_check) -> docs/results/relocalisation_LOG.txt, one line per query.
# fr079 and intel are the floor's sets (the defaults were chosen on them); the buildings of corrected/ validate.
# Then the in-map queries by true overlap (scripts/relocalisation_by_overlap.py).
# Usage: scripts/make-relocalisation.sh. Needs ../shared/data and build/relocalisation_check (about 6 min).
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
printf '| log | queries | in the map (overlap >= 30 %%) | pose within 0.3 m / 3 deg | within 0.1 m / 1 deg | confident wrong | outside, confident | median / p95 ms |\n|---|---|---|---|---|---|---|---|\n'
for log in "${logs[@]}"; do
  name=$(basename "$log" -corrected.log.gz)
  build/relocalisation_check "$log" "$TMP" | sed "s|$DATA/||" > "$OUT/relocalisation_$name.txt"
  reports+=("$OUT/relocalisation_$name.txt")
  /usr/bin/python3 - "$name" "$OUT/relocalisation_$name.txt" <<'PY'
import re, sys
t = open(sys.argv[2]).read()
q = re.search(r"queries: (\d+)", t).group(1)
inmap, correct, share = re.search(r"overlap >= 30 %\): (\d+), pose within [^:]*: (\d+) \(([\d.]+) %\)", t).groups()
conf, wrong = re.search(r"confident \(>= [\d.]+, probability >= [\d.]+\): (\d+), wrong among them: (\d+)", t).groups()
out, outc = re.search(r"outside the map \(overlap < 30 %\): (\d+), reported confidently: (\d+)", t).groups()
med, p95 = re.search(r"median ([\d.]+) ms, p95 ([\d.]+) ms", t).groups()
# Per-query lines: in the map and within 0.1 m / 1 deg (the refined pose).
fine = sum(1 for o, e, a in re.findall(r"overlap ([\d.]+) .* err ([\d.]+) m ([\d.]+) deg", t)
           if float(o) >= 0.3 and float(e) < 0.1 and float(a) < 1.0)
fine_share = 100.0 * fine / max(1, int(inmap))
print(f"| {sys.argv[1]} | {q} | {inmap} | {correct} ({share} %) | {fine} ({fine_share:.1f} %) | {wrong} of {conf} | {outc} of {out} | {med} / {p95} |")
PY
done
echo
/usr/bin/python3 scripts/relocalisation_by_overlap.py "${reports[@]}"
