// A recorded tool motion, for the fit's benchmarks (bench_fit, bench_work_estimate) and the
// CLI's timing: `count` poses at 100 Hz of a slow motion (frequencies below 0.1 Hz: positions of
// tens of cm, rotations up to 0.8 rad) with noise of 1 mm per axis and 0.5° per rotation axis,
// from a fixed seed.
#pragma once

#include <cmath>
#include <random>
#include <vector>

#include "se3_interpolation/geometry/pose.h"
#include "se3_interpolation/math/lie_groups.h"

namespace se3_bench
{
/// The recording's rate (Hz) and noise (m per axis, rad per rotation axis).
constexpr double kRecordingRate = 100.0;
constexpr double kRecordingNoiseLinear = 0.001;
constexpr double kRecordingNoiseAngular = 0.5 * 3.14159265358979323846 / 180.0;

struct Recording
{
  std::vector<se3_interpolation::Pose<double>> poses;
  std::vector<double> times;  ///< s, from 0
};

inline Recording noisyRecording(std::size_t count)
{
  using se3_interpolation::Pose;
  const double two_pi = 2.0 * 3.14159265358979323846;
  std::mt19937 rng(2026);
  std::normal_distribution<double> normal(0.0, 1.0);
  Recording r;
  r.poses.reserve(count);
  r.times.reserve(count);
  for (std::size_t i = 0; i < count; ++i)
  {
    const double t = static_cast<double>(i) / kRecordingRate;
    const Eigen::Vector3d p(0.3 * std::sin(two_pi * 0.05 * t), 0.2 * std::cos(two_pi * 0.08 * t),
                            0.1 * std::sin(two_pi * 0.03 * t + 1.0));
    const Eigen::Vector3d w(0.5 * std::sin(two_pi * 0.04 * t), 0.3 * std::cos(two_pi * 0.07 * t),
                            0.8 * std::sin(two_pi * 0.02 * t));
    const Eigen::Vector3d dp(normal(rng), normal(rng), normal(rng));
    const Eigen::Vector3d dw(normal(rng), normal(rng), normal(rng));
    r.poses.emplace_back(se3_interpolation::so3Exp<double>(w) * se3_interpolation::so3Exp<double>(
                                                                    Eigen::Vector3d(kRecordingNoiseAngular * dw)),
                         Eigen::Vector3d(p + kRecordingNoiseLinear * dp));
    r.times.push_back(t);
  }
  return r;
}
}  // namespace se3_bench
