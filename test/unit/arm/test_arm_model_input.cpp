// arm/arm_model.h and arm/joint_limits.h on hand-written input: a chain with a prismatic joint, a
// continuous joint, a non-unit axis, fixed joints between them, a branch off the chain and a fixed
// TCP (FK against the product written here, J and J̇ against KDL and finite differences); every
// bad input refused with a message naming the file, link, joint or field.
#include <gtest/gtest.h>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>

#include "arm/arm_test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::arm;

namespace
{
/// base_link —rail (prismatic x)→ carriage —mount (fixed: z 0.5, yaw π/2)→ mount —spin (continuous
/// z at x 0.1, no <limit>)→ spinner —tilt (revolute about "0 2 0" at x 0.2)→ arm —tcp (fixed: x 0.3)→
/// tool; a camera link hangs off the carriage (a branch off the chain).
const char* kMixedUrdf = R"(<robot name="mixed">
  <link name="base_link"/><link name="carriage"/><link name="mount"/><link name="spinner"/>
  <link name="arm"/><link name="tool"/><link name="camera"/>
  <joint name="rail" type="prismatic"><parent link="base_link"/><child link="carriage"/>
    <axis xyz="1 0 0"/><limit lower="-0.5" upper="1.5" effort="100" velocity="0.8"/></joint>
  <joint name="camera_mount" type="fixed"><parent link="carriage"/><child link="camera"/>
    <origin xyz="0 1 0"/></joint>
  <joint name="mount" type="fixed"><parent link="carriage"/><child link="mount"/>
    <origin xyz="0 0 0.5" rpy="0 0 1.5707963267948966"/></joint>
  <joint name="spin" type="continuous"><parent link="mount"/><child link="spinner"/>
    <origin xyz="0.1 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="tilt" type="revolute"><parent link="spinner"/><child link="arm"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 2 0"/><limit lower="-1" upper="1" effort="10" velocity="2"/></joint>
  <joint name="tcp" type="fixed"><parent link="arm"/><child link="tool"/><origin xyz="0.3 0 0"/></joint>
</robot>)";

Eigen::Isometry3d mixedFk(const Eigen::VectorXd& q)
{
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translate(Eigen::Vector3d(q[0], 0, 0))
      .translate(Eigen::Vector3d(0, 0, 0.5))
      .rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()))
      .translate(Eigen::Vector3d(0.1, 0, 0))
      .rotate(Eigen::AngleAxisd(q[1], Eigen::Vector3d::UnitZ()))
      .translate(Eigen::Vector3d(0.2, 0, 0))
      .rotate(Eigen::AngleAxisd(q[2], Eigen::Vector3d::UnitY()))
      .translate(Eigen::Vector3d(0.3, 0, 0));
  return t;
}

/// `text` with the first `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to)
{
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

/// Runs f, expects ArmModelError with every one of `parts` in its message.
template <class F>
void expectRefused(F f, std::initializer_list<std::string> parts)
{
  try
  {
    f();
    ADD_FAILURE() << "not refused";
  }
  catch (const ArmModelError& e)
  {
    const std::string what = e.what();
    for (const std::string& p : parts)
      EXPECT_NE(what.find(p), std::string::npos) << "'" << p << "' not in: " << what;
  }
}

ArmModel mixed()
{
  return ArmModel(kMixedUrdf, "base_link", "tool", "mixed.urdf");
}

ArmModel ur5e()
{
  return ArmModel::fromUrdfFile(test::robotFile("ur5e.urdf"), "base_link", "tool0");
}
}  // namespace

