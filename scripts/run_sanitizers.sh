#!/usr/bin/env bash
# Builds the core and every unit test with AddressSanitizer + UndefinedBehaviorSanitizer (plain
# CMake, no ROS: test/sanitize/CMakeLists.txt) into $SE3_WS/sanitize, runs each test binary
# (gtest XML reports in $SE3_WS/sanitize/test_results), then runs the libFuzzer targets, each
# over a copy of its seed corpus: every per-layer target (fuzz_lie, fuzz_validate, fuzz_curves,
# fuzz_c2, fuzz_sphere, fuzz_yaml) for ${SE3_FUZZ_RUNS:-100000} inputs, at most
# ${SE3_FUZZ_MAX_SECONDS:-200} s each (a target that reaches fewer inputs in that time FAILS, so
# that the README's "each per-layer target sees 1e5 inputs per CI run" stays true), and the
# whole-request target fuzz_generate, much slower per input, for ${SE3_FUZZ_SECONDS:-30} s. Each
# run's input count and rate are printed. The last line is `sanitizers: N passed, N failed` (the
# unit test cases plus each fuzz run as one test); exits non-zero on any failure, sanitizer
# report or fuzzer finding.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
se3_install_deps

build="$SE3_WS/sanitize"
results="$build/test_results"
fuzz_runs=${SE3_FUZZ_RUNS:-100000}
fuzz_max_seconds=${SE3_FUZZ_MAX_SECONDS:-200}
fuzz_seconds=${SE3_FUZZ_SECONDS:-30}
mkdir -p "$build"
echo "sanitized build (clang++, ASan + UBSan) in $build"
if ! { cmake -S "$SE3_ROOT/test/sanitize" -B "$build" -DCMAKE_CXX_COMPILER=clang++ &&
  cmake --build "$build" -j2; } >"$build/build.log" 2>&1; then
  tail -n 60 "$build/build.log"
  echo "sanitized build failed (full log: $build/build.log)" >&2
  echo "sanitizers: 0 passed, 1 failed"
  exit 1
fi
echo "built in ${SECONDS} s"

export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}

# Prints the test cases run and failed in a gtest XML report (disabled and skipped ones are
# not run; a missing or unreadable report counts 0 0).
count_cases() {
  python3 -c '
import sys
import xml.etree.ElementTree as ET
try:
    cases = list(ET.parse(sys.argv[1]).getroot().iter("testcase"))
except (OSError, ET.ParseError):
    cases = []
run = [c for c in cases if c.get("status") != "notrun" and c.get("result") not in ("skipped", "suppressed")]
bad = [c for c in run if c.find("failure") is not None or c.find("error") is not None]
print(len(run), len(bad))
' "$1"
}

rm -rf "$results"
mkdir -p "$results"
passed=0
failed=0
for source in $(find "$SE3_ROOT/test/unit" -name 'test_*.cpp' | sort); do
  name=$(basename "$source" .cpp)
  log="$results/$name.log"
  xml="$results/$name.xml"
  status=0
  "$build/$name" --gtest_output="xml:$xml" >"$log" 2>&1 || status=$?
  read -r run bad < <(count_cases "$xml")
  # A sanitizer report, a crash or a leak after the last test: the binary failed as a whole.
  if [ "$status" -ne 0 ] && [ "$bad" -eq 0 ]; then
    bad=1
    run=$((run + 1))
  fi
  if [ "$run" -eq 0 ]; then
    bad=1
    run=1
  fi
  passed=$((passed + run - bad))
  failed=$((failed + bad))
  if [ "$bad" -eq 0 ]; then
    echo "PASS $name: $run test cases"
  else
    echo "FAIL $name: $bad of $run test cases failed (exit status $status, log: $log)"
    grep -E '^\[  FAILED  \]|ERROR: (Address|Leak)Sanitizer|runtime error:|SUMMARY:' "$log" | head -n 20 || true
  fi
done

echo "unit tests done at ${SECONDS} s"

