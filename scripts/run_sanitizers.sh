#!/usr/bin/env bash
# Builds the core and every unit test with AddressSanitizer + UndefinedBehaviorSanitizer (plain
# CMake, no ROS: test/sanitize/CMakeLists.txt) into $SE3_WS/sanitize, runs each test binary
# (gtest XML reports in $SE3_WS/sanitize/test_results), then runs the libFuzzer targets, each
# twice over its seed corpus:
#  - the replay: every seed once (fixed findings' inputs included);
#  - the exploration, from the fixed seed ${SE3_FUZZ_SEED:-1} (reproducible: a passing run stays
#    passing): every per-layer target (fuzz_lie, fuzz_validate, fuzz_curves, fuzz_c2,
#    fuzz_sphere, fuzz_yaml) for ${SE3_FUZZ_RUNS:-100000} inputs, at most
#    ${SE3_FUZZ_MAX_SECONDS:-60} s each, and the whole-request target fuzz_generate, much slower
#    per input, for ${SE3_FUZZ_SECONDS:-30} s. Each run's input count, time and rate are printed.
# Each replay and each exploration is one test: a failing seed, a finding (printed with its
# input) or an exploration that reaches fewer inputs than targets.txt's last column asks for (a
# target slowed down about fourfold; SE3_FUZZ_MIN_RUNS overrides it for every target) fails it.
# The last line is `sanitizers: N passed, N failed` (the unit test cases plus those); exits
# non-zero on any failure.
# SE3_SANITIZE_PHASE: `all` (default) the build, the unit tests and the fuzz targets; `unit` the build
# and the unit tests; `fuzz` the build and the fuzz targets; `plain` the unit tests built without
# sanitizers (g++ -O2, ccache), the fast tier of scripts/run_tests.sh --fast. scripts/run_tests.sh runs `unit` at
# nice 19 beside its other stages from the start, and `fuzz` (whose explorations need their cores:
# targets.txt's minimum inputs) at the end, which finds the build up to date. Each phase prints its
# own last line.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
se3_install_deps

phase=${SE3_SANITIZE_PHASE:-all}
case "$phase" in
  all | unit | fuzz | plain) ;;
  *)
    echo "SE3_SANITIZE_PHASE=$phase: expected all, unit, fuzz or plain" >&2
    exit 2
    ;;
esac
fuzz_runs=${SE3_FUZZ_RUNS:-100000}
fuzz_max_seconds=${SE3_FUZZ_MAX_SECONDS:-60}
fuzz_seconds=${SE3_FUZZ_SECONDS:-30}
if [ "$phase" = plain ]; then
  # The fast tier's build (scripts/run_tests.sh --fast): the same unit tests without sanitizers,
  # g++ -O2 and ccache where it is installed, in a folder of its own.
  build="$SE3_WS/unit_plain"
  configure=(-DSE3_SANITIZE=OFF -DCMAKE_CXX_COMPILER=g++)
  ! command -v ccache >/dev/null || configure+=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  echo "unit test build (g++ -O2, no sanitizers) in $build"
else
  build="$SE3_WS/sanitize"
  configure=(-DCMAKE_CXX_COMPILER=clang++)
  echo "sanitized build (clang++, ASan + UBSan) in $build"
fi
results="$build/test_results"
mkdir -p "$build"
if ! { cmake -S "$SE3_ROOT/test/sanitize" -B "$build" "${configure[@]}" &&
  cmake --build "$build" -j2; } >"$build/build.log" 2>&1; then
  tail -n 60 "$build/build.log"
  echo "the build failed (full log: $build/build.log)" >&2
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

mkdir -p "$results"
passed=0
failed=0

# The tests and the fuzz targets run ${SE3_SANITIZE_JOBS:-2} at a time (se3_start_job; one per
# core: each is a single process). Each job writes its printed lines to $results/JOB.out and its
# counts to $results/JOB.counts ("passed failed"); they are printed and added in a fixed order
# afterwards.
# Prints job $1's lines and adds its counts.
collect_job() {
  local p=0 f=1
  cat "$results/$1.out" 2>/dev/null || echo "FAIL $1: its job left no output"
  [ -f "$results/$1.counts" ] && read -r p f <"$results/$1.counts"
  passed=$((passed + p))
  failed=$((failed + f))
}

# One sanitized unit test binary: its cases, plus one failure when the binary fails as a whole (a
# sanitizer report, a crash or a leak after the last test) or runs no case.
unit_test_job() {
  local name=$1 log="$results/$1.log" xml="$results/$1.xml" status=0 run bad
  "$build/$name" --gtest_output="xml:$xml" >"$log" 2>&1 || status=$?
  read -r run bad < <(count_cases "$xml")
  if [ "$status" -ne 0 ] && [ "$bad" -eq 0 ]; then
    bad=1
    run=$((run + 1))
  fi
  if [ "$run" -eq 0 ]; then
    bad=1
    run=1
  fi
  {
    if [ "$bad" -eq 0 ]; then
      echo "PASS $name: $run test cases"
    else
      echo "FAIL $name: $bad of $run test cases failed (exit status $status, log: $log)"
      grep -E '^\[  FAILED  \]|ERROR: (Address|Leak)Sanitizer|runtime error:|SUMMARY:' "$log" | head -n 20 || true
    fi
  } >"$results/$name.out"
  echo "$((run - bad)) $bad" >"$results/$name.counts"
}

