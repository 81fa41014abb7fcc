#!/usr/bin/env bash
# make fuzz: builds the libFuzzer targets of fuzz/ in the clang tree $FUZZ_BUILD (default build-fuzz, which
# `make fuzz` configures), writes their seeds from the shared data (make_fuzz_seeds), and runs each target in turn for FUZZ_SECONDS (default 30) or, when
# FUZZ_RUNS is set, for that many executions, printing the executions of each. Exits non-zero when any target
# reports a finding (crash, sanitizer report, exception other than InputError, timeout > 10 s, RSS > 2 GB); the
# input that caused it is saved as $FUZZ_BUILD/fuzz/findings/<target>-crash-... and the report is printed.
# FUZZ_JOBS (default JOBS) targets run at a time.
# FUZZ_TARGETS="fuzz_carmen fuzz_points" runs only those. The corpus each run grows is kept in
# $FUZZ_BUILD/fuzz/corpus/<target>, so later runs continue from it.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${FUZZ_BUILD:-build-fuzz}
seconds=${FUZZ_SECONDS:-30}
runs=${FUZZ_RUNS:-}
jobs=${JOBS:-2}
shared=${PARTSLAM_SHARED_DATA:-$(pwd)/../shared/data}

if ! grep -q '^PARTSLAM_FUZZ:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null; then
  echo "fuzz: $build is not a clang tree configured with -DPARTSLAM_FUZZ=ON (make fuzz configures it)" >&2
  exit 2
fi
cmake --build "$build" -j "$jobs" --target partslam_fuzz

out=$build/fuzz
rm -rf "$out/seeds" "$out/logs"
mkdir -p "$out/corpus" "$out/findings" "$out/logs"
"$out/make_fuzz_seeds" "$shared" "$out/seeds"

targets=${FUZZ_TARGETS:-$(cd fuzz && ls fuzz_*.cc | sed 's/\.cc$//')}
total_start=$(date +%s)
# One target: its log in $out/logs/<target>.log, its row of the table in $out/logs/<target>.row.
run_target() {
  local t=$1
  local args=(-rss_limit_mb=2048 -timeout=10 -print_final_stats=1 -close_fd_mask=1 "-artifact_prefix=$out/findings/$t-")
  if [ -n "$runs" ]; then args+=("-runs=$runs"); else args+=("-max_total_time=$seconds"); fi
  [ -f "fuzz/dict/$t.dict" ] && args+=("-dict=fuzz/dict/$t.dict")
  # Options of one target (fuzz/<target>.options, one per line, # comments): see each file for why.
  [ -f "fuzz/$t.options" ] && args+=($(grep -v '^#' "fuzz/$t.options"))
  local dirs=("$out/corpus/$t")
  mkdir -p "$out/corpus/$t"
  [ -d "$out/seeds/$t" ] && dirs+=("$out/seeds/$t")
  [ -d "fuzz/seeds/$t" ] && dirs+=("fuzz/seeds/$t")
  # Every past finding (fuzz/findings/<target>, committed with its fix): libFuzzer runs each input of its corpus
  # folders first, so a known crash that came back fails the run at once, whatever FUZZ_SECONDS is.
  [ -d "fuzz/findings/$t" ] && dirs+=("fuzz/findings/$t")
  local log=$out/logs/$t.log start result execs rate
  start=$(date +%s)
  if "$out/$t" "${args[@]}" "${dirs[@]}" > "$log" 2>&1; then result=ok; else result=FINDING; fi
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  printf '%-26s %14s %10s %8s  %s\n' "$t" "${execs:-?}" "${rate:-?}" "$(( $(date +%s) - start ))" "$result" \
    > "$out/logs/$t.row"
}
# FUZZ_JOBS targets at a time (default: JOBS, the cores make uses).
parallel=${FUZZ_JOBS:-$jobs}
running=0
for t in $targets; do
  run_target "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$parallel" ]; then wait -n || true; running=$((running - 1)); fi
done
wait
printf '%-26s %14s %10s %8s  %s\n' target executions exec/s seconds result
failed=()
for t in $targets; do
  cat "$out/logs/$t.row"
  if ! grep -q ' ok$' "$out/logs/$t.row"; then
    failed+=("$t")
    echo "---- $t: the end of $out/logs/$t.log ----"
    tail -n 60 "$out/logs/$t.log"
    echo "----"
  fi
done
echo "fuzz: $(( $(date +%s) - total_start )) s in all"
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzz: findings in ${failed[*]} (inputs in $out/findings)" >&2
  exit 1
fi