TEST(ArmModelInput, PrismaticContinuousAndFixedJointsInTheMiddle)
{
  const ArmModel m = mixed();
  ASSERT_EQ(m.jointNames(), (std::vector<std::string>{ "rail", "spin", "tilt" }));
  EXPECT_EQ(m.joints()[0].type, JointType::kPrismatic);
  EXPECT_EQ(m.joints()[1].type, JointType::kContinuous);
  EXPECT_EQ(m.joints()[2].type, JointType::kRevolute);
  EXPECT_EQ(m.joints()[2].axis, Eigen::Vector3d::UnitY());
  // Limits: the rail's from its <limit> (m, m/s), none for the continuous joint without <limit>.
  EXPECT_EQ(m.joints()[0].limits.min_position, -0.5);
  EXPECT_EQ(m.joints()[0].limits.max_position, 1.5);
  EXPECT_EQ(m.joints()[0].limits.max_velocity, 0.8);
  EXPECT_FALSE(m.joints()[1].limits.hasPositionLimits());
  EXPECT_FALSE(m.joints()[1].limits.hasVelocityLimit());
  EXPECT_EQ(m.joints()[2].limits.max_velocity, 2.0);

  const KDL::Chain chain = test::kdlChain(kMixedUrdf, "base_link", "tool");
  KDL::ChainFkSolverPos_recursive fk(chain);
  KDL::ChainJntToJacSolver jac(chain);
  for (const Eigen::VectorXd& q :
       { Eigen::VectorXd(Eigen::Vector3d(0, 0, 0)), Eigen::VectorXd(Eigen::Vector3d(0.7, 2.5, -0.4)),
         Eigen::VectorXd(Eigen::Vector3d(-0.5, -3.0, 1.0)), Eigen::VectorXd(Eigen::Vector3d(1.5, 7.0, 0.3)) })
  {
    const std::string at = ::testing::PrintToString(q);
    EXPECT_LE((m.base_T_tip(q).matrix() - mixedFk(q).matrix()).cwiseAbs().maxCoeff(), 1e-15) << at;
    KDL::JntArray kq(3);
    kq.data = q;
    KDL::Frame f;
    KDL::Jacobian kj(3);
    ASSERT_GE(fk.JntToCart(kq, f), 0);
    ASSERT_GE(jac.JntToJac(kq, kj), 0);
    EXPECT_LE((m.base_T_tip(q).matrix() - test::toMatrix(f)).cwiseAbs().maxCoeff(), 1e-15) << at;
    Eigen::MatrixXd kdl_omega_first(6, 3);
    kdl_omega_first << kj.data.bottomRows(3), kj.data.topRows(3);
    const Eigen::MatrixXd j = m.jacobian(q);
    EXPECT_LE((j - kdl_omega_first).cwiseAbs().maxCoeff(), 1e-15) << at << "\n" << j;
    EXPECT_LE((j - test::finiteDifferenceJacobian(m, q, 1e-6)).cwiseAbs().maxCoeff(), 1e-8) << at;
    // The prismatic column: no rotation, the rail's direction x.
    EXPECT_EQ(j.col(0), (Eigen::Matrix<double, 6, 1>() << 0, 0, 0, 1, 0, 0).finished()) << at;
    const Eigen::VectorXd qd = Eigen::Vector3d(0.6, -1.3, 0.9);
    const Eigen::MatrixXd jd = m.jacobianDerivative(q, qd);
    EXPECT_LE((jd - test::finiteDifferenceJacobianRate(m, q, qd, 1e-6)).cwiseAbs().maxCoeff(), 1e-8) << at;
  }
  // A tip inside the chain (the rail's child): one prismatic joint, the fixed mount excluded.
  const ArmModel rail(kMixedUrdf, "base_link", "carriage");
  EXPECT_EQ(rail.dof(), 1);
  EXPECT_TRUE(rail.last_T_tip().isApprox(Eigen::Isometry3d::Identity()));
  // A base inside the chain: the chain from the mount to the tool.
  EXPECT_EQ(ArmModel(kMixedUrdf, "mount", "tool").jointNames(), (std::vector<std::string>{ "spin", "tilt" }));
}

