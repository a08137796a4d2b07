#include "se3_interpolation/execution/goal_trajectory.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/chart_hermite.h"
#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/timing/jerk_limited.h"
#include "se3_interpolation/timing/peak_search.h"

namespace se3_interpolation
{
InvalidGoalError::InvalidGoalError(GoalError code, const std::string& what) : InvalidInputError(what), code_(code)
{
}

GoalError InvalidGoalError::code() const
{
  return code_;
}

namespace
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

SixRates boundsOf(const MotionLimits& l)
{
  return { l.max_linear_velocity,     l.max_angular_velocity, l.max_linear_acceleration,
           l.max_angular_acceleration, l.max_linear_jerk,      l.max_angular_jerk };
}

std::string pointField(std::size_t i)
{
  return indexedField("trajectory.points", i);
}

/// A constant of this file for a message, in its shortest form ("1e-06").
std::string shortNumber(double x)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%g", x);
  return text;
}

[[noreturn]] void refuse(const std::string& message)
{
  throw InvalidGoalError(GoalError::kInvalidGoal, message);
}

/// How many derivatives the points give: 0 (poses only), 1 (velocities), 2 (and accelerations).
int orderOf(const GoalPoint& p)
{
  return p.velocity ? (p.acceleration ? 2 : 1) : 0;
}

/// The quaternion with a sign fixed by the rotation alone: the first non-zero of w, x, y, z positive.
Quaternion<double> canonicalSign(const Quaternion<double>& q)
{
  for (double c : { q.w(), q.x(), q.y(), q.z() })
    if (c != 0.0)
      return c > 0.0 ? q : Quaternion<double>(-q.coeffs());
  return q;
}

/// Every rule of the constructor's contract but the half turns; normalises the quaternions.
/// Throws InvalidInputError (the validation helpers') naming the field.
void validatePoints(std::vector<GoalPoint>* points)
{
  if (points->empty())
    throw InvalidInputError("trajectory.points: empty (a goal needs at least one point)");
  const int order = orderOf(points->front());
  for (std::size_t i = 0; i < points->size(); ++i)
  {
    GoalPoint& p = (*points)[i];
    const std::string field = pointField(i);
    requireFinite(p.time_from_start, field + ".time_from_start");
    if (p.time_from_start < 0.0)
      throw InvalidInputError(field + ".time_from_start: " + formatNumber(p.time_from_start) + " is negative");
    if (i > 0 && !(p.time_from_start > (*points)[i - 1].time_from_start))
      throw InvalidInputError(field + ".time_from_start: " + formatNumber(p.time_from_start) + " is not after " +
                              pointField(i - 1) + ".time_from_start = " +
                              formatNumber((*points)[i - 1].time_from_start) + " (times must be strictly increasing)");
    requireBounded(p.pose.p, field + ".transforms[0].translation");
    p.pose.q = validateQuaternion(p.pose.q, field + ".transforms[0].rotation");
    if (p.acceleration && !p.velocity)
      throw InvalidInputError(field + ".accelerations: given without velocities (give velocities with them, or "
                                      "neither)");
    if (orderOf(p) != order)
    {
      const bool velocities = p.velocity.has_value() != points->front().velocity.has_value();
      const std::string what = velocities ? "velocities" : "accelerations";
      const bool here = velocities ? p.velocity.has_value() : p.acceleration.has_value();
      throw InvalidInputError(field + "." + what + ": " + (here ? "given here but not at " : "missing here but given at ") +
                              pointField(0) + " (give " + what + " at every point or at none)");
    }
    if (p.velocity)
    {
      requireBounded(p.velocity->linear, field + ".velocities[0].linear");
      requireBounded(p.velocity->angular, field + ".velocities[0].angular");
    }
    if (p.acceleration)
    {
      requireBounded(p.acceleration->linear, field + ".accelerations[0].linear");
      requireBounded(p.acceleration->angular, field + ".accelerations[0].angular");
    }
  }
}

