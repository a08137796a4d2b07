# Source this, from the repository root, to use the built package in your shell:
#
#   source scripts/setup.bash
#
# It puts /usr/bin first on PATH (Debian's ROS tools and their python3 modules live there; a
# python3 from pyenv or a virtualenv earlier on PATH lacks rospy and matplotlib), exports
# SE3_WS and sources $SE3_WS/devel/setup.bash, after which rosrun, roslaunch and rostest find
# se3_interpolation. Build first with ./scripts/run_demo.sh or ./scripts/run_tests.sh.
#
# The catkin workspace is $SE3_WS if set, else one per clone outside the source tree (a
# workspace inside the repository would link back to it and make rosrun's `find` report
# "File system loop detected"): ${XDG_CACHE_HOME:-$HOME/.cache}/se3_interpolation/<clone
# directory name>-<8 hex digits of the clone's path>, or under ${TMPDIR:-/tmp} when that is not
# writable. `echo $SE3_WS` shows it.
#
# `source scripts/setup.bash --env-only` (used by scripts/common.sh) sets PATH, SE3_ROOT and
# SE3_WS without sourcing the workspace. Sets no shell options, so it is safe in an interactive shell.

se3_default_ws() {
  local root=$1 name hash base
  name=$(basename "$root")
  hash=$(printf '%s' "$root" | md5sum | cut -c1-8)
  for base in "${XDG_CACHE_HOME:-${HOME:-/nonexistent}/.cache}/se3_interpolation" \
              "${TMPDIR:-/tmp}/se3_interpolation-$(id -u)"; do
    if mkdir -p "$base" 2>/dev/null && [ -w "$base" ]; then
      printf '%s/%s-%s\n' "$base" "$name" "$hash"
      return 0
    fi
  done
  echo "se3_interpolation: no writable directory for the workspace; set SE3_WS" >&2
  return 1
}

SE3_ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd -P)
case ":$PATH:" in
  :/usr/bin:*) ;;
  *) export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH ;;
esac
export ROS_PYTHON_VERSION=3
if [ -z "${SE3_WS:-}" ]; then
  SE3_WS=$(se3_default_ws "$SE3_ROOT") || return 1
fi
export SE3_WS

if [ "${1:-}" != "--env-only" ]; then
  if [ -f "$SE3_WS/devel/setup.bash" ]; then
    # shellcheck disable=SC1091
    source "$SE3_WS/devel/setup.bash"
  else
    echo "se3_interpolation: nothing built in $SE3_WS yet; run ./scripts/run_demo.sh first" >&2
    return 1
  fi
fi