TEST(ArmModelInput, PrismaticJointsBetweenRevoluteJoints)
{
  // A turning base, a tilted telescope (prismatic along a skew axis) and a wrist: the prismatic
  // axis turns with the links before it, so its J̇ column is not zero.
  const char* urdf = R"(<robot name="telescope">
    <link name="b"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="t"/>
    <joint name="turn" type="revolute"><parent link="b"/><child link="l1"/><origin xyz="0 0 0.3"/>
      <axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
    <joint name="reach" type="prismatic"><parent link="l1"/><child link="l2"/><origin xyz="0.1 0 0" rpy="0.2 -0.5 0.1"/>
      <axis xyz="1 0 1"/><limit lower="0" upper="0.5" effort="1" velocity="1"/></joint>
    <joint name="wrist" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0 0.05 0.1"/>
      <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
    <joint name="flange" type="fixed"><parent link="l3"/><child link="t"/><origin xyz="0.2 0 0" rpy="0 0.3 0"/></joint>
  </robot>)";
  const ArmModel m(urdf, "b", "t");
  const KDL::Chain chain = test::kdlChain(urdf, "b", "t");
  KDL::ChainJntToJacSolver jac(chain);
  for (const Eigen::Vector3d& q3 : { Eigen::Vector3d(0.4, 0.2, -0.7), Eigen::Vector3d(-2.0, 0.45, 1.3) })
  {
    const Eigen::VectorXd q = q3;
    KDL::JntArray kq(3);
    kq.data = q;
    KDL::Jacobian kj(3);
    ASSERT_GE(jac.JntToJac(kq, kj), 0);
    Eigen::MatrixXd kdl_omega_first(6, 3);
    kdl_omega_first << kj.data.bottomRows(3), kj.data.topRows(3);
    EXPECT_LE((Eigen::MatrixXd(m.jacobian(q)) - kdl_omega_first).cwiseAbs().maxCoeff(), 1e-15);
    const Eigen::VectorXd qd = Eigen::Vector3d(1.1, -0.4, 0.8);
    const Eigen::MatrixXd jd = m.jacobianDerivative(q, qd);
    EXPECT_GT(jd.col(1).norm(), 0.1);
    EXPECT_LE((jd - test::finiteDifferenceJacobianRate(m, q, qd, 1e-6)).cwiseAbs().maxCoeff(), 1e-8);
    // The tip's jerk: the sliding joint's Coriolis terms (it slides along a turning axis).
    const test::CubicJointMotion motion{ q, qd, Eigen::Vector3d(-0.9, 1.7, 0.5), Eigen::Vector3d(2.0, -1.2, 1.5) };
    ArmFrames f;
    m.frames(q, &f);
    const TipVector jerk = m.tipJerk(f, motion.qd, motion.qdd, motion.qddd);
    EXPECT_LE((jerk - test::finiteDifferenceTipJerk(m, motion, 1e-5)).cwiseAbs().maxCoeff(), 1e-6) << jerk;
    EXPECT_LE((jerk.tail<3>() - test::finiteDifferenceTipLinearJerk(m, motion, 5e-4)).cwiseAbs().maxCoeff(), 2e-4);
  }
}

