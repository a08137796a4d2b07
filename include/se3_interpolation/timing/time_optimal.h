// timing/: time parameterisation beyond the uniform stretch: time_optimal.h (this header).
//
// Time-optimal timing along a fixed path under velocity and acceleration norm bounds.
//
// The path is a curve C(s) on [s_0, s_1], its own time axis s (the waypoint times) serving
// as the path parameter. A timing s(t) with s(t_0) = s_0, ṡ ≥ 0 gives the motion C(s(t)) whose
// rates follow from the analytic path derivatives C′ = dC/ds, C″ = d²C/ds² by the chain rule
//   v = C′ ṡ,     a = C″ ṡ² + C′ s̈                                     (1)
// for each channel: the linear one (p′, p″) and the angular one (ω_s, ω′_s, the spatial angular
// velocity per unit s and its s-derivative, kinematics.h; eq. 1 holds because ω is linear in q̇).
// On the sphere S^m the angular channel is (x′, D²x/ds²): the covariant acceleration obeys eq. 1
// too, x′ being tangent. With x = ṡ² and u = s̈ (so that dx/ds = 2u) the bounds are
//   |C′| √x ≤ v_max              (velocity: x ≤ v_max² / |C′|²)          (2)
//   |C″ x + C′ u| ≤ a_max        (acceleration: a convex ellipse in (x, u))  (3)
// per channel, 0 meaning unbounded. The fastest traversal starting and ending at rest is found by
// reachability analysis (H. Pham, Q.-C. Pham, "A New Approach to Time-Optimal Path
// Parameterization Based on Reachability Analysis", IEEE T-RO 34(3), 2018: TOPP-RA):
//  - a grid s_0 < … < s_N containing every breakpoint of the curve, uniform on each analytic piece
//    and then halved wherever the path's rates change too much across an interval for its ends to
//    stand for its interior (Δ |C″| > 0.25 |C′| in a bounded channel: a path parameter that runs
//    10⁵ times faster at one end of a corner blend than at the other, uneven waypoint times); on
//    [s_i, s_{i+1}] the control u_i is constant, so x is linear in s: x_{i+1} = x_i + 2 Δ_i u_i
//    (Pham & Pham, eq. 4);
//  - the constraints (2), (3) hold at BOTH ends of every interval: at s_i (right-sided jets) with
//    (x_i, u_i) and at s_{i+1} (left-sided jets) with (x_{i+1}, u_i). Both are convex in (x_i, u_i)
//    (the second is (3) under the affine map x_{i+1} = x_i + 2Δu), so for a fixed x_i the admissible
//    u_i is an interval obtained exactly from the quadratics' roots (discriminant
//    α a_max² − |C′ × C″|² x², α = |C′ + 2Δ C″|² resp. |C′|²): no box approximation;
//  - backward pass: the controllable sets K_N = {0}, K_i = {x : ∃ u admissible with
//    x + 2Δu ∈ K_{i+1}} (Pham & Pham, eq. 9). Each K_i is an interval [0, k_i] (x = u = 0 is
//    always admissible), and the admissible x form an interval containing 0, so k_i is the root
//    of a monotone predicate, found by bisection to relative 1e-12 (a 1-D convex problem solved
//    to rounding, on the exact constraints);
//  - greedy forward pass: x_0 = 0 (or the requested start speed squared, exactly, when replanning
//    from a moving state: TimeOptimalOptions::start_speed, with a recovery by braking where it lies
//    outside K_0) and u_i the largest admissible control with x_{i+1} ∈ K_{i+1}
//    (Pham & Pham, eq. 12), which is time-optimal for the discretised problem;
//  - velocity corners (breakpoints where C′ jumps: piecewise_geodesic waypoints, B-spline knots
//    of full multiplicity) get K = {0}: the motion comes to rest there (a jump of C′ at ṡ > 0 is an
//    infinite acceleration);
//  - the times: t_{i+1} = t_i + 2 Δ_i / (√x_i + √x_{i+1}) (exact for constant s̈ on the interval).
// Between grid points the bounds are not imposed by the scheme; the guarantee comes from checks:
//  - every interval is evaluated at its middle (cached path jets); where a rate there exceeds its
//    bound by more than 1e-4, that bound is tightened at the interval's two ends by the excess and
//    the two passes are rerun (at most 4 times): a local slow-down instead of a global one;
//  - the final check evaluates every interval at its two ends (one-sided) and its middle; a parabola
//    through a rate's three values flags intervals whose interior could rise above that rate's
//    largest value seen (within 1e-3), and those are searched for their maximum on the exact rates
//    (successive parabolic interpolation to 1e-7 of the interval);
//  - from rest the whole profile is then run slower by the uniform factor k ≥ 1 that brings the
//    worst rate within its bound (velocities scale by 1/k, accelerations by 1/k²), typically
//    k − 1 < 1e-3; from a moving start (whose velocity a stretch would change) the local passes
//    go on, with a small margin, until every checked rate is within 1e-8 of its bound.
// The passes after the first recompute only what a tightening changed (the controllable sets
// upstream of a tightened point until they agree with the previous pass, the forward pass from the
// first changed point), and each rate's peak search serves both the stretch and the figures (the
// acceleration energy, too, comes from the final check's values at every interval's ends and middle).
//
// Grid size (TimeOptimalOptions): the discretisation of a bang-bang or cruise phase is exact for
// constant s̈ (x linear in s), so the loss against the optimum comes from where the active
// constraint's path data (C′, C″) vary inside an interval, and from the final correction, both
// shrinking roughly with Δ². Measured against the brute-force reference of test_time_optimal.cpp
// on 5-waypoint paths of every curve family (4 pieces): 64 intervals in all were 0.6–2.4 % above
// the optimum, 256 were 0.05–0.24 %, 1024 were 0.01–0.05 %. On a 1000-waypoint random-walk spline
// 8 intervals per piece were 1.5 % above the 32-per-piece result and 16 per piece 0.3 %. Hence
// 16 intervals per analytic piece and at least 512 in all: within 1 % of the optimum with margin,
// at a cost linear in the grid size (two path jets per interval; per grid point, a bracket of
// relative width 2e-10 around the set's upper end where braking at an acceleration bound decides
// it, bisected to 1e-12 in ~8 closed-form steps).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <vector>

