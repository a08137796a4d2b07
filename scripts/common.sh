# Shared by the README's commands: dependencies, workspace, build. Source it, do not run it.
# The catkin workspace lives in $SE3_WS (default: .ws/ in the repository, git-ignored), so no
# build output ever lands in the source tree.
set -euo pipefail
SE3_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
SE3_WS=${SE3_WS:-$SE3_ROOT/.ws}
# Debian's ROS lives under /usr; a pyenv python3 earlier on PATH lacks its modules.
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
export ROS_PYTHON_VERSION=3

SE3_APT_PACKAGES=(
  build-essential cmake ros-core-dev libtf2-ros-dev libtf2-geometry-msgs-dev libtf2-eigen-dev
  libeigen3-dev libnav-msgs-dev libvisualization-msgs-dev libtrajectory-msgs-dev libstd-srvs-dev
  python3-rostest python3-geometry-msgs python3-nav-msgs python3-visualization-msgs python3-std-srvs
  python3-trajectory-msgs libyaml-cpp-dev libgtest-dev googletest libbenchmark-dev liborocos-kdl-dev python3-yaml
  python3-matplotlib python3-numpy python3-pil rviz xvfb imagemagick valgrind clang libclang-rt-14-dev
)

se3_install_deps() {
  local missing=()
  for p in "${SE3_APT_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  if [ ${#missing[@]} -gt 0 ]; then
    echo "installing: ${missing[*]}"
    local sudo=""
    [ "$(id -u)" -eq 0 ] || sudo=sudo
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  fi
}

se3_build() {
  mkdir -p "$SE3_WS/src"
  ln -sfn "$SE3_ROOT" "$SE3_WS/src/se3_interpolation"
  (cd "$SE3_WS" && catkin_make -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release "$@" -j2 >"$SE3_WS/build.log" 2>&1) || {
    tail -n 60 "$SE3_WS/build.log"
    echo "build failed (full log: $SE3_WS/build.log)" >&2
    return 1
  }
  set +u
  # shellcheck disable=SC1091
  source "$SE3_WS/devel/setup.bash"
  set -u
}