TEST(ArmModelInput, BadUrdfsAndLinksAreRefusedByName)
{
  expectRefused([] { ArmModel("<robot name='x'><link", "a", "b", "broken.urdf"); },
                { "broken.urdf", "not a valid URDF" });
  expectRefused([] { ArmModel("", "a", "b", "empty.urdf"); }, { "empty.urdf" });
  expectRefused([] { ArmModel::fromUrdfFile("/nonexistent/robot.urdf", "a", "b"); },
                { "/nonexistent/robot.urdf", "cannot be read" });
  // A long path keeps its end, the file's name.
  expectRefused(
      [] { ArmModel::fromUrdfFile("/nonexistent/catkin_ws/src/my_robot_description/urdf/my_robot.urdf", "a", "b"); },
      { "URDF file '.../my_robot_description/urdf/my_robot.urdf': cannot be read" });
  expectRefused([] { ArmModel(kMixedUrdf, "base", "tool", "mixed.urdf"); },
                { "mixed.urdf", "'base'", "not in the URDF" });
  expectRefused([] { ArmModel(kMixedUrdf, "base_link", "tool0", "mixed.urdf"); }, { "'tool0'", "not in the URDF" });
  expectRefused([] { ArmModel(kMixedUrdf, "tool", "base_link", "mixed.urdf"); },
                { "'base_link'", "not a descendant of base link 'tool'" });
  expectRefused([] { ArmModel(kMixedUrdf, "camera", "tool", "mixed.urdf"); },
                { "'tool'", "not a descendant", "'camera'" });
  expectRefused([] { ArmModel(kMixedUrdf, "tool", "tool", "mixed.urdf"); }, { "same link 'tool'" });
  expectRefused([] { ArmModel(kMixedUrdf, "carriage", "camera", "mixed.urdf"); }, { "no movable joint" });
  // Joints on the chain: a floating joint, a zero axis, lower > upper, a negative or zero velocity,
  // a mimic joint.
  expectRefused(
      [] { ArmModel(replaced(kMixedUrdf, "type=\"continuous\"", "type=\"floating\""), "base_link", "tool", "m.urdf"); },
      { "m.urdf", "joint 'spin'", "floating" });
  expectRefused([] { ArmModel(replaced(kMixedUrdf, "xyz=\"0 2 0\"", "xyz=\"0 0 0\""), "base_link", "tool", "m.urdf"); },
                { "joint 'tilt'", "<axis>" });
  expectRefused(
      [] {
        ArmModel(replaced(kMixedUrdf, "lower=\"-1\" upper=\"1\"", "lower=\"1\" upper=\"-1\""), "base_link", "tool");
      },
      { "joint 'tilt'", "lower 1 > upper -1" });
  expectRefused([] { ArmModel(replaced(kMixedUrdf, "velocity=\"0.8\"", "velocity=\"-0.8\""), "base_link", "tool"); },
                { "joint 'rail'", "velocity -0.80000000000000004", "positive" });
  expectRefused([] { ArmModel(replaced(kMixedUrdf, "velocity=\"2\"", "velocity=\"0\""), "base_link", "tool"); },
                { "joint 'tilt'", "velocity 0" });
  expectRefused(
      [] {
        ArmModel(replaced(kMixedUrdf, "<axis xyz=\"0 2 0\"/>", "<axis xyz=\"0 2 0\"/><mimic joint=\"spin\"/>"),
                 "base_link", "tool");
      },
      { "joint 'tilt'", "mimic" });
  // Joints off the chain may be anything.
  EXPECT_EQ(ArmModel(replaced(kMixedUrdf, "type=\"fixed\"><parent link=\"carriage\"/><child link=\"camera\"/>",
                              "type=\"floating\"><parent link=\"carriage\"/><child link=\"camera\"/>"),
                     "base_link", "tool")
                .dof(),
            3);
}

TEST(ArmModelInput, BadJointVectorsAreRefusedByName)
{
  const ArmModel m = ur5e();
  expectRefused([&] { m.base_T_tip(Eigen::VectorXd::Zero(5)); },
                { "q: 5 entries", "the chain 'base_link' → 'tool0' has 6 joints" });
  Eigen::VectorXd q = Eigen::VectorXd::Zero(6);
  q[2] = std::nan("");
  expectRefused([&] { m.jacobian(q); }, { "q[2] (joint 'elbow_joint'): not finite (nan)" });
  q[2] = 0.0;
  q[5] = INFINITY;
  expectRefused([&] { m.basePoseOfTip(q); }, { "q[5] (joint 'wrist_3_joint'): not finite (inf)" });
  q[5] = 0.0;
  expectRefused([&] { m.jacobianDerivative(q, Eigen::VectorXd::Zero(7)); }, { "qd: 7 entries" });
  Eigen::VectorXd qd = Eigen::VectorXd::Zero(6);
  qd[0] = -INFINITY;
  EXPECT_NO_THROW(m.kinematics(q, qd, nullptr, nullptr, nullptr));  // qd is read for J̇ only
  expectRefused(
      [&] {
        ArmJacobian jd;
        m.kinematics(q, qd, nullptr, nullptr, &jd);
      },
      { "qd[0] (joint 'shoulder_pan_joint'): not finite (-inf)" });
}

