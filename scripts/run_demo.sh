#!/usr/bin/env bash
# Installs what is missing, builds, and runs the demo: the node with the example waypoints
# of config/demo_waypoints.yaml, printing a summary of the generated trajectories. With a
# display it also opens rviz and keeps running (Ctrl-C to stop); headless it exits after
# the summary. Idempotent.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
se3_install_deps
se3_build
if [ -n "${DISPLAY:-}" ]; then
  exec roslaunch se3_interpolation demo.launch rviz:=true
fi
export ROS_MASTER_URI=${ROS_MASTER_URI:-http://localhost:11311}
roslaunch se3_interpolation demo.launch rviz:=false exit_after_summary:=true 2>&1 |
  grep -vE '^(\.\.\. |started roslaunch|process\[|setting /run_id|auto-starting|ROS_MASTER_URI|SUMMARY|=+$|PARAMETERS|NODES|  /|  \* /|core service|shutting down|\[se3_interpolation_demo-|all processes|done$|$)' || true
