#!/usr/bin/env bash
# Runs `slam` on the two buildings not in ../shared that docs/NOTES.md reports ("Which pose the relations relate",
# "MIT Killian Court's relation error") and prints their figures: the Freiburg hospital (its ROS 1 bag with the log's
# own stamps) and MIT Killian Court (a re-timed bag, whose relations are first carried onto its clock by
# scripts/retimed_relations.py from a first `slam` run's poses). The files come from github.com/INESCTEC/ricoslam
# (inesctec_mrdt_slam_2d_datasets/bag and data) and are never committed here:
#   DIR/fr-clinic_robotlaser.orig.bag  DIR/fr-clinic.relations  DIR/mit-killian.clf2bag.bag  DIR/mit-killian.relations
# Usage: scripts/held-out.sh DIR [OUT] (make held-out HELDOUT=DIR; about 2 minutes on 2 cores). Each run's folder (map.png,
# slam.json, relations_error.json) is left in OUT (default: a new folder under /tmp, printed).
set -euo pipefail
DIR=$(realpath -m "${1:?usage: scripts/held-out.sh DIR [OUT]}")
for f in fr-clinic_robotlaser.orig.bag fr-clinic.relations mit-killian.clf2bag.bag mit-killian.relations; do
  [ -s "$DIR/$f" ] || { echo "held-out: $DIR/$f is missing or empty (see this script's header for where it comes from)" >&2; exit 1; }
done
OUT=$(realpath -m "${2:-$(mktemp -d /tmp/held-out.XXXXXX)}")
mkdir -p "$OUT"
cd "$(dirname "$0")/.."
# Exit status 3 is a map written but not trusted (the verdict, in the table); anything else non-zero is an error.
slam() {
  local status=0
  build/partslam slam "$@" --threads 2 --quiet > /dev/null || status=$?
  [ "$status" -eq 0 ] || [ "$status" -eq 3 ] || exit "$status"
}
slam "$DIR/fr-clinic_robotlaser.orig.bag" --out "$OUT/hospital" --relations "$DIR/fr-clinic.relations"
slam "$DIR/mit-killian.clf2bag.bag" --out "$OUT/killian-poses"
/usr/bin/python3 scripts/retimed_relations.py "$OUT/killian-poses/corrected.log" "$DIR/mit-killian.relations" \
  "$OUT/mit-killian.retimed.relations"
slam "$DIR/mit-killian.clf2bag.bag" --out "$OUT/killian" --relations "$OUT/mit-killian.retimed.relations"
/usr/bin/python3 - "$OUT" <<'PY'
import json, os, sys
out = sys.argv[1]
print("| building | scans | slam: relation error | odometry | verdict | s (slam's stages) |")
print("|---|---|---|---|---|---|")
for name, run in (("Freiburg hospital", "hospital"), ("MIT Killian Court (re-timed bag)", "killian")):
    s = json.load(open(os.path.join(out, run, "slam.json")))
    r = json.load(open(os.path.join(out, run, "relations_error.json")))
    o = s["relations"]["odometry"]
    if "translation_m" not in r or "translation_m" not in o:
        sys.exit("held-out: %s: no relation names a scan of the run (%s)" % (name, os.path.join(out, run)))
    print("| %s | %d | %.4f +- %.3f m, %.2f deg | %.3f m | %s | %.0f |" % (
        name, s["scans"], r["translation_m"]["mean"], r["translation_m"]["std"], r["rotation_deg"]["mean"],
        o["translation_m"]["mean"], s["verdict"],
        sum(v for k, v in s["seconds"].items() if k != "second_opinion")))  # it runs beside the front end
print("runs in", out)
PY
