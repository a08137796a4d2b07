#!/usr/bin/env bash
# End-to-end latency of the ~generate service for a large request (docs/performance.md
# "Service latency"): starts a roscore on a free port (never 11311) and se3_interpolation_node
# with its timing logger (ros.se3_interpolation.timing) at debug level, then calls the service
# from the roscpp client (bench/service_latency.cpp) and the rospy client
# (scripts/service_latency.py) with the same request: N waypoints, `interpolating`,
# double_geodesic, M samples; with both outputs (the default), then `outputs: [trajectory]`, then
# `[path]`. Prints the clients' round trips and the node's time inside the callback (planner;
# filling the response messages); then times se3_interpolate on the same request
# (scripts/cli_latency.py). Stops what it started. SE3_KEEP=1 keeps its logs (roscore,
# node) in the temporary folder it names.
#
# Usage: scripts/service_latency.sh [WAYPOINTS [SAMPLES [REPETITIONS]]]   (default 1000 100000 3)
# Needs the catkin build ($SE3_WS; targets se3_interpolation_node, service_latency and se3_interpolate).
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
set +u
# shellcheck disable=SC1091
source "$SE3_WS/devel/setup.bash"
set -u

waypoints=${1:-1000}
samples=${2:-100000}
repetitions=${3:-3}

port=$(se3_free_port)
[ -n "$port" ] || { echo "no free port in 11398 ... 11497" >&2; exit 2; }
export ROS_MASTER_URI=http://localhost:$port

work=$(mktemp -d "${TMPDIR:-/tmp}/se3_service_latency.XXXXXX")
[ -z "${SE3_KEEP:-}" ] || echo "logs in $work"
pids=()
cleanup() {
  for pid in "${pids[@]}"; do
    kill "$pid" 2>/dev/null || true
  done
  wait 2>/dev/null || true
  [ -n "${SE3_KEEP:-}" ] || rm -rf "$work"
}
trap cleanup EXIT

roscore -p "$port" >"$work/roscore.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do
  rosparam list >/dev/null 2>&1 && break
  sleep 0.2
done

printf 'log4j.logger.ros.se3_interpolation.timing=DEBUG\n' >"$work/rosconsole.config"
ROSCONSOLE_CONFIG_FILE="$work/rosconsole.config" \
  stdbuf -oL "$SE3_WS/devel/lib/se3_interpolation/se3_interpolation_node" >"$work/node.log" 2>&1 &
pids+=($!)

client="$SE3_WS/devel/lib/se3_interpolation/service_latency"
for outputs in "" trajectory path; do
  echo "== outputs [${outputs}]"
  before=$(wc -l <"$work/node.log")
  "$client" --waypoints "$waypoints" --samples "$samples" --repetitions "$repetitions" --outputs "$outputs"
  "$SE3_ROOT/scripts/service_latency.py" --waypoints "$waypoints" --samples "$samples" \
    --repetitions "$repetitions" --outputs "$outputs"
  echo "node, inside the callback (roscpp calls first, then rospy):"
  tail -n +"$((before + 1))" "$work/node.log" | sed -n 's/.*\(generate: [^\x1b]*\).*/  \1/p'
done

echo "== se3_interpolate (no ROS)"
"$SE3_ROOT/scripts/cli_latency.py" "$SE3_WS/devel/lib/se3_interpolation/se3_interpolate" --waypoints "$waypoints" \
  --samples "$samples" --repetitions "$repetitions"