/// The second-order jet of the motion through a point (its velocity and acceleration, zero if absent).
Pose<Jet<2>> pointJet(const GoalPoint& p)
{
  return poseJet(p.pose, p.velocity.value_or(Twist()), p.acceleration.value_or(Twist()));
}

/// (G1): the chart polynomials between the points, or for one point its own Taylor polynomial.
template <class G>
class GoalCurve final : public CurveBase<G, GoalCurve<G>>
{
public:
  using Point = typename G::template Point<double>;

  /// @param points validated points, quaternions sign-continuous, no two consecutive half a turn apart
  GoalCurve(const std::vector<GoalPoint>& points, int order)
  {
    points_.reserve(points.size());
    times_.reserve(points.size());
    for (const GoalPoint& p : points)
    {
      points_.push_back(p.pose);
      times_.push_back(p.time_from_start);
    }
    if (points.size() == 1)
    {
      degree_ = order;
      // Its own Taylor polynomial: the point's pose, velocity and acceleration at its time.
      const auto jet = chartJet<G>(points_[0], pointJet(points[0]));
      ChartPolynomial<G> taylor;
      for (std::size_t k = 0; k < taylor.size(); ++k)
        taylor[k] = k < jet.size() ? jet[k] : jet[0] * 0.0;
      pieces_.push_back(taylor);
      return;
    }
    degree_ = 2 * order + 1;
    pieces_.reserve(points.size() - 1);
    for (std::size_t i = 0; i + 1 < points.size(); ++i)
    {
      const double h = times_[i + 1] - times_[i];
      const auto start = chartJet<G>(points_[i], pointJet(points[i]));
      const auto end = chartJet<G>(points_[i], pointJet(points[i + 1]));
      pieces_.push_back(chartHermite<G>(start, end, h, order));
      if (!finiteCoefficients<G>(pieces_.back()))
        refuse(pointField(i + 1) + ".time_from_start: " + formatNumber(h) + " s after " + pointField(i) +
               ", too short for the motion between them (the interpolating polynomial overflows)");
    }
  }

  template <class S>
  typename G::template Point<S> evaluate(const S& t, Side side) const
  {
    const std::size_t i = times_.size() < 2 ? 0 : findInterval(times_, valueOf(t), side);
    return chartPolynomialAt<G>(points_[i], pieces_[i], degree_, S(t - S(times_[i])));
  }

