// The jerk-limited stop of a start state: the start's motion brought to rest (zero velocity and
// zero acceleration) with a continuous acceleration, for replanning under jerk bounds
// (src/planner/start_state.cpp chooses between it and the joined motion).
//
// One axis (JerkStop). From speed v_0 and acceleration a_0 to v = a = 0 with the position free, in
// least time under |a| ≤ A and |j| ≤ J, the acceleration is a trapezoid or a triangle in time: it
// moves at jerk ±J from a_0 to a peak a_p, holds a_p for T_2 ≥ 0, and returns to 0 at jerk ∓J
// (the velocity interface of a jerk-limited profile; L. Biagiotti, C. Melchiorri, "Trajectory
// Planning for Automatic Machines and Robots", Springer 2008, §3.4 for the rest-to-rest case).
// The velocity it gains is
//   Δv(a_p, T_2) = (a_0 + a_p) |a_p − a_0| / (2J) + a_p T_2 + a_p |a_p| / (2J),            (S1)
// which must equal −v_0. Ramping a_0 straight to 0 gains D_0 = a_0 |a_0| / (2J); the peak lies on
// the side σ = sign(−v_0 − D_0) (σ = 0: the ramp alone stops it). With the sign normalised to
// σ = +1 (w = σ(−v_0), â_0 = σ a_0) and a_p ≥ max(â_0, 0), (S1) without a plateau gives
//   a_p = sqrt(â_0² / 2 + J w)                                                             (S2)
// and, where that exceeds A (or â_0 > A already), a_p = A with
//   T_2 = (w − (a_p² + a_p² − â_0²) / (2J)) / A   (≥ 0)                                     (S3)
// (for â_0 > A the first ramp descends, and (S1) gives T_2 = (w − â_0²/(2J)) / A). An unbounded
// jerk (J = ∞) makes the ramps instantaneous: constant deceleration at A (the acceleration jumps
// at τ = 0, as curves/braked_start.h's B1). The motion may reverse briefly (a strongly braking
// start whose speed is nearly spent): it stays on its line.
//
// One channel (ChannelStop): the velocity v and acceleration a of the translation (or of the
// rotation) span a plane with axes e_1 = v/|v| and e_2 = the part of a across e_1, normalised.
// Along e_1 the stop runs from (|v|, a·e_1); across, from (0, |a_⊥|). With per-axis bounds
// A_1² + A_2² ≤ A² and J_1² + J_2² ≤ J² the channel's acceleration and jerk norms hold their
// bounds (the axes are orthogonal): J_1 = J_2 = J/√2 (J_1 = J without a sideways part), A_2 need
// not bound the across axis (its acceleration only falls from |a_⊥|, to at most |a_⊥|/√2 on the
// other side), and A_1 = sqrt(A² − |a_⊥|²) holds at all times. The sideways acceleration is gone
// after about 2.4 |a_⊥| / J_2, so a larger A_1 = A_safe + f (A − A_safe), share f ∈ [0, 1], may
// hold too; the planner lowers f from 1 until the measured rates hold (src/planner/start_brakes.cpp).
// The speed may rise above |v| while a forward acceleration ramps down (as it would in any motion
// under the jerk bound).
//
// A second design (kRamp) first ramps the channel's acceleration vector linearly to zero at the jerk
// bound, a(τ) = a (1 − τ/T_r), T_r = |a|/J (its norm only falls), then stops the velocity
// v + a T_r/2 along its own direction with the full bounds: faster where the sideways acceleration
// takes most of the acceleration bound, slower where the start already brakes hard. The planner
// keeps the faster design of each channel that holds the bounds.
//
// The brake (JerkBrake): p(τ) = p_0 + e_1 s_1(τ) + e_2 s_2(τ) exactly, and R(τ) = exp(φ(τ)) R_0 with
// φ(τ) = e_1 θ_1(τ) + e_2 θ_2(τ) in the exponential chart at R_0. Its spatial angular velocity
// is J_l(φ) φ̇ = φ̇ + ½ φ × φ̇ + O(|φ|²|φ̇|): the rotation's rates equal the axes' only to first order
// in the angle turned while braking (at τ = 0 its jerk has the extra ½ ω_0 × ω̇_0). The
// planner therefore evaluates the brake's rates from its exact jets and scales the per-axis
// bounds down until every rate holds its bound (src/planner/start_brakes.cpp). After both channels stop
// the brake holds its stop pose.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/geometry/pose.h"
#include "se3_interpolation/math/jet.h"
#include "se3_interpolation/math/lie_groups.h"

