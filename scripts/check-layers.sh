#!/usr/bin/env bash
# The include layers of src/ (ctest Layers.IncludesPointDown): apps -> plot -> io -> core; inside io
#   logs (log readers), store (the map database), formats (other files) -> files (file primitives);
# inside core
#   evaluation -> slam -> ranking -> parts -> matching, sim -> maps -> core/*.h (types, errors, parallel loops,
#   work split),
# each layer including only layers below it. Prints every include that points up (or sideways between two
# folders of one layer) and fails if there is one; test files (*_test.cc, core/testing/, io/testing/) are left out.
# It also fails on an include cycle between units of src/ (a unit: foo.h, foo_internal.h and foo.cc; test files
# left out as above), which would tie them into one.
# Usage: check-layers.sh SRC_DIR [--graph | --describe] (--graph: print the include edges between folders of
# src/core, with their counts, and exit; --describe: print the layers as Markdown, top first, for docs/DESIGN.md's
# generated block (scripts/design_layers.py), and exit).
set -euo pipefail
src=$1
cd "$src"

# "from to" for every #include "a/b/..." of a non-test file, folders as layer names: core/<folder>, or core for
# core's own top-level headers, or the top folder (apps, plot, io).
edges() {
  grep -rHoE '#include "(apps|plot|io|core)/[^"]*"' apps plot io core --include=*.h --include=*.cc \
    | grep -vE '_test\.cc:|^(core|io)/testing/' \
    | sed -E 's|^([^:]*):#include "([^"]*)"$|\1 \2|' \
    | while read -r from to; do
        printf '%s %s %s %s\n' "$(layer "$from")" "$(layer "$to")" "$from" "$to"
      done
}
layer() {
  case $1 in
    core/*/*) local rest=${1#core/}; echo "core/${rest%%/*}" ;;
    core/*) echo core ;;
    io/*/*) local rest=${1#io/}; echo "io/${rest%%/*}" ;;
    *) echo "${1%%/*}" ;;
  esac
}

# Rank of each layer: an include must go to a strictly lower rank (folders that share one may not include each
# other: sim and matching; io's logs, store and formats).
declare -A rank=([core]=0 [core/maps]=1 [core/sim]=2 [core/matching]=2 [core/parts]=3 [core/ranking]=4
                 [core/slam]=5 [core/evaluation]=6 [io/files]=10 [io/logs]=11 [io/store]=11 [io/formats]=11
                 [plot]=12 [apps]=13)

# What each layer holds, for --describe.
declare -A role=([apps]="the \`partslam\` command line: one file per subcommand, options and printing"
                 [plot]="pictures (cairo): maps, answers, curves"
                 [io/logs]="log readers: CARMEN, ROS 1 and ROS 2 bags, relations files, ground truth"
                 [io/store]="the map database (SQLite) and its stored descriptors"
                 [io/formats]="other files: map_server maps, point files, settings files, loop files"
                 [io/files]="file primitives: atomic writes, text lines and fields, YAML text, SQLite"
                 [core/evaluation]="the evaluation protocol: tasks, metrics, relocalisation, drifted twins"
                 [core/slam]="SLAM: front end, loop closures, pose graphs, back end, map check, log stretches"
                 [core/ranking]="ranking methods: the registry, rankers and the query entry point"
                 [core/parts]="parts: CPD, codec, descriptor matching"
                 [core/matching]="direct matching: dMM, verification, localisation, scan matching, descriptors"
                 [core/sim]="the simulated building"
                 [core/maps]="scans, submaps, Manhattan alignment, grids, dictionaries"
                 [core]="core's own headers: types, errors, parallel loops, work split")

if [[ ${2:-} == --graph ]]; then
  edges | awk '$1 ~ /^core/ && $1 != $2 { print $1 " -> " $2 }' | sort | uniq -c
  exit 0
fi
if [[ ${2:-} == --describe ]]; then
  echo "Each layer includes only layers below it; layers on one line may not include each other. Test files"
  echo "(\`*_test.cc\`, \`core/testing/\`, \`io/testing/\`) are exempt. No two units (\`foo.h\`, \`foo_internal.h\` and"
  echo "\`foo.cc\`) include each other, however indirectly."
  echo
  for r in $(printf '%s\n' "${rank[@]}" | sort -rnu); do
    line=""
    for layer in $(printf '%s\n' "${!rank[@]}" | sort); do
      [[ ${rank[$layer]} == "$r" ]] || continue
      [[ -n ${role[$layer]+x} ]] || { echo "$0: layer $layer has no role for --describe" >&2; exit 1; }
      line+="${line:+; }\`src/$layer\`: ${role[$layer]}"
    done
    echo "- $line"
  done
  exit 0
fi

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

# Include cycles between units: tsort names the files of a loop.
loops=$(grep -rHoE '#include "(apps|plot|io|core)/[^"]*"' apps plot io core --include=*.h --include=*.cc \
          | grep -vE '_test\.cc:|^(core|io)/testing/' \
          | sed -E 's|^([^:]*):#include "([^"]*)"$|\1 \2|; s/(_internal)?\.(h|cc)( |$)/\3/g' \
          | awk '$1 != $2' | tsort 2>&1 >/dev/null || true)
if [[ -n $loops ]]; then
  echo "an include cycle between units of src/:"
  echo "$loops"
  failed=1
fi
((failed == 0)) || exit 1
echo "every include of src/ points down its layers, and no two units include each other"
