# Shared by the README's commands: dependencies, workspace, build. Source it from a script, do
# not run it (it sets -euo pipefail; in an interactive shell use scripts/setup.bash instead).
# The catkin workspace is $SE3_WS, by default one per clone outside the source tree (see
# scripts/setup.bash, which chooses it), so no build output lands in the source tree and no path
# loops back into it.
set -euo pipefail
# shellcheck source=scripts/setup.bash
source "$(dirname "${BASH_SOURCE[0]}")/setup.bash" --env-only

# The one list of Debian packages: everything the README's commands use. The runtime ones are
# declared in package.xml too (exec_depend). rosbash gives rosrun (only a recommendation of
# ros-core); tf2-tools gives tf2_ros/static_transform_publisher and tf2_tools/echo.py; the
# dynamic_reconfigure and nodelet packages give the run-time parameter server (and dynparam) and the
# nodelet manager. catkin-lint gives catkin_lint (scripts/check_install.sh). librosbag-storage-dev
# (rosbag_storage) lets se3_interpolate read recorded waypoints from a bag (--bag). pybind11-dev builds
# the Python module (src/python/), python3-pytest runs its tests (test/python/). liburdfdom-dev lets
# the arm model (src/arm/) read URDFs; liborocos-kdl-dev is its tests' reference (and the benchmarks').
SE3_APT_PACKAGES=(
  build-essential cmake ros-core-dev rosbash tf2-tools libtf2-ros-dev libtf2-geometry-msgs-dev libtf2-eigen-dev
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure libnodeletlib-dev libnodeletlib-tools
  pluginlib-dev libeigen3-dev libnav-msgs-dev libvisualization-msgs-dev libtrajectory-msgs-dev libstd-srvs-dev
  python3-rospy python3-rostest python3-rosservice python3-rostopic python3-geometry-msgs python3-nav-msgs
  python3-visualization-msgs python3-std-srvs python3-trajectory-msgs python3-tf2-ros
  libyaml-cpp-dev libgtest-dev googletest libbenchmark-dev liborocos-kdl-dev python3-yaml
  python3-matplotlib python3-numpy python3-pil rviz xvfb imagemagick valgrind clang libclang-rt-14-dev doxygen
  catkin-lint clang-format libactionlib-dev libactionlib-msgs-dev python3-actionlib python3-actionlib-msgs
  librosbag-storage-dev python3-scipy pybind11-dev python3-pytest liburdfdom-dev
)

# Prints the first local TCP port from 11398 to 11497 that is free to bind (the ROS master of a
# check or benchmark: never the default 11311); prints nothing if none is.
se3_free_port() {
  local candidate
  for candidate in $(seq 11398 11497); do
    if /usr/bin/python3 -c 'import socket, sys; socket.socket().bind(("127.0.0.1", int(sys.argv[1])))' \
        "$candidate" 2>/dev/null; then
      echo "$candidate"
      return 0
    fi
  done
}

# A pool of background jobs, two at a time (one per core of the CI machine; SE3_SANITIZE_JOBS
# changes it): se3_start_job CMD ARGS... runs the command in the background once fewer than that
# run; se3_finish_jobs waits for them all (scripts/run_sanitizers.sh, scripts/fuzz_long_run.sh).
se3_jobs_running=0
se3_start_job() {
  if [ "$se3_jobs_running" -ge "${SE3_SANITIZE_JOBS:-2}" ]; then
    wait -n || true
    se3_jobs_running=$((se3_jobs_running - 1))
  fi
  "$@" &
  se3_jobs_running=$((se3_jobs_running + 1))
}
se3_finish_jobs() {
  wait || true
  se3_jobs_running=0
}

# One libFuzzer exploration, with the options of CI's and of the long run (docs/testing.md "Sanitizers
# and fuzzing"): se3_fuzz_explore BINARY CORPUS ARTIFACTS LOG MAX_LEN SEED [LIMIT FLAGS...]. ASan
# reports carry no allocation stacks (a finding's input replays with them): ASan's stack unwinding
# at every malloc and free slows the allocating numeric targets. Sets se3_fuzz_status (the exit
# status), se3_fuzz_runs (inputs run), se3_fuzz_seconds and se3_fuzz_finding: non-empty for a
# finding, an exit status or an input libFuzzer wrote (crash-, timeout-, leak-, oom-); a
# slow-unit- input (one input above 10 s of wall time, e.g. on a loaded machine) is not one.
se3_fuzz_explore() {
  local binary=$1 corpus=$2 artifacts=$3 log=$4 max_len=$5 seed=$6 start=$SECONDS
  shift 6
  se3_fuzz_status=0
  ASAN_OPTIONS=${SE3_FUZZ_ASAN_OPTIONS:-malloc_context_size=0} \
    "$binary" "$@" -seed="$seed" -rss_limit_mb=2048 -timeout=60 -max_len="$max_len" -len_control=10 \
    -print_final_stats=1 -artifact_prefix="$artifacts/" "$corpus" >"$log" 2>&1 || se3_fuzz_status=$?
  se3_fuzz_seconds=$((SECONDS - start))
  se3_fuzz_runs=$(sed -nE 's/^stat::number_of_executed_units: *([0-9]+)/\1/p' "$log" | tail -n 1)
  se3_fuzz_runs=${se3_fuzz_runs:-0}
  se3_fuzz_finding=""
  if [ "$se3_fuzz_status" -ne 0 ] || [ -n "$(find "$artifacts" -type f ! -name 'slow-unit-*')" ]; then
    se3_fuzz_finding=yes
  fi
}

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
  echo "catkin workspace: $SE3_WS (use it in a shell with: source scripts/setup.bash)"
  if [ -L "$SE3_ROOT/.ws/src/se3_interpolation" ] && [ "$SE3_WS" != "$SE3_ROOT/.ws" ]; then
    echo "note: .ws/ is an old workspace inside the repository; its link back makes rosrun's find" \
         "report 'File system loop detected': remove it with rm -rf .ws" >&2
  fi
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