  double startTime() const override { return times_.front(); }
  double endTime() const override { return times_.back(); }
  std::vector<double> breakpoints() const override { return times_; }
  std::vector<Point> controlPoints() const override { return points_; }

private:
  std::vector<Point> points_;
  std::vector<double> times_;
  std::vector<ChartPolynomial<G>> pieces_;
  int degree_ = 0;
};

}  // namespace

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
  SixRates ratesAt(double t, Side side) const
  {
    const timing::Kinematics3 k = at3(t, side);
    return { k.velocity.linear.norm(),     k.velocity.angular.norm(), k.acceleration.linear.norm(),
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

namespace
{
template <class G>
class CurveInterpolant final : public GoalTrajectory::Interpolant
{
public:
  CurveInterpolant(const std::vector<GoalPoint>& points, std::vector<double> times, int order)
    : Interpolant(std::move(times), order), curve_(points, order)
  {
  }
  Kinematics at(double t, Side side) const override { return kinematicsAt(curve_, t, side); }
  timing::Kinematics3 at3(double t, Side side) const override
  {
    return timing::kinematics3FromJet(curve_.jet3(Jet<3>::variable(t), side));
  }

private:
  GoalCurve<G> curve_;
};

/// The largest of f on a subinterval [lo, hi] of segment `segment`, with f's values at its ends and
/// middle: refined by timing::detail::localMaxOf, which reports values only, so the argument of the
/// largest is kept by the function it calls.
template <class F>
RatePeak refinedPeak(F f, double lo, double hi, std::size_t segment, double f0, double fm, double f1)
{
  RatePeak best{ f0, lo, segment };
  for (const auto& [v, t] : { std::make_pair(fm, 0.5 * (lo + hi)), std::make_pair(f1, hi) })
    if (v > best.value)
      best = { v, t, segment };
  timing::detail::localMaxOf(
      [&](double lambda) {
        const double t = lo + lambda * (hi - lo);
        const double v = f(t);
        if (v > best.value)
          best = { v, t, segment };
        return v;
      },
      f0, fm, f1);
  return best;
}

/// The peaks of the six rates (file comment of the header). With `ceilings`, only as far as telling
/// whether a peak exceeds its ceiling: a rate whose ceiling is 0 is not refined, nor a subinterval
/// whose values already exceed it, and the margin of refinement is taken below the ceiling instead
/// of below the largest value so far (the result is then a lower bound of the peaks, exact where
/// they come within kPeakRefineMargin of their ceilings from below).
MotionPeaks peaksOf(const GoalTrajectory::Interpolant& m, const SixRates* ceilings = nullptr)
{
  MotionPeaks peaks{};
  const std::vector<double>& b = m.times();
  auto consider = [&peaks](const SixRates& r, double t, std::size_t segment) {
    for (std::size_t c = 0; c < r.size(); ++c)
      if (r[c] > peaks[c].value)
        peaks[c] = { r[c], t, segment };
  };
  if (b.size() == 1)
  {
    consider(m.ratesAt(b[0], Side::kRight), b[0], 0);
    return peaks;
  }
  struct Span
  {
    double lo, hi;
    std::size_t segment;
    SixRates f0, fm, f1;
  };
  std::vector<Span> spans;
  spans.reserve((b.size() - 1) * kPeakSubintervals);
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
  {
    const double step = (b[i + 1] - b[i]) / static_cast<double>(kPeakSubintervals);
    for (std::size_t s = 0; s < kPeakSubintervals; ++s)
    {
      const double lo = b[i] + static_cast<double>(s) * step;
      const double hi = s + 1 == kPeakSubintervals ? b[i + 1] : lo + step;
      const double mid = 0.5 * (lo + hi);
      Span span{ lo, hi, i, m.ratesAt(lo, Side::kRight), m.ratesAt(mid, Side::kRight), m.ratesAt(hi, Side::kLeft) };
      consider(span.f0, lo, i);
      consider(span.fm, mid, i);
      consider(span.f1, hi, i);
      spans.push_back(span);
    }
  }
  for (const Span& span : spans)
    for (std::size_t c = 0; c < peaks.size(); ++c)
    {
      const double largest = std::max({ span.f0[c], span.fm[c], span.f1[c] });
      if (ceilings && (!((*ceilings)[c] > 0.0) || largest > (*ceilings)[c]))
        continue;
      const double threshold = (ceilings ? (*ceilings)[c] : peaks[c].value) * (1.0 - kPeakRefineMargin);
      if (largest < threshold && !timing::detail::parabolaPeaksInside(span.f0[c], span.fm[c], span.f1[c], threshold))
        continue;
      const RatePeak p = refinedPeak([&m, c](double t) { return m.ratesAt(t, Side::kRight)[c]; }, span.lo, span.hi,
                                     span.segment, span.f0[c], span.fm[c], span.f1[c]);
      if (p.value > peaks[c].value)
        peaks[c] = p;
    }
  return peaks;
}

/// Refuses a velocity jump at an interior point where an acceleration (or jerk) is bounded, and an
/// acceleration jump where a jerk is: the bounded rate is an impulse there.
void requireNoJumps(const GoalTrajectory::Interpolant& m, const SixRates& bounds)
{
  if (m.order() >= 2)
    return;  // C² by construction
  const std::vector<double>& b = m.times();
  for (std::size_t i = 1; i + 1 < b.size(); ++i)
  {
    const Kinematics l = m.at(b[i], Side::kLeft);
    const Kinematics r = m.at(b[i], Side::kRight);
    const double h = std::min(b[i] - b[i - 1], b[i + 1] - b[i]);
    for (std::size_t c = 0; c < 2; ++c)
    {
      const Eigen::Vector3d& vl = c == 0 ? l.velocity.linear : l.velocity.angular;
      const Eigen::Vector3d& vr = c == 0 ? r.velocity.linear : r.velocity.angular;
      const Eigen::Vector3d& al = c == 0 ? l.acceleration.linear : l.acceleration.angular;
      const Eigen::Vector3d& ar = c == 0 ? r.acceleration.linear : r.acceleration.angular;
      const bool velocity_jumps = (vl - vr).norm() > timing::kCornerTolerance * (vl.norm() + vr.norm());
      const bool acceleration_jumps =
          (al - ar).norm() > timing::kAccelerationJumpTolerance * (al.norm() + ar.norm() + vl.norm() / h);
      for (std::size_t rate : { accelerationRate(c), jerkRate(c) })
      {
        const bool jumps = velocity_jumps || (rate == jerkRate(c) && acceleration_jumps);
        if (bounds[rate] <= 0.0 || !jumps)
          continue;
        const std::size_t cause = velocity_jumps ? velocityRate(c) : accelerationRate(c);
        const Eigen::Vector3d jump = velocity_jumps ? Eigen::Vector3d(vr - vl) : Eigen::Vector3d(ar - al);
        refuse(pointField(i) + ": the " + kRateNames[cause].name + " jumps there by " + formatNumber(jump.norm()) +
               " " + kRateNames[cause].unit + ", so the " + kRateNames[rate].name + " is unbounded (" +
               kRateNames[rate].bound + " = " + formatNumber(bounds[rate]) + " " + kRateNames[rate].unit +
               "); give every point velocities and accelerations (a C² trajectory)");
      }
    }
  }
}

}  // namespace

GoalTrajectory::GoalTrajectory(std::vector<GoalPoint> points, GeometryType geometry)
{
  try
  {
    validatePoints(&points);
  }
  catch (const InvalidInputError& e)
  {
    refuse(e.what());
  }
  // Sign-continuous quaternions from a sign fixed by the first rotation: q and −q give one motion.
  points.front().pose.q = canonicalSign(points.front().pose.q);
  std::vector<double> times{ points.front().time_from_start };
  for (std::size_t i = 1; i < points.size(); ++i)
  {
    Quaternion<double>& q = points[i].pose.q;
    const double dot = points[i - 1].pose.q.coeffs().dot(q.coeffs());
    if (std::abs(dot) <= kAntipodalTolerance)
      refuse(pointField(i - 1) + " and " + pointField(i) +
             ": the relative rotation is exactly pi, so the geodesic between them is not unique");
    if (dot < 0.0)
      q.coeffs() = -q.coeffs();
    times.push_back(points[i].time_from_start);
  }
  const int order = orderOf(points.front());
  if (geometry == GeometryType::kScrew)
    interpolant_ = std::make_shared<CurveInterpolant<ScrewSe3>>(points, std::move(times), order);
  else
    interpolant_ = std::make_shared<CurveInterpolant<DoubleGeodesicSe3>>(points, std::move(times), order);
}

double GoalTrajectory::startTime() const
{
  return interpolant_->times().front();
}

double GoalTrajectory::endTime() const
{
  return interpolant_->times().back();
}

std::size_t GoalTrajectory::size() const
{
  return interpolant_->times().size();
}

TrajectorySample GoalTrajectory::stateAt(double t) const
{
  return interpolant_->stateAt(t);
}

Motion GoalTrajectory::motion(const std::string& frame_id, const std::string& child_frame_id) const
{
  Motion m;
  m.state_at = [interpolant = interpolant_](double t) { return interpolant->stateAt(t); };
  m.start_time = startTime();
  m.duration = endTime() - startTime();
  m.frame_id = frame_id;
  m.child_frame_id = child_frame_id;
  return m;
}

MotionPeaks GoalTrajectory::peaks() const
{
  return peaksOf(*interpolant_);
}

namespace
{
/// The peaks checkLimits compares with the bounds: the velocities' and accelerations' of the
/// motion, the jerks as each segment's mean |Δp̈| / h and |Δω̇| / h between its points (file comment).
MotionPeaks checkedPeaks(const GoalTrajectory::Interpolant& m, const SixRates* ceilings)
{
  MotionPeaks peaks = peaksOf(m, ceilings);
  const std::vector<double>& b = m.times();
  peaks[4] = RatePeak();
  peaks[5] = RatePeak();
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
  {
    const Kinematics k0 = m.at(b[i], Side::kRight);
    const Kinematics k1 = m.at(b[i + 1], Side::kLeft);
    const double h = b[i + 1] - b[i];
    const double linear = (k1.acceleration.linear - k0.acceleration.linear).norm() / h;
    const double angular = (k1.acceleration.angular - k0.acceleration.angular).norm() / h;
    if (linear > peaks[4].value)
      peaks[4] = { linear, b[i], i };
    if (angular > peaks[5].value)
      peaks[5] = { angular, b[i], i };
  }
  return peaks;
}
}  // namespace

double GoalTrajectory::boundExcess(const MotionLimits& limits, double tolerance) const
{
  const SixRates bounds = boundsOf(limits);
  SixRates ceilings;
  for (std::size_t c = 0; c < bounds.size(); ++c)
    ceilings[c] = bounds[c] * (1.0 + tolerance);
  const MotionPeaks peaks = checkedPeaks(*interpolant_, &ceilings);
  double excess = -1.0;
  for (std::size_t c = 0; c < bounds.size(); ++c)
    if (bounds[c] > 0.0)
      excess = std::max(excess, peaks[c].value / bounds[c] - 1.0);
  return excess;
}

void GoalTrajectory::checkLimits(const MotionLimits& limits, double tolerance) const
{
  const SixRates bounds = boundsOf(limits);
  requireNoJumps(*interpolant_, bounds);
  const MotionPeaks peaks = checkedPeaks(*interpolant_, nullptr);
  std::size_t worst = bounds.size();
  double worst_ratio = 1.0 + tolerance;
  for (std::size_t c = 0; c < bounds.size(); ++c)
    if (bounds[c] > 0.0 && peaks[c].value > worst_ratio * bounds[c])
    {
      worst = c;
      worst_ratio = peaks[c].value / bounds[c];
    }
  if (worst == bounds.size())
    return;
  const RatePeak& p = peaks[worst];
  const RateName& r = kRateNames[worst];
  const bool mean = worst >= 4;
  refuse(pointField(p.segment) + ": between it and " + pointField(p.segment + 1) + " the " +
         (mean ? "mean " : "") + r.name + " reaches " + formatNumber(p.value) + " " + r.unit + " at time_from_start " +
         formatNumber(p.time) + " s, above " + r.bound + " = " + formatNumber(bounds[worst]) + " " + r.unit +
         (worst == 2 || worst == 3 ?
              " (where a trajectory's acceleration jumps between two points, as time_optimal's does without a jerk "
              "bound, its interpolation overshoots: generate it with max_linear_jerk and max_angular_jerk)" :
              ""));
}

void GoalTrajectory::requireEndsAtRest() const
{
  const Kinematics k = interpolant_->at(endTime(), Side::kLeft);
  const double linear = k.velocity.linear.norm();
  const double angular = k.velocity.angular.norm();
  if (linear <= kRestLinear && angular <= kRestAngular)
    return;
  refuse(pointField(size() - 1) + ": the motion ends moving (linear speed " + formatNumber(linear) +
         " m/s, angular speed " + formatNumber(angular) + " rad/s; at rest is below " + shortNumber(kRestLinear) +
         " m/s and " + shortNumber(kRestAngular) + " rad/s): give the last point zero velocities, or plan it to stop there (the ~generate service's "
         "end_condition: clamped, or timing: time_optimal)");
}

}  // namespace se3_interpolation
