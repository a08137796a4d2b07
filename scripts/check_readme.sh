#!/usr/bin/env bash
# Runs every ```bash block of README.md and then of the pages of docs/ (in the order of `pages`
# below), verbatim, as a newcomer would type them: each page in one fresh bash shell started in
# the repository root, so the working directory, exported variables and background jobs carry
# over from block to block within a page. README.md's shell starts as after a fresh clone (its
# own blocks source scripts/setup.bash); a docs page's shell has sourced scripts/setup.bash, as
# the README asks of every shell. A block fails if any command in it fails (ERR trap with
# pipefail) or if it prints `success: False` (a service call that was refused).
#
# A marker on the line right before a block (an HTML comment, invisible in the rendered page):
#   <!-- readme-check: skip REASON -->            not run here (interactive, or this check itself)
#   <!-- readme-check: wait-for-service NAME -->  after the block, wait up to
#                                                 $SE3_README_SERVICE_WAIT s (default 120) until
#                                                 service NAME answers (rosservice type)
#
# One ROS master serves every page: this script starts it on $SE3_ROS_PORT (default: the first
# free port from 11398 on, so two checks on one machine do not meet) and ROS_MASTER_URI points
# there, so no command touches the default port 11311. After each page everything that page
# started is stopped (its process group) and the master forgets nodes that did not unregister
# (rosnode cleanup), so the next page may start a node of the same name. Each page may take
# $SE3_README_TIMEOUT s (default 420); blocks not reached count as failed. A page in docs/ that is
# missing from `pages` counts as one failure, so that no page goes unchecked.
#
# Prints `readme block N (FILE:LINE): ok | FAILED | skipped (REASON)` per block, then
# `readme: N passed, N failed` (scripts/run_tests.sh adds these to its totals). Logs:
# $SE3_WS/readme_check/*.log, all of them in $SE3_WS/readme_check.log. Assumes the dependencies
# are installed and $SE3_WS is built (scripts/run_tests.sh runs it after the build).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
SE3_ROS_PORT=${SE3_ROS_PORT:-$(se3_free_port)}
export SE3_ROS_PORT=${SE3_ROS_PORT:?no free port in 11398 ... 11497; set SE3_ROS_PORT}
export ROS_MASTER_URI=http://localhost:$SE3_ROS_PORT
pages=(README.md docs/ros_interface.md docs/curves.md docs/timing.md docs/command_line.md docs/api.md
       docs/testing.md docs/performance.md docs/python.md docs/joint_space.md)
timeout_s=${SE3_README_TIMEOUT:-420}
service_wait=${SE3_README_SERVICE_WAIT:-120}
work="$SE3_WS/readme_check"
log="$SE3_WS/readme_check.log"
rm -rf "$work" "$log"
mkdir -p "$work"

