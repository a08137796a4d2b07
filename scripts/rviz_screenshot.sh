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
# One try: Xvfb, the demo with rviz, the screenshot and its check.
attempt() {
  Xvfb "$display" -screen 0 1280x860x24 >>"$log" 2>&1 &
  xvfb=$!
  # The X server's socket appears once it listens: rviz started before that has no display.
  for _ in $(seq 100); do
    [ -S "/tmp/.X11-unix/X${display#:}" ] && break
    sleep 0.1
  done
  DISPLAY=$display LIBGL_ALWAYS_SOFTWARE=1 roslaunch -p "$port" se3_interpolation demo.launch rviz:=true >>"$log" 2>&1 &
  launch=$!
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
  local status=$?
  cleanup
  return $status
}
cleanup() {
  if [ -n "$launch" ]; then
    kill -INT "$launch" 2>/dev/null || true
    sleep 2
    kill "$launch" 2>/dev/null || true
  fi
  [ -z "$xvfb" ] || kill "$xvfb" 2>/dev/null || true
  wait 2>/dev/null || true
  launch= xvfb=
}
launch= xvfb=
trap cleanup EXIT
export ROS_MASTER_URI=http://localhost:$port
: >"$log"
# A second try where the first picture is blank: rviz under software OpenGL once died at start
# (SIGSEGV right after "Forcing OpenGl version 0") on a loaded machine, leaving a black screen.
for try in 1 2; do
  attempt && exit 0
  echo "rviz screenshot: try $try gave no picture (log: $log)" >&2
done
exit 1