namespace se3_interpolation
{
/// A one-axis stop from (v_0, a_0) to rest in least time (file comment, S1–S3).
class JerkStop
{
public:
  JerkStop() = default;

  /// `a_max`, `j_max` ≤ 0 mean unbounded; at least one of them must bound a moving axis.
  JerkStop(double v0, double a0, double a_max, double j_max)
  {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    const double A = a_max > 0.0 ? a_max : kInf;
    const double J = j_max > 0.0 ? j_max : kInf;
    const double w = -v0;
    const double d0 = std::isinf(J) ? 0.0 : a0 * std::abs(a0) / (2.0 * J);
    const double sigma = w > d0 ? 1.0 : (w < d0 ? -1.0 : 0.0);
    double peak = a0;
    double plateau = 0.0;
    if (sigma != 0.0)
    {
      const double wn = sigma * w;
      const double an = sigma * a0;
      const double ramps = std::isinf(J) ? 0.0 : 1.0 / (2.0 * J);
      double pn;
      if (an > A)
      {
        pn = A;
        plateau = (wn - an * an * ramps) / A;
      }
      else
      {
        pn = std::isinf(J) ? kInf : std::sqrt(0.5 * an * an + J * wn);
        if (pn > A)
        {
          pn = A;
          plateau = (wn - (2.0 * A * A - an * an) * ramps) / A;
        }
      }
      plateau = std::max(0.0, plateau);
      peak = sigma * pn;
    }
    const double durations[3] = { std::isinf(J) ? 0.0 : std::abs(peak - a0) / J, plateau,
                                  std::isinf(J) ? 0.0 : std::abs(peak) / J };
    const double accelerations[3] = { a0, peak, peak };
    const double ends[3] = { peak, peak, 0.0 };
    t_[0] = 0.0;
    p_[0] = 0.0;
    v_[0] = v0;
    for (int k = 0; k < 3; ++k)
    {
      const double d = durations[k];
      a_[k] = accelerations[k];
      j_[k] = d > 0.0 ? (ends[k] - accelerations[k]) / d : 0.0;
      t_[k + 1] = t_[k] + d;
      // Exact for a linear acceleration: v gains the mean, p the integral of v.
      v_[k + 1] = v_[k] + 0.5 * (accelerations[k] + ends[k]) * d;
      p_[k + 1] = p_[k] + v_[k] * d + d * d * (2.0 * accelerations[k] + ends[k]) / 6.0;
    }
  }

  /// When the axis is at rest (0 for an axis that never moves).
  double stopTime() const { return t_[3]; }
  /// The position at the stop (relative to the start).
  double stopPosition() const { return p_[3]; }
  /// The times at which the jerk changes, within (0, stopTime()).
  std::array<double, 2> switches() const { return { t_[1], t_[2] }; }

  /// The position at τ ≥ 0 (a double or a jet of time; one-sided at the switches, held after the stop).
  template <class S>
  S positionAt(const S& tau, Side side) const
  {
    const double tv = valueOf(tau);
    if (tv > t_[3] || (tv == t_[3] && side == Side::kRight))
      return S(p_[3]);
    int k = 0;
    while (k < 2 && (tv > t_[k + 1] || (tv == t_[k + 1] && side == Side::kRight)))
      ++k;
    const S h = tau - S(t_[k]);
    return S(p_[k]) + h * (S(v_[k]) + h * (S(0.5 * a_[k]) + h * S(j_[k] / 6.0)));
  }

private:
  std::array<double, 4> t_{};  ///< phase boundaries
  std::array<double, 4> p_{};  ///< position at each boundary
  std::array<double, 4> v_{};  ///< velocity at each boundary
  std::array<double, 3> a_{};  ///< acceleration at each phase's start
  std::array<double, 3> j_{};  ///< jerk within each phase
};

/// One channel's stop (file comment): split into the axes of its velocity and acceleration
/// (kSplit), or its acceleration ramped to zero first (kRamp).
struct ChannelStop
{
  Eigen::Vector3d along_axis = Eigen::Vector3d::Zero();   ///< e_1 (zero for a channel at rest)
  Eigen::Vector3d across_axis = Eigen::Vector3d::Zero();  ///< e_2 (zero without a sideways part)
  JerkStop along;
  JerkStop across;
  /// kRamp: the ramp's duration T_r = |a|/J, the start's velocity and acceleration, and the
  /// displacement at its end, where the axes' stops begin (T_r = 0 for kSplit).
  double ramp = 0.0;
  Eigen::Vector3d v0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d a0 = Eigen::Vector3d::Zero();
  Eigen::Vector3d ramp_end = Eigen::Vector3d::Zero();

