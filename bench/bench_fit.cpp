// Google Benchmark of curve fit's least-squares B-spline (fitting/bspline_fit.h) alone: a noisy
// 100 Hz recording (bench/recording.h) of N = 10³ … 10⁵ poses, knots every 0.25 s, in both
// geometries; at 10⁴ poses also with smoothing and with the Huber loss. The normal equations are
// banded and Levenberg–Marquardt's steps do not grow with N, so the cost is linear (BigO, and the
// `poses` counter: poses fitted per second). Target: at most 100 ms per 10⁴ poses in
// the default fit (double geodesic, squared loss, no smoothing).
#include <benchmark/benchmark.h>

#include "se3_interpolation/fitting/bspline_fit.h"
#include "se3_interpolation/geometry/geometry.h"
#include "recording.h"

namespace
{
using se3_interpolation::FitLoss;
using se3_interpolation::FitOptions;

/// range(1): 0 plain, 1 smoothing 1e-5, 2 Huber (loss_scale 2 cm).
FitOptions optionsOf(std::int64_t variant)
{
  FitOptions o;
  o.control_period = 0.25;
  if (variant == 1)
    o.smoothing = 1e-5;
  if (variant == 2)
  {
    o.loss = FitLoss::kHuber;
    o.loss_scale = 0.02;
  }
  return o;
}

template <class G>
void fit(benchmark::State& state)
{
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const se3_bench::Recording r = se3_bench::noisyRecording(n);
  const FitOptions o = optionsOf(state.range(1));
  int iterations = 0;
  for (auto _ : state)
  {
    const se3_interpolation::BSplineFitResult f = se3_interpolation::fitBSpline<G>(r.poses, r.times, o);
    iterations = f.iterations;
    benchmark::DoNotOptimize(f.control.data());
  }
  state.SetComplexityN(state.range(0));
  state.counters["poses"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["lm_steps"] = iterations;
}

BENCHMARK_TEMPLATE(fit, se3_interpolation::DoubleGeodesicSe3)
    ->ArgsProduct({ { 1000, 10000, 100000 }, { 0 } })
    ->Unit(benchmark::kMillisecond)
    ->Complexity(benchmark::oN);
BENCHMARK_TEMPLATE(fit, se3_interpolation::ScrewSe3)
    ->ArgsProduct({ { 1000, 10000, 100000 }, { 0 } })
    ->Unit(benchmark::kMillisecond)
    ->Complexity(benchmark::oN);
BENCHMARK_TEMPLATE(fit, se3_interpolation::DoubleGeodesicSe3)->Args({ 10000, 1 })->Args({ 10000, 2 })->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(fit, se3_interpolation::ScrewSe3)->Args({ 10000, 1 })->Args({ 10000, 2 })->Unit(benchmark::kMillisecond);
}  // namespace

BENCHMARK_MAIN();
