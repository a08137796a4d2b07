// The waypoints of the timing benchmarks (bench_time_optimal, bench_work_estimate): a random walk
// from a fixed seed, each step a rotation of 0.2 … 1 rad about a random axis and a translation
// ~ N(0, 0.5²) m per axis.
#pragma once

#include <random>
#include <vector>

#include "se3_interpolation/math/lie_groups.h"
#include "se3_interpolation/geometry/pose.h"

namespace se3_bench
{
inline std::vector<se3_interpolation::Pose<double>> randomWalk(std::size_t n)
{
  using se3_interpolation::Pose;
  std::mt19937 rng(2024);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> angle(0.2, 1.0);
  std::vector<Pose<double>> walk{ Pose<double>() };
  for (std::size_t i = 1; i < n; ++i)
  {
    const Eigen::Vector3d axis = Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    const Eigen::Vector3d step(0.5 * normal(rng), 0.5 * normal(rng), 0.5 * normal(rng));
    walk.push_back(walk.back() *
                   Pose<double>(se3_interpolation::so3Exp<double>(Eigen::Vector3d(angle(rng) * axis)), step));
  }
  return walk;
}
}  // namespace se3_bench
