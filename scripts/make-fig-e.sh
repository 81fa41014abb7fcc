#!/usr/bin/env bash
# Regenerates docs/fig_e_fr101.png, the paper's Fig. E for one fr101 map against the fr079 dictionary: the
# map's points with its parts' keypoint boxes, and the matching descriptor boxes on the dictionary.
# Usage: scripts/make-fig-e.sh [MAP_ID=100]. Needs ../shared/data and build/partslam.
set -euo pipefail
cd "$(dirname "$0")/.."
MAP=${1:-100}
DATA=../shared/data
BIN=build/partslam
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
"$BIN" submaps "$DATA/fr101/fr101-corrected.log.gz" --db "$TMP/fr101.db"
"$BIN" dictionary "$DATA/fr079/fr079-corrected.log.gz" --db "$TMP/fr101.db" --name fr079
"$BIN" describe "$TMP/fr101.db" --dict fr079 --threads 2
"$BIN" render "$TMP/fr101.db" --map "$MAP" --dict fr079 --parts 5 --out docs/fig_e_fr101.png
echo "wrote docs/fig_e_fr101.png (fr101 map $MAP, dictionary fr079)"
