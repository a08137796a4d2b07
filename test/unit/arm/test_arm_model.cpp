// arm/arm_model.h: the forward kinematics of config/robots/'s UR5e and Panda equal the vendors'
// DH products (standard for the UR5e, modified for the Panda) and KDL's; the Jacobian equals KDL's
// and the finite differences of the FK; J̇ equals the finite differences of J; a chain with a
// prismatic, a continuous and fixed joints between them; the tip's jerk equals the differences of
// its acceleration and of the FK; the limits of the URDF and the limits files; the kinematics
// allocate nothing.
#include <gtest/gtest.h>

#include <random>

#include <Eigen/SVD>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "allocation_counter.h"
#include "arm/arm_test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::arm;
using test::readText;
using test::robotFile;

namespace
{
ArmModel ur5e()
{
  return ArmModel::fromUrdfFile(robotFile("ur5e.urdf"), "base_link", "tool0");
}

ArmModel panda(const std::string& tip = "panda_link8")
{
  return ArmModel::fromUrdfFile(robotFile("panda.urdf"), "base_link", tip);
}

/// Uniform joint positions within the model's position limits (±π where a joint has none).
std::vector<Eigen::VectorXd> randomPositions(const ArmModel& model, int count, unsigned seed)
{
  std::mt19937 rng(seed);
  std::vector<Eigen::VectorXd> out;
  for (int k = 0; k < count; ++k)
  {
    Eigen::VectorXd q(model.dof());
    for (int i = 0; i < model.dof(); ++i)
    {
      const JointLimits& l = model.joints()[static_cast<std::size_t>(i)].limits;
      const double lo = l.hasPositionLimits() ? l.min_position : -M_PI;
      const double hi = l.hasPositionLimits() ? l.max_position : M_PI;
      q[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
    }
    out.push_back(q);
  }
  return out;
}

/// The hard points: zeros, every joint at its lower and at its upper limit, alternating limits.
std::vector<Eigen::VectorXd> limitPositions(const ArmModel& model)
{
  const int n = model.dof();
  Eigen::VectorXd lo(n), hi(n), alt(n);
  for (int i = 0; i < n; ++i)
  {
    lo[i] = model.joints()[static_cast<std::size_t>(i)].limits.min_position;
    hi[i] = model.joints()[static_cast<std::size_t>(i)].limits.max_position;
    alt[i] = i % 2 == 0 ? lo[i] : hi[i];
  }
  return { Eigen::VectorXd::Zero(n), lo, hi, alt };
}

Eigen::VectorXd vec(std::initializer_list<double> v)
{
  Eigen::VectorXd q(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v)
    q[i++] = x;
  return q;
}

/// UR5e singular configurations (rank J < 6, checked in Ur5eForwardKinematicsIsTheStandardDhProduct):
/// wrist (q5 = 0: axes 4 and 6 parallel), elbow (q3 = 0: the arm stretched), the arm upright with
/// both at once (rank 3), and the zero pose turned about the base.
std::vector<Eigen::VectorXd> ur5eSingular()
{
  return { vec({ 0.3, -1.0, 1.2, 0.4, 0.0, 0.7 }), vec({ 0.3, -1.0, 0.0, 0.4, 1.1, 0.7 }),
           vec({ 0.0, -M_PI / 2, 0.0, -M_PI / 2, 0.0, 0.0 }), vec({ 1.0, 0.0, 0.0, 0.0, 0.0, 0.0 }) };
}

/// Panda singular configurations (rank J < 6, checked in PandaForwardKinematicsIsTheModifiedDhProduct):
/// q2 = 0 (axes 1 and 3 on one line) with q3 = ±π/2, within the limits; the stretched arm at zero
/// (q4 = 0 is outside the limits, FK does not care).
std::vector<Eigen::VectorXd> pandaSingular()
{
  return { vec({ 0.0, 0.0, M_PI / 2, -M_PI / 2, 0.0, M_PI / 2, 0.0 }),
           vec({ 0.7, 0.0, -M_PI / 2, -3.0, M_PI / 2, 2.0, -1.0 }), vec({ 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0 }) };
}

/// The smallest of J's six singular values.
double smallestSingularValue(const ArmModel& model, const Eigen::VectorXd& q)
{
  return Eigen::JacobiSVD<Eigen::MatrixXd>(Eigen::MatrixXd(model.jacobian(q))).singularValues()[5];
}

void expectNear(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double tol, const std::string& what)
{
  ASSERT_EQ(a.rows(), b.rows()) << what;
  ASSERT_EQ(a.cols(), b.cols()) << what;
  EXPECT_LE((a - b).cwiseAbs().maxCoeff(), tol) << what << "\n" << a << "\nvs\n" << b;
}

/// Every claim against KDL and finite differences at q: FK, J (KDL's rows [ṗ; ω] swapped to [ω; ṗ]),
/// J by central differences of FK, J̇ by central differences of J along a q̇.
void checkAgainstKdl(const ArmModel& model, const KDL::Chain& chain, const Eigen::VectorXd& q, const std::string& what)
{
  KDL::JntArray kq(static_cast<unsigned>(q.size()));
  kq.data = q;
  KDL::Frame f;
  ASSERT_GE(KDL::ChainFkSolverPos_recursive(chain).JntToCart(kq, f), 0);
  expectNear(model.base_T_tip(q).matrix(), test::toMatrix(f), 1e-12, what + " FK vs KDL");
  KDL::Jacobian kj(chain.getNrOfJoints());
  ASSERT_GE(KDL::ChainJntToJacSolver(chain).JntToJac(kq, kj), 0);
  Eigen::MatrixXd kdl_omega_first(6, q.size());
  kdl_omega_first << kj.data.bottomRows(3), kj.data.topRows(3);
  const Eigen::MatrixXd j = model.jacobian(q);
  expectNear(j, kdl_omega_first, 1e-12, what + " J vs KDL");
  expectNear(j, test::finiteDifferenceJacobian(model, q, 1e-6), 1e-8, what + " J vs FD");
  const Eigen::VectorXd qd = Eigen::VectorXd::LinSpaced(q.size(), 0.9, -0.7);
  expectNear(model.jacobianDerivative(q, qd), test::finiteDifferenceJacobianRate(model, q, qd, 1e-6), 1e-8,
             what + " J̇ vs FD");
}
}  // namespace

TEST(ArmModel, Ur5eChainAndLimitsFromTheUrdf)
{
  const ArmModel m = ur5e();
  EXPECT_EQ(m.dof(), 6);
  EXPECT_EQ(m.jointNames(), (std::vector<std::string>{ "shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                                       "wrist_1_joint", "wrist_2_joint", "wrist_3_joint" }));
  for (const ArmJoint& j : m.joints())
  {
    EXPECT_EQ(j.type, JointType::kRevolute);
    EXPECT_EQ(j.limits.min_position, -2 * M_PI);
    EXPECT_EQ(j.limits.max_position, 2 * M_PI);
    EXPECT_EQ(j.limits.max_velocity, M_PI);
    EXPECT_FALSE(j.limits.hasAccelerationLimit());
  }
  EXPECT_TRUE(m.last_T_tip().isApprox(Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.0996)), 1e-15));
}

TEST(ArmModel, Ur5eForwardKinematicsIsTheStandardDhProduct)
{
  const ArmModel m = ur5e();
  std::vector<Eigen::VectorXd> qs = randomPositions(m, 200, 1);
  for (const auto& set : { limitPositions(m), ur5eSingular() })
    qs.insert(qs.end(), set.begin(), set.end());
  for (const Eigen::VectorXd& q : qs)
    expectNear(m.base_T_tip(q).matrix(), test::ur5eDh(q), 1e-12, "UR5e at " + ::testing::PrintToString(q));
  for (const Eigen::VectorXd& q : ur5eSingular())
    EXPECT_LT(smallestSingularValue(m, q), 1e-12) << ::testing::PrintToString(q);
  // At zero the arm lies stretched along −x (a2 + a3), the flange pointing down the wrist offsets.
  const Eigen::Vector3d p0 = m.base_T_tip(Eigen::VectorXd::Zero(6)).translation();
  EXPECT_TRUE(p0.isApprox(Eigen::Vector3d(-0.425 - 0.3922, -0.1333 - 0.0996, 0.1625 - 0.0997), 1e-15)) << p0;
}

TEST(ArmModel, PandaForwardKinematicsIsTheModifiedDhProduct)
{
  const ArmModel m = panda();
  EXPECT_EQ(m.dof(), 7);
  std::vector<Eigen::VectorXd> qs = randomPositions(m, 200, 2);
  for (const auto& set : { limitPositions(m), pandaSingular() })
    qs.insert(qs.end(), set.begin(), set.end());
  const ArmModel tcp = panda("panda_hand_tcp");
  Eigen::Isometry3d flange_T_tcp = Eigen::Isometry3d::Identity();
  flange_T_tcp.rotate(Eigen::AngleAxisd(-M_PI / 4, Eigen::Vector3d::UnitZ())).translate(Eigen::Vector3d(0, 0, 0.1034));
  for (const Eigen::VectorXd& q : qs)
  {
    const std::string at = "Panda at " + ::testing::PrintToString(q);
    expectNear(m.base_T_tip(q).matrix(), test::pandaDh(q), 1e-12, at);
    expectNear(tcp.base_T_tip(q).matrix(), test::pandaDh(q) * flange_T_tcp.matrix(), 1e-12, at + " (TCP)");
  }
  for (const Eigen::VectorXd& q : pandaSingular())
    EXPECT_LT(smallestSingularValue(m, q), 1e-12) << ::testing::PrintToString(q);
}

TEST(ArmModel, PandaLimitsFromTheUrdfAndTheLimitsFile)
{
  ArmModel m = panda();
  const double lo[] = { -2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973 };
  const double hi[] = { 2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973 };
  const double vel[] = { 2.1750, 2.1750, 2.1750, 2.1750, 2.6100, 2.6100, 2.6100 };
  const double acc[] = { 15, 7.5, 10, 12.5, 15, 20, 20 };
  const double jerk[] = { 7500, 3750, 5000, 6250, 7500, 10000, 10000 };
  m.applyLimits(readJointLimitsFile(robotFile("panda_joint_limits.yaml")));
  for (std::size_t i = 0; i < 7; ++i)
  {
    const JointLimits& l = m.joints()[i].limits;
    EXPECT_EQ(m.joints()[i].name, "panda_joint" + std::to_string(i + 1));
    EXPECT_EQ(l.min_position, lo[i]);
    EXPECT_EQ(l.max_position, hi[i]);
    EXPECT_EQ(l.max_velocity, vel[i]);
    EXPECT_EQ(l.max_acceleration, acc[i]);
    EXPECT_EQ(l.max_jerk, jerk[i]);
  }
  // The UR5e file: accelerations 5 rad/s², no jerk limit; a file's velocity replaces the URDF's.
  ArmModel u = ur5e();
  u.applyLimits(readJointLimitsFile(robotFile("ur5e_joint_limits.yaml")));
  for (const ArmJoint& j : u.joints())
  {
    EXPECT_EQ(j.limits.max_acceleration, 5.0);
    EXPECT_FALSE(j.limits.hasJerkLimit());
  }
  u.applyLimits(
      parseJointLimits("joint_limits: {elbow_joint: {has_velocity_limits: true, max_velocity: 1.5,"
                       " has_position_limits: true, min_position: -1, max_position: 2},"
                       " wrist_1_joint: {has_velocity_limits: false, max_velocity: 0.1}}"));
  EXPECT_EQ(u.joints()[2].limits.max_velocity, 1.5);
  EXPECT_EQ(u.joints()[2].limits.min_position, -1.0);
  EXPECT_EQ(u.joints()[2].limits.max_position, 2.0);
  EXPECT_EQ(u.joints()[3].limits.max_velocity, M_PI);  // has_velocity_limits false: the URDF's stays
}

TEST(ArmModel, Ur5eAndPandaAgreeWithKdlAndFiniteDifferences)
{
  for (const std::string tip : { "panda_link8", "panda_hand_tcp", "panda_link4" })
  {
    const ArmModel m = panda(tip);
    const KDL::Chain chain = test::kdlChain(readText(robotFile("panda.urdf")), "base_link", tip);
    ASSERT_EQ(static_cast<int>(chain.getNrOfJoints()), m.dof());
    std::vector<Eigen::VectorXd> qs = randomPositions(m, 50, 3);
    if (m.dof() == 7)
      for (const auto& set : { limitPositions(m), pandaSingular() })
        qs.insert(qs.end(), set.begin(), set.end());
    for (const Eigen::VectorXd& q : qs)
      checkAgainstKdl(m, chain, q, "Panda to " + tip + " at " + ::testing::PrintToString(q));
  }
  const ArmModel u = ur5e();
  const KDL::Chain chain = test::kdlChain(readText(robotFile("ur5e.urdf")), "base_link", "tool0");
  std::vector<Eigen::VectorXd> qs = randomPositions(u, 50, 4);
  for (const auto& set : { limitPositions(u), ur5eSingular() })
    qs.insert(qs.end(), set.begin(), set.end());
  for (const Eigen::VectorXd& q : qs)
    checkAgainstKdl(u, chain, q, "UR5e at " + ::testing::PrintToString(q));
}

/// tipJerk at q along random joint rates: against the central differences of the tip's acceleration
/// (J q̈ + J̇ q̇, each checked above against KDL and differences) and, for p⃛, of FK alone; linear
/// in q⃛ with J as its coefficient.
void checkTipJerk(const ArmModel& model, const Eigen::VectorXd& q, unsigned seed, const std::string& what)
{
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const auto random = [&] {
    Eigen::VectorXd v(q.size());
    for (Eigen::Index i = 0; i < v.size(); ++i)
      v[i] = u(rng);
    return v;
  };
  const test::CubicJointMotion m{ q, random(), random(), random() };
  ArmFrames f;
  model.frames(q, &f);
  const TipVector jerk = model.tipJerk(f, m.qd, m.qdd, m.qddd);
  expectNear(jerk, test::finiteDifferenceTipJerk(model, m, 1e-5), 1e-6, what + " tip jerk vs differences of J q̈ + J̇ q̇");
  expectNear(jerk.tail<3>(), test::finiteDifferenceTipLinearJerk(model, m, 5e-4), 2e-4,
             what + " p⃛ vs differences of FK");
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(q.size());
  expectNear(jerk - model.tipJerk(f, m.qd, m.qdd, zero), model.jacobian(f) * m.qddd, 1e-12, what + " linear in q⃛");
}

TEST(ArmModel, TipJerkIsTheDerivativeOfTheTipAcceleration)
{
  unsigned seed = 10;
  for (const std::string tip : { "panda_link8", "panda_hand_tcp" })
  {
    const ArmModel m = panda(tip);
    std::vector<Eigen::VectorXd> qs = randomPositions(m, 20, 6);
    for (const auto& set : { limitPositions(m), pandaSingular() })
      qs.insert(qs.end(), set.begin(), set.end());
    for (const Eigen::VectorXd& q : qs)
      checkTipJerk(m, q, ++seed, "Panda to " + tip + " at " + ::testing::PrintToString(q));
  }
  const ArmModel u = ur5e();
  std::vector<Eigen::VectorXd> qs = randomPositions(u, 20, 7);
  for (const auto& set : { limitPositions(u), ur5eSingular() })
    qs.insert(qs.end(), set.begin(), set.end());
  for (const Eigen::VectorXd& q : qs)
    checkTipJerk(u, q, ++seed, "UR5e at " + ::testing::PrintToString(q));
}

TEST(ArmModel, OnePassKinematicsAndThePoseTypeAgree)
{
  const ArmModel m = panda("panda_hand_tcp");
  const Eigen::VectorXd q = randomPositions(m, 1, 5)[0];
  const Eigen::VectorXd qd = Eigen::VectorXd::LinSpaced(7, -1.0, 1.0);
  Eigen::Isometry3d t;
  ArmJacobian j, jd;
  m.kinematics(q, qd, &t, &j, &jd);
  EXPECT_EQ(t.matrix(), m.base_T_tip(q).matrix());
  EXPECT_EQ(Eigen::MatrixXd(j), Eigen::MatrixXd(m.jacobian(q)));
  EXPECT_EQ(Eigen::MatrixXd(jd), Eigen::MatrixXd(m.jacobianDerivative(q, qd)));
  const Pose<double> x = m.basePoseOfTip(q);
  EXPECT_TRUE(x.p.isApprox(t.translation(), 1e-15));
  EXPECT_LE((x.q.toRotationMatrix() - t.linear()).cwiseAbs().maxCoeff(), 1e-15);
  // Fixed-size vectors bind too.
  const Eigen::Matrix<double, 7, 1> q7 = q;
  EXPECT_EQ(m.base_T_tip(q7).matrix(), t.matrix());
}

TEST(ArmModel, KinematicsAllocateNothing)
{
  const ArmModel m = panda("panda_hand_tcp");
  const Eigen::Matrix<double, 7, 1> q = randomPositions(m, 1, 6)[0];
  const Eigen::Matrix<double, 7, 1> qd = Eigen::Matrix<double, 7, 1>::Constant(0.5);
  Eigen::Isometry3d t;
  ArmJacobian j, jd;
  const long before = test::allocationCount();
  for (int k = 0; k < 10; ++k)
  {
    t = m.base_T_tip(q);
    j = m.jacobian(q);
    jd = m.jacobianDerivative(q, qd);
    m.kinematics(q, qd, &t, &j, &jd);
  }
  EXPECT_EQ(test::allocationCount() - before, 0);
  EXPECT_EQ(j.cols(), 7);
}
