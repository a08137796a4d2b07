#!/usr/bin/env bash
# Installs what is missing, builds, runs every test (unit, CLI, rostest integration, the rviz
# screenshot, the README's command blocks, sanitizers) and prints `N passed, N failed`. Exits
# non-zero if any test fails. Idempotent.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
se3_install_deps
se3_build
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
# rviz on the demo config under Xvfb: a screenshot that is not blank counts as one more test.
mkdir -p "$SE3_WS/artifacts"
if bash "$SE3_ROOT/scripts/rviz_screenshot.sh" "$SE3_WS/artifacts/rviz_demo.png"; then
  total=$((total + 1))
else
  echo "rviz screenshot check failed (log: $SE3_WS/rviz_screenshot.log)" >&2
  total=$((total + 1)); failed=$((failed + 1))
fi
passed=$((total - failed - skipped))
expected_suites=$(find "$SE3_ROOT/test/unit" -name 'test_*.cpp' | wc -l)
if [ "$total" -eq 0 ] || [ "$(find build/test_results -name '*.xml' | wc -l)" -lt "$expected_suites" ]; then
  echo "test reports are missing (see $SE3_WS/tests.log)" >&2
  tail -n 40 "$SE3_WS/tests.log" >&2
  failed=$((failed + 1))
fi
# Every ```bash block of README.md, run verbatim in order (scripts/check_readme.sh): each block is a test.
readme_status=0
bash "$SE3_ROOT/scripts/check_readme.sh" >"$SE3_WS/readme_summary.log" 2>&1 || readme_status=$?
grep -vE '^readme: |: ok$' "$SE3_WS/readme_summary.log" || true
readme_line=$(grep -E '^readme: [0-9]+ passed, [0-9]+ failed$' "$SE3_WS/readme_summary.log" | tail -n 1 || true)
readme_passed=$(echo "$readme_line" | sed -nE 's/^readme: ([0-9]+) passed.*/\1/p')
readme_failed=$(echo "$readme_line" | sed -nE 's/.* ([0-9]+) failed$/\1/p')
readme_passed=${readme_passed:-0}; readme_failed=${readme_failed:-0}
if [ "$readme_status" -ne 0 ] && [ "$readme_failed" -eq 0 ]; then
  echo "scripts/check_readme.sh failed (log: $SE3_WS/readme_summary.log)" >&2
  readme_failed=1
fi
passed=$((passed + readme_passed))
failed=$((failed + readme_failed))
# The core and unit tests under ASan + UBSan and a bounded libFuzzer run (scripts/run_sanitizers.sh):
# each sanitized test case and the fuzz run count as tests here too.
sanitizer_status=0
bash "$SE3_ROOT/scripts/run_sanitizers.sh" >"$SE3_WS/sanitizers.log" 2>&1 || sanitizer_status=$?
grep -vE '^sanitizers: ' "$SE3_WS/sanitizers.log" || true
sanitizer_line=$(grep -E '^sanitizers: [0-9]+ passed, [0-9]+ failed$' "$SE3_WS/sanitizers.log" | tail -n 1 || true)
sanitizer_passed=$(echo "$sanitizer_line" | sed -nE 's/^sanitizers: ([0-9]+) passed.*/\1/p')
sanitizer_failed=$(echo "$sanitizer_line" | sed -nE 's/.* ([0-9]+) failed$/\1/p')
sanitizer_passed=${sanitizer_passed:-0}; sanitizer_failed=${sanitizer_failed:-0}
if [ "$sanitizer_status" -ne 0 ] && [ "$sanitizer_failed" -eq 0 ]; then
  echo "scripts/run_sanitizers.sh failed (log: $SE3_WS/sanitizers.log)" >&2
  sanitizer_failed=1
fi
passed=$((passed + sanitizer_passed))
failed=$((failed + sanitizer_failed))
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
