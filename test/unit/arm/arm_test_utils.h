// The arm tests' independent references: the vendors' DH products written out (standard DH for the
// UR5e, modified DH for the Panda), a KDL chain built from a urdfdom model, finite differences of
// the model's kinematics; and the robots of config/robots/ as the tests and benchmarks load them.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <kdl/chain.hpp>
#include <kdl/frames.hpp>
#include <kdl/joint.hpp>
#include <kdl/segment.hpp>
#include <urdf_parser/urdf_parser.h>

#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/arm/joint_limits.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace test
{
/// config/robots/<name> of the source tree this header is in (test/unit/arm/arm_test_utils.h).
inline std::string robotFile(const std::string& name)
{
  const std::string here = __FILE__;
  return here.substr(0, here.rfind("/test/unit/arm/")) + "/config/robots/" + name;
}

/// The work limit of the arm's requests: the work estimate does not count the arm's inverse
/// kinematics (docs/joint_space.md), which under the sanitizers takes seconds.
inline PlannerLimits armLimits()
{
  PlannerLimits limits;
  limits.max_work_seconds = 600.0;
  return limits;
}

/// The robot `name` of config/robots/ ("ur5e": base_link → tool0; "panda": base_link →
/// panda_link8, the flange) with the limits of its joint_limits.yaml, every joint's velocity limit
/// scaled by `velocity_scale`, acceleration limit by `acceleration_scale` and jerk limit (the
/// Panda's) by `jerk_scale` (an infinite one drops them).
inline std::shared_ptr<arm::ArmModel> loadArm(const std::string& name, double velocity_scale = 1.0,
                                              double acceleration_scale = 1.0, double jerk_scale = 1.0)
{
  auto model = std::make_shared<arm::ArmModel>(
      arm::ArmModel::fromUrdfFile(robotFile(name + ".urdf"), "base_link", name == "panda" ? "panda_link8" : "tool0"));
  arm::JointLimitsFile limits = arm::readJointLimitsFile(robotFile(name + "_joint_limits.yaml"));
  for (auto& entry : limits.joints)
  {
    if (entry.second.max_velocity)
      entry.second.max_velocity = *entry.second.max_velocity * velocity_scale;
    if (entry.second.max_acceleration)
      entry.second.max_acceleration = *entry.second.max_acceleration * acceleration_scale;
    if (entry.second.max_jerk && std::isinf(jerk_scale))
      entry.second.max_jerk.reset();
    else if (entry.second.max_jerk)
      entry.second.max_jerk = *entry.second.max_jerk * jerk_scale;
  }
  model->applyLimits(limits);
  return model;
}

/// A time-optimal request through the arm's forward kinematics of `configurations` (the first the
/// joint_seed), under Cartesian bounds of 0.5 m/s, 1 rad/s, 2 m/s², 4 rad/s², with `samples` samples.
inline TrajectoryRequest requestThrough(const arm::ArmModel& model,
                                        const std::vector<std::vector<double>>& configurations, std::uint32_t samples)
{
  TrajectoryRequest r;
  for (const std::vector<double>& q : configurations)
    r.waypoints.push_back(
        model.basePoseOfTip(Eigen::Map<const Eigen::VectorXd>(q.data(), static_cast<Eigen::Index>(q.size()))));
  r.joint_seed = configurations.front();
  r.timing = "time_optimal";
  r.max_linear_velocity = 0.5;
  r.max_angular_velocity = 1.0;
  r.max_linear_acceleration = 2.0;
  r.max_angular_acceleration = 4.0;
  r.sample_count = samples;
  return r;
}

/// A working configuration of the robot `name` of loadArm (rad): the UR5e's elbow up with the tool
/// pointing down, the Panda's ready pose with its wrist turned; far from singular configurations.
inline std::vector<double> armHome(const std::string& name)
{
  return name == "panda" ? std::vector<double>{ 0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8 } :
                           std::vector<double>{ 0.0, -1.2, 1.5, -1.9, -1.57, 0.0 };
}

inline std::string readText(const std::string& path)
{
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Standard DH (Spong, Hutchinson & Vidyasagar, "Robot Modeling and Control", §3.2):
/// A_i = Rz(θ) Tz(d) Tx(a) Rx(α).
inline Eigen::Matrix4d standardDh(double a, double d, double alpha, double theta)
{
  const double ct = std::cos(theta), st = std::sin(theta), ca = std::cos(alpha), sa = std::sin(alpha);
  Eigen::Matrix4d m;
  m << ct, -st * ca, st * sa, a * ct,  //
      st, ct * ca, -ct * sa, a * st,   //
      0, sa, ca, d,                    //
      0, 0, 0, 1;
  return m;
}

/// Modified DH (Craig, "Introduction to Robotics", eq. 3.6): Rx(α) Tx(a) Rz(θ) Tz(d).
inline Eigen::Matrix4d modifiedDh(double a, double d, double alpha, double theta)
{
  const double ct = std::cos(theta), st = std::sin(theta), ca = std::cos(alpha), sa = std::sin(alpha);
  Eigen::Matrix4d m;
  m << ct, -st, 0, a,                  //
      st * ca, ct * ca, -sa, -sa * d,  //
      st * sa, ct * sa, ca, ca * d,    //
      0, 0, 0, 1;
  return m;
}

/// UR5e base → tool0 from Universal Robots' DH table (standard DH).
inline Eigen::Matrix4d ur5eDh(const Eigen::VectorXd& q)
{
  const double a[] = { 0, -0.425, -0.3922, 0, 0, 0 };
  const double d[] = { 0.1625, 0, 0, 0.1333, 0.0997, 0.0996 };
  const double alpha[] = { M_PI / 2, 0, 0, M_PI / 2, -M_PI / 2, 0 };
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 6; ++i)
    t = t * standardDh(a[i], d[i], alpha[i], q[i]);
  return t;
}

/// Panda base → flange (panda_link8) from Franka's DH table (modified DH), the flange row last.
inline Eigen::Matrix4d pandaDh(const Eigen::VectorXd& q)
{
  const double a[] = { 0, 0, 0, 0.0825, -0.0825, 0, 0.088, 0 };
  const double d[] = { 0.333, 0, 0.316, 0, 0.384, 0, 0, 0.107 };
  const double alpha[] = { 0, -M_PI / 2, M_PI / 2, M_PI / 2, -M_PI / 2, M_PI / 2, M_PI / 2, 0 };
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 8; ++i)
    t = t * modifiedDh(a[i], d[i], alpha[i], i < 7 ? q[i] : 0.0);
  return t;
}

