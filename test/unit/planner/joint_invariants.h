// The joint invariants of a request served with an arm (docs/joint_space.md), checked with the arm
// model's kinematics (arm/arm_model.h) and none of the planner's joint code:
//  - the result names the chain's joints, and every sample carries n finite joint positions,
//    velocities and accelerations;
//  - forward kinematics of every sample's q is its pose (kJointPoseTolerance: 1e-9 m, 1e-9 rad; the
//    planner's inverse kinematics solves to 1e-12, or 1e-10 where the FK's rounding is above that);
//  - J(q) q̇ is the sample's twist and J(q) q̈ + J̇(q, q̇) q̇ its acceleration (rows [ω; ṗ],
//    arm_model.h), to kJacobianTolerance of |V| + ‖J‖ |q̇| (the rounding of a solve J q̇ = V) and
//    kJacobianFloor;
//  - n − 6 joints are held (redundancy: at their first sample's value, at rest), none of a 6-joint arm;
//  - every joint is within its position limits and |q̇| ≤ max_velocity, |q̈| ≤ max_acceleration
//    (kJointRateTolerance relative) at the samples and between them: the joint state is carried
//    from each sample to the next through dense times by Newton's method on the motion's poses
//    (result.state_at), its rates q̇ = J_r⁻¹ V, q̈ = J_r⁻¹ (A − J̇ q̇) on the joints that move, and
//    must arrive at the next sample's q (no branch change between samples);
//  - the joint steps: |q_{i+1} − q_i| ≤ max_velocity (t_{i+1} − t_i) (1 + kJointRateTolerance);
//  - a joint with a jerk limit: the mean jerk (q̈(t_b) − q̈(t_a)) / (t_b − t_a) between neighbouring
//    dense states (a lower bound of the peak |q⃛| between them, so an acceleration step is caught)
//    is within max_jerk, less the rounding of the two q̈ (kJacobianTolerance of their size);
//  - the joint figures are the largest rates found (not below them) and within the limits, the
//    jerk's where the result reports it (JointRatesCheck::has_jerk).
// The Cartesian invariants are request_space.h's checkInvariants, on the same result.
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "invariant_basics.h"
#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace test
{
/// FK of a sample's joints against its pose: m and rad.
constexpr double kJointPoseTolerance = 1e-9;
/// A joint rate against its limit, relative: the planner's own checks' (planner/joint_space.cpp).
constexpr double kJointRateTolerance = 1e-6;
/// A joint figure below the largest rate found (relative): the figures are the checks' peaks at
/// their points and searched maxima, which docs/joint_space.md says may lie below the true peak
/// by up to 1e-4 (the grid's worst: 9e-5, from a moving start).
constexpr double kJointFigureTolerance = 1e-4;
/// J q̇ against the twist, relative to |V| + ‖J‖ |q̇|, plus kJacobianFloor (m/s, rad/s: the rounding
/// of a rate at rest); the same for J q̈ + J̇ q̇ against the acceleration.
constexpr double kJacobianTolerance = 1e-9;
constexpr double kJacobianFloor = 1e-12;
/// The joints carried to the next sample against its q (rad or m).
constexpr double kJointContinuityTolerance = 1e-8;

/// The largest value of one check seen so far, and where.
struct WorstOf
{
  double value = 0.0;
  std::string detail;
  template <class Describe>
  void see(double x, Describe describe)
  {
    if (x > value)
    {
      value = x;
      detail = describe();
    }
  }
};

/// A pose state's joints: positions, velocities, accelerations (n entries, the held ones at rest).
struct JointJet
{
  double t = 0.0;
  Eigen::VectorXd q, qd, qdd;
};

/// The joints the result holds (redundancy): at their first sample's value, at rest in every sample.
inline std::vector<int> heldJoints(const TrajectoryResult& result, int n)
{
  std::vector<int> held;
  for (int k = 0; k < n; ++k)
  {
    bool still = true;
    for (const TrajectorySample& s : result.samples)
      still = still && s.joint_position[k] == result.samples.front().joint_position[k] && s.joint_velocity[k] == 0.0 &&
              s.joint_acceleration[k] == 0.0;
    if (still)
      held.push_back(k);
  }
  return held;
}

/// J's columns of the joints in `moving` (6 of them).
inline Eigen::Matrix<double, 6, 6> columnsOf(const arm::ArmJacobian& j, const std::vector<int>& moving)
{
  Eigen::Matrix<double, 6, 6> r;
  for (int c = 0; c < 6; ++c)
    r.col(c) = j.col(moving[static_cast<std::size_t>(c)]);
  return r;
}

/// The pose error [log(R* Rᵀ)∨; p* − p] of the tip at `x` against the target pose (rad, m).
inline Eigen::Matrix<double, 6, 1> tipError(const Pose<double>& target, const Eigen::Isometry3d& x)
{
  const Eigen::AngleAxisd r(target.q.normalized().toRotationMatrix() * x.linear().transpose());
  Eigen::Matrix<double, 6, 1> e;
  e << r.angle() * r.axis(), target.p - x.translation();
  return e;
}

/// Newton's method for the joints in `moving` at the pose of `s` from `q`; the rates from the
/// twist and acceleration of `s`. False if it does not reach 1e-12 (or 1e-10 where it stalls).
inline bool solveJointJet(const arm::ArmModel& model, const std::vector<int>& moving, const TrajectorySample& s,
                          JointJet* jet)
{
  const int n = model.dof();
  double previous = 1e300;
  bool converged = false;
  for (int iteration = 0; iteration < 30 && !converged; ++iteration)
  {
    Eigen::Isometry3d x;
    arm::ArmJacobian j;
    model.kinematics(jet->q, jet->q, &x, &j, nullptr);
    const Eigen::Matrix<double, 6, 1> e = tipError(s.pose, x);
    const double size = e.lpNorm<Eigen::Infinity>();
    if (size <= 1e-12 || (size <= 1e-10 && size > 0.5 * previous))
    {
      converged = true;
      break;
    }
    previous = size;
    const Eigen::Matrix<double, 6, 1> step = columnsOf(j, moving).fullPivLu().solve(e);
    if (!step.allFinite())
      return false;
    for (int c = 0; c < 6; ++c)
      jet->q[moving[static_cast<std::size_t>(c)]] += step[c];
  }
  if (!converged)
    return false;
  arm::ArmJacobian j;
  model.kinematics(jet->q, jet->q, nullptr, &j, nullptr);
  const Eigen::FullPivLU<Eigen::Matrix<double, 6, 6>> lu(columnsOf(j, moving));
  Eigen::Matrix<double, 6, 1> v, a;
  v << s.velocity.angular, s.velocity.linear;
  a << s.acceleration.angular, s.acceleration.linear;
  const Eigen::Matrix<double, 6, 1> qd = lu.solve(v);
  jet->qd = Eigen::VectorXd::Zero(n);
  for (int c = 0; c < 6; ++c)
    jet->qd[moving[static_cast<std::size_t>(c)]] = qd[c];
  const Eigen::Matrix<double, 6, 1> qdd = lu.solve(a - model.jacobianDerivative(jet->q, jet->qd) * jet->qd);
  jet->qdd = Eigen::VectorXd::Zero(n);
  for (int c = 0; c < 6; ++c)
    jet->qdd[moving[static_cast<std::size_t>(c)]] = qdd[c];
  jet->t = s.time;
  return jet->qd.allFinite() && jet->qdd.allFinite();
}

/// Carries the joints `from` (a solved state) to time t along the motion: predicted by
/// q + q̇ h + ½ q̈ h², solved by Newton, and accepted where the correction is small beside the
/// step (else the step is halved, at most 24 times: a branch change is never taken). False if the
/// motion cannot be followed there.
inline bool carryJoints(const arm::ArmModel& model, const std::vector<int>& moving, const TrajectoryResult& result,
                        const JointJet& from, double t, JointJet* to, int depth = 0)
{
  const double h = t - from.t;
  JointJet next;
  next.q = from.q + from.qd * h + 0.5 * from.qdd * h * h;
  const Eigen::VectorXd predicted = next.q;
  const double step = (from.qd * h).lpNorm<Eigen::Infinity>() + (from.qdd * h * h).lpNorm<Eigen::Infinity>();
  if (solveJointJet(model, moving, result.state_at(t), &next) &&
      (next.q - predicted).lpNorm<Eigen::Infinity>() <= 0.25 * step + 1e-6)
  {
    *to = next;
    return true;
  }
  if (depth >= 24)
    return false;
  JointJet middle;
  return carryJoints(model, moving, result, from, from.t + 0.5 * h, &middle, depth + 1) &&
         carryJoints(model, moving, result, middle, t, to, depth + 1);
}

/// A joint's rate ratios (|q̇|/max_velocity, |q̈|/max_acceleration) and position-limit excess
/// (rad or m beyond [min_position, max_position]) at one state, into the worst ones seen.
struct JointLimitWorst
{
  WorstOf velocity, acceleration, position;
  void see(const arm::ArmModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
           double t, const char* where)
  {
    for (int k = 0; k < model.dof(); ++k)
    {
      const arm::JointLimits& l = model.joints()[static_cast<std::size_t>(k)].limits;
      const std::string joint = "joint '" + model.joints()[static_cast<std::size_t>(k)].name + "'";
      auto at = [&](const char* what, double value, double limit) {
        return joint + " " + what + " " + num(value) + " (limit " + num(limit) + ") at t = " + num(t) + " " + where;
      };
      velocity.see(std::abs(qd[k]) / l.max_velocity, [&] { return at("velocity", qd[k], l.max_velocity); });
      acceleration.see(std::abs(qdd[k]) / l.max_acceleration,
                       [&] { return at("acceleration", qdd[k], l.max_acceleration); });
      const double beyond = std::max(l.min_position - q[k], q[k] - l.max_position);
      position.see(beyond, [&] {
        return joint + " at " + num(q[k]) + ", outside [" + num(l.min_position) + ", " + num(l.max_position) +
               "] at t = " + num(t) + " " + where;
      });
    }
  }
  /// Each limit exceeded (beyond kJointRateTolerance, or 1e-12 for a position) as a violation.
  void report(const std::string& suffix, std::vector<Violation>& v) const
  {
    if (velocity.value > 1.0 + kJointRateTolerance)
      v.push_back({ "joint velocity limit" + suffix, velocity.value, velocity.detail });
    if (acceleration.value > 1.0 + kJointRateTolerance)
      v.push_back({ "joint acceleration limit" + suffix, acceleration.value, acceleration.detail });
    if (position.value > 1e-12)
      v.push_back({ "joint position limit" + suffix, position.value, position.detail });
  }
};

/// The samples' joints against their poses, twists and accelerations, the limits and each other
/// (the steps); false where the joint vectors themselves are wrong (nothing else is checked then).
inline bool checkJointSamples(const TrajectoryResult& result, const arm::ArmModel& model, std::vector<Violation>& v)
{
  const int n = model.dof();
  if (result.joint_names != model.jointNames())
    v.push_back({ "joint names", 0.0, std::to_string(result.joint_names.size()) + " joint names, not the chain's" });
  for (std::size_t i = 0; i < result.samples.size(); ++i)
  {
    const TrajectorySample& s = result.samples[i];
    if (s.joint_position.size() != n || s.joint_velocity.size() != n || s.joint_acceleration.size() != n ||
        !s.joint_position.allFinite() || !s.joint_velocity.allFinite() || !s.joint_acceleration.allFinite())
    {
      v.push_back(
          { "joint vectors", 0.0,
            "samples[" + std::to_string(i) + "]: joint vectors not of " + std::to_string(n) + " finite entries" });
      return false;
    }
  }
  WorstOf position, rotation, twist, acceleration, step;
  JointLimitWorst limits;
  for (std::size_t i = 0; i < result.samples.size(); ++i)
  {
    const TrajectorySample& s = result.samples[i];
    const std::string where = "samples[" + std::to_string(i) + "] (t = " + num(s.time) + ")";
    Eigen::Isometry3d x;
    arm::ArmJacobian j, jd;
    model.kinematics(s.joint_position, s.joint_velocity, &x, &j, &jd);
    const Eigen::Vector3d dp = x.translation() - s.pose.p;
    const double angle =
        rotationAngle(Quaternion<double>(Quaternion<double>(x.linear()).conjugate() * s.pose.q.normalized()));
    position.see(dp.norm(), [&] { return where + ": FK is " + num(dp.norm()) + " m from the pose"; });
    rotation.see(angle, [&] { return where + ": FK is " + num(angle) + " rad from the pose"; });
    Eigen::Matrix<double, 6, 1> vel, acc;
    vel << s.velocity.angular, s.velocity.linear;
    acc << s.acceleration.angular, s.acceleration.linear;
    const double jn = j.norm(), jdn = jd.norm();
    const double dv = (j * s.joint_velocity - vel).norm();
    const double ev = dv / (kJacobianTolerance * (vel.norm() + jn * s.joint_velocity.norm()) + kJacobianFloor);
    twist.see(ev, [&] { return where + ": |J q' - V| = " + num(dv) + " with |V| = " + num(vel.norm()); });
    const double da = (j * s.joint_acceleration + jd * s.joint_velocity - acc).norm();
    const double ea =
        da / (kJacobianTolerance * (acc.norm() + jn * s.joint_acceleration.norm() + jdn * s.joint_velocity.norm()) +
              kJacobianFloor);
    acceleration.see(ea,
                     [&] { return where + ": |J q'' + J' q' - A| = " + num(da) + " with |A| = " + num(acc.norm()); });
    limits.see(model, s.joint_position, s.joint_velocity, s.joint_acceleration, s.time, "(a sample)");
    if (i == 0)
      continue;
    const TrajectorySample& p = result.samples[i - 1];
    for (int k = 0; k < n; ++k)
    {
      const double dq = std::abs(s.joint_position[k] - p.joint_position[k]);
      const double allowed = model.joints()[static_cast<std::size_t>(k)].limits.max_velocity * (s.time - p.time);
      step.see(dq / (allowed + 1e-300), [&] {
        return where + ": joint '" + model.joints()[static_cast<std::size_t>(k)].name + "' steps " + num(dq) +
               " from the previous sample, max_velocity allows " + num(allowed);
      });
    }
  }
  if (position.value > kJointPoseTolerance)
    v.push_back({ "joint FK position", position.value, position.detail });
  if (rotation.value > kJointPoseTolerance)
    v.push_back({ "joint FK rotation", rotation.value, rotation.detail });
  if (twist.value > 1.0)
    v.push_back({ "joint J q' vs twist", twist.value, twist.detail });
  if (acceleration.value > 1.0)
    v.push_back({ "joint J q'' + J' q' vs acceleration", acceleration.value, acceleration.detail });
  if (step.value > 1.0 + kJointRateTolerance)
    v.push_back({ "joint step", step.value, step.detail });
  limits.report("", v);
  return true;
}

/// The mean jerk between neighbouring states of `track` (sorted here by time) against the joints'
/// jerk limits, and the jerk figures against it where the result reports them (header comment).
inline void checkJointJerk(const TrajectoryResult& result, const arm::ArmModel& model, std::vector<JointJet> track,
                           std::vector<Violation>& v)
{
  std::stable_sort(track.begin(), track.end(), [](const JointJet& a, const JointJet& b) { return a.t < b.t; });
  WorstOf worst;
  const int n = model.dof();
  Eigen::VectorXd peak = Eigen::VectorXd::Zero(n);
  for (std::size_t i = 0; i + 1 < track.size(); ++i)
  {
    const JointJet& a = track[i];
    const JointJet& b = track[i + 1];
    const double dt = b.t - a.t;
    if (!(dt > 0.0))
      continue;
    for (int k = 0; k < n; ++k)
    {
      const double rounding = kJacobianTolerance * (std::abs(a.qdd[k]) + std::abs(b.qdd[k]) + 1.0);
      const double jerk = std::max(0.0, std::abs(b.qdd[k] - a.qdd[k]) - rounding) / dt;
      peak[k] = std::max(peak[k], jerk);
      const arm::JointLimits& l = model.joints()[static_cast<std::size_t>(k)].limits;
      if (l.hasJerkLimit())
        worst.see(jerk / l.max_jerk, [&] {
          return "joint '" + model.joints()[static_cast<std::size_t>(k)].name + "': mean jerk " + num(jerk) +
                 " (limit " + num(l.max_jerk) + ") over [" + num(a.t) + ", " + num(b.t) + "]";
        });
    }
  }
  if (worst.value > 1.0 + kJointRateTolerance)
    v.push_back({ "joint jerk limit between samples", worst.value, worst.detail });
  if (!result.joint_figures.has_jerk || static_cast<int>(result.joint_figures.peaks.size()) != n)
    return;
  for (int k = 0; k < n; ++k)
  {
    const double figure = result.joint_figures.peaks[static_cast<std::size_t>(k)].jerk;
    if (figure < peak[k] * (1.0 - kJointFigureTolerance) - 1e-12)
      v.push_back({ "joint figure jerk", peak[k] / figure,
                    "joint '" + model.joints()[static_cast<std::size_t>(k)].name + "': figure " + num(figure) +
                        " below the mean jerk found, " + num(peak[k]) });
  }
}

/// The joints between the samples (header comment): carried from each sample to the next through
/// dense times (options.dense_points over the motion, at least 2 inside every interval), checked
/// against the limits there and, around each joint's largest rates, on 32 more points; and the
/// figures against the largest rates found.
inline void checkJointsBetweenSamples(const TrajectoryResult& result, const arm::ArmModel& model,
                                      const CheckOptions& options, std::vector<Violation>& v)
{
  const int n = model.dof();
  const std::vector<int> held = heldJoints(result, n);
  if (static_cast<int>(held.size()) != std::max(0, n - 6))
  {
    v.push_back({ "joint held", static_cast<double>(held.size()),
                  std::to_string(held.size()) + " joints held over the motion; a " + std::to_string(n) +
                      "-joint arm holds " + std::to_string(std::max(0, n - 6)) });
    return;
  }
  std::vector<int> moving;
  for (int k = 0; k < n; ++k)
    if (std::find(held.begin(), held.end(), k) == held.end())
      moving.push_back(k);
  const double span = std::max(result.duration, 1e-300);
  JointLimitWorst limits;
  WorstOf continuity;
  std::vector<JointJet> track;  // every state reached, in time order
  Eigen::VectorXd peak_velocity = Eigen::VectorXd::Zero(n), peak_acceleration = Eigen::VectorXd::Zero(n);
  std::vector<std::size_t> peak_velocity_at(static_cast<std::size_t>(n), 0), peak_acceleration_at(peak_velocity_at);
  auto reach = [&](const JointJet& jet) {
    limits.see(model, jet.q, jet.qd, jet.qdd, jet.t, "(between samples)");
    for (int k = 0; k < n; ++k)
    {
      const std::size_t at = track.size(), kk = static_cast<std::size_t>(k);
      if (std::abs(jet.qd[k]) > peak_velocity[k])
        std::tie(peak_velocity[k], peak_velocity_at[kk]) = std::make_pair(std::abs(jet.qd[k]), at);
      if (std::abs(jet.qdd[k]) > peak_acceleration[k])
        std::tie(peak_acceleration[k], peak_acceleration_at[kk]) = std::make_pair(std::abs(jet.qdd[k]), at);
    }
    track.push_back(jet);
  };
  for (std::size_t i = 0; i + 1 < result.samples.size(); ++i)
  {
    const TrajectorySample& a = result.samples[i];
    const TrajectorySample& b = result.samples[i + 1];
    if (!(b.time > a.time))
      continue;
    JointJet jet{ a.time, a.joint_position, a.joint_velocity, a.joint_acceleration };
    reach(jet);
    const std::size_t inside =
        std::max<std::size_t>(2, static_cast<std::size_t>(
                                     std::ceil(static_cast<double>(options.dense_points) * (b.time - a.time) / span)));
    for (std::size_t k = 1; k <= inside + 1; ++k)
    {
      const double t =
          k <= inside ? a.time + (b.time - a.time) * static_cast<double>(k) / static_cast<double>(inside + 1) : b.time;
      if (!carryJoints(model, moving, result, jet, t, &jet))
      {
        v.push_back(
            { "joint continuity", 1.0,
              "the joints of samples[" + std::to_string(i) + "] cannot be carried along the motion to t = " + num(t) });
        return;
      }
      if (k <= inside)
        reach(jet);
    }
    const double gap = (jet.q - b.joint_position).lpNorm<Eigen::Infinity>();
    continuity.see(gap, [&] {
      return "carried from samples[" + std::to_string(i) + "], the joints arrive " + num(gap) + " from samples[" +
             std::to_string(i + 1) + "]'s (t = " + num(b.time) + ")";
    });
  }
  if (continuity.value > kJointContinuityTolerance)
    v.push_back({ "joint continuity", continuity.value, continuity.detail });
  if (track.size() < 2)
    return;
  // Around each joint's largest rates: 32 points between the dense neighbours.
  std::vector<std::size_t> peaks(peak_velocity_at);
  peaks.insert(peaks.end(), peak_acceleration_at.begin(), peak_acceleration_at.end());
  std::sort(peaks.begin(), peaks.end());
  peaks.erase(std::unique(peaks.begin(), peaks.end()), peaks.end());
  for (std::size_t at : peaks)
  {
    JointJet jet = track[at > 0 ? at - 1 : 0];
    const double end = track[std::min(at + 1, track.size() - 1)].t;
    const double begin = jet.t;
    for (int k = 1; k < 32 && end > begin; ++k)
    {
      if (!carryJoints(model, moving, result, jet, begin + (end - begin) * k / 32.0, &jet))
        break;
      reach(jet);
    }
  }
  limits.report(" between samples", v);
  checkJointJerk(result, model, track, v);
  for (int k = 0; k < n && static_cast<int>(result.joint_figures.peaks.size()) == n; ++k)
  {
    const arm::JointPeak& f = result.joint_figures.peaks[static_cast<std::size_t>(k)];
    const std::string joint = "joint '" + model.joints()[static_cast<std::size_t>(k)].name + "'";
    if (f.velocity < peak_velocity[k] * (1.0 - kJointFigureTolerance) - 1e-12)
      v.push_back({ "joint figure velocity", peak_velocity[k] / f.velocity,
                    joint + ": figure " + num(f.velocity) + " below the rate found, " + num(peak_velocity[k]) });
    if (f.acceleration < peak_acceleration[k] * (1.0 - kJointFigureTolerance) - 1e-12)
      v.push_back(
          { "joint figure acceleration", peak_acceleration[k] / f.acceleration,
            joint + ": figure " + num(f.acceleration) + " below the rate found, " + num(peak_acceleration[k]) });
  }
}

/// Every joint invariant of the header comment of a served request with the arm `model`.
inline void checkJointInvariants(const TrajectoryResult& result, const arm::ArmModel& model,
                                 const CheckOptions& options, std::vector<Violation>& v)
{
  if (result.samples.empty() || !result.state_at)
    return;  // (checkInvariants reports these)
  if (!checkJointSamples(result, model, v))
    return;
  if (result.joint_figures.peaks.size() != static_cast<std::size_t>(model.dof()))
    v.push_back({ "joint figures", 0.0, std::to_string(result.joint_figures.peaks.size()) + " joint peaks" });
  for (std::size_t k = 0; k < result.joint_figures.peaks.size() && k < model.joints().size(); ++k)
  {
    const arm::JointLimits& l = model.joints()[k].limits;
    const arm::JointPeak& f = result.joint_figures.peaks[k];
    const double jerk = result.joint_figures.has_jerk ? f.jerk / l.max_jerk : 0.0;
    const double ratio = std::max({ f.velocity / l.max_velocity, f.acceleration / l.max_acceleration, jerk });
    if (!(ratio <= 1.0 + kJointRateTolerance))
      v.push_back({ "joint figures above the limits", ratio,
                    "joint '" + model.joints()[k].name + "': figures " + num(f.velocity) + ", " + num(f.acceleration) +
                        " against limits " + num(l.max_velocity) + ", " + num(l.max_acceleration) });
  }
  checkJointsBetweenSamples(result, model, options, v);
}
}  // namespace test
}  // namespace se3_interpolation