#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/analysis/kinematics.h"

namespace se3_interpolation
{
namespace timing
{
/// The bounded channels: linear (m) and angular (rad).
enum Channel
{
  kLinear = 0,
  kAngular = 1
};

/// The inner products of one channel's path derivatives b = C′(s), a = C″(s) that the norm
/// bounds (2), (3) need: |a x + b u|² = aa x² + 2 ab x u + bb u².
struct ChannelJet
{
  double bb = 0.0;     ///< |C′|²
  double ab = 0.0;     ///< C″ · C′
  double aa = 0.0;     ///< |C″|²
  double cross = 0.0;  ///< |C′|²|C″|² − (C′ · C″)² ≥ 0 (computed without cancellation)
};

/// Both channels at one path parameter.
using PathJet = std::array<ChannelJet, 2>;

template <class V>
ChannelJet channelJet(const V& b, const V& a)
{
  ChannelJet c;
  c.bb = b.squaredNorm();
  c.ab = a.dot(b);
  c.aa = a.squaredNorm();
  // |b|² |a − (a·b/|b|²) b|²: exact 0 for parallel vectors, unlike |a|²|b|² − (a·b)².
  if (c.bb > 0.0)
    c.cross = c.bb * (a - (c.ab / c.bb) * b).squaredNorm();
  return c;
}

/// max_* bounds per channel (0 = unbounded): velocity[kLinear] = max_linear_velocity, etc.
struct RateBounds
{
  std::array<double, 2> velocity{};
  std::array<double, 2> acceleration{};
  /// max_linear_jerk (m/s³, |d³p/dt³|), max_angular_jerk (rad/s³, |ω̈|): bounded by the
  /// jerk-limited timing (jerk_limited.h) only; timeOptimalProfile does not read them.
  std::array<double, 2> jerk{};
};

/// A local limit at one path parameter (TimeOptimalOptions::local_limits).
struct LocalLimit
{
  double acceleration_factor = 1.0;                            ///< in (0, 1], on both channels
  double speed_cap = std::numeric_limits<double>::infinity();  ///< largest ṡ (∞: none)
  /// Largest |s̈| on the intervals next to this point (∞: none). Where the path stands still
  /// (C′ = 0, a clamped end at rest) the acceleration bounds do not limit s̈; the jerk-limited
  /// timing bounds it by what they allow where the motion is a window later.
  double path_acceleration_cap = std::numeric_limits<double>::infinity();
};

/// The path as the timing sees it: the channels' derivatives w.r.t. the path parameter.
class PathModel
{
public:
  virtual ~PathModel() = default;
  virtual double start() const = 0;
  virtual double end() const = 0;
  /// Sorted path parameters, ends included, between which the path is analytic.
  virtual std::vector<double> breakpoints() const = 0;
  /// C′ and C″ of both channels at s, one-sided at a breakpoint.
  virtual PathJet jet(double s, Side side) const = 0;
  /// Whether C′ jumps at the breakpoint s (a velocity corner).
  virtual bool isCorner(double s) const = 0;
};

/// Most components a BoxConstraint may have (the controls' constraints live on the stack).
constexpr std::size_t kMaxBoxComponents = 16;

/// Limits on components of the motion that are linear in the path's derivatives, beside the norm
/// bounds (2), (3): component k moves at w_k(s) ṡ and accelerates at w_k s̈ + a_k ṡ² (an arm's joint
/// k following the path: w = q′_k, a = q″_k, arm/joint_path.h), bounded by
///   |w_k| √x ≤ V_k        (a cap on x)                                                     (4)
///   |w_k u + a_k x| ≤ A_k (a band in (x, u): the ellipse (3) of a one-dimensional channel)  (5)
/// both imposed at the two ends of every interval as (2), (3) are, and checked between the grid
/// points by the final check (and its searched peaks) before the stretch. A limit 0 is no limit.
class BoxConstraint
{
public:
  virtual ~BoxConstraint() = default;
  /// The number of components m (at most kMaxBoxComponents).
  virtual std::size_t size() const = 0;
  /// V_k of (4) (0: none).
  virtual double velocityLimit(std::size_t k) const = 0;
  /// A_k of (5) (0: none).
  virtual double accelerationLimit(std::size_t k) const = 0;
  /// w_k = dq_k/ds into w[0, m) and a_k = d²q_k/ds² into a[0, m) at path parameter s (one-sided
  /// at a breakpoint of the path).
  virtual void jet(double s, Side side, double* w, double* a) const = 0;
};

/// The grid (see the file comment for why these values).
struct TimeOptimalOptions
{
  std::size_t intervals_per_piece = 16;  ///< at least this many intervals between breakpoints
  std::size_t min_intervals = 512;       ///< at least this many in all (spread by piece length)
  /// ṡ at s_0 (replanning from a moving state: the motion starts at this path speed instead of at
  /// rest), kept exactly: no stretch follows (it would change the start velocity), the local passes
  /// continue until every checked rate after the recovery is within its bound. A start outside the
  /// controllable set K_0 (faster than the bounds allow, or too fast to brake for what lies ahead)
  /// is brought into the sets by the hardest braking the acceleration bounds allow: the recovery,
  /// which ends at TimingProfile::recovery_end; one that cannot come to rest before a velocity
  /// corner or the end of the path is refused naming `start_state`.
  double start_speed = 0.0;
  /// s̈ = 0 on a first interval of 1e-6 of the first grid interval, so that the motion's
  /// acceleration at s_0 is the path's C″ ṡ² (with start_speed 1 on a path whose own time is the
  /// motion's: the start state's acceleration, exactly).
  bool hold_start = false;
  /// Limits tighter than the bounds at some path parameters, for timings built on this one (the
  /// jerk-limited timing: its plateaus and per-segment accelerations): read once at every grid
  /// point (at a breakpoint, the tighter of its two sides is the caller's to give). Empty: none.
  std::function<LocalLimit(double)> local_limits;
  /// Limits (4), (5) beside the request's norm bounds (an arm's joint limits); null: none. Where
  /// every component has an acceleration limit the norm bounds may all be 0.
  std::shared_ptr<const BoxConstraint> boxes;
};

/// One component's peak rates over a timed motion (an arm joint's: rad/s, rad/s² or m/s, m/s²)
/// and the times at which they occur (s, the middle of the interval holding a searched peak).
struct BoxPeak
{
  double velocity = 0.0;      ///< max |w| ṡ
  double acceleration = 0.0;  ///< max |w s̈ + a ṡ²|
  double velocity_time = 0.0;
  double acceleration_time = 0.0;
};

/// The relative excess of TimingProfile::recovery_excess over 1 that a caller refuses.
constexpr double kRecoveryExcessTolerance = 1e-6;

/// The timing s(t): piecewise quadratic in t with constant s̈ = u_i on [t_i, t_{i+1}].
struct TimingProfile
{
  std::vector<double> s;  ///< grid of path parameters
  std::vector<double> t;  ///< the motion's time at each grid point (t[0] = s[0])
  std::vector<double> x;  ///< ṡ² at each grid point (0 at both ends and at corners)
  std::vector<double> u;  ///< s̈ on [t_i, t_{i+1}] (one fewer than the grid)
  double stretch = 1.0;   ///< the final uniform correction k ≥ 1 (already applied to t, x, u)
  /// The time from which every bound holds: t[0], unless the start is one the bounds cannot hold
  /// (TimeOptimalOptions::start_speed), then the end of its recovery.
  double recovery_end = 0.0;
  /// The largest ratio of an acceleration to its bound (a box's too) that braking out of such a
  /// start takes where the path bends too sharply for its speed (no braking keeps within the
  /// bounds there); 0 when the recovery keeps within them. Above 1 + kRecoveryExcessTolerance the
  /// motion is the caller's to refuse, and the final check leaves the refusal to it.
  double recovery_excess = 0.0;
  /// Figures of the timed motion per channel (kLinear, kAngular), from the final check: the peak
  /// speed |C′|ṡ and acceleration |C″ṡ² + C′s̈| over the ends and middles of all intervals (and
  /// the searched interior maxima of the bounded rates), and ∫|a|² dt by the quadratic through
  /// each interval's ends and middle (the path's length is the curve's: timing does not change it).
  std::array<double, 2> max_speed{};
  std::array<double, 2> max_acceleration{};
  std::array<double, 2> acceleration_energy{};
  /// The box constraint the timing held (TimeOptimalOptions::boxes; null: none), and each
  /// component's peaks from the final check (ends and middles of every interval after the
  /// recovery, and the searched maxima where a parabola through them peaks inside).
  std::shared_ptr<const BoxConstraint> boxes;
  std::vector<BoxPeak> box_peaks;