passed=0
failed=0
for page in "$SE3_ROOT"/docs/*.md; do
  name=docs/$(basename "$page")
  if ! printf '%s\n' "${pages[@]}" | grep -qxF "$name"; then
    echo "readme: $name is not in the pages scripts/check_readme.sh runs; add it there"
    failed=$((failed + 1))
  fi
done

# The shared ROS master, in its own process group (stopped at the end).
set +u
# shellcheck disable=SC1091
source "$SE3_WS/devel/setup.bash"
set -u
setsid roscore -p "$SE3_ROS_PORT" >"$work/roscore.log" 2>&1 &
master=$!
stop_master() {
  kill -INT -- "-$master" 2>/dev/null && sleep 2
  kill -KILL -- "-$master" 2>/dev/null || true
}
trap stop_master EXIT
for _ in $(seq 60); do
  rosparam get /run_id >/dev/null 2>&1 && break
  sleep 1
done
rosparam get /run_id >/dev/null 2>&1 || { tail -n 20 "$work/roscore.log"; echo "readme: no ROS master on port $SE3_ROS_PORT"; }

n=0
for page in "${pages[@]}"; do
  file="$SE3_ROOT/$page"
  tag=$(echo "$page" | tr '/.' '__')
  if [ ! -f "$file" ]; then
    echo "readme: $page is missing"
    failed=$((failed + 1))
    continue
  fi
  # Split the page into block files; blocks.tsv: global index, line, action (run|skip|wait), argument.
  blocks="$work/$tag.tsv"
  awk -v dir="$work" -v first="$n" -v tsv="$blocks" '
    /^```bash[[:space:]]*$/ && !inside {
      inside = 1; n++; file = dir "/block_" (first + n) ".sh"; printf "" > file
      action = "run"; arg = ""
      if (match(prev, /<!-- readme-check: skip .* -->/)) { action = "skip"; arg = prev; sub(/.*<!-- readme-check: skip /, "", arg); sub(/ -->.*/, "", arg) }
      else if (match(prev, /<!-- readme-check: wait-for-service [^ ]+ -->/)) { action = "wait"; arg = prev; sub(/.*wait-for-service /, "", arg); sub(/ -->.*/, "", arg) }
      printf "%d\t%d\t%s\t%s\n", first + n, NR + 1, action, arg > tsv
      next
    }
    /^```[[:space:]]*$/ && inside { inside = 0; close(file); prev = ""; next }
    inside { print >> file; next }
    { if ($0 !~ /^[[:space:]]*$/) prev = $0 }
  ' "$file"
  [ -s "$blocks" ] || continue
  n=$(tail -n 1 "$blocks" | cut -f 1)

  # The newcomer's shell for this page: one script sourcing its blocks in order.
  runner="$work/$tag.run.sh"
  page_log="$work/$tag.log"
  {
    echo 'set -o errtrace -o pipefail'
    echo 'trap "block_failed=1" ERR'
    echo "cd \"$SE3_ROOT\""
    [ "$page" = README.md ] || echo 'source scripts/setup.bash'
    while IFS=$'\t' read -r i line action arg; do
      [ "$action" = skip ] && continue
      echo "echo '@@ block $i start'"
      echo 'block_failed=0'
      echo "source \"$work/block_$i.sh\" </dev/null"
      if [ "$action" = wait ]; then
        echo "for _ in \$(seq $service_wait); do rosservice type '$arg' >/dev/null 2>&1 && break; sleep 1; done"
        echo "rosservice type '$arg' >/dev/null 2>&1 || { echo 'service $arg did not come up within $service_wait s'; block_failed=1; }"
      fi
      echo "echo \"@@ block $i status \$block_failed\""
    done <"$blocks"
  } >"$runner"

  env -u DISPLAY setsid timeout -s INT -k 10 "$timeout_s" bash "$runner" >"$page_log" 2>&1 &
  group=$!
  wait "$group" || true
  # Stop what the page left running (roslaunch, static_transform_publisher, ...): its whole group.
  # Background jobs of a non-interactive shell ignore SIGINT, so TERM follows before KILL.
  kill -INT -- "-$group" 2>/dev/null && sleep 1
  kill -TERM -- "-$group" 2>/dev/null && sleep 3
  kill -KILL -- "-$group" 2>/dev/null || true
  # Nodes killed without unregistering would leave their services registered for the next page.
  echo y | timeout 60 rosnode cleanup >>"$work/cleanup.log" 2>&1 || true
  { echo "==== $page"; cat "$page_log"; } >>"$log"

  while IFS=$'\t' read -r i line action arg; do
    where="$page:$line"
    if [ "$action" = skip ]; then
      echo "readme block $i ($where): skipped ($arg)"
      continue
    fi
    output=$(awk -v n="$i" '$0 == "@@ block " n " start" {on = 1; next} on && /^@@ block [0-9]+ status/ {exit} on' "$page_log")
    status=$(grep -E "^@@ block $i status [01]$" "$page_log" | awk '{print $5}' || true)
    if [ "$status" = 0 ] && ! grep -q "success: False" <<<"$output"; then
      echo "readme block $i ($where): ok"
      passed=$((passed + 1))
    else
      [ -n "$status" ] || output="$output
(not finished: the page was stopped after $timeout_s s)"
      echo "readme block $i ($where): FAILED"
      sed -n 1,200p "$work/block_$i.sh" | sed 's/^/    $ /'
      tail -n 25 <<<"$output" | sed 's/^/    | /'
      failed=$((failed + 1))
    fi
  done <"$blocks"
done
[ "$n" -gt 0 ] || { echo "readme: no bash blocks found" >&2; failed=$((failed + 1)); }
echo "readme: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
