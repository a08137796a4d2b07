// Google Benchmark of time-optimal timing (timing/time_optimal.h) on the natural interpolating
// spline through N = 100 … 3000 waypoints (… 10⁴ for the jerk-limited timing) (double-geodesic SE(3)), all four bounds set, against
// what the same request costs without it: the spline's construction and its sampling at 10
// samples per segment; and of the jerk-limited timing (timing/jerk_limited.h) of the same path
// with jerk bounds too (up to two more runs of the time-optimal timing and a dense check with
// third-order path jets). The timings are O(N) (a fixed number of grid intervals per segment, one
// bisection per grid point), so the `waypoints` counter (waypoints timed per second) stays flat;
// the fitted complexity is reported as BigO.
//
// Waypoints: a random walk from a fixed seed, each step a rotation of 0.2 … 1 rad about a random
// axis and a translation ~ N(0, 0.5²) m per axis; chord-spaced times. Bounds: 1 m/s, 1 rad/s,
// 2 m/s², 3 rad/s², and for the jerk-limited timing 10 m/s³, 15 rad/s³.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "se3_interpolation/planner/curve_factory.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/time_optimal.h"
#include "random_walk.h"

namespace
{
using namespace se3_interpolation;
using Geometry = DoubleGeodesicSe3;

ValidatedRequest request(std::size_t n)
{
  TrajectoryRequest r;
  r.waypoints = se3_bench::randomWalk(n);
  r.curve = "interpolating";
  return validateRequest(r, PlannerLimits());
}

timing::RateBounds bounds()
{
  timing::RateBounds b;
  b.velocity = { 1.0, 1.0 };
  b.acceleration = { 2.0, 3.0 };
  return b;
}

void construction(benchmark::State& state)
{
  const ValidatedRequest r = request(static_cast<std::size_t>(state.range(0)));
  const std::vector<double> times = waypointTimes(r);
  for (auto _ : state)
    benchmark::DoNotOptimize(makeCurve<Geometry>(r, times));
  state.SetComplexityN(state.range(0));
}

void sampling(benchmark::State& state)
{
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const ValidatedRequest r = request(n);
  const auto curve = makeCurve<Geometry>(r, waypointTimes(r));
  const std::size_t samples = 10 * (n - 1) + 1;
  for (auto _ : state)
    for (std::size_t i = 0; i < samples; ++i)
    {
      const double t = curve->startTime() + (curve->endTime() - curve->startTime()) * static_cast<double>(i) /
                                                static_cast<double>(samples - 1);
      benchmark::DoNotOptimize(kinematicsAt(*curve, t));
    }
  state.SetComplexityN(state.range(0));
}

/// Times `timing(path)` on the spline through state.range(0) waypoints; returns its last result.
template <class Path, class Timing>
auto timeTiming(benchmark::State& state, Timing timing)
{
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const ValidatedRequest r = request(n);
  const Path path(makeCurve<Geometry>(r, waypointTimes(r)));
  decltype(timing(path)) profile;
  for (auto _ : state)
  {
    profile = timing(path);
    benchmark::DoNotOptimize(profile);
  }
  state.SetComplexityN(state.range(0));
  state.counters["waypoints"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  return profile;
}

void timeOptimal(benchmark::State& state)
{
  const timing::TimingProfile profile = timeTiming<timing::CurvePath<Geometry>>(
      state, [](const timing::PathModel& path) { return timing::timeOptimalProfile(path, bounds()); });
  state.counters["grid"] = static_cast<double>(profile.s.size());
  state.counters["stretch"] = profile.stretch;
}

void jerkLimited(benchmark::State& state)
{
  timing::RateBounds b = bounds();
  b.jerk = { 10.0, 15.0 };
  const timing::JerkLimitedProfile profile = timeTiming<timing::CurveJerkPath<Geometry>>(
      state, [b](const timing::JerkPathModel& path) { return timing::jerkLimitedProfile(path, b); });
  state.counters["grid"] = static_cast<double>(profile.base.s.size());
  state.counters["pieces"] = static_cast<double>(profile.breakpoints.size());
  state.counters["stretch"] = profile.stretch;
}

BENCHMARK(construction)->Arg(100)->Arg(1000)->Arg(3000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);
BENCHMARK(sampling)->Arg(100)->Arg(1000)->Arg(3000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);
BENCHMARK(timeOptimal)->Arg(100)->Arg(1000)->Arg(3000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);
// (10⁴ waypoints: the size whose jerk-limited timing must fit the planner's default work limit of 1 s.)
BENCHMARK(jerkLimited)->Arg(100)->Arg(1000)->Arg(3000)->Arg(10000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);
}  // namespace

BENCHMARK_MAIN();
