// Google Benchmark of a straight move between two poses (Pilz's LIN, a UR `movel`) under
// `time_optimal`, with jerk bounds and without: the closed-form timing of geodesic chains
// (timing/geodesic_timing.h) against the general timings it replaces on such paths
// (time_optimal.h, jerk_limited.h) and, as an optional peer, against Ruckig's closed-form 1-DOF
// profile (L. Berscheid, T. Kröger, "Jerk-limited Real-time Trajectory Generation with Arbitrary
// Target States", RSS 2021; github.com/pantor/ruckig), compiled in only when a local checkout is
// given by path (SE3_BENCH_RUCKIG_DIR, scripts/common.sh's se3_bench_peer_setup: it defines
// SE3_BENCH_RUCKIG and links the checkout's own CMake build of libruckig). Nothing of Ruckig is part
// of the project.
//
// The move: from the identity to (0.6, 0.3, 0.2) m turned 0.8 rad about (1, 2, 2)/3, the double
// geodesic, under 1 m/s, 1 rad/s, 2 m/s², 3 rad/s² and (with jerk) 10 m/s³, 15 rad/s³. Along the
// geodesic both channels move at one rate (geodesic_timing.h), so Ruckig is given the same 1-DOF
// problem: the path parameter from 0 to 1 (the path's own time) under the scalar bounds
// V = min_c v_c / r_c, A and J alike (r_c = |C′_c|). Its duration is checked equal to ours to 1e-9
// (relative) before anything is timed.
//
// Rows (`lin_<what>` and `lin_<what>_nojerk`):
//  - profile: restToRestProfile alone (the analogue of Ruckig's calculate);
//  - timing: makeGeodesicTimedCurve, the unit the planner calls (the path's check and runs, the
//    profile, the timed curve);
//  - general: makeJerkLimitedCurve / makeTimeOptimalCurve on the same path (the grid, passes, check);
//  - planner: generate() of the request, two samples (validation, the curve, the timing, figures);
//  - ruckig: Ruckig<1>::calculate of the same 1-DOF problem (with the peer).
// `bench_lin --count NAME N` runs one row N times without Google Benchmark, for callgrind
// (docs/performance.md: instructions per operation from N = 0 and N = 2000).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/timing/geodesic_timing.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"

#ifdef SE3_BENCH_RUCKIG
#include <ruckig/ruckig.hpp>
#endif

