// The vocabulary of the request-space checkers (request_space.h, joint_invariants.h): a broken
// invariant, the checker's options, numbers in messages.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace se3_interpolation
{
namespace test
{
/// One broken invariant: what (a short kind, for grouping), how much (the ratio or error that
/// broke it) and where.
struct Violation
{
  std::string kind;
  double magnitude = 0.0;
  std::string detail;
};

/// Options of the checker: the dense evaluation's size and the finite-difference points.
struct CheckOptions
{
  std::size_t dense_points = 3000;
  std::size_t difference_points = 24;
  std::uint32_t seed = 1;
  /// The goal check (checkGoal): run at all, up to how many samples (its cost grows with them:
  /// ~5 ms for 64; every grid case has 64, the sweep's sample_period reaches 4000, of which the
  /// 1000 keeps the sweep's cost), and the brute-force evaluations per segment of the goal's
  /// motion.
  bool goal = true;
  std::size_t goal_max_samples = 1000;
  std::size_t goal_evaluations_per_segment = 16;
};

inline std::string num(double x)
{
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

}  // namespace test
}  // namespace se3_interpolation
