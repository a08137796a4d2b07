// The arm as a dimension of the request space (test_request_space.cpp): no arm, the UR5e (6 joints)
// or the Panda (7 joints, one held) of config/robots/ with the limits of their files; a request
// of the grid or the sweep mapped into the arm's workspace, its joint_seed solved for its first
// pose; and the classes of the arm's refusals.
//
// The mapping (mapIntoArmWorkspace). The grid's and the sweep's waypoints are poses anywhere (steps
// of about 1 m and up to half a turn, 50 waypoints spanning 25 m); an arm reaches about 0.85 m
// around its base. Each request is mapped as a whole, so that its shape stays:
//  - positions (waypoints and the start pose): scaled about the centre of their bounding box by
//    s = min(1, kArmBoxHalfSize / (its largest half-extent)) and moved to the tool's position at the
//    arm's home configuration (test/unit/arm/arm_test_utils.h, armHome): all within a cube of
//    ±0.15 m in front of the arm; numbers that are not finite stay so (and are refused as before);
//  - orientations: the rotation of each from the first one, r = log(q_0⁻¹ q), scaled by
//    kArmRotationFraction and applied to the tool's home orientation, h exp(0.2 r): within 0.63 rad of
//    it (a half turn of the grid becomes 0.63 rad, a step of 1e-9 rad one of 2e-10); each quaternion
//    keeps its sign relative to the previous one (the grid's −q steps) and its norm (the sweep's
//    quaternions of norm 1.05 or 0 are refused as before);
//  - velocities, accelerations, times, bounds, blend radii and the other fields keep their values
//    (m/s, rad/s: plausible for an arm's tool).
// The joint_seed is the test's own damped least squares inverse kinematics of the motion's first
// pose (the start state's, else waypoints[0]) from the home configuration, within the joints'
// position limits; where it does not converge (an invalid pose), the home configuration.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "arm/arm_test_utils.h"
#include "joint_invariants.h"
#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/math/lie_groups.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace test
{
/// The arm dimension's values.
enum class ArmKind
{
  kNone,
  kUr5e,
  kPanda
};

inline const char* armName(ArmKind a)
{
  return a == ArmKind::kNone ? "none" : a == ArmKind::kUr5e ? "ur5e" : "panda";
}

/// Half the side of the cube the positions are mapped into (m).
constexpr double kArmBoxHalfSize = 0.15;
/// The fraction of each orientation's rotation from the first that the mapping keeps.
constexpr double kArmRotationFraction = 0.2;

/// An arm of the dimension: its model and home configuration, and the tool's pose there.
struct GridArm
{
  std::shared_ptr<const arm::ArmModel> model;
  Eigen::VectorXd home;
  Pose<double> home_pose;
};

/// The arm of `kind` (not kNone), loaded once.
inline const GridArm& gridArm(ArmKind kind)
{
  static const auto load = [](const char* name) {
    GridArm a;
    a.model = loadArm(name);
    const std::vector<double> home = armHome(name);
    a.home = Eigen::Map<const Eigen::VectorXd>(home.data(), static_cast<Eigen::Index>(home.size()));
    a.home_pose = a.model->basePoseOfTip(a.home);
    return a;
  };
  static const GridArm kUr5e = load("ur5e"), kPanda = load("panda");
  return kind == ArmKind::kPanda ? kPanda : kUr5e;
}

/// Damped least squares IK of `target` from q (all joints, kept within their position limits):
/// false where it does not reach 1e-12 within 200 steps.
inline bool solveSeed(const arm::ArmModel& model, const Pose<double>& target, Eigen::VectorXd* q)
{
  for (int iteration = 0; iteration < 200; ++iteration)
  {
    Eigen::Isometry3d x;
    arm::ArmJacobian j;
    model.kinematics(*q, *q, &x, &j, nullptr);
    const Eigen::Matrix<double, 6, 1> e = tipError(target, x);
    if (!e.allFinite())
      return false;
    if (e.lpNorm<Eigen::Infinity>() <= 1e-12)
      return true;
    const double damping = e.norm() > 1e-3 ? 1e-2 : 0.0;
    const Eigen::Matrix<double, 6, 6> jjt = j * j.transpose() + damping * Eigen::Matrix<double, 6, 6>::Identity();
    Eigen::VectorXd step = j.transpose() * jjt.fullPivLu().solve(e);
    const double largest = step.lpNorm<Eigen::Infinity>();
    if (!(largest < 1e6))
      return false;
    if (largest > 0.3)
      step *= 0.3 / largest;
    *q += step;
    for (int k = 0; k < model.dof(); ++k)
    {
      const arm::JointLimits& l = model.joints()[static_cast<std::size_t>(k)].limits;
      (*q)[k] = std::min(std::max((*q)[k], l.min_position), l.max_position);
    }
  }
  return false;
}

/// The mapping of the header comment for one request's poses.
class WorkspaceMap
{
public:
  WorkspaceMap(const GridArm& arm, const TrajectoryRequest& r) : home_(arm.home_pose)
  {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    auto extend = [&](const Pose<double>& x) {
      if (x.p.allFinite())
      {
        lo = lo.cwiseMin(x.p);
        hi = hi.cwiseMax(x.p);
      }
      if (!reference_ && x.q.coeffs().allFinite() && x.q.norm() > 0.5)
        reference_ = x.q.normalized();
    };
    if (r.start_state)
      extend(r.start_state->pose);
    for (const Pose<double>& x : r.waypoints)
      extend(x);
    if (lo.allFinite())
    {
      centre_ = 0.5 * (lo + hi);
      scale_ = std::min(1.0, kArmBoxHalfSize / std::max(0.5 * (hi - lo).maxCoeff(), 1e-300));
    }
  }

  /// A pose mapped; `previous` (original and mapped) gives the sign relation to keep.
  Pose<double> operator()(const Pose<double>& x, const Pose<double>* previous,
                          const Pose<double>* previous_mapped) const
  {
    Pose<double> m = x;
    m.p = home_.p + scale_ * (x.p - centre_);
    const double norm = x.q.norm();
    if (!reference_ || !x.q.coeffs().allFinite() || !(norm > 0.0))
      return m;
    Quaternion<double> relative(reference_->conjugate() * Quaternion<double>(x.q.coeffs() / norm));
    if (relative.w() < 0.0)
      relative.coeffs() = -relative.coeffs();
    m.q = Quaternion<double>(home_.q * so3Exp<double>(Eigen::Vector3d(kArmRotationFraction * so3Log(relative))));
    if (previous && previous_mapped)
    {
      const bool flipped = x.q.coeffs().dot(previous->q.coeffs()) < 0.0;
      if (flipped != (m.q.coeffs().dot(previous_mapped->q.coeffs()) < 0.0))
        m.q.coeffs() = -m.q.coeffs();
    }
    m.q.coeffs() *= norm;
    return m;
  }

private:
  Pose<double> home_;
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
  double scale_ = 1.0;
  std::optional<Quaternion<double>> reference_;
};

/// Maps `r` into the workspace of `arm` and sets its joint_seed (header comment).
inline void mapIntoArmWorkspace(const GridArm& arm, TrajectoryRequest* r)
{
  const WorkspaceMap map(arm, *r);
  std::vector<Pose<double>> mapped;
  for (std::size_t i = 0; i < r->waypoints.size(); ++i)
    mapped.push_back(map(r->waypoints[i], i > 0 ? &r->waypoints[i - 1] : nullptr, i > 0 ? &mapped[i - 1] : nullptr));
  if (r->start_state)
  {
    const bool with_first = !r->waypoints.empty();
    r->start_state->pose =
        map(r->start_state->pose, with_first ? &r->waypoints[0] : nullptr, with_first ? &mapped[0] : nullptr);
  }
  r->waypoints = mapped;
  Eigen::VectorXd seed = arm.home;
  const Pose<double>* first = r->start_state       ? &r->start_state->pose :
                              r->waypoints.empty() ? nullptr :
                                                     &r->waypoints[0];
  if (first == nullptr || !solveSeed(*arm.model, *first, &seed))
    seed = arm.home;
  r->joint_seed.assign(seed.data(), seed.data() + seed.size());
}

/// The class of an arm request's refusal: where the arm cannot follow (the pose out of reach, a
/// singular configuration, a position limit, a joint rate that a moving start or constant_speed
/// may not stretch, a branch change), else the request field named first.
inline std::string armRefusalClass(const std::string& message, const std::string& first_field)
{
  if (message.find("out of the arm's reach") != std::string::npos)
    return "out of reach";
  if (message.find("singular configuration") != std::string::npos)
    return "singular configuration";
  if (message.find("position limit") != std::string::npos)
    return "position limit";
  if (message.find("above its limit") != std::string::npos)
    return "joint rate (no stretch of a moving start or constant_speed)";
  if (message.find("the arm's joint jerk limits") != std::string::npos)
    return "the arm's joint jerk limits (an acceleration step; the jerk-limited timing's refusals)";
  if (message.find("tracked branch") != std::string::npos)
    return "branch change";
  // The Cartesian brake to rest does not know the joints: such a start is refused naming start_state.
  if (message.find("start_state") != std::string::npos &&
      message.find("arm joint's acceleration limit") != std::string::npos)
    return "a moving start the joints cannot brake from along the path";
  return "field " + first_field;
}

/// Whether a refusal is the arm's (not a request field's): armRefusalClass gives no field.
inline bool isArmRefusal(const std::string& message)
{
  return armRefusalClass(message, "").rfind("field ", 0) != 0;
}
}  // namespace test
}  // namespace se3_interpolation
