// Google Benchmark of se3_interpolate's work on the request of docs/performance.md "Service
// latency": 1000 waypoints on the deterministic walk of bench/service_latency.cpp, an
// `interpolating` double-geodesic curve, 10⁵ samples.
//  - planner: generate(), what the CLI computes before it writes;
//  - pose_csv: the CSV text of those samples as the CLI makes it (src/cli/csv_writer.h:
//    std::to_chars, shortest round-trip form, 1 MiB pieces of one reused buffer), the pieces
//    counted, not written;
//  - pose_csv_iostreams: the same rows through an std::ostringstream at 17 significant digits,
//    how the CLI formatted them before csv_writer.h (the peer of pose_csv).
// Counters: bytes of CSV per second and samples per second (of wall time). scripts/cli_latency.py times the
// whole CLI run on the same request.
#include <benchmark/benchmark.h>

#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>

#include "csv_writer.h"
#include "se3_interpolation/planner/planner.h"

namespace
{
using namespace se3_interpolation;

/// The request's size: that of scripts/service_latency.sh's default.
constexpr int kWaypoints = 1000;
constexpr std::uint32_t kSamples = 100000;

/// Waypoint i of bench/service_latency.cpp (q = q_z(yaw) q_x(roll)).
Pose<double> waypoint(int i)
{
  const double yaw = 0.4 * i;
  const double roll = 0.3 * std::sin(0.7 * i);
  const double cy = std::cos(0.5 * yaw), sy = std::sin(0.5 * yaw);
  const double cr = std::cos(0.5 * roll), sr = std::sin(0.5 * roll);
  return Pose<double>(Eigen::Quaterniond(cy * cr, cy * sr, sy * sr, sy * cr),
                      Eigen::Vector3d(0.3 * i, std::sin(0.5 * i), 0.2 * std::cos(0.3 * i)));
}

TrajectoryRequest request()
{
  TrajectoryRequest r;
  for (int i = 0; i < kWaypoints; ++i)
    r.waypoints.push_back(waypoint(i));
  r.curve = "interpolating";
  r.geometry = "double_geodesic";
  r.sample_count = kSamples;
  return r;
}

const TrajectoryResult& result()
{
  static const TrajectoryResult r = generate(request(), PlannerLimits());
  return r;
}

void counters(benchmark::State& state, std::size_t bytes)
{
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes));
  state.counters["samples"] = benchmark::Counter(static_cast<double>(state.iterations() * result().samples.size()),
                                                 benchmark::Counter::kIsRate);
}

void planner(benchmark::State& state)
{
  const TrajectoryRequest r = request();
  for (auto _ : state)
    benchmark::DoNotOptimize(generate(r, PlannerLimits()));
}

void pose_csv(benchmark::State& state)
{
  std::size_t bytes = 0;
  for (auto _ : state)
  {
    bytes = 0;
    cli::writePoseCsv(result(), [&bytes](const char* text, std::size_t size) {
      benchmark::DoNotOptimize(text);
      bytes += size;
    });
  }
  counters(state, bytes);
}

std::string iostreamsCsv(const TrajectoryResult& result)
{
  std::ostringstream out;
  out << std::setprecision(17);
  out << "t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz\n";
  for (const auto& s : result.samples)
  {
    out << s.time;
    for (double v : { s.pose.p.x(), s.pose.p.y(), s.pose.p.z(), s.pose.q.x(), s.pose.q.y(), s.pose.q.z(), s.pose.q.w() })
      out << ',' << v;
    for (const Eigen::Vector3d* v : { &s.velocity.linear, &s.velocity.angular, &s.acceleration.linear,
                                      &s.acceleration.angular })
      out << ',' << v->x() << ',' << v->y() << ',' << v->z();
    out << '\n';
  }
  return out.str();
}

void pose_csv_iostreams(benchmark::State& state)
{
  std::size_t bytes = 0;
  for (auto _ : state)
  {
    const std::string csv = iostreamsCsv(result());
    bytes = csv.size();
    benchmark::DoNotOptimize(csv.data());
  }
  counters(state, bytes);
}
}  // namespace

// CPU time of the whole process (pose_csv formats in one thread per core), iterations by wall time.
BENCHMARK(planner)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(pose_csv)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(pose_csv_iostreams)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK_MAIN();
