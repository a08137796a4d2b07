#!/usr/bin/env bash
# Installs what is missing, checks the structure rules, builds, runs every test (unit, CLI, rostest
# integration, the rviz screenshot, the README's command blocks, the Python module's pytest suite,
# catkin_lint and the install space, sanitizers) and prints `N passed, N failed`. Exits non-zero if
# any test fails. Every failure is named on standard output (a CI log may keep only that). Idempotent.
# --fast: the fast tier, a change's first feedback: the structure check and the unit tests of
# test/unit/ but the request-space grid, built without ROS or sanitizers (g++ -O2, ccache where
# installed), no catkin build, rostests, sanitizers or fuzzing.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
if [ "${1:-}" = --fast ]; then
  se3_install_deps
  mkdir -p "$SE3_WS"
  status=0
  /usr/bin/python3 "$SE3_ROOT/scripts/check_structure.py" >"$SE3_WS/structure.log" 2>&1 || status=1
  cat "$SE3_WS/structure.log"
  SE3_SANITIZE_PHASE=plain bash "$SE3_ROOT/scripts/run_sanitizers.sh" >"$SE3_WS/fast.log" 2>&1 || status=1
  grep -vE '^PASS ' "$SE3_WS/fast.log" || true
  # The two stages' counts; a stage that fails without counting a failure counts as one.
  awk -v status="$status" '/^(structure|sanitizers): [0-9]+ passed, [0-9]+ failed$/ { p += $2; f += $4 }
    END { if (status != 0 && f == 0) f = 1; print p " passed, " f " failed" }' "$SE3_WS/structure.log" "$SE3_WS/fast.log"
  exit $status
fi
se3_install_deps
mkdir -p "$SE3_WS"
# The structure rules first (scripts/check_structure.py: a second, no build); counted below.
structure_status=0
/usr/bin/python3 "$SE3_ROOT/scripts/check_structure.py" >"$SE3_WS/structure.log" 2>&1 || structure_status=$?
grep -v '^PASS' "$SE3_WS/structure.log" || true
# The sanitized build (plain CMake, ROS-free, about 13 minutes on 2 cores) and its unit tests at
# nice 19 from the start, beside everything below, on the CPU the rest leaves idle (the catkin
# build's serial steps, the rostests' waits on ROS start-up and sleeps); counted at the end.
SE3_SANITIZE_PHASE=unit nice -n 19 bash "$SE3_ROOT/scripts/run_sanitizers.sh" >"$SE3_WS/sanitizers_unit.log" 2>&1 &
sanitized_unit_tests=$!
# Each test is built once: the unit tests of test/unit/ in the sanitized build above, the
# request-space grid (test_request_space, which needs an optimised build) and the ROS tests here;
# the benchmarks are not built (no stage runs them; scripts/run_benchmarks.sh builds its own).
se3_build -Dse3_interpolation_CATKIN_UNIT_TESTS=OFF -Dse3_interpolation_BENCHMARKS=OFF
# The test binaries on both cores (run_tests below runs the tests one at a time, -j1, and would
# build them on one).
(cd "$SE3_WS" && catkin_make tests -j2 >"$SE3_WS/tests_build.log" 2>&1) ||
  { tail -n 60 "$SE3_WS/tests_build.log"; echo "building the tests failed (log: $SE3_WS/tests_build.log)"; }
echo "built at ${SECONDS} s"
cd "$SE3_WS"
rm -rf build/test_results
catkin_make run_tests -j1 >"$SE3_WS/tests.log" 2>&1 || true
summary=$(catkin_test_results build/test_results --all 2>&1 || true)
echo "$summary" | grep -vE '^Skipping' | grep -E 'Summary|Failure|Error|failures|errors' || true
line=$(echo "$summary" | grep -E '^Summary:' | tail -n 1)
total=$(echo "$line" | sed -nE 's/^Summary: ([0-9]+) tests.*/\1/p')
errors=$(echo "$line" | sed -nE 's/.* ([0-9]+) errors.*/\1/p')
failures=$(echo "$line" | sed -nE 's/.* ([0-9]+) failures.*/\1/p')
skipped=$(echo "$line" | sed -nE 's/.* ([0-9]+) skipped.*/\1/p')
total=${total:-0}; errors=${errors:-0}; failures=${failures:-0}; skipped=${skipped:-0}
failed=$((errors + failures))
passed=$((total - failed - skipped))
# Which cases failed, and why (catkin_test_results prints only the counts per report).
[ "$failed" -eq 0 ] || /usr/bin/python3 "$SE3_ROOT/scripts/print_test_failures.py" build/test_results || true
echo "catkin tests done at ${SECONDS} s"
# rviz on the demo config under Xvfb: a screenshot that is not blank counts as one more test.
mkdir -p "$SE3_WS/artifacts"
if bash "$SE3_ROOT/scripts/rviz_screenshot.sh" "$SE3_WS/artifacts/rviz_demo.png"; then
  total=$((total + 1))
