// src/execution/goal_trajectory_internal.h: what the goal trajectory's units share (not installed):
// goal_trajectory.cpp (the points' rules, the chart polynomials (G1) between them, the motion) and
// goal_limits.cpp (the peaks of the six rates and the checks against the bounds).
#pragma once

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/execution/goal_trajectory.h"
#include "se3_interpolation/timing/jerk_limited.h"

namespace se3_interpolation
{
namespace goal_detail
{
/// The rates of the motion, in the order of MotionLimits and MotionPeaks.
using SixRates = std::array<double, 6>;

/// What an error message says of each rate: its name, the node parameter bounding it, its unit.
struct RateName
{
  const char* name;
  const char* bound;
  const char* unit;
};
constexpr std::array<RateName, 6> kRateNames{ { { "linear speed", "~max_linear_velocity", "m/s" },
                                                { "angular speed", "~max_angular_velocity", "rad/s" },
                                                { "linear acceleration", "~max_linear_acceleration", "m/s^2" },
                                                { "angular acceleration", "~max_angular_acceleration", "rad/s^2" },
                                                { "linear jerk", "~max_linear_jerk", "m/s^3" },
                                                { "angular jerk", "~max_angular_jerk", "rad/s^3" } } };

/// The index of the velocity, acceleration and jerk rates of a channel (0: linear, 1: angular).
constexpr std::size_t velocityRate(std::size_t channel)
{
  return channel;
}
constexpr std::size_t accelerationRate(std::size_t channel)
{
  return 2 + channel;
}
constexpr std::size_t jerkRate(std::size_t channel)
{
  return 4 + channel;
}

inline SixRates boundsOf(const MotionLimits& l)
{
  return { l.max_linear_velocity,      l.max_angular_velocity, l.max_linear_acceleration,
           l.max_angular_acceleration, l.max_linear_jerk,      l.max_angular_jerk };
}

inline std::string pointField(std::size_t i)
{
  return indexedField("trajectory.points", i);
}

/// A constant of this file for a message, in its shortest form ("1e-06").
inline std::string shortNumber(double x)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%g", x);
  return text;
}

[[noreturn]] inline void refuse(const std::string& message)
{
  throw InvalidGoalError(GoalError::kInvalidGoal, message);
}
}  // namespace goal_detail

/// The motion's kinematics, whatever its geometry.
class GoalTrajectory::Interpolant
{
public:
  Interpolant(std::vector<double> times, int order) : times_(std::move(times)), order_(order) {}
  virtual ~Interpolant() = default;
  /// Pose, velocity and acceleration at t (one-sided at a point).
  virtual Kinematics at(double t, Side side) const = 0;
  /// Velocity, acceleration and jerk at t (one-sided at a point).
  virtual timing::Kinematics3 at3(double t, Side side) const = 0;

  const std::vector<double>& times() const { return times_; }
  int order() const { return order_; }

  /// The six rates at t.
  goal_detail::SixRates ratesAt(double t, Side side) const
  {
    const timing::Kinematics3 k = at3(t, side);
    return { k.velocity.linear.norm(),      k.velocity.angular.norm(), k.acceleration.linear.norm(),
             k.acceleration.angular.norm(), k.jerk.linear.norm(),      k.jerk.angular.norm() };
  }

  TrajectorySample stateAt(double t) const
  {
    const double tc = std::min(std::max(t, times_.front()), times_.back());
    const Kinematics k = at(tc, Side::kRight);
    TrajectorySample s;
    s.time = tc;
    s.pose = k.pose;
    s.velocity = k.velocity;
    s.acceleration = k.acceleration;
    return s;
  }

private:
  std::vector<double> times_;
  int order_;
};

namespace goal_detail
{
/// The peaks of the six rates (file comment of the header). With `ceilings`, only as far as telling
/// whether a peak exceeds its ceiling: a rate whose ceiling is 0 is not refined, nor a subinterval
/// whose values already exceed it, and the margin of refinement is taken below the ceiling instead
/// of below the largest value so far (the result is then a lower bound of the peaks, exact where
/// they come within kPeakRefineMargin of their ceilings from below).
MotionPeaks peaksOf(const GoalTrajectory::Interpolant& m, const SixRates* ceilings = nullptr);
}  // namespace goal_detail
}  // namespace se3_interpolation