TEST(ArmModelInput, BadLimitsFilesAreRefusedByName)
{
  const auto parse = [](const std::string& text) { return parseJointLimits(text, "limits.yaml"); };
  expectRefused([&] { parse("joint_limits: [a, b"); }, { "limits.yaml", "not valid YAML", "line 1" });
  expectRefused([&] { parse("other: 1"); }, { "limits.yaml", "joint_limits: missing" });
  expectRefused([&] { parse("joint_limits: 3"); }, { "joint_limits: not a map" });
  expectRefused([&] { parse("joint_limits: {j1: 3}"); }, { "joint_limits.'j1': not a map" });
  expectRefused([&] { parse("joint_limits: {j1: {has_velocity_limits: true, max_velocity: -1}}"); },
                { "limits.yaml", "joint_limits.'j1'.max_velocity: -1 must be positive" });
  expectRefused([&] { parse("joint_limits: {j1: {has_acceleration_limits: true, max_acceleration: 0}}"); },
                { "joint_limits.'j1'.max_acceleration: 0 must be positive" });
  expectRefused([&] { parse("joint_limits: {j1: {has_jerk_limits: true, max_jerk: .nan}}"); },
                { "joint_limits.'j1'.max_jerk: nan is not finite" });
  expectRefused([&] { parse("joint_limits: {j1: {has_velocity_limits: true, max_velocity: .inf}}"); },
                { "max_velocity: inf is not finite" });
  expectRefused([&] { parse("joint_limits: {j1: {has_velocity_limits: true}}"); },
                { "joint_limits.'j1'.max_velocity: missing (has_velocity_limits is true)" });
  expectRefused([&] { parse("joint_limits: {j1: {has_velocity_limits: true, max_velocity: fast}}"); },
                { "joint_limits.'j1'.max_velocity: not a number" });
  expectRefused([&] { parse("joint_limits: {j1: {has_velocity_limits: maybe, max_velocity: 1}}"); },
                { "joint_limits.'j1'.has_velocity_limits: not a bool" });
  expectRefused([&] { parse("joint_limits: {j1: {has_velocity_limits: true, max_velocty: 1}}"); },
                { "joint_limits.'j1'.'max_velocty': unknown key" });
  expectRefused([&] { parse("joint_limits: {j1: {has_position_limits: true, min_position: 2, max_position: 1}}"); },
                { "joint_limits.'j1': min_position 2 > max_position 1" });
  expectRefused([] { readJointLimitsFile("/nonexistent/joint_limits.yaml"); },
                { "/nonexistent/joint_limits.yaml", "cannot be read" });
  // A value whose flag is false is not read (MoveIt's rule); MoveIt's top-level keys are ignored.
  const JointLimitsFile ok = parse(
      "default_velocity_scaling_factor: 0.1\n"
      "joint_limits: {j1: {has_velocity_limits: false, max_velocity: -5}}");
  EXPECT_FALSE(ok.joints.at("j1").max_velocity.has_value());

  // Against a model: a joint the URDF lacks is refused, and a position range on a continuous joint;
  // joints of the URDF off the chain are ignored.
  ArmModel m = mixed();
  expectRefused([&] { m.applyLimits(parse("joint_limits: {elbow: {has_velocity_limits: true, max_velocity: 1}}")); },
                { "limits.yaml", "joint 'elbow' is not in the URDF 'mixed.urdf'" });
  expectRefused(
      [&] {
        m.applyLimits(parse("joint_limits: {spin: {has_position_limits: true, min_position: -1, max_position: 1}}"));
      },
      { "limits.yaml", "joint 'spin'", "continuous joint has no position limits" });
  expectRefused([&] { parse("joint_limits: {rail: {has_position_limits: true, min_position: 1.6}}"); },
                { "joint_limits.'rail'.max_position: missing (has_position_limits is true)" });
  m.applyLimits(parse(
      "joint_limits: {camera_mount: {has_velocity_limits: true, max_velocity: 1},"
      " spin: {has_velocity_limits: true, max_velocity: 3, has_acceleration_limits: true, max_acceleration: 9}}"));
  EXPECT_EQ(m.joints()[1].limits.max_velocity, 3.0);
  EXPECT_EQ(m.joints()[1].limits.max_acceleration, 9.0);
  EXPECT_EQ(m.joints()[0].limits.max_velocity, 0.8);
}