  double duration() const { return t.back() - t.front(); }

  /// s(t) (in any scalar: double or a jet of t); outside [t_0, t_N] the end quadratics extend.
  /// Evaluated from the nearer end of its interval, so s(t_i) is exactly s_i.
  /// Before t_0 (and at t_0 from the left) the motion is the one it starts from, at its start
  /// speed without acceleration (a start at rest is held): the left limit at t_0 is the start state.
  template <class S>
  S pathParameter(const S& time, Side side) const
  {
    const double tv = valueOf(time);
    if (tv < t.front() || (tv == t.front() && side == Side::kLeft))
      return s.front() + std::sqrt(x.front()) * (time - t.front());
    const std::size_t i = findInterval(t, tv, side);
    if (tv - t[i] <= t[i + 1] - tv)
    {
      const S tau = time - t[i];
      return s[i] + std::sqrt(x[i]) * tau + (0.5 * u[i]) * (tau * tau);
    }
    const S sigma = t[i + 1] - time;
    return s[i + 1] - std::sqrt(x[i + 1]) * sigma + (0.5 * u[i]) * (sigma * sigma);
  }

  /// The time at which the motion passes the path parameter s (s⁻¹); grid points map exactly.
  double timeAt(double path_parameter) const;
};

/// The time-optimal timing of `path` under `bounds`, verified and corrected (file comment).
/// Throws InvalidInputError naming the missing bound where the path moves in a channel that no
/// bound limits, or when every bound is 0.
TimingProfile timeOptimalProfile(const PathModel& path, const RateBounds& bounds,
                                 const TimeOptimalOptions& options = TimeOptimalOptions());

/// The path derivatives C′ = (p′, ω_s), C″ of a pose curve from its velocity and acceleration
/// (each part in any frame: the inner products do not see a rotation).
inline PathJet pathJet(const Twist& velocity, const Twist& acceleration)
{
  return { channelJet(velocity.linear, acceleration.linear), channelJet(velocity.angular, acceleration.angular) };
}

/// The path derivatives of a pose curve (ScrewSe3, DoubleGeodesicSe3).
template <class G>
PathJet pathJetAt(const Curve<G>& curve, double s, Side side)
{
  const Kinematics k = kinematicsAt(curve, s, side);
  return pathJet(k.velocity, k.acceleration);
}

/// On S^m only the angular channel moves: (x′, D²x/ds²).
inline PathJet pathJetAt(const Curve<Sphere>& curve, double s, Side side)
{
  const SphereKinematics k = kinematicsAt(curve, s, side);
  return { ChannelJet(), channelJet(k.velocity, k.acceleration) };
}

/// A channel moves at a grid point when |C′| exceeds this fraction of its largest |C′| on the
/// path; a channel whose largest |C′| is below this fraction of the other's does not move at all
/// (rounding of a pure rotation's translation, or vice versa).
constexpr double kMoveTolerance = 1e-9;

/// Relative jump of C′ across s above which the breakpoint is a velocity corner: far above the
/// rounding of the one-sided jets (~1e-15) at breakpoints where the curve is C¹.
constexpr double kCornerTolerance = 1e-8;

/// Whether each channel's velocity (kLinear, kAngular) jumps across the breakpoint s: by more
/// than kCornerTolerance of its two sides and than `floor` of the channel (a channel that comes to
/// rest at s from one side only, its other side's velocity at rounding level, jumps by nothing
/// that matters, which the relative test alone would take for a corner).
template <class G>
std::array<bool, 2> velocityJumpsByChannel(const Curve<G>& curve, double s, const std::array<double, 2>& floor = {})
{
  const Kinematics l = kinematicsAt(curve, s, Side::kLeft);
  const Kinematics r = kinematicsAt(curve, s, Side::kRight);
  auto jumps = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, double at_least) {
    return (a - b).norm() > std::max(kCornerTolerance * (a.norm() + b.norm()), at_least);
  };
  return { jumps(l.velocity.linear, r.velocity.linear, floor[kLinear]),
           jumps(l.velocity.angular, r.velocity.angular, floor[kAngular]) };
}

/// On S^m only the angular channel moves.
inline std::array<bool, 2> velocityJumpsByChannel(const Curve<Sphere>& curve, double s,
                                                  const std::array<double, 2>& floor = {})
{
  const SphereKinematics l = kinematicsAt(curve, s, Side::kLeft);
  const SphereKinematics r = kinematicsAt(curve, s, Side::kRight);
  return { false, (l.velocity - r.velocity).norm() >
                      std::max(kCornerTolerance * (l.velocity.norm() + r.velocity.norm()), floor[kAngular]) };
}

/// Whether the velocity jumps across the breakpoint s: a velocity corner of the path.
template <class G>
bool velocityJumps(const Curve<G>& curve, double s)
{
  const std::array<bool, 2> jumps = velocityJumpsByChannel(curve, s);
  return jumps[kLinear] || jumps[kAngular];
}

/// A curve of any geometry seen as a path (its time axis is the path parameter).
template <class G>
class CurvePath final : public PathModel
{
public:
  explicit CurvePath(std::shared_ptr<const Curve<G>> curve)
    : curve_(std::move(curve)), spline_(closedFormKinematicsSpline(*curve_))
  {
  }
  double start() const override { return curve_->startTime(); }
  double end() const override { return curve_->endTime(); }
  std::vector<double> breakpoints() const override { return curve_->breakpoints(); }
  /// (A C² spline with closed-form kinematics gives its rates alone: the pose and the rotation of
  /// the angular parts into the world frame change no inner product.)
  PathJet jet(double s, Side side) const override
  {
    if constexpr (HasExpKinematics<G>::value)
      if (spline_)
      {
        const MotionRates r = spline_->rates(s, side);
        return pathJet(r.velocity, r.acceleration);
      }
    return pathJetAt(*curve_, s, side);
  }
  bool isCorner(double s) const override { return velocityJumps(*curve_, s); }

private:
  std::shared_ptr<const Curve<G>> curve_;
  const ChartCubicSpline<G>* spline_;  ///< curve_ as closedFormKinematicsSpline sees it (or null)
};

/// The timed motion t ↦ C(s(t)) as a curve: sampling, figures and TF use it like any other.
/// Its jets compose the path's jets with s(t) (eq. 1). Breakpoints: every grid time (s̈ jumps).
template <class G>
class TimeOptimalCurve final : public RetimedCurve<G>
{
public:
  /// @param path the path, its time axis the path parameter s
  /// @param profile the timing s(t) along it
  TimeOptimalCurve(std::shared_ptr<const Curve<G>> path, TimingProfile profile)
    : RetimedCurve<G>(std::move(path)), profile_(std::move(profile))
  {
  }

