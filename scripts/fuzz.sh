#!/usr/bin/env bash
# Runs the libFuzzer harnesses of fuzz/ (docs/RELIABILITY.md, "Sanitizers and fuzzing"):
#   scripts/fuzz.sh [SECONDS [HARNESS...]]
# builds the fuzz preset (clang 14, ASan + UBSan, in build-fuzz/), replays each harness's seed corpus
# (tests/fuzz_corpus/NAME) and fuzzes it for SECONDS (default 5; 0 only replays), growing a working
# corpus in build-fuzz/corpus/NAME (the seeds are not changed). A crash, a leak, a sanitizer report,
# an input that takes over 10 s or 2.5 GB is a finding: its input is saved in build-fuzz/findings/NAME
# and the script fails. Skipped, with a note, where clang 14 is not installed.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
seconds=${1:-5}
shift || true
harnesses=("$@")
((${#harnesses[@]})) || harnesses=(job scene materials ktx2 merl environment)
if ! command -v clang++-14 >/dev/null; then
  echo "scripts/fuzz.sh: clang++-14 is not installed: the fuzz harnesses were not run (their corpora were replayed by ctest)" >&2
  exit 0
fi
cmake --preset fuzz >/dev/null
targets=()
for h in "${harnesses[@]}"; do targets+=("fuzz_$h"); done
cmake --build --preset fuzz -j "$(nproc)" --target "${targets[@]}" >&2
# Leaks are checked after every input (libFuzzer's -detect_leaks); the check at exit is off: its
# stop-the-world tracer crashed ("Tracer caught signal 11") at the end of a clean 150 s run of the
# environment harness, whose OpenEXR thread pool is alive at exit.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:leak_check_at_exit=0}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan.supp:print_suppressions=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
for h in "${harnesses[@]}"; do
  # absolute paths: harnesses may change their working folder (fuzz_job runs in an empty one), and
  # libFuzzer opens the seed files one by one as it runs them
  corpus=$PWD/build-fuzz/corpus/$h findings=$PWD/build-fuzz/findings/$h
  mkdir -p "$corpus" "$findings"
  args=(-rss_limit_mb=2560 -timeout=10 -max_len=65536 -artifact_prefix="$findings/" -print_final_stats=1)
  if [[ $seconds == 0 ]]; then args+=(-runs=0); else args+=(-max_total_time="$seconds"); fi
  log=build-fuzz/fuzz_$h.log
  if build-fuzz/fuzz/fuzz_"$h" "${args[@]}" "$corpus" "$PWD"/tests/fuzz_corpus/"$h" >"$log" 2>&1; then
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    echo "fuzz_$h: ${seconds} s, $runs executions, no finding" >&2
  else
    echo "fuzz_$h: FINDING (input in $findings/, log in $log):" >&2
    grep -E "ERROR|runtime error|SUMMARY|Test unit written" "$log" | head -5 >&2 || true
    status=1
  fi
done
exit $status
