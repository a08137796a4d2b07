#!/usr/bin/env bash
# Reproduces the performance figures of the core and prints their tables:
#  1. bench_core (Google Benchmark): ns per operation for the screw and double-geodesic
#     geometries against KDL and plain Eigen, the ratio table, and sampling throughput;
#     bench_interpolating (the interpolating solve, N = 10 … 10⁴) when bench/bench_interpolating.cpp exists;
#     bench_time_optimal (time-optimal and jerk-limited timing of the interpolating spline, N = 100 … 3000);
#     bench_lin (a two-pose move under time_optimal: the closed form, the general timings, the
#     planner, and Ruckig when SE3_BENCH_RUCKIG_DIR is given);
#     bench_cli_output (se3_interpolate's CSV of 10⁵ samples against iostreams, and the planner
#     on that request);
#     bench_toppra (the time-optimal timing against TOPP-RA, N = 10 … 10⁴) and bench_toppra_joints
#     (the UR5e's joint-limited timing against the Cartesian-only one and TOPP-RA with joint
#     boxes on the same joint path, N = 100 and 1000) when SE3_BENCH_TOPPRA_DIR is given;
#  2. scripts/instruction_counts.sh --check: instructions per operation (callgrind) against
#     the committed bench/instruction_counts.txt.
# The benchmarks are built without catkin with g++ into $SE3_WS/bench.
#
# Usage: scripts/run_benchmarks.sh [Google Benchmark flags, e.g. --benchmark_filter=screw]
# Environment: SE3_BENCH_CXXFLAGS   compiler flags (default "-O2 -DNDEBUG"; "-O3 -DNDEBUG" is
#                                   what the catkin Release build uses)
#              SE3_BENCH_REPETITIONS repetitions per benchmark (default 5; the tables use medians)
#              SE3_BENCH_MIN_TIME    seconds per repetition (default 0.3)
#              SE3_BENCH_SOPHUS_DIR, SE3_BENCH_MANIF_DIR, SE3_BENCH_BASALT_DIR  local copies of the
#                                   optional peers (bench/bench_peers.h; scripts/common.sh,
#                                   se3_bench_peer_setup); unset: left out, nothing else changes
#              SE3_BENCH_RUCKIG_DIR  a local Ruckig checkout built with its own CMake into build/
#                                   (bench/bench_lin.cpp); unset: bench_lin runs without it
#              SE3_BENCH_TOPPRA_DIR  a local TOPP-RA checkout (bench/bench_toppra.cpp,
#                                   bench/bench_toppra_joints.cpp): its C++ library (cpp/) is built
#                                   once into $SE3_WS/bench/toppra with Eigen only; unset: both
#                                   are left out
# Timings are noisy on a loaded machine; the instruction counts are not.
# shellcheck source=scripts/common.sh
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"

CXX=${CXX:-g++}
CXXFLAGS=${SE3_BENCH_CXXFLAGS:-"-O2 -DNDEBUG"}
REPETITIONS=${SE3_BENCH_REPETITIONS:-5}
MIN_TIME=${SE3_BENCH_MIN_TIME:-0.3}
OUT="$SE3_WS/bench"
mkdir -p "$OUT"
se3_bench_peer_setup || exit 2

# The core's sources, from the list every build reads (src/core_sources.txt).
mapfile -t core_sources < <(grep -v '^#' "$SE3_ROOT/src/core_sources.txt" | sed "s|^|$SE3_ROOT/|")

# Builds $1 from bench/$1.cpp + the core sources unless it is up to date for these flags.
build() {
  local name=$1
  shift
  local bin="$OUT/$name" stamp="$OUT/$name.flags"
  if [ -x "$bin" ] && [ "$(cat "$stamp" 2>/dev/null)" = "$CXX $CXXFLAGS ${se3_bench_peer_flags[*]} $*" ] &&
    [ -z "$(find "$SE3_ROOT/bench" "$SE3_ROOT/include" "$SE3_ROOT/src" -newer "$bin" -type f | head -n 1)" ]; then
    return 0
  fi
  echo "building $bin ($CXX -std=c++17 $CXXFLAGS)" >&2
  # shellcheck disable=SC2086
  "$CXX" -std=c++17 $CXXFLAGS -I"$SE3_ROOT/include" -I/usr/include/eigen3 "${se3_bench_peer_flags[@]}" \
    "$SE3_ROOT/bench/$name.cpp" "${core_sources[@]}" -o "$bin" "$@" -lbenchmark -lpthread
  echo "$CXX $CXXFLAGS ${se3_bench_peer_flags[*]} $*" >"$stamp"
}

echo "== machine"
lscpu | head -n 20
"$CXX" --version | head -n 1
echo "flags: $CXXFLAGS; $REPETITIONS repetitions of >= $MIN_TIME s each (medians); optional peers: ${se3_bench_peers:-none}"

build bench_core -lorocos-kdl
echo
echo "== bench_core"
"$OUT/bench_core" --benchmark_repetitions="$REPETITIONS" --benchmark_min_time="$MIN_TIME" \
  --benchmark_display_aggregates_only=true "$@"

