#!/usr/bin/env bash
# make sanitize / make sanitize-long: the ctest suite of the sanitizer tree BUILD without (short) or with only (long)
# the tests listed in tests/long-under-sanitizers.txt, JOBS at a time, always leaving out the compile-only header
# check (it compiles headers and runs nothing of ours; make test runs it). Fails, before running anything, when a
# listed name is no test of the tree: a renamed test would otherwise drop out of both runs unnoticed.
#   scripts/sanitize-tests.sh BUILD short|long JOBS
set -euo pipefail
build=$1 which=$2 jobs=${3:-2}
list="$(cd "$(dirname "$0")/.." && pwd)/tests/long-under-sanitizers.txt"
names=$(sed 's/#.*//' "$list" | awk 'NF {print $1}')
# A parameterised test's ctest name goes on after a space ("  # GetParam() = ..."): its first word is compared.
known=$(cd "$build" && ctest -N | sed -n 's/^ *Test *#[0-9]*: //p' | awk '{print $1}')
missing=$(comm -23 <(sort <<<"$names") <(sort <<<"$known"))
if [ -n "$missing" ]; then
  echo "sanitize: $list names tests that $build does not have:" >&2
  echo "$missing" >&2
  exit 2
fi
# One alternative per name, its regex characters escaped, ending the ctest name or its first word.
regex="^($(sed 's/[][\.*^$+?(){}|/]/\\&/g' <<<"$names" | paste -sd'|'))( |\$)"
cd "$build"
case $which in
  short)
    echo "sanitize: $(wc -l <<<"$names") long tests left to make sanitize-long ($list)"
    ctest --output-on-failure -j "$jobs" -LE compile-only -E "$regex" ;;
  long) ctest --output-on-failure -j "$jobs" -LE compile-only -R "$regex" ;;
  *) echo "usage: $0 BUILD short|long [JOBS]" >&2; exit 2 ;;
esac
