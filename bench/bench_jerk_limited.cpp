// Google Benchmark of the jerk-limited timing (timing/jerk_limited.h) on the natural interpolating
// spline through N = 100 … 3000 waypoints (double-geodesic SE(3)), all six bounds set, next to the
// acceleration-only time-optimal timing of the same path (what the jerk bounds add: up to two more
// runs of it and the dense check with third-order path jets). Both are O(N), so the `waypoints`
// counter (waypoints timed per second) stays flat; the fitted complexity is reported as BigO.
//
// Waypoints: bench/random_walk.h (as bench_time_optimal). Bounds: 1 m/s, 1 rad/s, 2 m/s², 3 rad/s²,
// 10 m/s³, 15 rad/s³.
#include <benchmark/benchmark.h>

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

std::shared_ptr<const Curve<Geometry>> spline(std::size_t n)
{
  TrajectoryRequest r;
  r.waypoints = se3_bench::randomWalk(n);
  r.curve = "interpolating";
  const ValidatedRequest v = validateRequest(r, PlannerLimits());
  return makeCurve<Geometry>(v, waypointTimes(v));
}

timing::RateBounds bounds()
{
  timing::RateBounds b;
  b.velocity = { 1.0, 1.0 };
  b.acceleration = { 2.0, 3.0 };
  b.jerk = { 10.0, 15.0 };
  return b;
}

void timeOptimal(benchmark::State& state)
{
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const timing::CurvePath<Geometry> path(spline(n));
  timing::RateBounds b = bounds();
  b.jerk = { 0.0, 0.0 };
  for (auto _ : state)
    benchmark::DoNotOptimize(timing::timeOptimalProfile(path, b));
  state.SetComplexityN(state.range(0));
  state.counters["waypoints"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

void jerkLimited(benchmark::State& state)
{
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const timing::CurveJerkPath<Geometry> path(spline(n));
  timing::JerkLimitedProfile profile;
  for (auto _ : state)
  {
    profile = timing::jerkLimitedProfile(path, bounds());
    benchmark::DoNotOptimize(profile);
  }
  state.SetComplexityN(state.range(0));
  state.counters["waypoints"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["grid"] = static_cast<double>(profile.base.s.size());
  state.counters["pieces"] = static_cast<double>(profile.breakpoints.size());
  state.counters["stretch"] = profile.stretch;
}

BENCHMARK(timeOptimal)->Arg(100)->Arg(1000)->Arg(3000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);
BENCHMARK(jerkLimited)->Arg(100)->Arg(1000)->Arg(3000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);
}  // namespace

BENCHMARK_MAIN();
