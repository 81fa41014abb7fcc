#!/usr/bin/env bash
# Every .cc of src/ (tests aside) longer than 100 lines is tested (ctest Tests.CoverEveryUnit): a foo_test.cc
# beside foo.cc, or, for code that its own test file would only repeat (a CLI command, which the CLI tests run as a
# user does; a reader's internal pieces, which their reader's tests reach), a line in its opening comment
#   // Tested by: apps/cli_eval_test.cc, apps/cli_parts_test.cc
# naming test files of src/ that exist. Prints every unit that has neither and fails if there is one.
# Usage: check-tests.sh SRC_DIR
set -euo pipefail
cd "$1"
failed=0
while read -r file; do
  (( $(wc -l < "$file") > 100 )) || continue
  [[ -f ${file%.cc}_test.cc ]] && continue
  named=$(head -n 30 "$file" | sed -n 's|^// Tested by: ||p' | tr ',' ' ')
  if [[ -z $named ]]; then
    echo "$file: no ${file##*/} test beside it and no '// Tested by:' line naming the tests that cover it"
    failed=1
    continue
  fi
  for test in $named; do
    if [[ $test != *_test.cc || ! -f $test ]]; then
      echo "$file: its '// Tested by:' names $test, which is not a test file of src/"
      failed=1
    fi
  done
done < <(find apps plot io core -name '*.cc' ! -name '*_test.cc' ! -path '*/testing/*' | sort)
((failed == 0)) || exit 1
echo "every .cc of src/ over 100 lines has its tests"
