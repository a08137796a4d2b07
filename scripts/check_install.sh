#!/usr/bin/env bash
# The package as a release installs it: catkin_lint, then `catkin_make install` of the built
# workspace $SE3_WS into $SE3_WS/install_check (emptied first; no rebuild: the install reuses
# build/) and, with nothing but <prefix>/setup.bash sourced in an empty environment (no devel
# space, no source tree, run from a scratch directory):
#   - the install holds the node, the CLI, the libraries, the nodelet plugin and its XML, every
#     launch and config file, every executable scripts/*.py, and what the launch files refer to;
#   - rospack, the nodelet plugin index, Python (the messages and the module se3_interpolation) and
#     the dynamic linker find the package there only;
#   - the demo (launch/demo.launch, rviz:=false) on its own master at a free port: the node's
#     ~generate service answers a light request with success, and the demo client's summary has
#     every curve and geometry and no failure;
#   - se3_interpolate on docs/examples/screw.yaml: exit 0 and the sampled CSV it promises, and
#     plot_trajectory.py draws it.
# Prints `install check N (WHAT): ok | FAILED`, then `install: N passed, N failed`
# (scripts/run_tests.sh adds them to its totals); exits non-zero if one failed. Logs:
# $SE3_WS/check_install/. $SE3_INSTALL_SERVICE_WAIT (default 90) is the wait in s for ~generate.
# Assumes the dependencies are installed and $SE3_WS is built (scripts/run_tests.sh runs it after
# the build).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
prefix="$SE3_WS/install_check"
work="$SE3_WS/check_install"
service_wait=${SE3_INSTALL_SERVICE_WAIT:-90}
rm -rf "$work"
mkdir -p "$work/ros_home"
passed=0
failed=0
n=0

# check WHAT COMMAND...: one counted check, its output and duration in $work/<n>.log. COMMAND runs
# without errexit (its status is tested): each check function returns its failures explicitly.
check() {
  local what=$1 t0=$SECONDS status=0
  shift
  n=$((n + 1))
  "$@" >"$work/$n.log" 2>&1 || status=$?
  echo "($what: status $status after $((SECONDS - t0)) s)" >>"$work/$n.log"
  if [ "$status" -eq 0 ]; then
    echo "install check $n ($what): ok"
    passed=$((passed + 1))
  else
    echo "install check $n ($what): FAILED (log: $work/$n.log)"
    tail -n 15 "$work/$n.log" | sed 's/^/    /'
    failed=$((failed + 1))
  fi
}

# in_install COMMAND...: runs COMMAND in an empty environment with only the install space
# sourced, in $work, against the master at $port (in_install_bg LOG COMMAND...: the same in the
# background as its own process group, $! its id).
port=""
install_argv() {
  argv=(env -i HOME="$HOME" PATH=/usr/bin:/bin LANG=C.UTF-8 ROS_HOME="$work/ros_home"
        ROS_MASTER_URI="http://localhost:${port:-11311}" SE3_PREFIX="$prefix"
        bash --noprofile --norc -c 'set +u; source "$SE3_PREFIX/setup.bash" || exit 1; set -u; "$@"' in_install)
}
in_install() {
  install_argv
  (cd "$work" && "${argv[@]}" "$@")
}
in_install_bg() {
  local log=$1
  shift
  install_argv
  (cd "$work" && exec setsid "${argv[@]}" "$@") >"$log" 2>&1 &
}

lint() {
  # The package as its workspace holds it (src/se3_interpolation), so the folder has the
  # package's name whatever the clone's directory is called.
  local path="$SE3_WS/src/se3_interpolation"
  [ -d "$path" ] || path="$SE3_ROOT"
  catkin_lint --strict -W2 "$path" || return 1
  # CMakeLists.txt silences uninstalled_script for the shell scripts in scripts/ (the checkout's
  # developer tools): any other finding it silences fails here.
  local others
  others=$(catkin_lint --strict -W2 --show-ignored "$path" 2>/dev/null |
           grep -vE "^se3_interpolation: error: file 'scripts/[^/']+\.sh' is executable but not installed\$" || true)
  [ -z "$others" ] || { echo "silenced findings other than the developer scripts':"; echo "$others"; return 1; }
}

install_space() {
  rm -rf "$prefix"
  # An empty environment: the configure step must not take this shell's devel space (sourced by
  # se3_build) as a parent workspace of the install.
  (cd "$SE3_WS" && env -i HOME="$HOME" PATH=/usr/bin:/bin LANG=C.UTF-8 \
     catkin_make install -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCMAKE_BUILD_TYPE=Release \
     -DCMAKE_INSTALL_PREFIX="$prefix" -j2)
}