if [ "$phase" != fuzz ]; then
  rm -f "$results"/test_*
  # Longest source first (the longest-running tests are among the longest sources: replanning,
  # jerk-limited timing, goal trajectories), so that no long test starts last.
  # test_request_space is not among them (test/sanitize/CMakeLists.txt: it runs in the optimised build).
  mapfile -t unit_tests < <(for source in $(find "$SE3_ROOT/test/unit" -name 'test_*.cpp' ! -name test_request_space.cpp); do
    echo "$(wc -l <"$source") $(basename "$source" .cpp)"
  done | sort -k1,1nr -k2 | awk '{print $2}')
  for name in "${unit_tests[@]}"; do
    se3_start_job unit_test_job "$name"
  done
  se3_finish_jobs
  for name in $(printf '%s\n' "${unit_tests[@]}" | sort); do
    collect_job "$name"
  done
  echo "unit tests done at ${SECONDS} s"
fi

# A fixed seed makes a CI run reproducible (a finding replays with the same command); a long
# exploratory run sets SE3_FUZZ_SEED=0 (libFuzzer then picks a random seed).
fuzz_seed=${SE3_FUZZ_SEED:-1}
# One fuzz target, two tests: the replay of its seeds and the exploration. Writes the number of
# inputs explored and whether there was a finding to $results/TARGET.fuzz ("runs findings").
fuzz_job() {
  local target=$1 seeds=$2 max_len=$3 need=${SE3_FUZZ_MIN_RUNS:-$4} p=0 f=0 runs seconds rate
  local budget=(-runs="$fuzz_runs" -max_total_time="$fuzz_max_seconds")
  # Per-layer targets: a number of inputs (with a time cap); the whole request: a time.
  if [ "$target" = fuzz_generate ]; then
    budget=(-max_total_time="$fuzz_seconds")
  fi
  local corpus="$build/corpus_$target" artifacts="$build/artifacts_$target" log="$build/$target.log"
  rm -rf "$corpus" "$artifacts"
  mkdir -p "$artifacts"
  cp -r "$SE3_ROOT/$seeds" "$corpus"
  {
    # Replay: every seed, fixed findings' reproducers included, once each.
    local replay_log="$build/$target.replay.log" seed_files
    mapfile -t seed_files < <(find "$SE3_ROOT/$seeds" -type f | sort)
    if "$build/$target" -rss_limit_mb=2048 -timeout=60 "${seed_files[@]}" >"$replay_log" 2>&1; then
      p=$((p + 1))
      echo "PASS $target replay: ${#seed_files[@]} seed inputs"
    else
      f=$((f + 1))
      echo "FAIL $target replay: a seed input fails (log: $replay_log)"
      grep -E "^$target:|ERROR: |runtime error:|SUMMARY:" "$replay_log" | head -n 20 || true
    fi
    # Exploration: new inputs from the seeds, from the fixed seed. A finding or fewer inputs than
    # asked fails it.
    se3_fuzz_explore "$build/$target" "$corpus" "$artifacts" "$log" "$max_len" "$fuzz_seed" "${budget[@]}"
    runs=$se3_fuzz_runs
    seconds=$se3_fuzz_seconds
    rate=$((runs / (seconds > 0 ? seconds : 1)))
    find "$artifacts" -type f -name 'slow-unit-*' -exec echo "$target: slow input (not a finding):" {} \;
    if [ -z "$se3_fuzz_finding" ] && [ "$runs" -ge "$need" ]; then
      p=$((p + 1))
      echo "explored $target: $runs inputs in $seconds s (${rate}/s), no finding; corpus $(find "$corpus" -type f | wc -l) files"
    elif [ -z "$se3_fuzz_finding" ]; then
      f=$((f + 1))
      echo "FAIL explored $target: only $runs inputs in $seconds s (${rate}/s), fewer than the $need required" \
        "(test/fuzz/targets.txt, SE3_FUZZ_MIN_RUNS; log: $log)"
    else
      f=$((f + 1))
      echo "FINDING $target: exit status $se3_fuzz_status after $runs inputs (log: $log; inputs: $artifacts)"
      grep -E "^$target:|ERROR: |runtime error:|SUMMARY:|Test unit written" "$log" | head -n 20 || true
    fi
    echo "$runs ${se3_fuzz_finding:+1}" >"$results/$target.fuzz"
  } >"$results/$target.out"
  echo "$p $f" >"$results/$target.counts"
}
if [ "$phase" = all ] || [ "$phase" = fuzz ]; then
  rm -f "$results"/fuzz_*
  mapfile -t fuzz_targets < <(grep -vE '^(#|$)' "$SE3_ROOT/test/fuzz/targets.txt")
  for line in "${fuzz_targets[@]}"; do
    read -r target seeds max_len min_runs <<<"$line"
    se3_start_job fuzz_job "$target" "$seeds" "$max_len" "$min_runs"
  done
  se3_finish_jobs
  fuzz_total=0
  fuzz_findings=0
  for line in "${fuzz_targets[@]}"; do
    read -r target _ <<<"$line"
    collect_job "$target"
    runs=0
    finding=""
    [ -f "$results/$target.fuzz" ] && read -r runs finding <"$results/$target.fuzz"
    fuzz_total=$((fuzz_total + runs))
    [ -z "$finding" ] || fuzz_findings=$((fuzz_findings + 1))
  done
  echo "fuzzing: $fuzz_total inputs explored, $fuzz_findings targets with findings"
fi

echo "done in ${SECONDS} s"
echo "sanitizers: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