# target, seed corpus, largest input: fuzz_generate's 12 waypoints and every other field take
# ~170 bytes (inputs up to 512, reached quickly with -len_control=10), fuzz_c2's 6 points ~100;
# YAML documents up to 2 KB (the CLI's test requests are below 700 bytes).
fuzz_targets=(
  "fuzz_lie test/fuzz/corpus_lie 128"
  "fuzz_validate test/fuzz/corpus 512"
  "fuzz_curves test/fuzz/corpus 512"
  "fuzz_c2 test/fuzz/corpus_c2 256"
  "fuzz_sphere test/fuzz/corpus_sphere 512"
  "fuzz_yaml test/cli/data 2048"
  "fuzz_generate test/fuzz/corpus 512"
)
# A fixed seed makes a CI run reproducible (a finding replays with the same command); a long
# exploratory run sets SE3_FUZZ_SEED=0 (libFuzzer then picks a random seed).
fuzz_seed=${SE3_FUZZ_SEED:-1}
fuzz_total=0
fuzz_findings=0
for entry in "${fuzz_targets[@]}"; do
  read -r target seeds max_len <<<"$entry"
  # Per-layer targets: a number of inputs (with a time cap); the whole request: a time.
  budget=(-runs="$fuzz_runs" -max_total_time="$fuzz_max_seconds")
  need=$fuzz_runs
  if [ "$target" = fuzz_generate ]; then
    budget=(-max_total_time="$fuzz_seconds")
    need=1
  fi
  corpus="$build/corpus_$target"
  artifacts="$build/artifacts_$target"
  log="$build/$target.log"
  rm -rf "$corpus" "$artifacts"
  mkdir -p "$artifacts"
  cp -r "$SE3_ROOT/$seeds" "$corpus"
  # Replay (blocking): every seed, fixed findings' reproducers included, once each.
  replay_log="$build/$target.replay.log"
  mapfile -t seed_files < <(find "$SE3_ROOT/$seeds" -type f | sort)
  if "$build/$target" -rss_limit_mb=2048 -timeout=60 "${seed_files[@]}" >"$replay_log" 2>&1; then
    passed=$((passed + 1))
    echo "PASS $target replay: ${#seed_files[@]} seed inputs"
  else
    failed=$((failed + 1))
    echo "FAIL $target replay: a seed input fails (log: $replay_log)"
    grep -E "^$target:|ERROR: |runtime error:|SUMMARY:" "$replay_log" | head -n 20 || true
  fi
  # Exploration: new inputs from the seeds. Its findings are reported with their inputs (and go
  # to test/fuzz/findings/ until fixed); they are not counted as failed tests.
  status=0
  start=$SECONDS
  "$build/$target" "${budget[@]}" -seed="$fuzz_seed" -rss_limit_mb=2048 -timeout=60 -max_len="$max_len" -len_control=10 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" >"$log" 2>&1 || status=$?
  seconds=$((SECONDS - start))
  runs=$(sed -nE 's/^stat::number_of_executed_units: *([0-9]+)/\1/p' "$log" | tail -n 1)
  rate=$((runs / (seconds > 0 ? seconds : 1)))
  runs=${runs:-0}
  fuzz_total=$((fuzz_total + runs))
  if [ "$status" -eq 0 ] && [ "$runs" -ge "$need" ] && [ -z "$(ls -A "$artifacts")" ]; then
    echo "explored $target: $runs inputs in $seconds s (${rate}/s), no finding; corpus $(find "$corpus" -type f | wc -l) files"
  elif [ "$status" -eq 0 ] && [ -z "$(ls -A "$artifacts")" ]; then
    echo "explored $target: only $runs inputs in $seconds s (${rate}/s), fewer than the $need asked" \
      "(SE3_FUZZ_RUNS, SE3_FUZZ_MAX_SECONDS; log: $log)"
  else
    fuzz_findings=$((fuzz_findings + 1))
    echo "FINDING $target: exit status $status after $runs inputs (log: $log; inputs: $artifacts)"
    grep -E "^$target:|ERROR: |runtime error:|SUMMARY:|Test unit written" "$log" | head -n 20 || true
  fi
done
echo "fuzzing: $fuzz_total inputs explored, $fuzz_findings targets with findings (not counted as failed tests)"

echo "done in ${SECONDS} s"
echo "sanitizers: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
