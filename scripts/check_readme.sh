#!/usr/bin/env bash
# Runs every ```bash block of README.md verbatim, in order, in one bash shell started in the
# repository root, as a newcomer would type them: the working directory, exported variables and
# background jobs carry over from block to block. A block fails if any command in it fails
# (ERR trap with pipefail) or if it prints `success: False` (a service call that was refused).
#
# A marker on the line right before a block (an HTML comment, invisible in the rendered README):
#   <!-- readme-check: skip REASON -->            not run here (interactive, or this check itself)
#   <!-- readme-check: wait-for-service NAME -->  after the block, wait up to 60 s for service NAME
#
# The ROS master port is $SE3_ROS_PORT (default: the first free port from 11398 on, so two checks on
# one machine do not meet): ROS_MASTER_URI points there before the first block, so no command
# touches the default port 11311. Everything the blocks start is
# stopped at the end (one process group). The whole run is capped at $SE3_README_TIMEOUT s
# (default 240); blocks not reached count as failed.
#
# Prints `readme block N (README.md:LINE): ok | FAILED | skipped (REASON)` per block, then
# `readme: N passed, N failed` (scripts/run_tests.sh adds these to its totals). Log:
# $SE3_WS/readme_check.log. Assumes the dependencies are installed and $SE3_WS is built
# (scripts/run_tests.sh runs it after the build).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
SE3_ROS_PORT=${SE3_ROS_PORT:-$(se3_free_port)}
export SE3_ROS_PORT=${SE3_ROS_PORT:?no free port in 11398 ... 11497; set SE3_ROS_PORT}
export ROS_MASTER_URI=http://localhost:$SE3_ROS_PORT
readme="$SE3_ROOT/README.md"
work="$SE3_WS/readme_check"
log="$SE3_WS/readme_check.log"
rm -rf "$work"
mkdir -p "$work"

# Split the README into block files; blocks.tsv: index, line, action (run|skip), argument.
awk -v dir="$work" '
  /^```bash[[:space:]]*$/ && !inside {
    inside = 1; n++; file = dir "/block_" n ".sh"; printf "" > file
    action = "run"; arg = ""
    if (match(prev, /<!-- readme-check: skip .* -->/)) { action = "skip"; arg = prev; sub(/.*<!-- readme-check: skip /, "", arg); sub(/ -->.*/, "", arg) }
    else if (match(prev, /<!-- readme-check: wait-for-service [^ ]+ -->/)) { action = "wait"; arg = prev; sub(/.*wait-for-service /, "", arg); sub(/ -->.*/, "", arg) }
    printf "%d\t%d\t%s\t%s\n", n, NR + 1, action, arg > (dir "/blocks.tsv")
    next
  }
  /^```[[:space:]]*$/ && inside { inside = 0; close(file); prev = ""; next }
  inside { print >> file; next }
  { if ($0 !~ /^[[:space:]]*$/) prev = $0 }
' "$readme"
[ -s "$work/blocks.tsv" ] || { echo "readme: no bash blocks found in $readme" >&2; echo "readme: 0 passed, 1 failed"; exit 1; }

# The newcomer's shell: one script sourcing the blocks in order.
runner="$work/run.sh"
{
  echo 'set -o errtrace -o pipefail'
  echo 'trap "block_failed=1" ERR'
  echo "cd \"$SE3_ROOT\""
  while IFS=$'\t' read -r n line action arg; do
    [ "$action" = skip ] && continue
    echo "echo '@@ block $n start'"
    echo 'block_failed=0'
    echo "source \"$work/block_$n.sh\" </dev/null"
    if [ "$action" = wait ]; then
      echo "for _ in \$(seq 60); do rosservice list 2>/dev/null | grep -qx '$arg' && break; sleep 1; done"
      echo "rosservice list 2>/dev/null | grep -qx '$arg' || { echo 'service $arg did not come up'; block_failed=1; }"
    fi
    echo "echo \"@@ block $n status \$block_failed\""
  done <"$work/blocks.tsv"
} >"$runner"

env -u DISPLAY setsid timeout -s INT -k 10 "${SE3_README_TIMEOUT:-240}" bash "$runner" >"$log" 2>&1 &
group=$!
wait "$group" || true
# Stop what the blocks left running (roslaunch, static_transform_publisher, ...): the whole group.
kill -INT -- "-$group" 2>/dev/null && sleep 3
kill -KILL -- "-$group" 2>/dev/null || true

passed=0
failed=0
while IFS=$'\t' read -r n line action arg; do
  where="README.md:$line"
  if [ "$action" = skip ]; then
    echo "readme block $n ($where): skipped ($arg)"
    continue
  fi
  output=$(awk -v n="$n" '$0 == "@@ block " n " start" {on = 1; next} on && /^@@ block [0-9]+ status/ {exit} on' "$log")
  status=$(grep -E "^@@ block $n status [01]$" "$log" | awk '{print $5}' || true)
  if [ "$status" = 0 ] && ! grep -q "success: False" <<<"$output"; then
    echo "readme block $n ($where): ok"
    passed=$((passed + 1))
  else
    [ -n "$status" ] || output="$output
(not finished: the run was stopped after ${SE3_README_TIMEOUT:-240} s)"
    echo "readme block $n ($where): FAILED"
    sed -n 1,200p "$work/block_$n.sh" | sed 's/^/    $ /'
    tail -n 25 <<<"$output" | sed 's/^/    | /'
    failed=$((failed + 1))
  fi
done <"$work/blocks.tsv"
echo "readme: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
