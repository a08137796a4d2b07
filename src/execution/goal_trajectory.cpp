// The goal trajectory (goal_trajectory.h): its points' rules, the chart polynomials (G1) between
// them and the motion they make; its peaks and checks are goal_limits.cpp's.
#include "se3_interpolation/execution/goal_trajectory.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "goal_trajectory_internal.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/chart_hermite.h"
#include "se3_interpolation/curves/curve.h"
#include "se3_interpolation/geometry/value_checks.h"
#include "se3_interpolation/timing/jerk_limited.h"

namespace se3_interpolation
{
using namespace goal_detail;

InvalidGoalError::InvalidGoalError(GoalError code, const std::string& what) : InvalidInputError(what), code_(code) {}

GoalError InvalidGoalError::code() const
{
  return code_;
}

namespace
{
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
      throw InvalidInputError(field +
                              ".accelerations: given without velocities (give velocities with them, or "
                              "neither)");
    if (orderOf(p) != order)
    {
      const bool velocities = p.velocity.has_value() != points->front().velocity.has_value();
      const std::string what = velocities ? "velocities" : "accelerations";
      const bool here = velocities ? p.velocity.has_value() : p.acceleration.has_value();
      throw InvalidInputError(field + "." + what + ": " +
                              (here ? "given here but not at " : "missing here but given at ") + pointField(0) +
                              " (give " + what + " at every point or at none)");
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

}  // namespace se3_interpolation