  double stopTime() const { return ramp + std::max(along.stopTime(), across.stopTime()); }

  /// The times within (0, stopTime()) at which the jerk changes.
  std::vector<double> switches() const
  {
    std::vector<double> b{ ramp };
    for (const JerkStop* s : { &along, &across })
    {
      for (double x : s->switches())
        b.push_back(ramp + x);
      b.push_back(ramp + s->stopTime());
    }
    return b;
  }

  /// The channel's displacement (translation, or rotation vector) at τ.
  template <class S>
  Vector3<S> at(const S& tau, Side side) const
  {
    const double tv = valueOf(tau);
    if (ramp > 0.0 && (tv < ramp || (tv == ramp && side == Side::kLeft)))
      return v0.template cast<S>() * tau + a0.template cast<S>() * (tau * tau * (S(0.5) - tau / S(6.0 * ramp)));
    const S t = tau - S(ramp);
    return ramp_end.template cast<S>() + along_axis.template cast<S>() * along.positionAt(t, side) +
           across_axis.template cast<S>() * across.positionAt(t, side);
  }
};

/// How a channel stops (ChannelStop).
enum class StopDesign
{
  kSplit,
  kRamp
};

/// kRamp's stop (file comment): the acceleration a ramped linearly to zero at the jerk bound (its
/// norm only falls), then the velocity v + a T_r / 2 stopped along its own direction.
inline ChannelStop makeRampStop(const Eigen::Vector3d& v, const Eigen::Vector3d& a, double a_max, double j_max)
{
  ChannelStop c;
  c.v0 = v;
  c.a0 = a;
  c.ramp = a.norm() / j_max;
  const double t = c.ramp;
  const Eigen::Vector3d v1 = v + 0.5 * a * t;
  c.ramp_end = v * t + a * (t * t / 3.0);
  const double speed = v1.norm();
  if (speed > 0.0)
  {
    c.along_axis = v1 / speed;
    c.along = JerkStop(speed, 0.0, a_max, j_max);
  }
  return c;
}

/// The stop of a channel with velocity v and acceleration a under |a| ≤ A·scale, |j| ≤ J·scale
/// (0 = unbounded) with along-axis share f of the acceleration bound (file comment). `stop_time` is
/// used only by a channel with neither bound, which decelerates uniformly to stop then (its
/// acceleration jumps, as no bound forbids).
inline ChannelStop makeChannelStop(const Eigen::Vector3d& v, const Eigen::Vector3d& a, double a_max, double j_max,
                                   double scale, double share, double stop_time, StopDesign design)
{
  if (design == StopDesign::kRamp && j_max > 0.0 && a.norm() > 0.0)
    return makeRampStop(v, a, scale * a_max, scale * j_max);
  ChannelStop c;
  const double speed = v.norm();
  if (speed > 0.0)
    c.along_axis = v / speed;
  else if (a.norm() > 0.0 && (a_max > 0.0 || j_max > 0.0))
    c.along_axis = a.normalized();
  else
    return c;
  const double a_along = a.dot(c.along_axis);
  const Eigen::Vector3d a_across = a - a_along * c.along_axis;
  const double across = a_across.norm();
  const bool sideways = j_max > 0.0 && across > 1e-12 * std::max(1.0, a.norm());
  if (!(a_max > 0.0) && !(j_max > 0.0))
  {
    c.along = JerkStop(speed, 0.0, stop_time > 0.0 ? speed / stop_time : 0.0, 0.0);
    return c;
  }
  const double jerk = j_max > 0.0 ? scale * j_max / (sideways ? std::sqrt(2.0) : 1.0) : 0.0;
  double accel = 0.0;
  if (a_max > 0.0)
  {
    const double bound = scale * a_max;
    const double safe =
        std::sqrt(std::max(sideways ? bound * bound - across * across : bound * bound, 1e-6 * bound * bound));
    accel = safe + share * (bound - safe);
  }
  c.along = JerkStop(speed, a_along, accel, jerk);
  if (sideways)
  {
    c.across_axis = a_across / across;
    c.across = JerkStop(0.0, across, 0.0, jerk);
  }
  return c;
}

/// The jerk-limited stop of a start state (file comment): translation and rotation channels.
struct JerkBrake
{
  Pose<double> start;
  Twist start_velocity;
  Twist start_acceleration;
  ChannelStop linear;
  ChannelStop angular;

