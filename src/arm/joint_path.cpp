// arm/joint_path.h: inverse kinematics along a pose motion (method and equations in the header).
#include "se3_interpolation/arm/joint_path.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/SVD>

namespace se3_interpolation
{
namespace arm
{
namespace
{
using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// The header's pose tolerance (m and rad) and the rounding-floor acceptance beside it.
constexpr double kPoseTolerance = 1e-12;
constexpr double kPoseFloor = 1e-10;
/// Newton iterations a tracking step may take, and an evaluation at() or a final solve.
constexpr int kStepIterations = 6;
constexpr int kSolveIterations = 20;
/// σ_min(J_r) / σ_max(J_r) below this: a singular configuration.
constexpr double kSingularRatio = 1e-8;
/// Largest Newton correction of a step or an evaluation that stays on the branch (rad, m).
constexpr double kBranchJump = 1e-3;
/// A step halved below this fraction of the motion's span: a singular configuration.
constexpr double kMinStepFraction = 1e-9;
/// The damped first solve: per-joint step limit (rad, m), iteration limit, largest damping.
constexpr double kSeedStepLimit = 0.5;
constexpr int kSeedIterations = 500;
constexpr double kMaxDamping = 1e8;
/// Pose error (m, rad) at which the damped solve hands over to full Newton: well inside Newton's
/// quadratic convergence for arms of about 1 m (J_r's second derivatives are of order 1).
constexpr double kSeedHandoff = 1e-6;

/// e(q) of the header: [log(R* Rᵀ)∨; p* − p].
Vector6d poseError(const Pose<double>& target, const Eigen::Isometry3d& x)
{
  const Eigen::AngleAxisd r(target.q.toRotationMatrix() * x.linear().transpose());
  Vector6d e;
  e << r.angle() * r.axis(), target.p - x.translation();
  return e;
}

Matrix6d freeColumns(const ArmJacobian& j, const std::vector<int>& free)
{
  Matrix6d r;
  for (int c = 0; c < 6; ++c)
    r.col(c) = j.col(free[static_cast<std::size_t>(c)]);
  return r;
}

std::string vectorText(const Eigen::VectorXd& v)
{
  std::ostringstream s;
  s.precision(6);
  s << "(";
  for (Eigen::Index i = 0; i < v.size(); ++i)
    s << (i ? ", " : "") << v[i];
  s << ")";
  return s.str();
}

/// "at t = 1.5 s (position (0.9, 0, 0.3) m)".
std::string poseWhere(double t, const Pose<double>& pose)
{
  return "at t = " + formatNumber(t) + " s (position " + vectorText(pose.p) + " m)";
}

/// The first joint of `arm` whose position in q is past its limits, or −1.
int jointPastLimit(const ArmModel& arm, const Eigen::VectorXd& q)
{
  for (int i = 0; i < arm.dof(); ++i)
  {
    const JointLimits& l = arm.joints()[static_cast<std::size_t>(i)].limits;
    if (!(q[i] >= l.min_position && q[i] <= l.max_position))
      return i;
  }
  return -1;
}

JointPathError singularError(double t, const Eigen::VectorXd& q)
{
  return JointPathError("the arm passes a singular configuration at t = " + formatNumber(t) +
                            " s (q = " + vectorText(q) + ")",
                        t);
}

double smallestSingularValue(const Eigen::MatrixXd& m)
{
  return Eigen::JacobiSVD<Eigen::MatrixXd>(m).singularValues().tail(1)(0);
}
}  // namespace

double timeWithin(double t, double start, double end)
{
  // A time past an end by the rounding of a time computed from the ends (a sample's) is that end.
  const double rounding =
      4.0 * std::numeric_limits<double>::epsilon() * std::max({ 1.0, std::abs(start), std::abs(end) });
  if (t > end && t <= end + rounding)
    return end;
  if (t < start && t >= start - rounding)
    return start;
  if (!(t >= start && t <= end))
    throw JointPathError("joint motion: t = " + formatNumber(t) + " s is outside [" + formatNumber(start) + ", " +
                         formatNumber(end) + "] s");
  return t;
}

JointPath::JointPath(const ArmModel& arm, PoseMotion motion, std::vector<double> breakpoints,
                     const Eigen::VectorXd& seed, const JointPathOptions& options)
  : arm_(std::make_shared<const ArmModel>(arm)), motion_(std::move(motion)), breakpoints_(std::move(breakpoints))
{
  const std::string chain = "the chain '" + arm.baseLink() + "' → '" + arm.tipLink() + "'";
  if (arm.dof() < 6)
    throw JointPathError(chain + " has " + std::to_string(arm.dof()) +
                         " movable joints; following a pose motion takes at least 6");
  if (!motion_)
    throw JointPathError("joint path: no pose motion given");
  if (breakpoints_.size() < 2)
    throw JointPathError("joint path breakpoints: " + std::to_string(breakpoints_.size()) +
                         " given, the start and end times at least");
  for (std::size_t i = 0; i < breakpoints_.size(); ++i)
    if (!std::isfinite(breakpoints_[i]) || (i > 0 && !(breakpoints_[i] > breakpoints_[i - 1])))
      throw JointPathError(indexedField("joint path breakpoints", i) + ": " + formatNumber(breakpoints_[i]) +
                           " is not finite or not after the previous one");
  arm.checkJointVector(seed, "joint_seed");
  chooseHeldJoints(seed, options);

  const Kinematics k0 = motion_(start(), Side::kRight);
  const Eigen::VectorXd q0 = solveFromSeed(seed, k0.pose, start());
  ArmFrames f;
  arm_->frames(q0, &f);
  FreeJacobian free_jacobian;
  TrackedPoint point = trackedPoint(start(), q0, f, k0, &free_jacobian);
  checkPoint(point, free_jacobian);
  pieces_.resize(breakpoints_.size() - 1);
  for (std::size_t k = 0; k + 1 < breakpoints_.size(); ++k)
    trackPiece(k, point);
  for (const std::vector<TrackedPoint>& piece : pieces_)
    for (const TrackedPoint& p : piece)
      tracked_times_.push_back(p.t);
}

std::size_t JointPath::trackedPointsWithin(double t0, double t1) const
{
  const auto first = std::upper_bound(tracked_times_.begin(), tracked_times_.end(), t0);
  const auto last = std::lower_bound(first, tracked_times_.end(), t1);
  return static_cast<std::size_t>(last - first);
}

void JointPath::chooseHeldJoints(const Eigen::VectorXd& seed, const JointPathOptions& options)
{
  const int n = arm_->dof();
  if (!options.held_joints.empty())
  {
    std::vector<int> held = options.held_joints;
    std::sort(held.begin(), held.end());
    const bool distinct = std::adjacent_find(held.begin(), held.end()) == held.end();
    if (static_cast<int>(held.size()) != n - 6 || !distinct || held.front() < 0 || held.back() >= n)
      throw JointPathError("held_joints: " + std::to_string(held.size()) + " given; give n − 6 = " +
                           std::to_string(n - 6) + " distinct joint indices in [0, " + std::to_string(n) + ")");
    held_ = held;
  }
  else
  {
    const ArmJacobian j = arm_->jacobian(seed);
    std::vector<int> kept(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i)
      kept[static_cast<std::size_t>(i)] = i;
    while (static_cast<int>(kept.size()) > 6)
    {
      std::size_t best = 0;
      double best_sigma = -1.0;
      for (std::size_t drop = 0; drop < kept.size(); ++drop)
      {
        Eigen::MatrixXd m(6, static_cast<Eigen::Index>(kept.size() - 1));
        for (std::size_t c = 0, col = 0; c < kept.size(); ++c)
          if (c != drop)
            m.col(static_cast<Eigen::Index>(col++)) = j.col(kept[c]);
        const double sigma = smallestSingularValue(m);
        if (sigma > best_sigma)
          best_sigma = sigma, best = drop;
      }
      held_.push_back(kept[best]);
      kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(best));
    }
    std::sort(held_.begin(), held_.end());
  }
  for (int i = 0; i < n; ++i)
    if (!std::binary_search(held_.begin(), held_.end(), i))
      free_.push_back(i);
}

int JointPath::newton(const Pose<double>& target, Eigen::VectorXd& q, int max_iterations, ArmFrames* frames) const
{
  ArmFrames local;
  ArmFrames& f = frames ? *frames : local;
  double previous = std::numeric_limits<double>::infinity();
  for (int it = 0; it <= max_iterations; ++it)
  {
    arm_->frames(q, &f);
    const Vector6d e = poseError(target, f.base_T_tip);
    const double err = e.lpNorm<Eigen::Infinity>();
    if (err <= kPoseTolerance || (err <= kPoseFloor && err > 0.5 * previous))
      return it;
    if (it == max_iterations || !std::isfinite(err))
      return -1;
    previous = err;
    // LU with its reciprocal condition estimate (L1 norm, within a factor 6 of σ_min/σ_max for a
    // 6 × 6 matrix): a fifth of an SVD's work per step.
    const Eigen::PartialPivLU<Matrix6d> lu(freeColumns(arm_->jacobian(f), free_));
    if (!(lu.rcond() > kSingularRatio))
      return -1;
    const Vector6d dq = lu.solve(e);
    for (int c = 0; c < 6; ++c)
      q[free_[static_cast<std::size_t>(c)]] += dq[c];
  }
  return -1;
}

Eigen::VectorXd JointPath::solveFromSeed(const Eigen::VectorXd& seed, const Pose<double>& target, double t) const
{
  Eigen::VectorXd q = seed;
  double lambda = 1e-3;
  Vector6d e = poseError(target, arm_->base_T_tip(q));
  for (int it = 0; it < kSeedIterations && e.lpNorm<Eigen::Infinity>() > kSeedHandoff && lambda < kMaxDamping; ++it)
  {
    const Matrix6d jr = freeColumns(arm_->jacobian(q), free_);
    Vector6d dq = (jr.transpose() * jr + lambda * Matrix6d::Identity()).ldlt().solve(jr.transpose() * e);
    const double largest = dq.lpNorm<Eigen::Infinity>();
    if (largest > kSeedStepLimit)
      dq *= kSeedStepLimit / largest;
    Eigen::VectorXd trial = q;
    for (int c = 0; c < 6; ++c)
      trial[free_[static_cast<std::size_t>(c)]] += dq[c];
    const Vector6d e_trial = poseError(target, arm_->base_T_tip(trial));
    if (e_trial.norm() < e.norm())
      q = trial, e = e_trial, lambda = std::max(lambda / 10, 1e-12);
    else
      lambda *= 10;
  }
  if (e.lpNorm<Eigen::Infinity>() <= kSeedHandoff && newton(target, q, kSolveIterations) >= 0)
    return q;
  const Eigen::JacobiSVD<Matrix6d> svd(freeColumns(arm_->jacobian(q), free_));
  if (e.lpNorm<Eigen::Infinity>() <= kSeedHandoff &&
      !(svd.singularValues()[5] > kSingularRatio * svd.singularValues()[0]))
    throw JointPathError("the arm passes a singular configuration " + poseWhere(t, target) + " (q = " + vectorText(q) +
                             ")",
                         t);
  throw JointPathError("the pose " + poseWhere(t, target) + " is out of the arm's reach (pose error " +
                           formatNumber(e.lpNorm<Eigen::Infinity>()) + " m or rad left by the damped solve)",
                       t);
}

JointState JointPath::rates(const Eigen::VectorXd& q, const Kinematics& k) const
{
  ArmFrames f;
  arm_->frames(q, &f);
  return ratesAt(q, f, k, nullptr);
}

JointState JointPath::ratesAt(const Eigen::VectorXd& q, const ArmFrames& f, const Kinematics& k,
                              FreeJacobian* free_jacobian) const
{
  const int n = arm_->dof();
  JointState s;
  s.position = q;
  s.velocity = Eigen::VectorXd::Zero(n);
  s.acceleration = Eigen::VectorXd::Zero(n);
  const ArmJacobian j = arm_->jacobian(f);
  const Eigen::PartialPivLU<Matrix6d> lu(freeColumns(j, free_));
  Vector6d v, a;
  v << k.velocity.angular, k.velocity.linear;
  const Vector6d qd = lu.solve(v);
  for (int c = 0; c < 6; ++c)
    s.velocity[free_[static_cast<std::size_t>(c)]] = qd[c];
  const ArmJacobian jd = arm_->jacobianDerivative(f, j, s.velocity);
  a << k.acceleration.angular, k.acceleration.linear;
  const Vector6d qdd = lu.solve(a - jd * s.velocity);
  for (int c = 0; c < 6; ++c)
    s.acceleration[free_[static_cast<std::size_t>(c)]] = qdd[c];
  if (free_jacobian)
    *free_jacobian = FreeJacobian{ lu.determinant(), lu.rcond() };
  return s;
}

Eigen::VectorXd JointPath::jerk(const JointState& state, const TipVector& tip_jerk) const
{
  ArmFrames f;
  arm_->frames(state.position, &f);
  const Eigen::VectorXd none = Eigen::VectorXd::Zero(arm_->dof());
  const Vector6d bias = arm_->tipJerk(f, state.velocity, state.acceleration, none);
  const Vector6d free = Eigen::PartialPivLU<Matrix6d>(freeColumns(arm_->jacobian(f), free_)).solve(tip_jerk - bias);
  Eigen::VectorXd out = none;
  for (int c = 0; c < 6; ++c)
    out[free_[static_cast<std::size_t>(c)]] = free[c];
  return out;
}

TrackedPoint JointPath::trackedPoint(double t, const Eigen::VectorXd& q, const ArmFrames& f, const Kinematics& k,
                                     FreeJacobian* free_jacobian) const
{
  JointState s = ratesAt(q, f, k, free_jacobian);
  return TrackedPoint{ t, q, std::move(s.velocity), std::move(s.acceleration) };
}

void JointPath::checkPoint(const TrackedPoint& point, const FreeJacobian& free_jacobian) const
{
  if (!(free_jacobian.rcond > kSingularRatio))
    throw singularError(point.t, point.q);
  checkLimits(point.t, point.q);
}

void JointPath::checkLimits(double t, const Eigen::VectorXd& q) const
{
  if (jointPastLimit(*arm_, q) >= 0)
    throw limitError(t, q);
}

JointPathError JointPath::limitError(double t, const Eigen::VectorXd& q) const
{
  const int i = jointPastLimit(*arm_, q);
  const ArmJoint& joint = arm_->joints()[static_cast<std::size_t>(i)];
  const std::string unit = joint.isPrismatic() ? " m" : " rad";
  return JointPathError("joint '" + joint.name + "' would pass its position limit [" +
                            formatNumber(joint.limits.min_position) + ", " + formatNumber(joint.limits.max_position) +
                            "]" + unit + " at t = " + formatNumber(t) + " s (q = " + formatNumber(q[i]) + unit + ")",
                        t);
}

double JointPath::firstTimeWhere(const TrackedPoint& from, double t, Eigen::VectorXd& q,
                                 const std::function<bool(const Eigen::VectorXd&)>& past,
                                 Eigen::VectorXd* q_before) const
{
  // Bisection of the step (from.t, t], each midpoint solved by Newton from the step's predictor,
  // to 1e-9 of the motion's span. A midpoint where Newton fails (a singular configuration, where
  // J_r cannot be inverted) counts as past: the refusal is about where the path stops.
  double lo = from.t, hi = t;
  while (hi - lo > kMinStepFraction * (end() - start()))
  {
    const double mid = 0.5 * (lo + hi), dt = mid - from.t;
    Eigen::VectorXd qm = from.q + from.qd * dt + 0.5 * from.qdd * dt * dt;
    if (newton(motion_(mid, Side::kRight).pose, qm, kStepIterations) < 0)
      hi = mid;
    else if (past(qm))
      hi = mid, q = qm;
    else
    {
      lo = mid;
      if (q_before)
        *q_before = qm;
    }
  }
  return hi;
}

double JointPath::freeDeterminant(const Eigen::VectorXd& q) const
{
  return freeColumns(arm_->jacobian(q), free_).determinant();
}

void JointPath::trackPiece(std::size_t k, TrackedPoint& point)
{
  const double a = breakpoints_[k], b = breakpoints_[k + 1];
  const double min_step = kMinStepFraction * (end() - start());
  if (k > 0)
  {
    const Kinematics kin = motion_(a, Side::kRight);
    Eigen::VectorXd q = point.q;
    ArmFrames f;
    if (newton(kin.pose, q, kStepIterations, &f) < 0 || (q - point.q).lpNorm<Eigen::Infinity>() > kBranchJump)
      throw JointPathError("the pose motion jumps at its breakpoint " + poseWhere(a, kin.pose), a);
    FreeJacobian free_jacobian;
    point = trackedPoint(a, q, f, kin, &free_jacobian);
    checkPoint(point, free_jacobian);
  }
  double sign = freeDeterminant(point.q);
  std::vector<TrackedPoint>& piece = pieces_[k];
  piece.push_back(point);
  const double max_step = (b - a) / 4;
  double h = max_step;
  while (point.t < b)
  {
    const bool last = point.t + h >= b - min_step;
    const double t = last ? b : point.t + h;
    const double dt = t - point.t;
    const Kinematics kin = motion_(t, last ? Side::kLeft : Side::kRight);
    const Eigen::VectorXd predicted = point.q + point.qd * dt + 0.5 * point.qdd * dt * dt;
    Eigen::VectorXd q = predicted;
    ArmFrames f;
    const int iterations = newton(kin.pose, q, kStepIterations, &f);
    const double allowed = std::min(kBranchJump, 0.1 * ((point.qd * dt).lpNorm<Eigen::Infinity>() +
                                                        (point.qdd * dt * dt).lpNorm<Eigen::Infinity>()) +
                                                     1e-9);
    if (iterations < 0 || (q - predicted).lpNorm<Eigen::Infinity>() > allowed)
    {
      h = dt / 2;
      if (h < min_step)
      {
        // Out of reach or singular: a pose just beyond the stall that the damped solve cannot
        // reach is out of reach (solveFromSeed throws naming it); otherwise the branch ends in a
        // singular configuration.
        for (double probe = min_step; probe <= 1e-3 * (end() - start()); probe *= 10)
          solveFromSeed(point.q, motion_(std::min(point.t + probe, b), Side::kLeft).pose, std::min(point.t + probe, b));
        throw JointPathError("the arm passes a singular configuration at t = " + formatNumber(point.t) +
                                 " s (q = " + vectorText(point.q) + "; the IK branch cannot be followed beyond)",
                             point.t);
      }
      continue;
    }
    if (jointPastLimit(*arm_, q) >= 0)
    {
      const double crossing =
          firstTimeWhere(point, t, q, [this](const auto& x) { return jointPastLimit(*arm_, x) >= 0; });
      throw limitError(crossing, q);
    }
    FreeJacobian free_jacobian;
    TrackedPoint next = trackedPoint(t, q, f, kin, &free_jacobian);
    // det J_r changes sign only through a singular configuration, which a step may step over.
    if (free_jacobian.determinant * sign <= 0)
    {
      Eigen::VectorXd before = point.q;
      const double crossing = firstTimeWhere(
          point, t, q, [&](const auto& x) { return freeDeterminant(x) * sign <= 0; }, &before);
      throw singularError(crossing, before);
    }
    checkPoint(next, free_jacobian);
    sign = free_jacobian.determinant;
    point = std::move(next);
    piece.push_back(point);
    h = std::min(iterations <= 2 ? 2 * dt : dt, max_step);
  }
}

JointState JointPath::at(double t, Side side) const
{
  t = timeWithin(t, start(), end());
  const std::size_t k = findInterval(breakpoints_, t, side);
  const std::vector<TrackedPoint>& piece = pieces_[k];
  auto upper =
      std::upper_bound(piece.begin(), piece.end(), t, [](double time, const TrackedPoint& p) { return time < p.t; });
  const std::size_t i1 = std::min<std::size_t>(static_cast<std::size_t>(upper - piece.begin()), piece.size() - 1);
  const TrackedPoint& p0 = piece[i1 - 1];
  const TrackedPoint& p1 = piece[i1];
  const double h = p1.t - p0.t, s = (t - p0.t) / h;
  const double s2 = s * s, s3 = s2 * s;
  const Eigen::VectorXd predicted =
      (2 * s3 - 3 * s2 + 1) * p0.q + (s3 - 2 * s2 + s) * h * p0.qd + (-2 * s3 + 3 * s2) * p1.q + (s3 - s2) * h * p1.qd;
  // At the motion's first and last time on the side asked for (the first sample, from the left, is
  // the state the motion starts from, as the pose sample's); at a breakpoint inside, on its piece's.
  const bool motion_end = t == start() || t == end();
  const Side motion_side = motion_end           ? side :
                           t == breakpoints_[k] ? Side::kRight :
                                                  (t == breakpoints_[k + 1] ? Side::kLeft : side);
  const Kinematics kin = motion_(t, motion_side);
  Eigen::VectorXd q = predicted;
  for (int i : held_)
    q[i] = p0.q[i];
  ArmFrames f;
  if (newton(kin.pose, q, kSolveIterations, &f) < 0 || (q - predicted).lpNorm<Eigen::Infinity>() > kBranchJump)
    throw JointPathError("joint path: the evaluation " + poseWhere(t, kin.pose) + " would leave the tracked branch", t);
  checkLimits(t, q);
  return ratesAt(q, f, kin, nullptr);
}

}  // namespace arm
}  // namespace se3_interpolation