# Compiler flags of the benchmarks' optional peers (bench/bench_peers.h), from local copies given by
# path (never fetched, never committed): SE3_BENCH_SOPHUS_DIR (a Sophus checkout: its root holds
# sophus/se3.hpp), SE3_BENCH_MANIF_DIR (manif's root: manif/SE3.h under its include folder, external/tl/),
# SE3_BENCH_BASALT_DIR (basalt-headers' root: include/basalt/spline/; needs Sophus as well),
# SE3_BENCH_RUCKIG_DIR (a Ruckig checkout with its CMake build in build/: bench_lin only).
# Unset: that peer is left out. Sets the arrays se3_bench_peer_flags and se3_bench_ruckig_flags and
# the list se3_bench_peers ("sophus manif basalt ruckig", those given); a given directory without the
# expected header (or Ruckig's library) is an error.
se3_bench_peer_setup() {
  se3_bench_peer_flags=()
  se3_bench_peers=""
  if [ -n "${SE3_BENCH_SOPHUS_DIR:-}" ]; then
    [ -f "$SE3_BENCH_SOPHUS_DIR/sophus/se3.hpp" ] ||
      { echo "SE3_BENCH_SOPHUS_DIR=$SE3_BENCH_SOPHUS_DIR has no sophus/se3.hpp" >&2; return 2; }
    se3_bench_peer_flags+=(-DSE3_BENCH_SOPHUS -isystem "$SE3_BENCH_SOPHUS_DIR")
    se3_bench_peers+=" sophus"
  fi
  if [ -n "${SE3_BENCH_MANIF_DIR:-}" ]; then
    [ -f "$SE3_BENCH_MANIF_DIR/include/manif/SE3.h" ] ||
      { echo "SE3_BENCH_MANIF_DIR=$SE3_BENCH_MANIF_DIR has no include/manif/SE3.h" >&2; return 2; }
    se3_bench_peer_flags+=(-DSE3_BENCH_MANIF -isystem "$SE3_BENCH_MANIF_DIR/include" -isystem
                           "$SE3_BENCH_MANIF_DIR/external/tl")
    se3_bench_peers+=" manif"
  fi
  if [ -n "${SE3_BENCH_BASALT_DIR:-}" ]; then
    [ -f "$SE3_BENCH_BASALT_DIR/include/basalt/spline/so3_spline.h" ] ||
      { echo "SE3_BENCH_BASALT_DIR=$SE3_BENCH_BASALT_DIR has no include/basalt/spline/so3_spline.h" >&2; return 2; }
    [ -n "${SE3_BENCH_SOPHUS_DIR:-}" ] ||
      { echo "SE3_BENCH_BASALT_DIR needs SE3_BENCH_SOPHUS_DIR (basalt-headers includes Sophus)" >&2; return 2; }
    se3_bench_peer_flags+=(-DSE3_BENCH_BASALT -isystem "$SE3_BENCH_BASALT_DIR/include")
    se3_bench_peers+=" basalt"
  fi
  # Ruckig (bench/bench_lin.cpp): a checkout built with its own CMake into build/ (libruckig.so);
  # its flags and library apart from the header-only peers' (count_ops does not use it).
  se3_bench_ruckig_flags=()
  if [ -n "${SE3_BENCH_RUCKIG_DIR:-}" ]; then
    [ -f "$SE3_BENCH_RUCKIG_DIR/include/ruckig/ruckig.hpp" ] ||
      { echo "SE3_BENCH_RUCKIG_DIR=$SE3_BENCH_RUCKIG_DIR has no include/ruckig/ruckig.hpp" >&2; return 2; }
    [ -f "$SE3_BENCH_RUCKIG_DIR/build/libruckig.so" ] ||
      { echo "SE3_BENCH_RUCKIG_DIR=$SE3_BENCH_RUCKIG_DIR has no build/libruckig.so (build it: cmake -S . -B build" \
          "-DCMAKE_BUILD_TYPE=Release -DBUILD_EXAMPLES=OFF -DBUILD_TESTS=OFF && cmake --build build -j2)" >&2; return 2; }
    se3_bench_ruckig_flags=(-DSE3_BENCH_RUCKIG -isystem "$SE3_BENCH_RUCKIG_DIR/include"
                            "$SE3_BENCH_RUCKIG_DIR/build/libruckig.so" "-Wl,-rpath,$SE3_BENCH_RUCKIG_DIR/build")
    se3_bench_peers+=" ruckig"
  fi
  se3_bench_peers=${se3_bench_peers# }
}
