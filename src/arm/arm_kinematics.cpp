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
  ArmFrames f;
  frames(q, &f);
  if (jacobian_derivative)
    checkJointVector(qd, "qd");
  if (base_T_tip)
    *base_T_tip = f.base_T_tip;
  if (!jacobian && !jacobian_derivative)
    return;
  const ArmJacobian j = this->jacobian(f);
  if (jacobian)
    *jacobian = j;
  if (jacobian_derivative)
    *jacobian_derivative = this->jacobianDerivative(f, j, qd);
}

void ArmModel::frames(const JointVectorRef& q, ArmFrames* f) const
{
  checkJointVector(q, "q");
  forward(q, &f->base_T_tip, f->z.data(), f->o.data());
}

ArmJacobian ArmModel::jacobian(const ArmFrames& f) const
{
  const int n = dof();
  const Eigen::Vector3d p = f.base_T_tip.translation();
  ArmJacobian jac(6, n);
  for (int i = 0; i < n; ++i)
  {
    const Eigen::Vector3d& z = f.z[static_cast<std::size_t>(i)];
    if (joints_[static_cast<std::size_t>(i)].isPrismatic())
      jac.col(i) << Eigen::Vector3d::Zero(), z;
    else
      jac.col(i) << z, z.cross(p - f.o[static_cast<std::size_t>(i)]);
  }
  return jac;
}

ArmJacobian ArmModel::jacobianDerivative(const ArmFrames& f, const ArmJacobian& jac, const JointVectorRef& qd) const
{
  // ṗ = J_v q̇; ω, the angular velocity of joint i's parent link, and v_o, the velocity of o_i.
  const int n = dof();
  const Eigen::Vector3d p = f.base_T_tip.translation();
  const Eigen::Vector3d p_dot = jac.bottomRows<3>() * qd;
  ArmJacobian jd(6, n);
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_o = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i)
  {
    const std::size_t k = static_cast<std::size_t>(i);
    const bool prismatic = joints_[k].isPrismatic();
    const Eigen::Vector3d z_dot = omega.cross(f.z[k]);
    if (prismatic)
      jd.col(i) << Eigen::Vector3d::Zero(), z_dot;
    else
      jd.col(i) << z_dot, z_dot.cross(p - f.o[k]) + f.z[k].cross(p_dot - v_o);
    // The child link of joint i: its angular velocity, then the velocity of o_{i+1}, fixed on it.
    if (prismatic)
      v_o += f.z[k] * qd[i];
    else
      omega += f.z[k] * qd[i];
    if (i + 1 < n)
      v_o += omega.cross(f.o[k + 1] - f.o[k]);
  }
  return jd;
}

namespace
{
/// The first three time derivatives of a vector d fixed on a link turning at ω, α = ω̇, ζ = ω̈
/// but for a part that slides in the link at relative rates r1, r2, r3 (a prismatic joint's
/// z q̇, z q̈, z q⃛; zero between two points of the link): a link-frame quantity X changes as
/// Ẋ = ω × X + (its change in the link).
struct MovingVector
{
  Eigen::Vector3d d1, d2, d3;

  MovingVector(const Eigen::Vector3d& d, const Eigen::Vector3d& omega, const Eigen::Vector3d& alpha,
               const Eigen::Vector3d& zeta, const Eigen::Vector3d& r1, const Eigen::Vector3d& r2,
               const Eigen::Vector3d& r3)
  {
    const Eigen::Vector3d r1_dot = omega.cross(r1) + r2;  // d/dt r1
    d1 = omega.cross(d) + r1;
    d2 = alpha.cross(d) + omega.cross(d1) + r1_dot;
    d3 = zeta.cross(d) + 2.0 * alpha.cross(d1) + omega.cross(d2) + alpha.cross(r1) + omega.cross(r1_dot) +
         omega.cross(r2) + r3;
  }
};
}  // namespace

TipVector ArmModel::tipJerk(const ArmFrames& f, const JointVectorRef& qd, const JointVectorRef& qdd,
                            const JointVectorRef& qddd) const
{
  // The current link's ω, α, ζ, and its joint origin's jerk: o_0 is fixed in the base, and the
  // tip's jerk sums the jerks of the vectors o_{i+1} − o_i and p − o_{n−1}.
  const Eigen::Vector3d zero = Eigen::Vector3d::Zero();
  Eigen::Vector3d omega = zero, alpha = zero, zeta = zero, j = zero;
  const int n = dof();
  for (int i = 0; i < n; ++i)
  {
    const std::size_t k = static_cast<std::size_t>(i);
    const Eigen::Vector3d& z = f.z[k];
    const Eigen::Vector3d next = i + 1 < n ? f.o[k + 1] : f.base_T_tip.translation();
    if (joints_[k].isPrismatic())
    {
      const MovingVector d(next - f.o[k], omega, alpha, zeta, z * qd[i], z * qdd[i], z * qddd[i]);
      j += d.d3;
      continue;
    }
    // About z, fixed on the parent link: ż = ω⁻ × z, z̈ = α⁻ × z + ω⁻ × ż.
    const Eigen::Vector3d z1 = omega.cross(z);
    const Eigen::Vector3d z2 = alpha.cross(z) + omega.cross(z1);
    omega += z * qd[i];
    alpha += z1 * qd[i] + z * qdd[i];
    zeta += z2 * qd[i] + 2.0 * z1 * qdd[i] + z * qddd[i];
    const MovingVector d(next - f.o[k], omega, alpha, zeta, zero, zero, zero);
    j += d.d3;
  }
  TipVector out;
  out << zeta, j;
  return out;
}

}  // namespace arm
}  // namespace se3_interpolation
