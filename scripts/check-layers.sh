#!/usr/bin/env bash
# The include layers of src/ (ctest Layers.IncludesPointDown): apps -> plot -> io -> core, and inside core
#   evaluation -> slam -> ranking -> parts -> matching, sim -> maps -> core/*.h (types, errors, parallel loops,
#   work split),
# each layer including only layers below it. Prints every include that points up (or sideways between two
# folders of one layer) and fails if there is one; test files (*_test.cc, core/testing/) are left out.
# Usage: check-layers.sh SRC_DIR [--graph] (--graph: print the include edges between folders of src/core, with
# their counts, and exit).
set -euo pipefail
src=$1
cd "$src"

# "from to" for every #include "a/b/..." of a non-test file, folders as layer names: core/<folder>, or core for
# core's own top-level headers, or the top folder (apps, plot, io).
edges() {
  grep -rHoE '#include "(apps|plot|io|core)/[^"]*"' apps plot io core --include=*.h --include=*.cc \
    | grep -vE '_test\.cc:|^core/testing/' \
    | sed -E 's|^([^:]*):#include "([^"]*)"$|\1 \2|' \
    | while read -r from to; do
        printf '%s %s %s %s\n' "$(layer "$from")" "$(layer "$to")" "$from" "$to"
      done
}
layer() {
  case $1 in
    core/*/*) local rest=${1#core/}; echo "core/${rest%%/*}" ;;
    core/*) echo core ;;
    *) echo "${1%%/*}" ;;
  esac
}

if [[ ${2:-} == --graph ]]; then
  edges | awk '$1 ~ /^core/ && $1 != $2 { print $1 " -> " $2 }' | sort | uniq -c
  exit 0
fi

# Rank of each layer: an include must go to a strictly lower rank (sim and matching share one and may not
# include each other).
declare -A rank=([core]=0 [core/maps]=1 [core/sim]=2 [core/matching]=2 [core/parts]=3 [core/ranking]=4
                 [core/slam]=5 [core/evaluation]=6 [io]=10 [plot]=11 [apps]=12)

failed=0
while read -r from_layer to_layer from to; do
  [[ $from_layer == "$to_layer" ]] && continue
  if [[ -z ${rank[$from_layer]+x} || -z ${rank[$to_layer]+x} ]]; then
    echo "$from includes $to: layer ${from_layer} or ${to_layer} has no rank in $0"
    failed=1
    continue
  fi
  ((rank[$to_layer] < rank[$from_layer])) && continue
  echo "$from includes $to: $from_layer may not include $to_layer"
  failed=1
done < <(edges)
((failed == 0)) || exit 1
echo "every include of src/ points down its layers"
