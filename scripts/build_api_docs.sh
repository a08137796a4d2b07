#!/usr/bin/env bash
# Builds the C++ API reference with Doxygen (the Doxyfile at the repository root: the public
# headers of include/, README.md as the main page, the pages of docs/) into
# "${SE3_WS:-/tmp}/api_docs" or the directory given as the first argument, never into the source
# tree. Fails, printing them, if Doxygen printed any warning (the Doxyfile keeps WARN_AS_ERROR=NO
# so that every warning is collected; a warning-free log is the test). Needs the Debian package
# doxygen (in SE3_APT_PACKAGES, scripts/common.sh). Ends with `apidocs: 1 passed, 0 failed` or
# `apidocs: 0 passed, 1 failed` (scripts/run_tests.sh adds it to its totals).
#   scripts/build_api_docs.sh [OUTPUT_DIRECTORY]    then open OUTPUT_DIRECTORY/html/index.html
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
out=${1:-${SE3_WS:-/tmp}/api_docs}
case "$(cd "$(dirname "$out")" 2>/dev/null && pwd -P)/$(basename "$out")/" in
  "$SE3_ROOT"/*) echo "build_api_docs: $out is inside the source tree; give a directory outside it" >&2
                 echo "apidocs: 0 passed, 1 failed"; exit 1 ;;
esac
if ! command -v doxygen >/dev/null; then
  echo "build_api_docs: doxygen is not installed (apt-get install doxygen, or scripts/common.sh's se3_install_deps)" >&2
  echo "apidocs: 0 passed, 1 failed"
  exit 1
fi
rm -rf "$out"
mkdir -p "$out"
warnings="$out/warnings.log"
status=0
# The Doxyfile's paths are relative to the repository root; the output and the warning log are
# set here (a later assignment overrides the file's).
(cd "$SE3_ROOT" && { cat Doxyfile; echo "OUTPUT_DIRECTORY = \"$out\""; echo "WARN_LOGFILE = \"$warnings\""; } |
  doxygen - >"$out/doxygen.log" 2>&1) || status=$?
if [ "$status" -ne 0 ]; then
  tail -n 30 "$out/doxygen.log"
  echo "build_api_docs: doxygen failed with status $status (log: $out/doxygen.log)" >&2
  echo "apidocs: 0 passed, 1 failed"
  exit 1
fi
if [ -s "$warnings" ]; then
  sed "s|$SE3_ROOT/||" "$warnings"
  echo "build_api_docs: doxygen printed $(grep -c 'warning:' "$warnings") warning(s); fix the comments above" >&2
  echo "apidocs: 0 passed, 1 failed"
  exit 1
fi
[ -f "$out/html/index.html" ] || { echo "build_api_docs: no $out/html/index.html" >&2; echo "apidocs: 0 passed, 1 failed"; exit 1; }
echo "API reference: $out/html/index.html"
echo "apidocs: 1 passed, 0 failed"