  double stopTime() const { return std::max(linear.stopTime(), angular.stopTime()); }

  Pose<double> stopPose() const { return at(stopTime(), Side::kRight); }

  /// The switches of both channels' axes within (0, stopTime()), sorted.
  std::vector<double> breakpoints() const
  {
    std::vector<double> b = linear.switches();
    for (double x : angular.switches())
      b.push_back(x);
    const double stop = stopTime();
    b.erase(std::remove_if(b.begin(), b.end(), [stop](double x) { return !(x > 0.0 && x < stop); }), b.end());
    std::sort(b.begin(), b.end());
    b.erase(std::unique(b.begin(), b.end()), b.end());
    return b;
  }

  /// The braking motion at τ ∈ [0, T]; at τ = 0 from the left the start state itself (its
  /// second-order Taylor motion, as curves/braked_start.h's BrakeToRest::at).
  template <class S>
  Pose<S> at(const S& tau, Side side) const
  {
    const Pose<S> x0 = start.template cast<S>();
    Vector3<S> dp;
    Vector3<S> phi;
    if (valueOf(tau) == 0.0 && side == Side::kLeft)
    {
      dp = start_velocity.linear.template cast<S>() * tau +
           (0.5 * start_acceleration.linear).template cast<S>() * (tau * tau);
      phi = start_velocity.angular.template cast<S>() * tau +
            (0.5 * start_acceleration.angular).template cast<S>() * (tau * tau);
    }
    else
    {
      dp = linear.at(tau, side);
      phi = angular.at(tau, side);
    }
    return Pose<S>(Quaternion<S>(so3Exp<S>(phi) * x0.q), Vector3<S>(x0.p + dp));
  }
};

/// The brake of a start state under bounds (a_max, j_max per channel: linear, angular; 0 =
/// unbounded) with each channel's bounds scaled by its `scale` ∈ (0, 1], its along-axis share
/// `share` of the acceleration bound and its design (makeChannelStop). A channel with neither bound stops with the others.
/// Stop time 0: no channel with a bound moves.
inline JerkBrake makeJerkBrake(const Pose<double>& pose, const Twist& velocity, const Twist& acceleration,
                               const std::array<double, 2>& a_max, const std::array<double, 2>& j_max,
                               const std::array<double, 2>& scale, const std::array<double, 2>& share,
                               const std::array<StopDesign, 2>& design)
{
  JerkBrake b;
  b.start = pose;
  b.start_velocity = velocity;
  b.start_acceleration = acceleration;
  const bool bounded[2] = { a_max[0] > 0.0 || j_max[0] > 0.0, a_max[1] > 0.0 || j_max[1] > 0.0 };
  if (bounded[0])
    b.linear =
        makeChannelStop(velocity.linear, acceleration.linear, a_max[0], j_max[0], scale[0], share[0], 0.0, design[0]);
  if (bounded[1])
    b.angular =
        makeChannelStop(velocity.angular, acceleration.angular, a_max[1], j_max[1], scale[1], share[1], 0.0, design[1]);
  const double stop = b.stopTime();
  if (!bounded[0])
    b.linear = makeChannelStop(velocity.linear, acceleration.linear, 0.0, 0.0, 1.0, 1.0, stop, StopDesign::kSplit);
  if (!bounded[1])
    b.angular = makeChannelStop(velocity.angular, acceleration.angular, 0.0, 0.0, 1.0, 1.0, stop, StopDesign::kSplit);
  return b;
}
}  // namespace se3_interpolation
