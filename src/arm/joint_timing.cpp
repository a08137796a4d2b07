// The joint limits as the time-optimal timing's box constraint, and the dense check of a timed
// motion's joint rates (arm/joint_timing.h).
#include "se3_interpolation/arm/joint_timing.h"

#include <algorithm>
#include <cmath>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/timing/peak_search.h"

namespace se3_interpolation
{
namespace arm
{
static_assert(kMaxArmJoints <= static_cast<int>(timing::kMaxBoxComponents),
              "every joint of an arm must fit the time-optimal timing's box constraint");

namespace
{
/// A motion of at most this many analytic pieces is checked on kJointCheckIntervals intervals per
/// piece; one of more pieces (a time-optimal motion's pieces are its refined grid's intervals) on
/// one per piece; and every motion on at least kJointCheckMinIntervals in all.
constexpr std::size_t kJointCheckDensePieces = 2048;
constexpr std::size_t kJointCheckMinIntervals = 512;
/// Intervals whose parabola through ends and middle peaks inside within this fraction of the
/// joint's peak so far are searched (a parabola underestimates a sharp peak by more than 1e-3).
constexpr double kJointSearchMargin = 1e-2;
/// Intervals of the check per tracked point of the joint path inside one of its intervals.
constexpr std::size_t kJointCheckPartsPerTrackedPoint = 4;
/// Evaluations between two checks of the request's deadline.
constexpr std::size_t kEvaluationsPerDeadlineCheck = 256;

double limitOrNone(double limit)
{
  return std::isfinite(limit) ? limit : 0.0;
}

/// The running peaks of checkJointRates.
class PeakTracker
{
public:
  PeakTracker(const JointMotion& motion, JointRatesCheck* check) : motion_(motion), check_(*check) {}

  /// One state at time t (the motion's start from the left: the state it starts from).
  void point(double t, const JointState& q)
  {
    for (std::size_t k = 0; k < check_.peaks.size(); ++k)
    {
      JointPeak& p = check_.peaks[k];
      const Eigen::Index i = static_cast<Eigen::Index>(k);
      record(&p.velocity, &p.velocity_time, { std::abs(q.velocity[i]), 0.0, 0.0 }, t, 0.0);
      record(&p.acceleration, &p.acceleration_time, { std::abs(q.acceleration[i]), 0.0, 0.0 }, t, 0.0);
      if (q.jerk.size() > 0)
        record(&p.jerk, &p.jerk_time, { std::abs(q.jerk[i]), 0.0, 0.0 }, t, 0.0);
    }
  }

  /// Interval [t0, t1] with its ends' states (a, b): the middle, and the searched peaks.
  void interval(double t0, double t1, const JointState& a, const JointState& b)
  {
    const double h = t1 - t0;
    checkDeadlineEvery(count_++, kEvaluationsPerDeadlineCheck / 3, "joint limits");
    const JointState m = motion_.at(t0 + 0.5 * h, Side::kRight);
    const int n = static_cast<int>(check_.peaks.size());
    for (int k = 0; k < n; ++k)
    {
      JointPeak& p = check_.peaks[static_cast<std::size_t>(k)];
      const double va = std::abs(a.velocity[k]), vm = std::abs(m.velocity[k]), vb = std::abs(b.velocity[k]);
      const double aa = std::abs(a.acceleration[k]), am = std::abs(m.acceleration[k]), ab = std::abs(b.acceleration[k]);
      record(&p.velocity, &p.velocity_time, { va, vm, vb }, t0, h);
      record(&p.acceleration, &p.acceleration_time, { aa, am, ab }, t0, h);
      if (timing::detail::parabolaPeaksInside(va, vm, vb, p.velocity * (1.0 - kJointSearchMargin)))
        raise(&p.velocity, &p.velocity_time, t0, h,
              timing::detail::localMaxOf(
                  [&](double l) { return std::abs(motion_.at(t0 + l * h, Side::kRight).velocity[k]); }, va, vm, vb));
      if (timing::detail::parabolaPeaksInside(aa, am, ab, p.acceleration * (1.0 - kJointSearchMargin)))
        raise(&p.acceleration, &p.acceleration_time, t0, h,
              timing::detail::localMaxOf(
                  [&](double l) { return std::abs(motion_.at(t0 + l * h, Side::kRight).acceleration[k]); }, aa, am,
                  ab));
      if (m.jerk.size() > 0)
        jerk(k, t0, h, { std::abs(a.jerk[k]), std::abs(m.jerk[k]), std::abs(b.jerk[k]) });
    }
  }

private:
  /// Joint k's jerk at the ends and middle j of the interval [t0, t0 + h], and its searched peak.
  void jerk(int k, double t0, double h, const std::array<double, 3>& j)
  {
    JointPeak& p = check_.peaks[static_cast<std::size_t>(k)];
    record(&p.jerk, &p.jerk_time, j, t0, h);
    if (timing::detail::parabolaPeaksInside(j[0], j[1], j[2], p.jerk * (1.0 - kJointSearchMargin)))
      raise(&p.jerk, &p.jerk_time, t0, h,
            timing::detail::localMaxOf([&](double l) { return std::abs(motion_.at(t0 + l * h, Side::kRight).jerk[k]); },
                                       j[0], j[1], j[2]));
  }

