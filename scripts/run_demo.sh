#!/usr/bin/env bash
# Installs what is missing, builds, and runs the demo: the node with the example waypoints
# of config/demo_waypoints.yaml, printing a summary of the generated trajectories. With a
# display it also opens rviz and keeps running (Ctrl-C to stop); headless it exits after
# the summary. Idempotent. The ROS master runs on port $SE3_ROS_PORT (default 11311, the ROS
# default; pick another one when a master already runs there).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
se3_install_deps
se3_build
port=${SE3_ROS_PORT:-11311}
export ROS_MASTER_URI=http://localhost:$port
if [ -n "${DISPLAY:-}" ]; then
  exec roslaunch -p "$port" se3_interpolation demo.launch rviz:=true
fi
summary="$SE3_WS/demo_summary.txt"
rm -f "$summary"
if ! roslaunch -p "$port" se3_interpolation demo.launch rviz:=false exit_after_summary:=true summary_file:="$summary" \
    >"$SE3_WS/demo.log" 2>&1 || [ ! -s "$summary" ]; then
  tail -n 30 "$SE3_WS/demo.log"
  echo "demo failed (log: $SE3_WS/demo.log)" >&2
  exit 1
fi
cat "$summary"
