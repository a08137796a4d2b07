// The kinematics of arm/arm_model.h, the chain's members that need Eigen only (core sources): (FK)
// as a product of the joints' transforms, (J) and (J̇) from the joints' base-frame axes and
// origins, all on stack buffers of kMaxArmJoints.
#include <cmath>

#include "se3_interpolation/arm/arm_model.h"

namespace se3_interpolation
{
namespace arm
{
std::vector<std::string> ArmModel::jointNames() const
{
  std::vector<std::string> names;
  names.reserve(joints_.size());
  for (const ArmJoint& j : joints_)
    names.push_back(j.name);
  return names;
}

void ArmModel::checkJointVector(const JointVectorRef& v, const std::string& field) const
{
  if (v.size() != dof())
    throw ArmModelError(field + ": " + std::to_string(v.size()) + " entries, the chain " + quotedText(base_link_) +
                        " → " + quotedText(tip_link_) + " has " + std::to_string(dof()) + " joints");
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      throw ArmModelError(indexedField(field, static_cast<std::size_t>(i)) + " (joint " +
                          quotedText(joints_[static_cast<std::size_t>(i)].name) + "): not finite (" +
                          formatNumber(v[i]) + ")");
}

void ArmModel::forward(const JointVectorRef& q, Eigen::Isometry3d* base_T_tip, Eigen::Vector3d* z,
                       Eigen::Vector3d* o) const
{
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < joints_.size(); ++i)
  {
    const ArmJoint& j = joints_[i];
    t = t * j.prev_T_joint;  // base_T_joint_i
    if (z)
    {
      z[i] = t.linear() * j.axis;
      o[i] = t.translation();
    }
    const double qi = q[static_cast<Eigen::Index>(i)];
    if (j.isPrismatic())
      t.translation() += t.linear() * (j.axis * qi);
    else
      t.linear() = t.linear() * Eigen::AngleAxisd(qi, j.axis).toRotationMatrix();
  }
  *base_T_tip = t * last_T_tip_;
}

Eigen::Isometry3d ArmModel::base_T_tip(const JointVectorRef& q) const
{
  checkJointVector(q, "q");
  Eigen::Isometry3d t;
  forward(q, &t, nullptr, nullptr);
  return t;
}

Pose<double> ArmModel::basePoseOfTip(const JointVectorRef& q) const
{
  const Eigen::Isometry3d t = base_T_tip(q);
  return Pose<double>(Quaternion<double>(Eigen::Quaterniond(t.linear())), t.translation());
}

ArmJacobian ArmModel::jacobian(const JointVectorRef& q) const
{
  ArmJacobian j;
  kinematics(q, q, nullptr, &j, nullptr);
  return j;
}

ArmJacobian ArmModel::jacobianDerivative(const JointVectorRef& q, const JointVectorRef& qd) const
{
  ArmJacobian jd;
  kinematics(q, qd, nullptr, nullptr, &jd);
  return jd;
}

void ArmModel::kinematics(const JointVectorRef& q, const JointVectorRef& qd, Eigen::Isometry3d* base_T_tip,
                          ArmJacobian* jacobian, ArmJacobian* jacobian_derivative) const
{
  checkJointVector(q, "q");
  if (jacobian_derivative)
    checkJointVector(qd, "qd");
  Eigen::Vector3d z[kMaxArmJoints];
  Eigen::Vector3d o[kMaxArmJoints];
  Eigen::Isometry3d t;
  forward(q, &t, z, o);
  if (base_T_tip)
    *base_T_tip = t;
  if (!jacobian && !jacobian_derivative)
    return;
  const int n = dof();
  const Eigen::Vector3d p = t.translation();
  // (J), and ṗ = J_v q̇ for (J̇).
  Eigen::Vector3d p_dot = Eigen::Vector3d::Zero();
  ArmJacobian local;
  ArmJacobian& jac = jacobian ? *jacobian : local;
  jac.resize(6, n);
  for (int i = 0; i < n; ++i)
  {
    if (joints_[static_cast<std::size_t>(i)].isPrismatic())
      jac.col(i) << Eigen::Vector3d::Zero(), z[i];
    else
      jac.col(i) << z[i], z[i].cross(p - o[i]);
    if (jacobian_derivative)
      p_dot += jac.block<3, 1>(3, i) * qd[i];
  }
  if (!jacobian_derivative)
    return;
  // (J̇): ω, the angular velocity of joint i's parent link, and v_o, the velocity of o_i.
  ArmJacobian& jd = *jacobian_derivative;
  jd.resize(6, n);
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_o = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i)
  {
    const bool prismatic = joints_[static_cast<std::size_t>(i)].isPrismatic();
    const Eigen::Vector3d z_dot = omega.cross(z[i]);
    if (prismatic)
      jd.col(i) << Eigen::Vector3d::Zero(), z_dot;
    else
      jd.col(i) << z_dot, z_dot.cross(p - o[i]) + z[i].cross(p_dot - v_o);
    // The child link of joint i: its angular velocity, then the velocity of o_{i+1}, fixed on it.
    if (prismatic)
      v_o += z[i] * qd[i];
    else
      omega += z[i] * qd[i];
    if (i + 1 < n)
      v_o += omega.cross(o[i + 1] - o[i]);
  }
}

}  // namespace arm
}  // namespace se3_interpolation