contents() {
  local missing=0 f name ref
  local share="$prefix/share/se3_interpolation" bin="$prefix/lib/se3_interpolation"
  for f in "$bin/se3_interpolation_node" "$bin/se3_interpolate"; do
    [ -x "$f" ] || { echo "missing program: $f"; missing=1; }
  done
  for f in "$prefix"/lib/libse3_interpolation_{arm,core,ros,nodelet}.so "$share"/{package.xml,nodelet_plugins.xml} \
           "$share/cfg/InterpolationNode.cfg" "$prefix"/include/se3_interpolation/{InterpolationNodeConfig.h,GenerateTrajectory.h} \
           "$prefix/include/se3_interpolation/planner/planner.h" "$prefix/include/se3_interpolation/node_parameter_table.h" \
           "$prefix"/lib/python3/dist-packages/se3_interpolation/{__init__.py,_core.cpython-*.so}; do
    [ -f "$f" ] || { echo "missing file: $f"; missing=1; }
  done
  # Every launch and config file of the tree (config/robots/ included).
  while IFS= read -r f; do
    name=${f#"$SE3_ROOT"/}
    [ -f "$share/$name" ] || { echo "missing file: $share/$name"; missing=1; }
  done < <(find "$SE3_ROOT/launch" "$SE3_ROOT/config" -type f | sort)
  # Every executable Python script (the rule catkin_lint's uninstalled_script check would hold,
  # silenced in CMakeLists.txt for the shell scripts, the checkout's developer tools).
  for f in "$SE3_ROOT"/scripts/*.py; do
    [ -x "$f" ] || continue
    name=$(basename "$f")
    [ -x "$bin/$name" ] || { echo "executable $f is not installed as $bin/$name"; missing=1; }
  done
  # What the installed launch files refer to: $(find se3_interpolation)/... and this package's
  # node types.
  for f in "$share"/launch/*.launch; do
    for ref in $(grep -o '\$(find se3_interpolation)/[^" ]*' "$f" | sed 's|^\$(find se3_interpolation)/||' | sort -u); do
      [ -e "$share/$ref" ] || { echo "$f refers to $ref, not installed"; missing=1; }
    done
    for ref in $(grep -o 'pkg="se3_interpolation" type="[^"]*"' "$f" | sed 's/.*type="\([^"]*\)"/\1/' | sort -u); do
      [ -x "$bin/$ref" ] || { echo "$f runs $ref, not installed in $bin"; missing=1; }
    done
  done
  # The nodelet's library, named in the plugin XML.
  ref=$(sed -n 's/.*<library path="\([^"]*\)".*/\1/p' "$share/nodelet_plugins.xml")
  [ -f "$prefix/$ref.so" ] || { echo "nodelet_plugins.xml names $ref: $prefix/$ref.so is missing"; missing=1; }
  [ "$missing" -eq 0 ] && echo "all expected files installed"
}

# In the empty environment: every search path leads to the install space, none to the devel
# space or the source tree.
environment() {
  in_install bash -c '
    set -e
    for v in ROS_PACKAGE_PATH CMAKE_PREFIX_PATH PYTHONPATH LD_LIBRARY_PATH PATH; do
      echo "$v=${!v:-}"
      case ":${!v:-}:" in *"$1"/devel*|*"$2"*) echo "$v leads outside the install space"; exit 1 ;; esac
    done
    found=$(rospack find se3_interpolation)
    echo "rospack find: $found"
    [ "$found" = "$SE3_PREFIX/share/se3_interpolation" ]
    plugin=$(rospack plugins --attrib=plugin nodelet | grep "^se3_interpolation ")
    echo "nodelet plugin: $plugin"
    [ "$plugin" = "se3_interpolation $SE3_PREFIX/share/se3_interpolation/nodelet_plugins.xml" ]
    python3 -c "import se3_interpolation.srv as s, se3_interpolation.cfg.InterpolationNodeConfig as c; print(s.__file__); print(c.__file__)" |
      tee /dev/stderr | grep -v "^$SE3_PREFIX/" && exit 1
    # The Python module (package and compiled core) beside the messages, generating a motion.
    module=$(python3 -c "import se3_interpolation as m, se3_interpolation._core as k; print(m.__file__); print(k.__file__)
m.generate(waypoints=[[0, 0, 0, 0, 0, 0, 1], [1, 0, 0, 0, 0, 0, 1]])") || exit 1
    echo "$module"
    [ "$(echo "$module" | grep -c "^$SE3_PREFIX/lib/python3/dist-packages/se3_interpolation/")" -eq 2 ] || exit 1
    ldd "$SE3_PREFIX/lib/se3_interpolation/se3_interpolation_node" | grep se3_interpolation | tee /dev/stderr |
      grep -v "=> $SE3_PREFIX/lib/" && exit 1
    true
  ' environment "$SE3_WS" "$SE3_ROOT"
}

# The demo from the install space: its own master on a free port, roslaunch demo.launch.
roscore_pid=""
launch_pid=""
stop_demo() {
  local pid
  for pid in $launch_pid $roscore_pid; do
    kill -INT -- "-$pid" 2>/dev/null || true
  done
  sleep 2
  for pid in $launch_pid $roscore_pid; do
    kill -TERM -- "-$pid" 2>/dev/null || true
  done
  sleep 1
  for pid in $launch_pid $roscore_pid; do
    kill -KILL -- "-$pid" 2>/dev/null || true
  done
  launch_pid=""
  roscore_pid=""
}
trap stop_demo EXIT

demo_service() {
  local request i
  port=$(se3_free_port)
  [ -n "$port" ] || { echo "no free port in 11398 ... 11497"; return 1; }
  echo "master port $port"
  in_install_bg "$work/roscore.log" roscore -p "$port"
  roscore_pid=$!
  for i in $(seq 30); do
    in_install rosparam get /rosdistro >/dev/null 2>&1 && break
    sleep 1
  done
  in_install_bg "$work/roslaunch.log" roslaunch se3_interpolation demo.launch rviz:=false \
    summary_file:="$work/demo_summary.txt"
  launch_pid=$!
  for i in $(seq "$service_wait"); do
    in_install rosservice type /se3_interpolation_node/generate >/dev/null 2>&1 && break
    sleep 1
  done
  in_install rosservice type /se3_interpolation_node/generate ||
    { echo "~generate did not come up within $service_wait s"; tail -n 30 "$work/roslaunch.log"; return 1; }
  echo "~generate up after about $i s"
  request='{waypoints: {header: {frame_id: map}, poses: [{position: {x: 0, y: 0, z: 0}, orientation: {w: 1}},
            {position: {x: 1, y: 0.5, z: 0}, orientation: {z: 0.7071067811865476, w: 0.7071067811865476}}]},
            curve: piecewise_geodesic, duration: 1.0, sample_count: 5, outputs: [path]}'
  in_install timeout 60 rosservice call /se3_interpolation_node/generate "$request" >"$work/generate_response.txt" ||
    { echo "rosservice call failed"; cat "$work/generate_response.txt"; return 1; }
  grep -E '^(success|message|duration):' "$work/generate_response.txt"
  grep -qx 'success: True' "$work/generate_response.txt"
}