  double startTime() const override { return profile_.t.front(); }
  double endTime() const override { return profile_.t.back(); }
  std::vector<double> breakpoints() const override { return profile_.t; }

  const TimingProfile& profile() const { return profile_; }
  const Curve<G>& path() const { return this->base(); }

private:
  double baseTime(double t) const override { return profile_.pathParameter(t, Side::kRight); }
  /// The path is evaluated from the side of the timing interval that t falls in: a time that maps
  /// exactly onto a breakpoint of the path (a velocity corner, reached at the end of an interval)
  /// takes the path's one-sided jet of that interval, not of the next one.
  Jet<2> baseTime(const Jet<2>& t, Side side, Side* path_side) const override
  {
    const Jet<2> s = profile_.pathParameter(t, side);
    const std::size_t i = findInterval(profile_.t, t.value(), side);
    // (Within rounding of the interval's ends, s(t) computed from the interval's polynomial may
    // land on either side of the path's breakpoint there.)
    const auto near = [](double a, double b) {
      return std::abs(a - b) <= kBreakpointSnapRelative * std::max(1.0, std::abs(b));
    };
    if (s.value() >= profile_.s[i + 1] || near(s.value(), profile_.s[i + 1]))
      *path_side = Side::kLeft;
    else if (s.value() <= profile_.s[i] || near(s.value(), profile_.s[i]))
      *path_side = Side::kRight;
    return s;
  }

  TimingProfile profile_;
};

/// The time-optimal motion along `path` (a curve whose time axis is the path parameter).
template <class G>
std::shared_ptr<const TimeOptimalCurve<G>> makeTimeOptimalCurve(
    std::shared_ptr<const Curve<G>> path, const RateBounds& bounds,
    const TimeOptimalOptions& options = TimeOptimalOptions())
{
  TimingProfile profile = timeOptimalProfile(CurvePath<G>(path), bounds, options);
  return std::make_shared<TimeOptimalCurve<G>>(std::move(path), std::move(profile));
}

}  // namespace timing
}  // namespace se3_interpolation
