// Google Benchmark of the natural C² interpolating spline solve (interpolating_spline.h):
// N = 10 … 10⁴ waypoints in both SE(3) geometries. Each Newton iteration is O(N) (block
// tridiagonal Jacobian, banded LU), and the iteration count does not grow with N, so the time
// per waypoint stays flat (the `waypoints` counter: waypoints solved per second); the fitted
// complexity is reported as BigO.
//
// Waypoints: a random walk from a fixed seed, each step a rotation of 0.2 … 1 rad about a random
// axis and a translation ~ N(0, 0.5²) m per axis; waypoint times 0, 1, …, N − 1 s.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "se3_interpolation/curves/interpolating_spline.h"

namespace
{
using se3_interpolation::Pose;
using se3_interpolation::Vector6;

std::vector<Pose<double>> randomWalk(std::size_t n)
{
  std::mt19937 rng(2024);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> angle(0.2, 1.0);
  std::vector<Pose<double>> x{ Pose<double>() };
  for (std::size_t i = 1; i < n; ++i)
  {
    const Eigen::Vector3d axis = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const Eigen::Vector3d step(0.5 * normal(rng), 0.5 * normal(rng), 0.5 * normal(rng));
    x.push_back(x.back() * Pose<double>(se3_interpolation::so3Exp<double>(Eigen::Vector3d(angle(rng) * axis)), step));
  }
  return x;
}

template <class G>
void naturalSolve(benchmark::State& state)
{
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  const std::vector<Pose<double>> x = randomWalk(n);
  std::vector<double> t(n);
  for (std::size_t i = 0; i < n; ++i)
    t[i] = static_cast<double>(i);
  const Vector6<double> zero = Vector6<double>::Zero();
  for (auto _ : state)
  {
    auto curve = se3_interpolation::solveC2Spline<G>(x, t, se3_interpolation::EndCondition::kNatural, zero, zero);
    benchmark::DoNotOptimize(curve);
  }
  state.SetComplexityN(state.range(0));
  state.counters["waypoints"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK_TEMPLATE(naturalSolve, se3_interpolation::ScrewSe3)
    ->RangeMultiplier(10)
    ->Range(10, 10000)
    ->Unit(benchmark::kMillisecond)
    ->Complexity(benchmark::oN);
BENCHMARK_TEMPLATE(naturalSolve, se3_interpolation::DoubleGeodesicSe3)
    ->RangeMultiplier(10)
    ->Range(10, 10000)
    ->Unit(benchmark::kMillisecond)
    ->Complexity(benchmark::oN);
}  // namespace

BENCHMARK_MAIN();