  static void record(double* peak, double* when, const std::array<double, 3>& v, double t0, double h)
  {
    for (int j = 0; j < 3; ++j)
      if (v[static_cast<std::size_t>(j)] > *peak)
      {
        *peak = v[static_cast<std::size_t>(j)];
        *when = t0 + 0.5 * j * h;
      }
  }
  /// A searched peak: its time is the interval's middle (within half the interval).
  static void raise(double* peak, double* when, double t0, double h, double value)
  {
    if (value > *peak)
    {
      *peak = value;
      *when = t0 + 0.5 * h;
    }
  }

  const JointMotion& motion_;
  JointRatesCheck& check_;
  std::size_t count_ = 0;
};

/// Whether the joint accelerations step from `before` to `after` (kAccelerationStepTolerance).
bool stepsBetween(const Eigen::VectorXd& before, const Eigen::VectorXd& after)
{
  for (Eigen::Index k = 0; k < before.size(); ++k)
    if (std::abs(after[k] - before[k]) >
        kAccelerationStepTolerance * (std::abs(after[k]) + std::abs(before[k])) + kAccelerationStepFloor)
      return true;
  return false;
}

/// The breakpoints within [start, end], sorted and distinct, the ends included.
std::vector<double> pieces(const std::vector<double>& breakpoints, double start, double end)
{
  std::vector<double> b{ start, end };
  for (double t : breakpoints)
    if (t > start && t < end)
      b.push_back(t);
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  return b;
}

/// The limit ratios of c's peaks: the binding joint and the stretch.
void rate(const ArmModel& arm, JointRatesCheck* c)
{
  c->stretch = 1.0;
  c->binding_joint = -1;
  c->binding_quantity.clear();
  c->binding_ratio = 0.0;
  c->binding_time = 0.0;
  for (std::size_t k = 0; k < c->peaks.size(); ++k)
  {
    const JointLimits& l = arm.joints()[k].limits;
    const JointPeak& p = c->peaks[k];
    const double v = l.hasVelocityLimit() ? p.velocity / l.max_velocity : 0.0;
    const double a = l.hasAccelerationLimit() ? p.acceleration / l.max_acceleration : 0.0;
    const double j = c->has_jerk && l.hasJerkLimit() ? p.jerk / l.max_jerk : 0.0;
    c->stretch = std::max({ c->stretch, v, std::sqrt(a), std::cbrt(j) });
    if (std::max({ v, a, j }) > c->binding_ratio || c->binding_joint < 0)
    {
      c->binding_joint = static_cast<int>(k);
      c->binding_ratio = std::max({ v, a, j });
      c->binding_quantity = v >= std::max(a, j) ? "velocity" : a >= j ? "acceleration" : "jerk";
      c->binding_time = v >= std::max(a, j) ? p.velocity_time : a >= j ? p.acceleration_time : p.jerk_time;
    }
  }
}
}  // namespace

JointBoxes::JointBoxes(JointPath path) : path_(std::make_shared<const JointPath>(std::move(path))) {}

std::size_t JointBoxes::size() const
{
  return static_cast<std::size_t>(path_->arm().dof());
}

double JointBoxes::velocityLimit(std::size_t k) const
{
  return limitOrNone(path_->arm().joints()[k].limits.max_velocity);
}

double JointBoxes::accelerationLimit(std::size_t k) const
{
  return limitOrNone(path_->arm().joints()[k].limits.max_acceleration);
}

void JointBoxes::jet(double s, Side side, double* w, double* a) const
{
  const JointState q = path_->at(s, side);
  for (Eigen::Index k = 0; k < q.velocity.size(); ++k)
  {
    w[k] = q.velocity[k];
    a[k] = q.acceleration[k];
  }
}

RetimedJointPath::RetimedJointPath(std::shared_ptr<const JointPath> path, Clock clock, double start, double end,
                                   TipJerk tip_jerk)
  : path_(std::move(path)), clock_(std::move(clock)), start_(start), end_(end), tip_jerk_(std::move(tip_jerk))
{
}

JointState RetimedJointPath::at(double t, Side side) const
{
  Side path_side = side;
  t = timeWithin(t, start_, end_);
  const Jet<2> s = clock_(t, side, &path_side);
  // (The clock maps the ends onto the path's ends up to rounding.)
  JointState q = path_->at(std::clamp(s.value(), path_->start(), path_->end()), path_side);
  const double sd = s.derivative(1), sdd = s.derivative(2);
  q.acceleration = q.acceleration * (sd * sd) + q.velocity * sdd;
  q.velocity *= sd;
  if (tip_jerk_)
    q.jerk = path_->jerk(q, tip_jerk_(t, side));
  return q;
}

std::size_t RetimedJointPath::trackedPointsWithin(double t0, double t1) const
{
  Side side = Side::kRight;
  const double s0 = clock_(timeWithin(t0, start_, end_), Side::kRight, &side).value();
  const double s1 = clock_(timeWithin(t1, start_, end_), Side::kLeft, &side).value();
  return path_->trackedPointsWithin(s0, s1);
}

JointRatesCheck checkJointRates(const JointMotion& motion, const std::vector<double>& breakpoints)
{
  JointRatesCheck check;
  check.peaks.assign(static_cast<std::size_t>(motion.arm().dof()), JointPeak());
  check.has_jerk = motion.hasJerk();
  const std::vector<double> b = pieces(breakpoints, motion.start(), motion.end());
  const std::size_t count = b.size() - 1;
  const double span = b.back() - b.front();
  PeakTracker tracker(motion, &check);
  JointState left = motion.at(b.front(), Side::kLeft);
  tracker.point(b.front(), left);
  for (std::size_t j = 0; j < count; ++j)
  {
    const double length = b[j + 1] - b[j];
    const std::size_t share =
        static_cast<std::size_t>(std::ceil(static_cast<double>(kJointCheckMinIntervals) * length / span));
    const std::size_t m = std::max<std::size_t>(share, count <= kJointCheckDensePieces ? kJointCheckIntervals : 1);
    JointState a = motion.at(b[j], Side::kRight);
    if (std::isnan(check.acceleration_step_time) && stepsBetween(left.acceleration, a.acceleration))
      check.acceleration_step_time = b[j];
    for (std::size_t i = 0; i < m; ++i)
    {
      const double t0 = b[j] + length * static_cast<double>(i) / static_cast<double>(m);
      const bool last = i + 1 == m;
      const double t1 = last ? b[j + 1] : b[j] + length * static_cast<double>(i + 1) / static_cast<double>(m);
      const std::size_t parts =
          std::max<std::size_t>(1, kJointCheckPartsPerTrackedPoint * motion.trackedPointsWithin(t0, t1));
      for (std::size_t p = 0; p < parts; ++p)
      {
        const bool end = last && p + 1 == parts;
        const double u0 = t0 + (t1 - t0) * static_cast<double>(p) / static_cast<double>(parts);
        const double u1 =
            p + 1 == parts ? t1 : t0 + (t1 - t0) * static_cast<double>(p + 1) / static_cast<double>(parts);
        JointState e = motion.at(u1, end ? Side::kLeft : Side::kRight);
        tracker.interval(u0, u1, a, e);
        a = std::move(e);
      }
    }
    left = std::move(a);
  }
  check.has_jerk = check.has_jerk && std::isnan(check.acceleration_step_time);
  rate(motion.arm(), &check);
  return check;
}

bool hasJerkLimits(const ArmModel& arm)
{
  for (const ArmJoint& j : arm.joints())
    if (j.limits.hasJerkLimit())
      return true;
  return false;
}

double jointJerkWindow(const ArmModel& arm)
{
  double window = 0.0;
  for (const ArmJoint& j : arm.joints())
  {
    const JointLimits& l = j.limits;
    if (!l.hasJerkLimit())
      continue;
    if (l.hasAccelerationLimit())
      window = std::max(window, 2.0 * l.max_acceleration / l.max_jerk);
    else if (l.hasVelocityLimit())
      window = std::max(window, 2.0 * std::sqrt(l.max_velocity * l.max_jerk) / l.max_jerk);
  }
  return window;
}

JointRatesCheck jointRatesOf(const ArmModel& arm, const std::vector<timing::BoxPeak>& peaks)
{
  JointRatesCheck check;
  for (const timing::BoxPeak& p : peaks)
    check.peaks.push_back(JointPeak{ p });
  rate(arm, &check);
  return check;
}

JointRatesCheck stretchJointRates(const ArmModel& arm, const JointRatesCheck& check, double k, double t0)
{
  JointRatesCheck out;
  out.peaks = check.peaks;
  out.has_jerk = check.has_jerk;
  out.acceleration_step_time = t0 + (check.acceleration_step_time - t0) * k;
  for (JointPeak& p : out.peaks)
  {
    p.velocity /= k;
    p.acceleration /= k * k;
    p.jerk /= k * k * k;
    p.velocity_time = t0 + (p.velocity_time - t0) * k;
    p.acceleration_time = t0 + (p.acceleration_time - t0) * k;
    p.jerk_time = t0 + (p.jerk_time - t0) * k;
  }
  rate(arm, &out);
  return out;
}

std::string jointExcessMessage(const ArmModel& arm, const JointRatesCheck& check)
{
  const std::size_t k = static_cast<std::size_t>(std::max(check.binding_joint, 0));
  const ArmJoint& joint = arm.joints()[k];
  const int order = check.binding_quantity == "velocity" ? 1 : check.binding_quantity == "acceleration" ? 2 : 3;
  const std::string unit = std::string(joint.isPrismatic() ? "m/s" : "rad/s") + (order == 2 ? "²" :
                                                                                 order == 3 ? "³" :
                                                                                              "");
  const JointPeak& p = check.peaks[k];
  const double value = order == 1 ? p.velocity : order == 2 ? p.acceleration : p.jerk;
  const JointLimits& l = joint.limits;
  const double limit = order == 1 ? l.max_velocity : order == 2 ? l.max_acceleration : l.max_jerk;
  return "joint " + quotedText(joint.name) + ": " + check.binding_quantity + " " + formatNumber(value) + " " + unit +
         " at t = " + formatNumber(check.binding_time) + " s, above its limit " + formatNumber(limit) + " " + unit;
}

}  // namespace arm
}  // namespace se3_interpolation