/// A KDL chain from the urdfdom model of `urdf`, base to tip, built here: per URDF joint a fixed
/// segment with its <origin>, then (movable joints) a segment turning or sliding about its axis.
inline KDL::Chain kdlChain(const std::string& urdf, const std::string& base, const std::string& tip)
{
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf);
  std::vector<urdf::JointConstSharedPtr> path;
  for (urdf::LinkConstSharedPtr link = model->getLink(tip); link->name != base;
       link = model->getLink(path.back()->parent_link_name))
    path.push_back(link->parent_joint);
  std::reverse(path.begin(), path.end());
  KDL::Chain chain;
  for (const urdf::JointConstSharedPtr& j : path)
  {
    const urdf::Pose& o = j->parent_to_joint_origin_transform;
    const KDL::Frame origin(KDL::Rotation::Quaternion(o.rotation.x, o.rotation.y, o.rotation.z, o.rotation.w),
                            KDL::Vector(o.position.x, o.position.y, o.position.z));
    chain.addSegment(KDL::Segment(j->name + "_origin", KDL::Joint(KDL::Joint::Fixed), origin));
    if (j->type == urdf::Joint::FIXED)
      continue;
    KDL::Vector axis(j->axis.x, j->axis.y, j->axis.z);
    axis.Normalize();
    const KDL::Joint::JointType type = j->type == urdf::Joint::PRISMATIC ? KDL::Joint::TransAxis : KDL::Joint::RotAxis;
    chain.addSegment(KDL::Segment(j->child_link_name, KDL::Joint(j->name, KDL::Vector::Zero(), axis, type)));
  }
  return chain;
}

