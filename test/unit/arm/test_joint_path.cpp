// arm/joint_path.h: the joint path of a pose motion checked against what does not depend on it:
// the motions are C² splines through poses made by the forward kinematics of joint configurations
// (so they are reachable), and the path's joint states must give back the motion's pose (FK), twist
// (J q̇), and be the derivatives of one another (central differences); KDL's Levenberg–Marquardt
// IK, seeded by the previous sample, finds the same joint positions for the UR5e; the refusals
// (out of reach, bad seed, a joint limit passed, a singular start, a chain of five joints) name
// what and where; a path close to the wrist singularity is followed.
#include <gtest/gtest.h>

#include <kdl/chainiksolverpos_lma.hpp>

#include "arm/arm_test_utils.h"
#include "se3_interpolation/arm/joint_path.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "spline_test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::arm;
using test::readText;
using test::robotFile;

namespace
{
using PoseCurve = std::shared_ptr<const Curve<ScrewSe3>>;

ArmModel ur5e(const std::string& tip = "tool0")
{
  return ArmModel::fromUrdfFile(robotFile("ur5e.urdf"), "base_link", tip);
}

ArmModel panda()
{
  return ArmModel::fromUrdfFile(robotFile("panda.urdf"), "base_link", "panda_link8");
}

Eigen::VectorXd vec(std::initializer_list<double> v)
{
  Eigen::VectorXd q(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v)
    q[i++] = x;
  return q;
}

/// The natural C² spline (screw geometry) through the FK poses of `configurations` at 0, 1, 2, ... s.
PoseCurve motionThrough(const ArmModel& arm, const std::vector<Eigen::VectorXd>& configurations)
{
  std::vector<Pose<double>> poses;
  std::vector<double> times;
  for (const Eigen::VectorXd& q : configurations)
  {
    poses.push_back(arm.basePoseOfTip(q));
    times.push_back(static_cast<double>(times.size()));
  }
  return test::spline<ScrewSe3>(poses, times, EndCondition::kNatural);
}

double rotationError(const Pose<double>& a, const Eigen::Isometry3d& b)
{
  return Eigen::AngleAxisd(a.q.toRotationMatrix() * b.linear().transpose()).angle();
}

/// Dense times of [start, end]: 200 intervals, every breakpoint.
std::vector<double> denseTimes(const JointPath& path)
{
  std::vector<double> t;
  for (int i = 0; i <= 200; ++i)
    t.push_back(path.start() + (path.end() - path.start()) * i / 200.0);
  t.insert(t.end(), path.breakpoints().begin(), path.breakpoints().end());
  return t;
}

/// FK(q(t)) is the curve's pose and J q̇ its twist, at the dense times on both sides.
void expectFollows(const JointPath& path, const Curve<ScrewSe3>& curve)
{
  const ArmModel& arm = path.arm();
  for (double t : denseTimes(path))
    for (Side side : { Side::kLeft, Side::kRight })
    {
      const JointState s = path.at(t, side);
      const Kinematics k = kinematicsAt(curve, t, side);
      const Eigen::Isometry3d x = arm.base_T_tip(s.position);
      EXPECT_LT((x.translation() - k.pose.p).norm(), 1e-9) << "t = " << t;
      EXPECT_LT(rotationError(k.pose, x), 1e-9) << "t = " << t;
      Eigen::Matrix<double, 6, 1> v;
      v << k.velocity.angular, k.velocity.linear;
      // J q̇ = V to the rounding of a 6 × 6 solve: 1e-9 relative to the twist (condition ≲ 10³).
      EXPECT_LT((arm.jacobian(s.position) * s.velocity - v).norm(), 1e-9 * (1 + v.norm())) << "t = " << t;
    }
}

/// Central differences (step δ = 1e-5 s) of q and q̇ equal q̇ and q̈, away from the breakpoints.
/// Their error is δ²/6 |q⃛| (about 1e-10 here) plus the rounding of the Newton solves (1e-12 rad)
/// over 2δ (5e-8): 1e-6 (1 + |value|) leaves a margin of 20.
void expectDerivatives(const JointPath& path)
{
  const double d = 1e-5;
  for (int i = 0; i < 100; ++i)
  {
    const double t = path.start() + (path.end() - path.start()) * (i + 0.37) / 100.0;
    const bool near_break = std::any_of(path.breakpoints().begin(), path.breakpoints().end(),
                                        [&](double b) { return std::abs(b - t) <= 2 * d; });
    if (near_break)
      continue;
    const JointState s = path.at(t), p = path.at(t + d), m = path.at(t - d);
    const Eigen::VectorXd qd = (p.position - m.position) / (2 * d);
    const Eigen::VectorXd qdd = (p.velocity - m.velocity) / (2 * d);
    EXPECT_LT((qd - s.velocity).lpNorm<Eigen::Infinity>(), 1e-6 * (1 + s.velocity.lpNorm<Eigen::Infinity>()));
    EXPECT_LT((qdd - s.acceleration).lpNorm<Eigen::Infinity>(), 1e-6 * (1 + s.acceleration.lpNorm<Eigen::Infinity>()));
    const JointState later = path.at(std::min(t + 1e-9, path.end()));
    EXPECT_LT((later.position - s.position).lpNorm<Eigen::Infinity>(), 1e-6);
  }
}

std::string messageOf(const std::function<void()>& f)
{
  try
  {
    f();
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "(no error)";
}

/// The pose motion of the joint motion q(t) = a + (b − a)(3t² − 2t³) on [0, 1] (FK; V = J q̇,
/// A = J q̈ + J̇ q̇), and that joint motion.
struct JointSweep
{
  Eigen::VectorXd a, b;
  JointState at(double t) const
  {
    const double s = t * t * (3 - 2 * t), sd = 6 * t * (1 - t), sdd = 6 - 12 * t;
    return JointState{ a + (b - a) * s, (b - a) * sd, (b - a) * sdd, Eigen::VectorXd() };
  }
  PoseMotion motion(const ArmModel& arm) const
  {
    return [arm, self = *this](double t, Side) {
      const JointState s = self.at(t);
      Eigen::Isometry3d x;
      ArmJacobian j, jd;
      arm.kinematics(s.position, s.velocity, &x, &j, &jd);
      const Eigen::Matrix<double, 6, 1> v = j * s.velocity, acc = j * s.acceleration + jd * s.velocity;
      Kinematics k;
      k.pose = Pose<double>(Quaternion<double>(x.linear()), x.translation());
      k.velocity.angular = v.head<3>(), k.velocity.linear = v.tail<3>();
      k.acceleration.angular = acc.head<3>(), k.acceleration.linear = acc.tail<3>();
      return k;
    };
  }
};

const Eigen::VectorXd kUrA = vec({ 0.3, -1.2, 1.4, -1.8, -1.5, 0.4 });
const Eigen::VectorXd kUrB = vec({ 0.6, -1.0, 1.1, -1.6, -1.3, 0.8 });
const Eigen::VectorXd kUrC = vec({ 0.9, -1.3, 1.5, -1.2, -1.6, 1.2 });
const Eigen::VectorXd kPandaA = vec({ 0.2, -0.5, 0.1, -2.0, 0.1, 1.6, 0.8 });
const Eigen::VectorXd kPandaB = vec({ 0.5, -0.3, 0.2, -1.8, 0.2, 1.8, 1.2 });
const Eigen::VectorXd kPandaC = vec({ 0.7, -0.6, 0.0, -2.2, -0.1, 1.5, 0.5 });
}  // namespace

TEST(JointPath, Ur5eFollowsTheMotionOnTheSeedsBranch)
{
  const ArmModel arm = ur5e();
  const PoseCurve curve = motionThrough(arm, { kUrA, kUrB, kUrC });
  const JointPath path = jointPathOf(arm, curve, kUrA);
  EXPECT_TRUE(path.heldJoints().empty());
  EXPECT_LT((path.at(path.start()).position - kUrA).lpNorm<Eigen::Infinity>(), 1e-9);
  // Through FK(kUrB) at t = 1 on the same branch: the UR5e's IK is locally unique.
  EXPECT_LT((path.at(1.0).position - kUrB).lpNorm<Eigen::Infinity>(), 1e-9);
  EXPECT_LT((path.at(path.end()).position - kUrC).lpNorm<Eigen::Infinity>(), 1e-9);
  expectFollows(path, *curve);
  expectDerivatives(path);
}

TEST(JointPath, Ur5eRecoversTheJointMotionOfAPoseMotion)
{
  // The UR5e's IK is locally unique, so the path of FK(q(t)) from q(0) is q(t) itself, with its
  // rates: q to the pose tolerance through J_r⁻¹ (1e-9), q̇ and q̈ to the rounding of the solves.
  const ArmModel arm = ur5e();
  const JointSweep joint{ kUrA, kUrC };
  const JointPath path(arm, joint.motion(arm), { 0.0, 1.0 }, kUrA);
  for (int i = 0; i <= 100; ++i)
  {
    const double t = i / 100.0;
    const JointState s = path.at(t), expected = joint.at(t);
    EXPECT_LT((s.position - expected.position).lpNorm<Eigen::Infinity>(), 1e-9) << "t = " << t;
    EXPECT_LT((s.velocity - expected.velocity).lpNorm<Eigen::Infinity>(), 1e-8) << "t = " << t;
    EXPECT_LT((s.acceleration - expected.acceleration).lpNorm<Eigen::Infinity>(), 1e-7) << "t = " << t;
  }
}

TEST(JointPath, SeedAwayFromTheSolutionFindsTheSameBranch)
{
  const ArmModel arm = ur5e();
  const PoseCurve curve = motionThrough(arm, { kUrA, kUrB });
  const Eigen::VectorXd seed = kUrA + vec({ 0.5, -0.4, 0.3, 0.5, -0.5, 0.5 });
  const JointPath path = jointPathOf(arm, curve, seed);
  EXPECT_LT((path.at(path.start()).position - kUrA).lpNorm<Eigen::Infinity>(), 1e-9);
}

TEST(JointPath, Ur5eEqualsKdlLevenbergMarquardtSeededByThePreviousSample)
{
  const ArmModel arm = ur5e();
  const PoseCurve curve = motionThrough(arm, { kUrA, kUrB, kUrC });
  const JointPath path = jointPathOf(arm, curve, kUrA);
  const KDL::Chain chain = test::kdlChain(readText(robotFile("ur5e.urdf")), "base_link", "tool0");
  KDL::ChainIkSolverPos_LMA solver(chain, 1e-12, 1000, 1e-15);
  KDL::JntArray previous(6), out(6);
  previous.data = kUrA;
  for (int i = 0; i <= 100; ++i)
  {
    const double t = path.end() * i / 100.0;
    const Pose<double> x = curve->value(t);
    const KDL::Frame f(KDL::Rotation::Quaternion(x.q.x(), x.q.y(), x.q.z(), x.q.w()),
                       KDL::Vector(x.p[0], x.p[1], x.p[2]));
    ASSERT_GE(solver.CartToJnt(previous, f, out), 0) << "t = " << t;
    // LMA's answers keep rotation errors up to 6e-7 rad (measured; its default weights scale
    // rotation by 10⁻² and it reads rotation differences from the trace's arccosine, which resolves
    // about 1.5e-8 rad), so its q is that accurate: 1e-6 rad for its pose, 1e-5 rad for q (J_r⁻¹
    // amplifies ≲ 10 here); another IK branch would differ by ≳ 0.1 rad.
    EXPECT_LT(rotationError(x, arm.base_T_tip(out.data)), 1e-6) << "t = " << t;
    EXPECT_LT((path.at(t).position - out.data).lpNorm<Eigen::Infinity>(), 1e-5) << "t = " << t;
    previous = out;
  }
}

TEST(JointPath, PandaHoldsTheChosenJointAtTheSeed)
{
  const ArmModel arm = panda();
  const PoseCurve curve = motionThrough(arm, { kPandaA, kPandaB, kPandaC });
  const JointPath path = jointPathOf(arm, curve, kPandaA);
  ASSERT_EQ(path.heldJoints().size(), 1u);
  EXPECT_LT((path.at(path.start()).position - kPandaA).lpNorm<Eigen::Infinity>(), 1e-9);
  for (double t : denseTimes(path))
    EXPECT_EQ(path.at(t).position[path.heldJoints()[0]], kPandaA[path.heldJoints()[0]]);
  expectFollows(path, *curve);
  expectDerivatives(path);
}

TEST(JointPath, PandaHeldJointsGivenByTheCaller)
{
  const ArmModel arm = panda();
  const PoseCurve curve = motionThrough(arm, { kPandaA, kPandaB, kPandaC });
  JointPathOptions options;
  options.held_joints = { 2 };
  const JointPath path = jointPathOf(arm, curve, kPandaA, options);
  EXPECT_EQ(path.heldJoints(), std::vector<int>{ 2 });
  for (double t : denseTimes(path))
    EXPECT_EQ(path.at(t).position[2], kPandaA[2]);
  expectFollows(path, *curve);
  options.held_joints = { 2, 2 };
  EXPECT_THROW(jointPathOf(arm, curve, kPandaA, options), JointPathError);
  options.held_joints = { 7 };
  EXPECT_THROW(jointPathOf(arm, curve, kPandaA, options), JointPathError);
}

TEST(JointPath, NearTheWristSingularityIsFollowed)
{
  // q5 passes 0.02 rad from the wrist singularity (q5 = 0: axes 4 and 6 parallel).
  const ArmModel arm = ur5e();
  const Eigen::VectorXd a = vec({ 0.3, -1.2, 1.4, -1.8, 0.3, 0.4 });
  const Eigen::VectorXd b = vec({ 0.3, -1.2, 1.4, -1.8, 0.02, 0.4 });
  const PoseCurve curve = motionThrough(arm, { a, b, a });
  const JointPath path = jointPathOf(arm, curve, a);
  double closest = 1.0;
  for (double t : denseTimes(path))
    closest = std::min(closest, std::abs(path.at(t).position[4]));
  EXPECT_GT(closest, 0.0);
  EXPECT_LT(closest, 0.03);
  expectFollows(path, *curve);
}

TEST(JointPathRefusals, PoseOutOfReach)
{
  const ArmModel arm = ur5e();
  Pose<double> far = arm.basePoseOfTip(kUrB);
  far.p += Eigen::Vector3d(3, 0, 0);
  const PoseCurve curve =
      test::spline<ScrewSe3>({ arm.basePoseOfTip(kUrA), far }, { 0.0, 1.0 }, EndCondition::kNatural);
  const std::string m = messageOf([&] { jointPathOf(arm, curve, kUrA); });
  EXPECT_NE(m.find("out of the arm's reach"), std::string::npos) << m;
  EXPECT_NE(m.find("at t = "), std::string::npos) << m;
}

TEST(JointPathRefusals, BadSeed)
{
  const ArmModel arm = ur5e();
  const PoseCurve curve = motionThrough(arm, { kUrA, kUrB });
  EXPECT_NE(messageOf([&] { jointPathOf(arm, curve, vec({ 0, 0, 0, 0, 0 })); }).find("joint_seed"), std::string::npos);
  Eigen::VectorXd nan = kUrA;
  nan[3] = std::nan("");
  EXPECT_NE(messageOf([&] { jointPathOf(arm, curve, nan); }).find("joint_seed[3]"), std::string::npos);
}

TEST(JointPathRefusals, Ur5eJointPastATighterLimit)
{
  ArmModel arm = ur5e();
  const PoseCurve curve = motionThrough(arm, { kUrA, kUrB, kUrC });
  JointLimitsFile limits;
  limits.source = "tight limits";
  limits.joints["wrist_3_joint"].min_position = -1.0;
  limits.joints["wrist_3_joint"].max_position = 1.0;
  arm.applyLimits(limits);
  const std::string m = messageOf([&] { jointPathOf(arm, curve, kUrA); });
  const std::string expected = "joint 'wrist_3_joint' would pass its position limit [-1, 1] rad at t = ";
  ASSERT_NE(m.find(expected), std::string::npos) << m;
  // The time named is the crossing: there the path without the tighter limit has q6 = 1.
  const double t = std::stod(m.substr(m.find(expected) + expected.size()));
  const JointPath free = jointPathOf(ur5e(), curve, kUrA);
  EXPECT_NEAR(free.at(t).position[5], 1.0, 1e-6) << m;
}

TEST(JointPathRefusals, PandaToolTurnedBeyondJoint7)
{
  const ArmModel arm = panda();
  const double upper = arm.joints()[6].limits.max_position;
  Eigen::VectorXd a = kPandaA, b = kPandaA, c = kPandaA;
  a[6] = upper - 0.8, b[6] = upper - 0.2, c[6] = upper + 0.4;
  const PoseCurve curve = motionThrough(arm, { a, b, c });
  JointPathOptions options;
  options.held_joints = { 2 };
  const std::string m = messageOf([&] { jointPathOf(arm, curve, a, options); });
  EXPECT_NE(m.find("joint 'panda_joint7' would pass its position limit"), std::string::npos) << m;
}

TEST(JointPathRefusals, SingularStart)
{
  const ArmModel arm = ur5e();
  const Eigen::VectorXd singular = vec({ 0.3, -1.2, 1.4, -1.8, 0.0, 0.4 });
  const PoseCurve curve = motionThrough(arm, { singular, kUrB });
  const std::string m = messageOf([&] { jointPathOf(arm, curve, singular); });
  EXPECT_NE(m.find("the arm passes a singular configuration at t = 0"), std::string::npos) << m;
}

TEST(JointPathRefusals, MotionThroughTheWristSingularity)
{
  // q5 from −0.4 to 0.4 rad: the joint motion crosses q5 = 0 at t = 0.5 s, which no tracked point
  // need land on; det J_r changes sign over the step, and the refusal names the crossing.
  const ArmModel arm = ur5e();
  Eigen::VectorXd a = kUrA, b = kUrA;
  a[4] = -0.4, b[4] = 0.4;
  const JointSweep joint{ a, b };
  const std::string m = messageOf([&] { JointPath(arm, joint.motion(arm), { 0.0, 1.0 }, a); });
  const std::string expected = "the arm passes a singular configuration at t = ";
  ASSERT_NE(m.find(expected), std::string::npos) << m;
  EXPECT_NEAR(std::stod(m.substr(m.find(expected) + expected.size())), 0.5, 1e-6) << m;
}

TEST(JointPathRefusals, ChainOfFiveJoints)
{
  const ArmModel arm = ur5e("wrist_3_link");
  const ArmModel five = ur5e("wrist_2_link");
  ASSERT_EQ(five.dof(), 5);
  const PoseCurve curve = motionThrough(arm, { kUrA, kUrB });
  const std::string m = messageOf([&] { jointPathOf(five, curve, kUrA.head(5)); });
  EXPECT_NE(m.find("the chain 'base_link' → 'wrist_2_link' has 5 movable joints; following a pose motion takes at "
                   "least 6"),
            std::string::npos)
      << m;
}

TEST(JointPath, StepsStopAtEveryBreakpoint)
{
  const ArmModel arm = ur5e();
  const PoseCurve curve = motionThrough(arm, { kUrA, kUrB, kUrC, kUrB });
  const JointPath path = jointPathOf(arm, curve, kUrA);
  ASSERT_EQ(path.breakpoints(), (std::vector<double>{ 0, 1, 2, 3 }));
  ASSERT_EQ(path.trackedPoints().size(), 3u);
  for (std::size_t k = 0; k < 3; ++k)
  {
    EXPECT_EQ(path.trackedPoints()[k].front().t, path.breakpoints()[k]);
    EXPECT_EQ(path.trackedPoints()[k].back().t, path.breakpoints()[k + 1]);
  }
  expectFollows(path, *curve);
}

TEST(JointPathRefusals, BadBreakpointsAndMotion)
{
  const ArmModel arm = ur5e();
  const PoseCurve curve = motionThrough(arm, { kUrA, kUrB });
  const PoseMotion motion = [curve](double t, Side side) { return kinematicsAt(*curve, t, side); };
  EXPECT_THROW(JointPath(arm, motion, { 0.0 }, kUrA), JointPathError);
  EXPECT_THROW(JointPath(arm, motion, { 1.0, 0.0 }, kUrA), JointPathError);
  EXPECT_THROW(JointPath(arm, PoseMotion(), { 0.0, 1.0 }, kUrA), JointPathError);
  EXPECT_NO_THROW(JointPath(arm, motion, { 0.0, 0.5, 1.0 }, kUrA));
}

TEST(JointPathRefusals, EvaluationOutsideTheDomain)
{
  const ArmModel arm = ur5e();
  const JointPath path = jointPathOf(arm, motionThrough(arm, { kUrA, kUrB }), kUrA);
  EXPECT_THROW(path.at(1.5), JointPathError);
  EXPECT_THROW(path.at(std::nan("")), JointPathError);
}
