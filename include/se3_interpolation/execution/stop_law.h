// execution/stop_law.h: how Playback::stop (execution/playback.h) slows a motion to rest along its
// own path, within acceleration and jerk bounds, without ROS.
//
// The stopped motion c(τ) keeps its path; only its path time τ is slowed, from τ̇ = 1 at the stop's
// start t_c to τ̇ = 0. With r = τ̇ (the rate), the played motion c(τ(t)) has (chain rule; the spatial
// angular velocity is linear in the rate too)
//     velocity      v r,
//     acceleration  a r² + v ṙ,
//     jerk          j r³ + 3 a r ṙ + v r̈,
// v, a, j being the stopped motion's velocity, acceleration and jerk at τ (linear and angular part
// alike: ω, ω̇, ω̈).
//
// The law (a "delayed double S" of the rate). For t − t_c < d (the delay) the motion plays on as it
// is (r = 1); from there r̈ is piecewise constant: −β for t₁ = α/β, 0 for t₂ = 1/α − α/β (ṙ = −α),
// +β for t₁, so that ṙ rises from 0 to −α and back to 0 while r falls from 1 to 0 (when α² > β
// there is no plateau: t₁ = 1/√β, t₂ = 0). The ramp lasts T = 2 t₁ + t₂ and advances τ by T/2 (ṙ
// is symmetric about T/2). ṙ = 0 at both ends: the played acceleration is continuous at the start
// (a) and at rest (0), and the played jerk is bounded (r̈ only jumps by β).
//
// On a straight line at constant speed |v| the played acceleration and jerk are |v| ṙ and |v| r̈:
// with α = A/|v| and β = J/|v| this is the time-optimal jerk-limited stop, T = |v|/A + A/J (without
// a jerk bound β = 10 α²: the acceleration ramps in a tenth of |v|/A, T = 1.1 |v|/A). Elsewhere a
// and j add to the path terms, so the law is chosen by search: candidates (d, k) with
// α = k α₀, β = k β₀ (α₀, β₀ from the start speed of each bounded part as above) for k = 0.8^i and
// d = 0 or 2^i ms, tried in the order of their rest instant d + T, and the motion's own remaining
// course (it ends at rest, as goals do) as the last candidate. A candidate is taken when, at every
// millisecond of its ramp (and at both sides of the ramp's switches; checked every 8 ms first, which
// rejects most candidates that fail for an eighth of the cost), each bounded part keeps
//     |a r² + v ṙ| ≤ max(A, |a|)   and   |j r³ + 3 a r ṙ + v r̈| ≤ max(J, |j|),
// i.e. within the bound, or within what the motion itself does at that point of its path where it
// exceeds the bound (a goal's interpolation overshoots its bounds slightly between its points,
// execution/goal_trajectory.h): whatever the motion was doing, the stop adds no excess of its own.
// j is the central difference of a over kJerkStep of path time. A motion that reaches its end during
// the ramp comes to rest there. If no candidate passes within kMaxStopSeconds (a looping motion has
// no end to fall back to) or kMaxStopChecks evaluations, the slowest candidate ramp is taken
// unchecked. Without any bound the law is the smooth ramp of stop_time (smoothRamp).
#pragma once

#include <functional>
#include <memory>

#include "se3_interpolation/geometry/trajectory_sample.h"

namespace se3_interpolation
{
/// How a stop brings the frame to rest. A bound of 0 is no bound on that part.
struct StopLimits
{
  double max_linear_acceleration = 0.0;   ///< A_lin (m/s²) on the played |p̈|; 0 = not bounded
  double max_angular_acceleration = 0.0;  ///< A_ang (rad/s²) on the played |ω̇|; 0 = not bounded
  double max_linear_jerk = 0.0;           ///< J_lin (m/s³) on the played |p⃛|; 0 = not bounded
  double max_angular_jerk = 0.0;          ///< J_ang (rad/s³) on the played |ω̈|; 0 = not bounded
  double stop_time = 1.0;                 ///< T (s) of the smooth ramp used when nothing is bounded
};

/// The path time law at one instant of a stop: τ − τ_c, τ̇, τ̈.
struct PathPoint
{
  double advance = 0.0;
  double rate = 0.0;
  double rate_dot = 0.0;
};

/// The smooth ramp of T s at t s after its start: with σ = t/T ∈ [0, 1],
///   τ̇ = 1 − 3σ² + 2σ³,   τ − τ_c = T (σ − σ³ + σ⁴/2),   τ̈ = 6 (σ² − σ)/T.
PathPoint smoothRamp(double T, double t);

/// The motion being stopped, by its path advance u = τ − τ_c.
struct StoppedPath
{
  /// Its state at advance u (u ≥ 0; also slightly below 0 for differences); *moving false where
  /// the motion has ended (its state there is its end).
  std::function<TrajectorySample(double u, bool* moving)> at;
  /// The advance at which the motion ends (infinite when it loops).
  double end_advance = 0.0;
};

/// The stop law of the file comment, chosen for one stopped motion.
class StopLaw
{
public:
  /// The law for `path` within `limits` (at least one bound set).
  StopLaw(const StoppedPath& path, const StopLimits& limits);

  /// The law at t s after the stop's start (at rest, τ̇ = 0, from restTime() on).
  PathPoint at(double t) const;
  /// s from the stop's start to rest.
  double restTime() const;

  /// The candidate law's parameters (exposed for the tests).
  struct Ramp
  {
    double delay = 0.0;  ///< d (s)
    double alpha = 0.0;  ///< α (1/s): the plateau of −τ̈
    double beta = 0.0;   ///< β (1/s²): |τ⃛| while τ̈ changes
    double t1 = 0.0;     ///< s of each of the two phases in which τ̈ changes
    double t2 = 0.0;     ///< s of the plateau τ̈ = −α
    double rest = 0.0;   ///< s from the stop's start to rest (the motion's end when reached first)
  };
  const Ramp& ramp() const { return ramp_; }

private:
  Ramp ramp_;
};

}  // namespace se3_interpolation