inline Eigen::Matrix4d toMatrix(const KDL::Frame& f)
{
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 3; ++r)
  {
    for (int c = 0; c < 3; ++c)
      m(r, c) = f.M(r, c);
    m(r, 3) = f.p[r];
  }
  return m;
}

/// The Jacobian by central differences of the model's FK (step h): ṗ from the positions,
/// ω from (R₊ − R₋)/(2h) Rᵀ = [ω]×; rows [ω; ṗ] as the model's.
inline Eigen::MatrixXd finiteDifferenceJacobian(const arm::ArmModel& model, const Eigen::VectorXd& q, double h)
{
  Eigen::MatrixXd j(6, model.dof());
  const Eigen::Matrix3d r = model.base_T_tip(q).linear();
  for (int i = 0; i < model.dof(); ++i)
  {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += h;
    qm[i] -= h;
    const Eigen::Isometry3d tp = model.base_T_tip(qp), tm = model.base_T_tip(qm);
    const Eigen::Matrix3d w = (tp.linear() - tm.linear()) / (2 * h) * r.transpose();
    j.col(i) << w(2, 1), w(0, 2), w(1, 0), (tp.translation() - tm.translation()) / (2 * h);
  }
  return j;
}

/// dJ/dt along qd by central differences of the model's Jacobian: (J(q + h qd) − J(q − h qd))/(2h).
inline Eigen::MatrixXd finiteDifferenceJacobianRate(const arm::ArmModel& model, const Eigen::VectorXd& q,
                                                    const Eigen::VectorXd& qd, double h)
{
  const Eigen::VectorXd qp = q + h * qd, qm = q - h * qd;
  return (model.jacobian(qp) - model.jacobian(qm)) / (2 * h);
}

/// q(t) = q + qd t + qdd t²/2 + qddd t³/6 and its first two derivatives at t.
struct CubicJointMotion
{
  Eigen::VectorXd q, qd, qdd, qddd;

  Eigen::VectorXd position(double t) const { return q + t * qd + t * t / 2 * qdd + t * t * t / 6 * qddd; }
  Eigen::VectorXd velocity(double t) const { return qd + t * qdd + t * t / 2 * qddd; }
  Eigen::VectorXd acceleration(double t) const { return qdd + t * qddd; }
};

/// The tip's [ω̈; p⃛] at t = 0 of m by central differences of its acceleration J q̈ + J̇ q̇ (step h).
inline arm::TipVector finiteDifferenceTipJerk(const arm::ArmModel& model, const CubicJointMotion& m, double h)
{
  const auto tipAcceleration = [&](double t) {
    arm::ArmJacobian j, jd;
    model.kinematics(m.position(t), m.velocity(t), nullptr, &j, &jd);
    return arm::TipVector(j * m.acceleration(t) + jd * m.velocity(t));
  };
  return (tipAcceleration(h) - tipAcceleration(-h)) / (2 * h);
}

/// The tip origin's p⃛ at t = 0 of m from forward kinematics alone (the five-point central
/// difference of the positions, step h; error O(h²)).
inline Eigen::Vector3d finiteDifferenceTipLinearJerk(const arm::ArmModel& model, const CubicJointMotion& m, double h)
{
  const auto p = [&](double t) { return Eigen::Vector3d(model.base_T_tip(m.position(t)).translation()); };
  return (p(2 * h) - 2 * p(h) + 2 * p(-h) - p(-2 * h)) / (2 * h * h * h);
}

}  // namespace test
}  // namespace se3_interpolation