namespace
{
using namespace se3_interpolation;
using Geometry = DoubleGeodesicSe3;

Pose<double> target()
{
  return Pose<double>(Quaternion<double>(Eigen::AngleAxisd(0.8, Eigen::Vector3d(1.0, 2.0, 2.0) / 3.0)),
                      Eigen::Vector3d(0.6, 0.3, 0.2));
}

timing::RateBounds bounds(bool jerk)
{
  timing::RateBounds b;
  b.velocity = { 1.0, 1.0 };
  b.acceleration = { 2.0, 3.0 };
  if (jerk)
    b.jerk = { 10.0, 15.0 };
  return b;
}

std::shared_ptr<const Curve<Geometry>> path()
{
  return std::make_shared<PiecewiseGeodesic<Geometry>>(std::vector<Pose<double>>{ Pose<double>(), target() },
                                                       std::vector<double>{ 0.0, 1.0 });
}

/// The 1-DOF problem along the path: distance 1 under V, A, J (J = ∞ without jerk).
struct Scalar
{
  double v, a, j;
};

Scalar scalarBounds(bool jerk)
{
  const timing::RateBounds b = bounds(jerk);
  const double r[2] = { target().p.norm(), 0.8 };
  Scalar s{ std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity() };
  for (int c = 0; c < 2; ++c)
  {
    s.v = std::min(s.v, b.velocity[c] / r[c]);
    s.a = std::min(s.a, b.acceleration[c] / r[c]);
    if (jerk)
      s.j = std::min(s.j, b.jerk[c] / r[c]);
  }
  return s;
}

TrajectoryRequest request(bool jerk)
{
  const timing::RateBounds b = bounds(jerk);
  TrajectoryRequest r;
  r.waypoints = { Pose<double>(), target() };
  r.curve = "piecewise_geodesic";
  r.timing = "time_optimal";
  r.max_linear_velocity = b.velocity[0];
  r.max_angular_velocity = b.velocity[1];
  r.max_linear_acceleration = b.acceleration[0];
  r.max_angular_acceleration = b.acceleration[1];
  r.max_linear_jerk = b.jerk[0];
  r.max_angular_jerk = b.jerk[1];
  r.sample_count = 2;
  return r;
}

double closedFormDuration(bool jerk)
{
  const auto timed = timing::makeGeodesicTimedCurve<Geometry>(path(), bounds(jerk));
  return timed->endTime() - timed->startTime();
}

#ifdef SE3_BENCH_RUCKIG
/// Ruckig's time-optimal 1-DOF trajectory of the same problem; its duration.
double ruckigDuration(const Scalar& s, ruckig::Ruckig<1>& otg, ruckig::Trajectory<1>& trajectory)
{
  ruckig::InputParameter<1> input;
  input.current_position = { 0.0 };
  input.target_position = { 1.0 };
  input.max_velocity = { s.v };
  input.max_acceleration = { s.a };
  input.max_jerk = { s.j };
  if (otg.calculate(input, trajectory) != ruckig::Result::Working)
    return std::numeric_limits<double>::quiet_NaN();
  return trajectory.get_duration();
}
#endif

/// Every row: its name and one operation.
std::vector<std::pair<std::string, std::function<double()>>> operations()
{
  std::vector<std::pair<std::string, std::function<double()>>> ops;
  for (bool jerk : { true, false })
  {
    const std::string suffix = jerk ? "" : "_nojerk";
    const Scalar s = scalarBounds(jerk);
    const auto p = path();
    const timing::RateBounds b = bounds(jerk);
    const TrajectoryRequest r = request(jerk);
    ops.emplace_back("lin_profile" + suffix,
                     [s] { return timing::restToRestProfile(1.0, s.v, s.a, s.j)->duration(); });
    ops.emplace_back("lin_timing" + suffix, [p, b] {
      const auto timed = timing::makeGeodesicTimedCurve<Geometry>(p, b);
      return timed->endTime();
    });
    ops.emplace_back("lin_general" + suffix, [p, b, jerk] {
      if (jerk)
        return timing::makeJerkLimitedCurve<Geometry>(p, b)->endTime();
      return timing::makeTimeOptimalCurve<Geometry>(p, b)->endTime();
    });
    ops.emplace_back("lin_planner" + suffix, [r] { return generate(r, PlannerLimits()).duration; });
#ifdef SE3_BENCH_RUCKIG
    auto otg = std::make_shared<ruckig::Ruckig<1>>();
    auto trajectory = std::make_shared<ruckig::Trajectory<1>>();
    ops.emplace_back("lin_ruckig" + suffix, [s, otg, trajectory] { return ruckigDuration(s, *otg, *trajectory); });
#endif
  }
  return ops;
}

/// The durations agree before anything is timed: Ruckig's and the closed form's to 1e-9, the
/// planner's equal to the closed form's. Returns false (and says which) otherwise.
bool sameDurations()
{
  bool ok = true;
  for (bool jerk : { true, false })
  {
    const double ours = closedFormDuration(jerk);
    const double planner = generate(request(jerk), PlannerLimits()).duration;
    if (std::abs(planner - ours) > 1e-12 * ours)
    {
      std::fprintf(stderr, "planner duration %.17g != closed form %.17g\n", planner, ours);
      ok = false;
    }
#ifdef SE3_BENCH_RUCKIG
    ruckig::Ruckig<1> otg;
    ruckig::Trajectory<1> trajectory;
    const double theirs = ruckigDuration(scalarBounds(jerk), otg, trajectory);
    std::printf("duration%s: closed form %.12f s, Ruckig %.12f s (relative difference %.2e)\n",
                jerk ? "" : " (no jerk)", ours, theirs, std::abs(theirs - ours) / ours);
    if (!(std::abs(theirs - ours) <= 1e-9 * ours))
      ok = false;
#else
    std::printf("duration%s: closed form %.12f s\n", jerk ? "" : " (no jerk)", ours);
#endif
  }
  return ok;
}

/// `--count NAME N`: NAME run N times (callgrind's totals of N = 0 and N = 2000 differ by 2000 rows).
int count(const char* name, long n)
{
  for (const auto& [op_name, op] : operations())
    if (op_name == name)
    {
      double sink = 0.0;
      for (long i = 0; i < n; ++i)
        sink += op();
      std::printf("%s %ld %.3g\n", name, n, sink);
      return 0;
    }
  std::fprintf(stderr, "unknown operation %s\n", name);
  return 2;
}
}  // namespace

int main(int argc, char** argv)
{
  if (argc == 4 && std::strcmp(argv[1], "--count") == 0)
    return count(argv[2], std::atol(argv[3]));
  if (argc == 2 && std::strcmp(argv[1], "--list") == 0)
  {
    for (const auto& op : operations())
      std::printf("%s\n", op.first.c_str());
    return 0;
  }
  if (!sameDurations())
    return 1;
  for (const auto& [name, op] : operations())
    benchmark::RegisterBenchmark(name.c_str(), [f = op](benchmark::State& state) {
      for (auto _ : state)
        benchmark::DoNotOptimize(f());
    })->Unit(name.find("general") != std::string::npos ? benchmark::kMicrosecond : benchmark::kNanosecond);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