if [ -f "$SE3_ROOT/bench/bench_interpolating.cpp" ]; then
  build bench_interpolating
  echo
  echo "== bench_interpolating"
  "$OUT/bench_interpolating" --benchmark_repetitions="$REPETITIONS" --benchmark_min_time="$MIN_TIME" \
    --benchmark_display_aggregates_only=true
fi

build bench_time_optimal
echo
echo "== bench_time_optimal"
"$OUT/bench_time_optimal" --benchmark_repetitions="$REPETITIONS" --benchmark_min_time="$MIN_TIME" \
  --benchmark_display_aggregates_only=true

build bench_lin "${se3_bench_ruckig_flags[@]}"
echo
echo "== bench_lin${SE3_BENCH_RUCKIG_DIR:+ (Ruckig $(git -C "$SE3_BENCH_RUCKIG_DIR" describe --tags --always 2>/dev/null ||
  sed -n 's/^version = "\(.*\)"/\1/p' "$SE3_BENCH_RUCKIG_DIR/Cargo.toml" 2>/dev/null | head -n 1))}"
"$OUT/bench_lin" --benchmark_repetitions="$REPETITIONS" --benchmark_min_time="$MIN_TIME" \
  --benchmark_display_aggregates_only=true

build bench_joint_space "$SE3_ROOT/src/arm/arm_model.cpp" "$SE3_ROOT/src/arm/joint_limits.cpp" -lurdfdom_model \
  -lyaml-cpp -lorocos-kdl
echo
echo "== bench_joint_space"
"$OUT/bench_joint_space" --benchmark_repetitions="$REPETITIONS" --benchmark_min_time="$MIN_TIME" \
  --benchmark_display_aggregates_only=true

build bench_cli_output -I"$SE3_ROOT/src/cli" "$SE3_ROOT/src/cli/csv_writer.cpp"
echo
echo "== bench_cli_output"
"$OUT/bench_cli_output" --benchmark_repetitions="$REPETITIONS" --benchmark_min_time="$MIN_TIME" \
  --benchmark_display_aggregates_only=true

if [ -n "${SE3_BENCH_TOPPRA_DIR:-}" ]; then
  [ -f "$SE3_BENCH_TOPPRA_DIR/cpp/CMakeLists.txt" ] ||
    { echo "SE3_BENCH_TOPPRA_DIR=$SE3_BENCH_TOPPRA_DIR has no cpp/CMakeLists.txt" >&2; exit 2; }
  # TOPP-RA's own CMake build of its C++ library, as CMakeLists.txt's external project does.
  toppra_prefix="$OUT/toppra"
  if [ ! -f "$toppra_prefix/lib/libtoppra.a" ]; then
    echo "building TOPP-RA from $SE3_BENCH_TOPPRA_DIR/cpp into $toppra_prefix" >&2
    if ! { cmake -S "$SE3_BENCH_TOPPRA_DIR/cpp" -B "$toppra_prefix/build" -DCMAKE_BUILD_TYPE=Release \
             -DCMAKE_INSTALL_PREFIX="$toppra_prefix" -DCMAKE_CXX_COMPILER="$(command -v "$CXX")" \
             -DBUILD_SHARED_LIBS=OFF -DBUILD_TESTS=OFF -DPYTHON_BINDINGS=OFF -DBUILD_WITH_PINOCCHIO=OFF \
             -DBUILD_WITH_qpOASES=OFF -DBUILD_WITH_GLPK=OFF -DINSTALL_DOCUMENTATION=OFF \
             -DTOPPRA_WARN_ON=OFF >/dev/null &&
           cmake --build "$toppra_prefix/build" --target install >/dev/null; }; then
      echo "TOPP-RA's build failed (see $toppra_prefix/build)" >&2
      exit 2
    fi
  fi
  echo
  echo "== bench_toppra (TOPP-RA $(git -C "$SE3_BENCH_TOPPRA_DIR" describe --tags --always 2>/dev/null ||
    cat "$SE3_BENCH_TOPPRA_DIR/VERSION" 2>/dev/null))"
  build bench_toppra -isystem "$toppra_prefix/include" "$toppra_prefix/lib/libtoppra.a"
  "$OUT/bench_toppra" --benchmark_repetitions="$REPETITIONS" --benchmark_min_time="$MIN_TIME" \
    --benchmark_display_aggregates_only=true
  build bench_toppra_joints "$SE3_ROOT/src/arm/arm_model.cpp" "$SE3_ROOT/src/arm/joint_limits.cpp" \
    -lurdfdom_model -lyaml-cpp -lorocos-kdl -isystem "$toppra_prefix/include" "$toppra_prefix/lib/libtoppra.a"
  echo
  echo "== bench_toppra_joints (load average: $(cut -d ' ' -f 1-3 /proc/loadavg))"
  "$OUT/bench_toppra_joints" --benchmark_repetitions="$REPETITIONS" --benchmark_min_time="$MIN_TIME" \
    --benchmark_display_aggregates_only=true --benchmark_counters_tabular=true
fi

echo
echo "== instruction counts"
"$SE3_ROOT/scripts/instruction_counts.sh" --check
