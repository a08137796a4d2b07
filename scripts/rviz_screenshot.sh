#!/usr/bin/env bash
# Starts a virtual display (Xvfb), runs the demo with rviz on config/demo.rviz, and saves a
# screenshot of the screen to $1 (default: $SE3_WS/rviz_demo.png). Fails if rviz does not
# come up or the picture is blank. Assumes the package is built (scripts/common.sh se3_build).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
set +u
source "$SE3_WS/devel/setup.bash"
set -u
out=${1:-$SE3_WS/rviz_demo.png}
display=:${SE3_XVFB_DISPLAY:-97}
port=${SE3_ROS_PORT:-11397}
log="$SE3_WS/rviz_screenshot.log"
Xvfb "$display" -screen 0 1280x860x24 >"$log" 2>&1 &
xvfb=$!
export ROS_MASTER_URI=http://localhost:$port
DISPLAY=$display LIBGL_ALWAYS_SOFTWARE=1 roslaunch -p "$port" se3_interpolation demo.launch rviz:=true >>"$log" 2>&1 &
launch=$!
cleanup() {
  kill -INT "$launch" 2>/dev/null
  sleep 2
  kill "$launch" "$xvfb" 2>/dev/null
  wait 2>/dev/null
}
trap cleanup EXIT
# rviz needs a few seconds to start in software rendering, then the latched path and markers arrive.
sleep "${SE3_RVIZ_WAIT:-25}"
DISPLAY=$display import -window root "$out"
/usr/bin/python3 - "$out" <<'PY'
import sys
from PIL import Image, ImageStat
img = Image.open(sys.argv[1]).convert("RGB")
stat = ImageStat.Stat(img)
spread = max(stat.stddev)
colors = len(img.getcolors(1 << 24) or [])
print("screenshot %s: %dx%d, %d colours, stddev %.1f" % (sys.argv[1], img.width, img.height, colors, spread))
sys.exit(0 if colors > 50 and spread > 5 else 1)
PY
