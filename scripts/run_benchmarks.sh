#!/usr/bin/env bash
# Reproduces the performance figures of the core and prints their tables:
#  1. bench_core (Google Benchmark): ns per operation for the screw and double-geodesic
#     geometries against KDL and plain Eigen, the ratio table, and sampling throughput;
#     bench_interpolating (the interpolating solve, N = 10 … 10⁴) when bench/bench_interpolating.cpp exists;
#     bench_time_optimal (time-optimal and jerk-limited timing of the interpolating spline, N = 100 … 3000);
#     bench_cli_output (se3_interpolate's CSV of 10⁵ samples against iostreams, and the planner
#     on that request);
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
  if [ -x "$bin" ] && [ "$(cat "$stamp" 2>/dev/null)" = "$CXX $CXXFLAGS ${se3_bench_peer_flags[*]}" ] &&
    [ -z "$(find "$SE3_ROOT/bench" "$SE3_ROOT/include" "$SE3_ROOT/src" -newer "$bin" -type f | head -n 1)" ]; then
    return 0
  fi
  echo "building $bin ($CXX -std=c++17 $CXXFLAGS)" >&2
  # shellcheck disable=SC2086
  "$CXX" -std=c++17 $CXXFLAGS -I"$SE3_ROOT/include" -I/usr/include/eigen3 "${se3_bench_peer_flags[@]}" \
    "$SE3_ROOT/bench/$name.cpp" "${core_sources[@]}" -o "$bin" "$@" -lbenchmark -lpthread
  echo "$CXX $CXXFLAGS ${se3_bench_peer_flags[*]}" >"$stamp"
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

build bench_cli_output -I"$SE3_ROOT/src/cli" "$SE3_ROOT/src/cli/csv_writer.cpp"
echo
echo "== bench_cli_output"
"$OUT/bench_cli_output" --benchmark_repetitions="$REPETITIONS" --benchmark_min_time="$MIN_TIME" \
  --benchmark_display_aggregates_only=true

echo
echo "== instruction counts"
"$SE3_ROOT/scripts/instruction_counts.sh" --check