else
  echo "rviz screenshot check failed (log: $SE3_WS/rviz_screenshot.log)"
  tail -n 20 "$SE3_WS/rviz_screenshot.log"
  total=$((total + 1)); failed=$((failed + 1))
fi
passed=$((total - failed - skipped))
# Every gtest and rostest registered in the catkin build leaves a report (the unit tests of
# test/unit/ other than the grid are counted by the sanitizers' stage).
expected_suites=$(grep -cE '^\s*(catkin_add_gtest|add_rostest_gtest|add_rostest)\(' "$SE3_ROOT/CMakeLists.txt")
if [ "$total" -eq 0 ] || [ "$(find build/test_results -name '*.xml' | wc -l)" -lt "$expected_suites" ]; then
  echo "test reports are missing: $(find build/test_results -name '*.xml' | wc -l) reports for $expected_suites registered suites (see $SE3_WS/tests.log)"
  tail -n 40 "$SE3_WS/tests.log"
  failed=$((failed + 1))
fi
# A stage run by its own script, which ends with the line `<prefix>: N passed, N failed`: its
# counts are added to the totals; a script that fails without counting a failure counts as one.
run_counted_stage() {
  local status=0
  bash "$2" >"$3" 2>&1 || status=$?
  count_stage "$1" "$2" "$3" "$status"
}
# The counting of a stage that has finished with exit status $4 (run_counted_stage's, or one run
# in the background).
count_stage() {
  local prefix=$1 script=$2 log=$3 status=$4 line stage_passed stage_failed
  grep -vE "^$prefix: |: ok\$" "$log" || true
  line=$(grep -E "^$prefix: [0-9]+ passed, [0-9]+ failed\$" "$log" | tail -n 1 || true)
  stage_passed=$(echo "$line" | sed -nE "s/^$prefix: ([0-9]+) passed.*/\1/p")
  stage_failed=$(echo "$line" | sed -nE 's/.* ([0-9]+) failed$/\1/p')
  stage_passed=${stage_passed:-0}; stage_failed=${stage_failed:-0}
  if [ "$status" -ne 0 ] && [ "$stage_failed" -eq 0 ]; then
    echo "$script failed with exit status $status without counting a failure (log: $log); its last lines:"
    tail -n 20 "$log"
    stage_failed=1
  fi
  passed=$((passed + stage_passed))
  failed=$((failed + stage_failed))
  echo "$prefix stage done at ${SECONDS} s"
}
count_stage structure "$SE3_ROOT/scripts/check_structure.py" "$SE3_WS/structure.log" "$structure_status"
# Every ```bash block of README.md and of docs/*.md, run verbatim in order (scripts/check_readme.sh):
# each block is a test.
run_counted_stage readme "$SE3_ROOT/scripts/check_readme.sh" "$SE3_WS/readme_summary.log"
# The Python module's tests (scripts/run_python_tests.sh: pytest over test/python/): each test case is a test.
run_counted_stage python "$SE3_ROOT/scripts/run_python_tests.sh" "$SE3_WS/python_tests.log"
# The API reference (scripts/build_api_docs.sh): Doxygen over the public headers without a warning.
run_counted_stage apidocs "$SE3_ROOT/scripts/build_api_docs.sh" "$SE3_WS/api_docs.log"
# catkin_lint --strict, then the install space (scripts/check_install.sh): `catkin_make install` into
# a scratch prefix, and the demo launch and the CLI run from it alone; each check is a test.
run_counted_stage install "$SE3_ROOT/scripts/check_install.sh" "$SE3_WS/install_summary.log"
# The unit tests under ASan + UBSan (scripts/run_sanitizers.sh, started above) and then, on the
# idle cores, the libFuzzer targets: each sanitized test case and each fuzz replay and exploration
# count as tests here too.
sanitized_unit_status=0
wait "$sanitized_unit_tests" || sanitized_unit_status=$?
count_stage sanitizers "$SE3_ROOT/scripts/run_sanitizers.sh" "$SE3_WS/sanitizers_unit.log" "$sanitized_unit_status"
# Instructions per core operation (scripts/instruction_counts.sh --check: callgrind, deterministic
# under any load) against the committed counts and the performance targets of
# bench/instruction_targets.txt, each row and target a test: beside the sanitizers' stage (its
# tests run two at a time; callgrind's counts do not depend on the load, and it is done in about
# a minute).
bash "$SE3_ROOT/scripts/instruction_counts.sh" --check >"$SE3_WS/instruction_counts.log" 2>&1 &
instruction_counts=$!
SE3_SANITIZE_PHASE=fuzz run_counted_stage sanitizers "$SE3_ROOT/scripts/run_sanitizers.sh" "$SE3_WS/sanitizers_fuzz.log"
instruction_status=0
wait "$instruction_counts" || instruction_status=$?
count_stage instructions "$SE3_ROOT/scripts/instruction_counts.sh" "$SE3_WS/instruction_counts.log" "$instruction_status"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
