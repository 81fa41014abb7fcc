#!/usr/bin/env bash
# Checks the installed include tree (ctest InstalledPackage.HeadersStandAlone): installs the build tree's PartSLAM
# into a temporary prefix, fails if any internal header is there (those listed in INTERNAL_LIST, one path per line
# relative to include/partslam, as CMakeLists.txt's PARTSLAM_INTERNAL_HEADERS; any *_internal.h, testing/ or
# test_files.h), then compiles every installed header on its own (-fsyntax-only) in a project that only sees the
# install through find_package(partslam), so a public header that includes an internal one, or misses an include
# of its own, fails. Usage: check-installed-headers.sh BUILD_DIR INTERNAL_LIST
set -euo pipefail
build=$1
internal_list=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" > /dev/null
include=$tmp/prefix/include/partslam

failed=0
while IFS= read -r header; do
  [[ -z $header ]] && continue
  if [[ -e $include/$header ]]; then
    echo "internal header installed: $header"
    failed=1
  fi
done < "$internal_list"
while IFS= read -r header; do
  echo "internal header installed: ${header#"$include"/}"
  failed=1
done < <(find "$include" -name '*_internal.h' -o -name 'test_files.h' -o -path '*/testing/*')
((failed == 0)) || exit 1

mapfile -t headers < <(cd "$include" && find . -name '*.h' | sed 's|^\./||' | sort)
if ((${#headers[@]} == 0)); then
  echo "no header installed under $include"
  exit 1
fi
project=$tmp/headers
mkdir -p "$project"
sources=""
for i in "${!headers[@]}"; do
  printf '#include "%s"\n' "${headers[$i]}" > "$project/header_$i.cc"
  sources+=" header_$i.cc"
done
cat > "$project/CMakeLists.txt" << EOF
cmake_minimum_required(VERSION 3.25)
project(partslam_headers LANGUAGES CXX)
set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
find_package(partslam 0.1 REQUIRED)
add_library(headers OBJECT$sources)
target_link_libraries(headers PRIVATE partslam::plot)
EOF
cmake -S "$project" -B "$tmp/build" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$tmp/prefix" \
      -DCMAKE_EXPORT_COMPILE_COMMANDS=ON > /dev/null
# Each header on its own: the compile command of its translation unit with -fsyntax-only, so that one failing
# header does not hide the others.
mapfile -t commands < <(/usr/bin/python3 -c '
import json, sys
for entry in json.load(open(sys.argv[1])):
    print(entry["file"] + "\t" + entry["command"].replace(" -c ", " -fsyntax-only -c "))
' "$tmp/build/compile_commands.json")
if ((${#commands[@]} != ${#headers[@]})); then
  echo "${#commands[@]} compile commands for ${#headers[@]} headers"
  exit 1
fi
for entry in "${commands[@]}"; do
  file=${entry%%$'\t'*}
  command=${entry#*$'\t'}
  index=$(basename "$file" .cc)
  index=${index#header_}
  if ! (cd "$tmp/build" && eval "$command") > "$tmp/log" 2>&1; then
    echo "does not compile on its own: ${headers[$index]}"
    head -20 "$tmp/log"
    failed=1
  fi
done
((failed == 0)) || exit 1
echo "${#headers[@]} installed headers, none internal, each compiles on its own"