demo_summary() {
  local i rows
  for i in $(seq 60); do
    [ -s "$work/demo_summary.txt" ] && break
    sleep 1
  done
  cat "$work/demo_summary.txt" || { echo "no summary from demo_client.py"; tail -n 30 "$work/roslaunch.log"; return 1; }
  ! grep -q FAILED "$work/demo_summary.txt" || return 1
  # One row per curve and geometry: 6 curves x 2 geometries.
  rows=$(grep -cE '^(piecewise_geodesic|bezier|bspline|hermite|interpolating|blended) +(double_geodesic|screw) +[0-9]+ ' \
         "$work/demo_summary.txt")
  echo "rows: $rows"
  [ "$rows" -eq 12 ]
}

# The CLI on a docs example (copied: the run reads nothing from the tree): a header, one row
# per sample, ending at the last waypoint at the last time.
example="$SE3_ROOT/docs/examples/screw.yaml"
cli() {
  local samples last_time last_position
  cp "$example" "$work/request.yaml"
  local status=0
  in_install rosrun se3_interpolation se3_interpolate request.yaml >"$work/cli.csv" 2>"$work/cli_figures.txt" ||
    status=$?
  cat "$work/cli_figures.txt"
  [ "$status" -eq 0 ] || { echo "se3_interpolate exited with $status"; return 1; }
  samples=$(sed -nE 's/^sample_count: *([0-9]+).*/\1/p' "$work/request.yaml")
  last_time=$(sed -nE 's/^times: *\[.*, *([0-9.eE+-]+) *\].*/\1/p' "$work/request.yaml")
  last_position=$(grep -oE 'position: *\[[^]]*\]' "$work/request.yaml" | tail -n 1 | sed -E 's/.*\[(.*)\]/\1/')
  echo "expect $samples samples, the last at t = $last_time, position $last_position"
  head -n 1 "$work/cli.csv" | grep -q '^t,x,y,z,qx,qy,qz,qw,' || { echo "no CSV header"; return 1; }
  [ "$(($(wc -l <"$work/cli.csv") - 1))" -eq "$samples" ] || { echo "$(wc -l <"$work/cli.csv") lines"; return 1; }
  tail -n 1 "$work/cli.csv" | awk -F, -v t="$last_time" -v p="$last_position" '
    function near(a, b) { return (a - b) ^ 2 < 1e-18 }
    { split(p, q, / *, */); print "last row: t " $1 ", position " $2 ", " $3 ", " $4
      exit !(near($1, t) && near($2, q[1]) && near($3, q[2]) && near($4, q[3])) }'
  grep -q '^duration: ' "$work/cli_figures.txt"
}

plot() {
  in_install rosrun se3_interpolation plot_trajectory.py cli.csv plot.png || return 1
  [ -s "$work/plot.png" ]
}

start=$SECONDS
check "catkin_lint --strict -W2" lint
if check "catkin_make install into $prefix" install_space; then
  check "installed files" contents
  check "environment of <prefix>/setup.bash alone" environment
  check "demo.launch: ~generate answers" demo_service
  check "demo.launch: demo_client.py summary" demo_summary
  stop_demo
  if [ -f "$example" ]; then
    check "se3_interpolate on docs/examples/screw.yaml" cli
    check "plot_trajectory.py on its output" plot
  else
    n=$((n + 1))
    echo "install check $n (se3_interpolate): FAILED ($example is missing)"
    failed=$((failed + 1))
  fi
fi
echo "install check time: $((SECONDS - start)) s"
echo "install: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
