#!/usr/bin/env bash
# The Python module's tests (test/python/: pytest with Debian's /usr/bin/python3, the module and the
# CLI of the built workspace $SE3_WS). Prints pytest's report, then `python: N passed, N failed`
# (scripts/run_tests.sh adds them to its totals; a run that ends without a report, such as an
# interpreter that crashed, counts as one failure). The JUnit report: $SE3_WS/python_tests.xml.
# Assumes the dependencies are installed and $SE3_WS is built (scripts/run_tests.sh runs it after
# the build).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
set +u
# shellcheck disable=SC1091
source "$SE3_WS/devel/setup.bash"
set -u
report="$SE3_WS/python_tests.xml"
rm -f "$report"
status=0
# No cache folder in the source tree (-p no:cacheprovider).
(cd "$SE3_ROOT" && /usr/bin/python3 -m pytest -p no:cacheprovider -q -rfE --junitxml="$report" test/python) ||
  status=$?
counts=$(/usr/bin/python3 - "$report" <<'PY' 2>/dev/null || true
import sys
import xml.etree.ElementTree as ET

suite = ET.parse(sys.argv[1]).getroot()
suite = suite if suite.tag == "testsuite" else suite.find("testsuite")
tests, failed = int(suite.get("tests")), int(suite.get("failures")) + int(suite.get("errors"))
print(tests - failed - int(suite.get("skipped")), failed)
PY
)
if [ -z "$counts" ]; then
  echo "run_python_tests: pytest left no report (status $status)" >&2
  echo "python: 0 passed, 1 failed"
  exit 1
fi
read -r passed failed <<<"$counts"
if [ "$status" -ne 0 ] && [ "$failed" -eq 0 ]; then
  failed=1
fi
echo "python: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
