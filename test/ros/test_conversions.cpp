// ROS conversions (ros/conversions.h), without a roscore, one test per conversion as tf2_eigen has:
// the pose, twist and transform round trips (random values and the hard points: identity, a rotation
// of π − 1e-9, q and −q, large translations), the quaternion's (x, y, z, w) and the twist's (linear,
// angular) order, every field of the service request copied into the core request (the list of
// fields checked against the message definition, so that a new field without a check fails), the
// path, the trajectory and the figures of the response and of ~status, and the rviz markers. Every
// expectation is written here independently of the function under test (a rotation matrix from
// Eigen's AngleAxis against one written out from the message's four numbers, stamps from
// nanoseconds, marker ends from the sample's pose).
#include <gtest/gtest.h>
#include <ros/message_traits.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "se3_interpolation/ros/conversions.h"

using namespace se3_interpolation;

namespace
{
Pose<double> samplePose()
{
  // A rotation of 0.3 rad about (1, 2, 2)/3 at (1, -2, 0.5).
  const Eigen::Vector3d axis = Eigen::Vector3d(1.0, 2.0, 2.0) / 3.0;
  return Pose<double>(Quaternion<double>(Eigen::AngleAxisd(0.3, axis)), Eigen::Vector3d(1.0, -2.0, 0.5));
}

/// The rotation matrix of the unit quaternion (x, y, z, w), written out (not Eigen's conversion).
Eigen::Matrix3d matrixOf(double x, double y, double z, double w)
{
  Eigen::Matrix3d r;
  r << 1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),  //
      2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),   //
      2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y);
  return r;
}
Eigen::Matrix3d matrixOf(const geometry_msgs::Quaternion& q)
{
  return matrixOf(q.x, q.y, q.z, q.w);
}

Eigen::Vector3d unitVector(std::mt19937& rng)
{
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Vector3d v(n(rng), n(rng), n(rng));
  while (v.norm() < 1e-3)
    v = Eigen::Vector3d(n(rng), n(rng), n(rng));
  return v.normalized();
}

/// A pose with its rotation given as angle-axis, the independent expectation of its matrix.
struct TestPose
{
  std::string name;
  Pose<double> pose;
  Eigen::Matrix3d rotation;  ///< Eigen::AngleAxisd(angle, axis).toRotationMatrix()
};

TestPose angleAxisPose(const std::string& name, double angle, const Eigen::Vector3d& axis, const Eigen::Vector3d& p,
                       bool negate = false)
{
  const Eigen::AngleAxisd aa(angle, axis);
  Quaternion<double> q(aa);
  if (negate)
    q.coeffs() = -q.coeffs();
  return { name, Pose<double>(q, p), aa.toRotationMatrix() };
}

/// Random poses and the hard points: identity, angles near π, q and −q, large translations.
std::vector<TestPose> testPoses()
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(0.0, M_PI);
  std::normal_distribution<double> n(0.0, 3.0);
  std::vector<TestPose> poses;
  poses.push_back({ "identity", Pose<double>::Identity(), Eigen::Matrix3d::Identity() });
  for (int k = 0; k < 8; ++k)
  {
    const Eigen::Vector3d axis = unitVector(rng);
    const Eigen::Vector3d p(n(rng), n(rng), n(rng));
    const std::string i = std::to_string(k);
    poses.push_back(angleAxisPose("pi - 1e-9 #" + i, M_PI - 1e-9, axis, p));
    poses.push_back(angleAxisPose("-(pi - 1e-9) #" + i, M_PI - 1e-9, axis, p, true));
    poses.push_back(angleAxisPose("pi #" + i, M_PI, axis, p));
    poses.push_back(angleAxisPose("1e-12 rad #" + i, 1e-12, axis, p));
  }
  for (double t : { 1e6, -3.5e9, 1e12 })
    poses.push_back(
        angleAxisPose("translation " + std::to_string(t), 1.0, unitVector(rng), Eigen::Vector3d(t, -t, 0.5 * t)));
  for (int k = 0; k < 500; ++k)
  {
    const std::string i = std::to_string(k);
    const double a = angle(rng);
    const Eigen::Vector3d axis = unitVector(rng);
    const Eigen::Vector3d p(n(rng), n(rng), n(rng));
    poses.push_back(angleAxisPose("random q #" + i, a, axis, p));
    poses.push_back(angleAxisPose("random -q #" + i, a, axis, p, true));
  }
  return poses;
}

Twist twistOf(double a, double b, double c, double d, double e, double f)
{
  Twist t;
  t.linear = Eigen::Vector3d(a, b, c);
  t.angular = Eigen::Vector3d(d, e, f);
  return t;
}

void expectTwistMsg(const geometry_msgs::Twist& m, const Twist& t, const std::string& where)
{
  EXPECT_EQ(m.linear.x, t.linear.x()) << where;
  EXPECT_EQ(m.linear.y, t.linear.y()) << where;
  EXPECT_EQ(m.linear.z, t.linear.z()) << where;
  EXPECT_EQ(m.angular.x, t.angular.x()) << where;
  EXPECT_EQ(m.angular.y, t.angular.y()) << where;
  EXPECT_EQ(m.angular.z, t.angular.z()) << where;
}

/// The top-level fields (name → type) of a message definition as gencpp embeds it: the lines
/// before the first dependency's "====" separator, comments and constants left out.
std::vector<std::pair<std::string, std::string>> topLevelFields(const std::string& definition)
{
  std::vector<std::pair<std::string, std::string>> fields;
  std::istringstream in(definition);
  std::string line;
  while (std::getline(in, line))
  {
    if (line.rfind("===", 0) == 0)
      break;
    line = line.substr(0, line.find('#'));
    std::istringstream words(line);
    std::string type, name;
    if (!(words >> type >> name) || name.find('=') != std::string::npos || type.find('=') != std::string::npos)
      continue;
    fields.emplace_back(name, type);
  }
  return fields;
}

std::set<std::string> namesOf(const std::vector<std::pair<std::string, std::string>>& fields,
                              const std::string& type = "")
{
  std::set<std::string> names;
  for (const auto& f : fields)
    if (type.empty() || f.second == type)
      names.insert(f.first);
  return names;
}

/// A result with `n` samples of distinct poses, velocities, accelerations and times.
TrajectoryResult syntheticResult(std::size_t n)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  TrajectoryResult result;
  double t = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    TrajectorySample s;
    s.time = t;
    t += 0.001 + 0.37 * std::abs(u(rng));
    s.pose = Pose<double>(Quaternion<double>(Eigen::AngleAxisd(std::abs(u(rng)), unitVector(rng))),
                          Eigen::Vector3d(u(rng), u(rng), 100.0 * u(rng)));
    s.velocity = twistOf(u(rng), u(rng), u(rng), u(rng), u(rng), u(rng));
    s.acceleration = twistOf(u(rng), u(rng), u(rng), u(rng), u(rng), u(rng));
    result.samples.push_back(s);
  }
  result.duration = t;
  return result;
}

/// A result of the planner: piecewise_geodesic with corner blends (blend zones), or bspline
/// (a control polygon apart from the waypoints).
TrajectoryResult plannedResult(const std::string& curve, std::vector<Pose<double>>* waypoints)
{
  TrajectoryRequest r;
  r.waypoints = {
    Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(0, 0, 0)),
    Pose<double>(Quaternion<double>(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())), Eigen::Vector3d(1, 0, 0)),
    Pose<double>(Quaternion<double>(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitX())), Eigen::Vector3d(1, 1, 0.5)),
    Pose<double>(Quaternion<double>(Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitY())), Eigen::Vector3d(2, 1, 1))
  };
  r.curve = curve;
  if (curve == "piecewise_geodesic")
    r.blend_radius = 0.2;
  r.sample_count = 57;
  *waypoints = r.waypoints;
  return generate(r, PlannerLimits());
}

std::int64_t nsec(const ros::Time& t)
{
  return static_cast<std::int64_t>(t.sec) * 1000000000LL + t.nsec;
}
}  // namespace

// ---------------------------------------------------------------------------------------------
// Poses, twists, transforms

TEST(Conversions, PoseFieldsAndRoundTrip)
{
  const Pose<double> x = samplePose();
  const geometry_msgs::Pose msg = toMsg(x);
  EXPECT_EQ(msg.position.x, 1.0);
  EXPECT_EQ(msg.position.y, -2.0);
  EXPECT_EQ(msg.position.z, 0.5);
  // (x, y, z, w) = (sin(θ/2) axis, cos(θ/2)).
  EXPECT_NEAR(msg.orientation.w, std::cos(0.15), 1e-15);
  EXPECT_NEAR(msg.orientation.x, std::sin(0.15) / 3.0, 1e-15);
  EXPECT_NEAR(msg.orientation.y, 2.0 * std::sin(0.15) / 3.0, 1e-15);
  EXPECT_NEAR(msg.orientation.z, 2.0 * std::sin(0.15) / 3.0, 1e-15);
  const Pose<double> back = fromMsg(msg);
  EXPECT_EQ(back.p, x.p);
  EXPECT_EQ(back.q.coeffs(), x.q.coeffs());

  geometry_msgs::Transform t;
  toMsg(x, t);
  EXPECT_EQ(t.translation.y, -2.0);
  EXPECT_EQ(t.rotation.w, msg.orientation.w);
  EXPECT_EQ(t.rotation.z, msg.orientation.z);
}

// Pose → geometry_msgs/Pose → Pose over random poses and the hard points: the message holds the
// rotation Eigen's AngleAxis gives (its matrix written out from x, y, z, w), the quaternion's sign
// is kept (a sign-continuous trajectory stays so: q and −q are different messages), translations
// are exact at any magnitude, and the way back gives the same numbers.
TEST(Conversions, PoseRoundTripsIncludingHardPoints)
{
  for (const TestPose& c : testPoses())
  {
    const geometry_msgs::Pose msg = toMsg(c.pose);
    EXPECT_EQ(msg.orientation.x, c.pose.q.x()) << c.name;
    EXPECT_EQ(msg.orientation.y, c.pose.q.y()) << c.name;
    EXPECT_EQ(msg.orientation.z, c.pose.q.z()) << c.name;
    EXPECT_EQ(msg.orientation.w, c.pose.q.w()) << c.name;
    EXPECT_EQ(msg.position.x, c.pose.p.x()) << c.name;
    EXPECT_EQ(msg.position.y, c.pose.p.y()) << c.name;
    EXPECT_EQ(msg.position.z, c.pose.p.z()) << c.name;
    EXPECT_LT((matrixOf(msg.orientation) - c.rotation).cwiseAbs().maxCoeff(), 1e-12) << c.name;

    const Pose<double> back = fromMsg(msg);
    EXPECT_EQ(back.q.coeffs(), c.pose.q.coeffs()) << c.name;
    EXPECT_EQ(back.p, c.pose.p) << c.name;
    EXPECT_LT((back.q.toRotationMatrix() - c.rotation).cwiseAbs().maxCoeff(), 1e-12) << c.name;
  }
}

// The message's (x, y, z, w) land in the core's x, y, z, w whatever they are: fromMsg does not
// normalise (validatePose does) nor flip the sign.
TEST(Conversions, PoseFromMsgKeepsTheQuaternionAsGiven)
{
  geometry_msgs::Pose msg;
  msg.orientation.x = 0.1;
  msg.orientation.y = -0.2;
  msg.orientation.z = 0.3;
  msg.orientation.w = -1.7;
  msg.position.x = -1e15;
  msg.position.y = 5e-300;
  msg.position.z = 42.0;
  const Pose<double> x = fromMsg(msg);
  EXPECT_EQ(x.q.x(), 0.1);
  EXPECT_EQ(x.q.y(), -0.2);
  EXPECT_EQ(x.q.z(), 0.3);
  EXPECT_EQ(x.q.w(), -1.7);
  EXPECT_EQ(x.p, Eigen::Vector3d(-1e15, 5e-300, 42.0));
}

// The transform parent_T_child of a pose: the same numbers as the pose message, translation for
// position; its rotation is Eigen's AngleAxis matrix. tf2's own Transform → Eigen::Isometry3d reads
// it back to the same pose (a transform message has no fromMsg of ours).
TEST(Conversions, TransformOfEveryPose)
{
  for (const TestPose& c : testPoses())
  {
    geometry_msgs::Transform t;
    t.translation.x = 99.0;  // converting into a used message replaces its content
    t.rotation.w = 99.0;
    toMsg(c.pose, t);
    EXPECT_EQ(t.translation.x, c.pose.p.x()) << c.name;
    EXPECT_EQ(t.translation.y, c.pose.p.y()) << c.name;
    EXPECT_EQ(t.translation.z, c.pose.p.z()) << c.name;
    EXPECT_EQ(t.rotation.x, c.pose.q.x()) << c.name;
    EXPECT_EQ(t.rotation.y, c.pose.q.y()) << c.name;
    EXPECT_EQ(t.rotation.z, c.pose.q.z()) << c.name;
    EXPECT_EQ(t.rotation.w, c.pose.q.w()) << c.name;
    EXPECT_LT((matrixOf(t.rotation) - c.rotation).cwiseAbs().maxCoeff(), 1e-12) << c.name;
    // The transform maps body coordinates into the parent: the body's x axis end at p + R e_x.
    const Eigen::Vector3d p(t.translation.x, t.translation.y, t.translation.z);
    const Eigen::Vector3d expected = c.pose.p + c.rotation.col(0);
    EXPECT_LT((p + matrixOf(t.rotation).col(0) - expected).norm(), 1e-12 * (1.0 + c.pose.p.norm())) << c.name;
  }
}

TEST(Conversions, TransformRoundTripsAsThePose)
{
  for (const TestPose& c : testPoses())
  {
    geometry_msgs::Transform t;
    const Pose<double> back = fromMsg(toMsg(c.pose, t));
    EXPECT_EQ(back.p, c.pose.p) << c.name;
    EXPECT_EQ(back.q.coeffs(), c.pose.q.coeffs()) << c.name;  // the sign as given: q and -q both kept
    // The same pose as the Pose message of the same numbers.
    geometry_msgs::Pose m;
    m.position.x = t.translation.x;
    m.position.y = t.translation.y;
    m.position.z = t.translation.z;
    m.orientation = t.rotation;
    EXPECT_EQ(fromMsg(m).q.coeffs(), back.q.coeffs()) << c.name;
  }
}

TEST(Conversions, TwistOrderIsLinearThenAngular)
{
  Twist v;
  v.linear = Eigen::Vector3d(1.0, 2.0, 3.0);
  v.angular = Eigen::Vector3d(-4.0, -5.0, -6.0);
  const geometry_msgs::Twist msg = toMsg(v);
  EXPECT_EQ(msg.linear.x, 1.0);
  EXPECT_EQ(msg.linear.y, 2.0);
  EXPECT_EQ(msg.linear.z, 3.0);
  EXPECT_EQ(msg.angular.x, -4.0);
  EXPECT_EQ(msg.angular.y, -5.0);
  EXPECT_EQ(msg.angular.z, -6.0);
  const Twist back = fromMsg(msg);
  EXPECT_EQ(back.linear, v.linear);
  EXPECT_EQ(back.angular, v.angular);
}

// Twist → message → Twist over random twists, zeros, large and tiny magnitudes: exact, each of
// the six numbers in its own place.
TEST(Conversions, TwistRoundTrips)
{
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 10.0);
  std::vector<Twist> twists = { Twist(), twistOf(1e300, -1e-300, 0.0, -0.0, 7e15, -3.25), twistOf(1, 2, 3, 4, 5, 6) };
  for (int k = 0; k < 1000; ++k)
    twists.push_back(twistOf(n(rng), n(rng), n(rng), n(rng), n(rng), n(rng)));
  for (std::size_t k = 0; k < twists.size(); ++k)
  {
    const Twist& t = twists[k];
    const geometry_msgs::Twist msg = toMsg(t);
    expectTwistMsg(msg, t, "twist " + std::to_string(k));
    const Twist back = fromMsg(msg);
    EXPECT_EQ(back.linear, t.linear) << k;
    EXPECT_EQ(back.angular, t.angular) << k;
  }
}

// ---------------------------------------------------------------------------------------------
// The service request

namespace
{
/// One field of GenerateTrajectory's request that fromMsg copies: `set` gives it a distinctive
/// non-default value, `copied` tells whether the core request carries that value.
struct CopiedField
{
  std::string name;
  std::function<void(GenerateTrajectory::Request&)> set;
  std::function<bool(const TrajectoryRequest&)> copied;
};

Twist distinctTwist(double base)
{
  return twistOf(base + 0.1, base + 0.2, base + 0.3, base + 0.4, base + 0.5, base + 0.6);
}
geometry_msgs::Twist distinctTwistMsg(double base)
{
  geometry_msgs::Twist m;
  m.linear.x = base + 0.1;
  m.linear.y = base + 0.2;
  m.linear.z = base + 0.3;
  m.angular.x = base + 0.4;
  m.angular.y = base + 0.5;
  m.angular.z = base + 0.6;
  return m;
}
bool sameTwist(const Twist& a, const Twist& b)
{
  return a.linear == b.linear && a.angular == b.angular;
}

std::vector<geometry_msgs::Pose> distinctPoses()
{
  std::vector<geometry_msgs::Pose> poses;
  for (int i = 0; i < 3; ++i)
  {
    const Eigen::Vector3d axis = Eigen::Vector3d(1.0 + i, -2.0, 0.5 * i).normalized();
    poses.push_back(toMsg(Pose<double>(Quaternion<double>(Eigen::AngleAxisd(0.4 + i, axis)),
                                       Eigen::Vector3d(10.0 + i, -20.0 - i, 30.5 * i))));
  }
  return poses;
}

/// The request's fields that fromMsg copies into TrajectoryRequest, each with its own value
/// (no two alike, so that two fields swapped fail as well).
std::vector<CopiedField> copiedFields()
{
  using R = GenerateTrajectory::Request;
  using T = TrajectoryRequest;
  std::vector<CopiedField> f;
  f.push_back({ "waypoints", [](R& m) { m.waypoints.poses = distinctPoses(); },
                [](const T& r) {
                  const auto poses = distinctPoses();
                  if (r.waypoints.size() != poses.size())
                    return false;
                  for (std::size_t i = 0; i < poses.size(); ++i)
                  {
                    const auto& o = poses[i].orientation;
                    const auto& p = poses[i].position;
                    if (r.waypoints[i].q.coeffs() != Eigen::Vector4d(o.x, o.y, o.z, o.w) ||
                        r.waypoints[i].p != Eigen::Vector3d(p.x, p.y, p.z))
                      return false;
                  }
                  return true;
                } });
  f.push_back({ "times",
                [](R& m) {
                  m.times = { 0.0, 1.25, 3.5 };
                },
                [](const T& r) {
                  return r.times == std::vector<double>{ 0.0, 1.25, 3.5 };
                } });
  f.push_back({ "curve", [](R& m) { m.curve = "curve-name"; }, [](const T& r) { return r.curve == "curve-name"; } });
  f.push_back({ "geometry", [](R& m) { m.geometry = "geometry-name"; },
                [](const T& r) { return r.geometry == "geometry-name"; } });
  f.push_back({ "degree", [](R& m) { m.degree = 201; }, [](const T& r) { return r.degree == 201; } });
  f.push_back({ "knots",
                [](R& m) {
                  m.knots = { 0.0, 0.0, 0.5, 7.0 };
                },
                [](const T& r) {
                  return r.knots == std::vector<double>{ 0.0, 0.0, 0.5, 7.0 };
                } });
  f.push_back({ "continuity", [](R& m) { m.continuity = 7; }, [](const T& r) { return r.continuity == 7; } });
  f.push_back(
      { "blend_radius", [](R& m) { m.blend_radius = 0.0625; }, [](const T& r) { return r.blend_radius == 0.0625; } });
  f.push_back({ "end_condition", [](R& m) { m.end_condition = "end-name"; },
                [](const T& r) { return r.end_condition == "end-name"; } });
  f.push_back({ "start_velocity", [](R& m) { m.start_velocity = distinctTwistMsg(10.0); },
                [](const T& r) { return sameTwist(r.start_velocity, distinctTwist(10.0)); } });
  f.push_back({ "end_velocity", [](R& m) { m.end_velocity = distinctTwistMsg(20.0); },
                [](const T& r) { return sameTwist(r.end_velocity, distinctTwist(20.0)); } });
  f.push_back({ "start_acceleration", [](R& m) { m.start_acceleration = distinctTwistMsg(30.0); },
                [](const T& r) { return sameTwist(r.start_acceleration, distinctTwist(30.0)); } });
  f.push_back({ "velocities",
                [](R& m) {
                  m.velocities = { distinctTwistMsg(40.0), distinctTwistMsg(50.0), distinctTwistMsg(60.0) };
                },
                [](const T& r) {
                  return r.velocities.size() == 3 && sameTwist(r.velocities[0], distinctTwist(40.0)) &&
                         sameTwist(r.velocities[1], distinctTwist(50.0)) &&
                         sameTwist(r.velocities[2], distinctTwist(60.0));
                } });
  f.push_back({ "parameterization", [](R& m) { m.parameterization = "param-name"; },
                [](const T& r) { return r.parameterization == "param-name"; } });
  f.push_back(
      { "rotation_scale", [](R& m) { m.rotation_scale = 2.75; }, [](const T& r) { return r.rotation_scale == 2.75; } });
  f.push_back({ "duration", [](R& m) { m.duration = 12.5; }, [](const T& r) { return r.duration == 12.5; } });
  f.push_back({ "max_linear_velocity", [](R& m) { m.max_linear_velocity = 1.5; },
                [](const T& r) { return r.max_linear_velocity == 1.5; } });
  f.push_back({ "max_angular_velocity", [](R& m) { m.max_angular_velocity = 2.5; },
                [](const T& r) { return r.max_angular_velocity == 2.5; } });
  f.push_back({ "max_linear_acceleration", [](R& m) { m.max_linear_acceleration = 3.5; },
                [](const T& r) { return r.max_linear_acceleration == 3.5; } });
  f.push_back({ "max_angular_acceleration", [](R& m) { m.max_angular_acceleration = 4.5; },
                [](const T& r) { return r.max_angular_acceleration == 4.5; } });
  f.push_back({ "max_linear_jerk", [](R& m) { m.max_linear_jerk = 5.5; },
                [](const T& r) { return r.max_linear_jerk == 5.5; } });
  f.push_back({ "max_angular_jerk", [](R& m) { m.max_angular_jerk = 6.5; },
                [](const T& r) { return r.max_angular_jerk == 6.5; } });
  f.push_back(
      { "timing", [](R& m) { m.timing = "timing-name"; }, [](const T& r) { return r.timing == "timing-name"; } });
  f.push_back({ "speed", [](R& m) { m.speed = 7.5; }, [](const T& r) { return r.speed == 7.5; } });
  f.push_back({ "control_period", [](R& m) { m.control_period = 0.375; },
                [](const T& r) { return r.control_period == 0.375; } });
  f.push_back({ "smoothing", [](R& m) { m.smoothing = 8.5; }, [](const T& r) { return r.smoothing == 8.5; } });
  f.push_back({ "loss", [](R& m) { m.loss = "loss-name"; }, [](const T& r) { return r.loss == "loss-name"; } });
  f.push_back({ "loss_scale", [](R& m) { m.loss_scale = 9.5; }, [](const T& r) { return r.loss_scale == 9.5; } });
  f.push_back({ "sample_times",
                [](R& m) {
                  m.sample_times = { 0.125, 0.375 };
                },
                [](const T& r) {
                  return r.sample_times == std::vector<double>{ 0.125, 0.375 };
                } });
  f.push_back({ "sample_period", [](R& m) { m.sample_period = 0.03125; },
                [](const T& r) { return r.sample_period == 0.03125; } });
  f.push_back({ "sample_count", [](R& m) { m.sample_count = 4000000007u; },
                [](const T& r) { return r.sample_count == 4000000007u; } });
  f.push_back({ "sample_tolerance", [](R& m) { m.sample_tolerance = 2.5e-4; },
                [](const T& r) { return r.sample_tolerance == 2.5e-4; } });
  f.push_back({ "joint_seed",
                [](R& m) {
                  m.joint_seed = { 0.25, -1.5, 2.75 };
                },
                [](const T& r) {
                  return r.joint_seed == std::vector<double>{ 0.25, -1.5, 2.75 };
                } });
  return f;
}

/// The request's fields the node handles itself, not part of TrajectoryRequest (checked by the
/// node's rostests), with where they go.
const std::vector<std::pair<std::string, std::string>> kNodeFields = {
  { "waypoint_frames", "looked up in TF by the node; their poses follow waypoints.poses in fromMsg's `poses`" },
  { "child_frame_id", "the trajectory's joint name and the moving TF frame (toMsg's joint_name)" },
  { "publish", "the node publishes ~path, ~trajectory, ~markers and TF" },
  { "from_current", "the node fills TrajectoryRequest::start_state from the motion it plays" },
  { "outputs", "parseResponseOutputs: which response arrays the node fills" },
};

/// fromMsg as the node calls it: the poses are the request's own.
TrajectoryRequest convert(const GenerateTrajectory::Request& msg)
{
  return fromMsg(msg, msg.waypoints.poses);
}
}  // namespace

// Every field of the request's definition is either copied by fromMsg (and checked below) or
// handled by the node: a field added to the .srv without a check here fails this test.
TEST(Conversions, EveryRequestFieldIsAccountedFor)
{
  const auto fields = topLevelFields(ros::message_traits::Definition<GenerateTrajectory::Request>::value());
  ASSERT_GE(fields.size(), 20u) << "the definition was not parsed";
  std::set<std::string> accounted;
  for (const auto& c : copiedFields())
    EXPECT_TRUE(accounted.insert(c.name).second) << c.name << " is listed twice";
  for (const auto& n : kNodeFields)
    EXPECT_TRUE(accounted.insert(n.first).second) << n.first << " is listed twice";
  const std::set<std::string> defined = namesOf(fields);
  EXPECT_EQ(defined.size(), fields.size()) << "a field name repeats in the definition";
  for (const std::string& name : defined)
    EXPECT_EQ(accounted.count(name), 1u) << "GenerateTrajectory.srv's request field " << name
                                         << " is neither checked as copied into TrajectoryRequest nor listed as "
                                            "handled by the node (kNodeFields)";
  for (const std::string& name : accounted)
    EXPECT_EQ(defined.count(name), 1u) << name << " is checked here but not a field of the request";
}

// Each copied field alone, set to its own value, reaches the core request, and no other field
// changes (a field copied into the wrong place fails twice); all of them together too.
TEST(Conversions, EveryRequestFieldIsCopied)
{
  const std::vector<CopiedField> fields = copiedFields();
  const TrajectoryRequest untouched = convert(GenerateTrajectory::Request());
  for (const CopiedField& c : fields)
    EXPECT_FALSE(c.copied(untouched)) << c.name << ": its test value is the default";
  EXPECT_FALSE(untouched.start_state.has_value());

  GenerateTrajectory::Request all;
  for (const CopiedField& c : fields)
  {
    GenerateTrajectory::Request msg;
    c.set(msg);
    const TrajectoryRequest r = convert(msg);
    EXPECT_TRUE(c.copied(r)) << c.name << " is not copied into the core request";
    for (const CopiedField& other : fields)
    {
      if (other.name == c.name)
        continue;
      EXPECT_FALSE(other.copied(r)) << "setting " << c.name << " changed " << other.name;
    }
    c.set(all);
  }
  const TrajectoryRequest r = convert(all);
  for (const CopiedField& c : fields)
    EXPECT_TRUE(c.copied(r)) << c.name << " is not copied when every field is set";
  EXPECT_FALSE(r.start_state.has_value()) << "start_state is the node's (from_current), not the message's";
}

// The waypoints are the `poses` argument (the request's own, transformed, then the TF frames'),
// not the message's: fromMsg takes them in order, whatever msg.waypoints holds.
TEST(Conversions, WaypointsComeFromThePosesArgument)
{
  GenerateTrajectory::Request msg;
  msg.waypoints.poses = distinctPoses();
  std::vector<geometry_msgs::Pose> poses = distinctPoses();
  poses.push_back(toMsg(samplePose()));
  std::reverse(poses.begin(), poses.end());
  const TrajectoryRequest r = fromMsg(msg, poses);
  ASSERT_EQ(r.waypoints.size(), 4u);
  EXPECT_EQ(r.waypoints[0].p, samplePose().p);
  EXPECT_EQ(r.waypoints[0].q.coeffs(), samplePose().q.coeffs());
  for (std::size_t i = 0; i < poses.size(); ++i)
    EXPECT_EQ(r.waypoints[i].p, Eigen::Vector3d(poses[i].position.x, poses[i].position.y, poses[i].position.z)) << i;
  EXPECT_TRUE(fromMsg(msg, {}).waypoints.empty());
}

TEST(Conversions, RequestFieldsAreCopied)
{
  GenerateTrajectory::Request msg;
  msg.curve = "bspline";
  msg.geometry = "screw";
  msg.degree = 4;
  msg.times = { 0.0, 1.5 };
  msg.start_velocity.angular.z = 0.25;
  msg.velocities.resize(2);
  msg.velocities[1].linear.x = 2.0;
  msg.sample_count = 7;
  msg.blend_radius = 0.1;
  const std::vector<geometry_msgs::Pose> poses = { toMsg(samplePose()), toMsg(samplePose()) };
  const TrajectoryRequest r = fromMsg(msg, poses);
  ASSERT_EQ(r.waypoints.size(), 2u);
  EXPECT_EQ(r.waypoints[1].p, samplePose().p);
  EXPECT_EQ(r.curve, "bspline");
  EXPECT_EQ(r.geometry, "screw");
  EXPECT_EQ(r.degree, 4);
  EXPECT_EQ(r.times, msg.times);
  EXPECT_EQ(r.start_velocity.angular.z(), 0.25);
  ASSERT_EQ(r.velocities.size(), 2u);
  EXPECT_EQ(r.velocities[1].linear.x(), 2.0);
  EXPECT_EQ(r.sample_count, 7u);
  EXPECT_EQ(r.blend_radius, 0.1);
}

// ---------------------------------------------------------------------------------------------
// The response: path, trajectory, figures; ~status's figures

TEST(Conversions, SamplesAreStampedAndTimedFromTheHeader)
{
  TrajectoryResult result;
  for (double t : { 0.0, 0.25, 2.0 })
  {
    TrajectorySample s;
    s.time = t;
    s.pose = samplePose();
    s.pose.p.x() += t;
    s.velocity.linear.x() = 1.0;
    s.acceleration.angular.y() = t;
    result.samples.push_back(s);
  }
  std_msgs::Header header;
  header.frame_id = "map";
  header.stamp = ros::Time(100, 500000000);

  nav_msgs::Path path;
  toMsg(result, header, path);
  ASSERT_EQ(path.poses.size(), 3u);
  EXPECT_EQ(path.header.frame_id, "map");
  EXPECT_EQ(path.poses[1].header.stamp, ros::Time(100, 750000000));
  EXPECT_EQ(path.poses[2].header.stamp, ros::Time(102, 500000000));
  EXPECT_EQ(path.poses[2].pose.position.x, 3.0);

  trajectory_msgs::MultiDOFJointTrajectory traj;
  toMsg(result, header, "body", traj);
  ASSERT_EQ(traj.points.size(), 3u);
  ASSERT_EQ(traj.joint_names.size(), 1u);
  EXPECT_EQ(traj.joint_names[0], "body");
  EXPECT_EQ(traj.points[1].time_from_start, ros::Duration(0, 250000000));
  ASSERT_EQ(traj.points[2].transforms.size(), 1u);
  EXPECT_EQ(traj.points[2].transforms[0].translation.x, 3.0);
  EXPECT_EQ(traj.points[2].velocities[0].linear.x, 1.0);
  EXPECT_EQ(traj.points[2].accelerations[0].angular.y, 2.0);
  // Converting into a used message replaces its content.
  toMsg(result, header, "body", traj);
  EXPECT_EQ(traj.points.size(), 3u);
  EXPECT_EQ(traj.points[0].transforms.size(), 1u);
}

namespace
{
/// The path of `result` against the core values: one stamped pose per sample, in order.
void expectPath(const nav_msgs::Path& path, const TrajectoryResult& result, const std_msgs::Header& header)
{
  EXPECT_EQ(path.header.frame_id, header.frame_id);
  EXPECT_EQ(path.header.stamp, header.stamp);
  ASSERT_EQ(path.poses.size(), result.samples.size());
  for (std::size_t i = 0; i < result.samples.size(); ++i)
  {
    const TrajectorySample& s = result.samples[i];
    const geometry_msgs::PoseStamped& p = path.poses[i];
    EXPECT_EQ(p.header.frame_id, header.frame_id) << i;
    // Stamp = header.stamp + time, to the nanosecond (ros::Duration rounds to the nearest one).
    EXPECT_LE(std::llabs(nsec(p.header.stamp) - nsec(header.stamp) - std::llround(s.time * 1e9)), 1) << i;
    EXPECT_EQ(p.pose.position.x, s.pose.p.x()) << i;
    EXPECT_EQ(p.pose.position.y, s.pose.p.y()) << i;
    EXPECT_EQ(p.pose.position.z, s.pose.p.z()) << i;
    EXPECT_EQ(p.pose.orientation.x, s.pose.q.x()) << i;
    EXPECT_EQ(p.pose.orientation.y, s.pose.q.y()) << i;
    EXPECT_EQ(p.pose.orientation.z, s.pose.q.z()) << i;
    EXPECT_EQ(p.pose.orientation.w, s.pose.q.w()) << i;
  }
}

/// The trajectory of `result`: one joint; per sample one transform, velocity and acceleration
/// and the time from the header's stamp.
void expectTrajectory(const trajectory_msgs::MultiDOFJointTrajectory& traj, const TrajectoryResult& result,
                      const std_msgs::Header& header, const std::string& joint)
{
  EXPECT_EQ(traj.header.frame_id, header.frame_id);
  EXPECT_EQ(traj.header.stamp, header.stamp);
  ASSERT_EQ(traj.joint_names, std::vector<std::string>{ joint });
  ASSERT_EQ(traj.points.size(), result.samples.size());
  for (std::size_t i = 0; i < result.samples.size(); ++i)
  {
    const TrajectorySample& s = result.samples[i];
    const auto& point = traj.points[i];
    ASSERT_EQ(point.transforms.size(), 1u) << i;
    ASSERT_EQ(point.velocities.size(), 1u) << i;
    ASSERT_EQ(point.accelerations.size(), 1u) << i;
    const auto& t = point.transforms[0];
    EXPECT_EQ(t.translation.x, s.pose.p.x()) << i;
    EXPECT_EQ(t.translation.y, s.pose.p.y()) << i;
    EXPECT_EQ(t.translation.z, s.pose.p.z()) << i;
    EXPECT_EQ(t.rotation.x, s.pose.q.x()) << i;
    EXPECT_EQ(t.rotation.y, s.pose.q.y()) << i;
    EXPECT_EQ(t.rotation.z, s.pose.q.z()) << i;
    EXPECT_EQ(t.rotation.w, s.pose.q.w()) << i;
    expectTwistMsg(point.velocities[0], s.velocity, "velocity " + std::to_string(i));
    expectTwistMsg(point.accelerations[0], s.acceleration, "acceleration " + std::to_string(i));
    EXPECT_LE(std::llabs(point.time_from_start.toNSec() - std::llround(s.time * 1e9)), 1) << i;
  }
}
}  // namespace

// Path and MultiDOFJointTrajectory of a planned trajectory and of random samples (times not on
// round numbers, a stamp near a second's end), each sample against the core's values; converting
// into a used message (longer before) replaces it.
TEST(Conversions, PathAndTrajectoryCarryEverySample)
{
  std::vector<Pose<double>> waypoints;
  const TrajectoryResult planned = plannedResult("bspline", &waypoints);
  ASSERT_EQ(planned.samples.size(), 57u);
  const TrajectoryResult synthetic = syntheticResult(300);
  std_msgs::Header header;
  header.frame_id = "odom";
  header.stamp = ros::Time(1700000000, 999999999);
  header.seq = 17;
  for (const TrajectoryResult* result : { &planned, &synthetic })
  {
    nav_msgs::Path path;
    path.poses.resize(1000);
    path.poses[0].header.frame_id = "stale";
    toMsg(*result, header, path);
    expectPath(path, *result, header);

    trajectory_msgs::MultiDOFJointTrajectory traj;
    traj.joint_names = { "a", "b" };
    traj.points.resize(1000);
    traj.points[0].transforms.resize(3);
    traj.points[0].velocities.resize(3);
    toMsg(*result, header, "tool0", traj);
    expectTrajectory(traj, *result, header, "tool0");
  }
}

// A goal's points: what toMsg writes for a trajectory, fromMsg reads back as the samples (the
// action executes what ~generate returns); absent velocities and accelerations stay absent, a
// second joint's entries are not read, and the quaternion is kept as given (GoalTrajectory checks it).
TEST(Conversions, GoalPointsAreTheTrajectorysSamples)
{
  const TrajectoryResult synthetic = syntheticResult(50);
  std_msgs::Header header;
  header.stamp = ros::Time(1700000000, 5);
  trajectory_msgs::MultiDOFJointTrajectory traj;
  toMsg(synthetic, header, "tool0", traj);
  ASSERT_EQ(traj.points.size(), synthetic.samples.size());
  for (std::size_t i = 0; i < traj.points.size(); ++i)
  {
    const GoalPoint p = fromMsg(traj.points[i]);
    const TrajectorySample& s = synthetic.samples[i];
    EXPECT_EQ(p.time_from_start, traj.points[i].time_from_start.toSec());
    EXPECT_NEAR(p.time_from_start, s.time, 1e-9);
    EXPECT_EQ(p.pose.p, s.pose.p);
    EXPECT_LT(std::min((p.pose.q.coeffs() - s.pose.q.coeffs()).norm(), (p.pose.q.coeffs() + s.pose.q.coeffs()).norm()),
              1e-15);
    ASSERT_TRUE(p.velocity && p.acceleration);
    EXPECT_EQ(p.velocity->linear, s.velocity.linear);
    EXPECT_EQ(p.velocity->angular, s.velocity.angular);
    EXPECT_EQ(p.acceleration->linear, s.acceleration.linear);
    EXPECT_EQ(p.acceleration->angular, s.acceleration.angular);
  }
  trajectory_msgs::MultiDOFJointTrajectoryPoint bare;
  bare.transforms.resize(2);
  bare.transforms[0].translation.x = 1.5;
  bare.transforms[0].rotation.w = 0.5;
  bare.transforms[1].translation.x = 9.0;
  bare.time_from_start = ros::Duration(2, 500000000);
  const GoalPoint p = fromMsg(bare);
  EXPECT_EQ(p.time_from_start, 2.5);
  EXPECT_EQ(p.pose.p.x(), 1.5);
  EXPECT_EQ(p.pose.q.w(), 0.5);
  EXPECT_FALSE(p.velocity);
  EXPECT_FALSE(p.acceleration);
}

namespace
{
/// One figure of the response: set in the result, read in the response and in ~status.
struct Figure
{
  std::string name;
  std::function<void(TrajectoryResult&, double)> set;
  std::function<double(const GenerateTrajectory::Response&)> response;
  std::function<double(const GenerationStatus&)> status;
};

std::vector<Figure> figures()
{
  using Res = GenerateTrajectory::Response;
  using S = GenerationStatus;
  using T = TrajectoryResult;
  return {
    { "duration", [](T& r, double v) { r.duration = v; }, [](const Res& m) { return m.duration; },
      [](const S& s) { return s.duration; } },
    { "length", [](T& r, double v) { r.figures.length = v; }, [](const Res& m) { return m.length; },
      [](const S& s) { return s.length; } },
    { "rotation_length", [](T& r, double v) { r.figures.rotation_length = v; },
      [](const Res& m) { return m.rotation_length; }, [](const S& s) { return s.rotation_length; } },
    { "max_linear_speed", [](T& r, double v) { r.figures.max_linear_speed = v; },
      [](const Res& m) { return m.max_linear_speed; }, [](const S& s) { return s.max_linear_speed; } },
    { "max_angular_speed", [](T& r, double v) { r.figures.max_angular_speed = v; },
      [](const Res& m) { return m.max_angular_speed; }, [](const S& s) { return s.max_angular_speed; } },
    { "peak_linear_acceleration", [](T& r, double v) { r.figures.max_linear_acceleration = v; },
      [](const Res& m) { return m.peak_linear_acceleration; }, [](const S& s) { return s.peak_linear_acceleration; } },
    { "peak_angular_acceleration", [](T& r, double v) { r.figures.max_angular_acceleration = v; },
      [](const Res& m) { return m.peak_angular_acceleration; },
      [](const S& s) { return s.peak_angular_acceleration; } },
    { "peak_linear_jerk", [](T& r, double v) { r.figures.max_linear_jerk = v; },
      [](const Res& m) { return m.peak_linear_jerk; }, [](const S& s) { return s.peak_linear_jerk; } },
    { "peak_angular_jerk", [](T& r, double v) { r.figures.max_angular_jerk = v; },
      [](const Res& m) { return m.peak_angular_jerk; }, [](const S& s) { return s.peak_angular_jerk; } },
    { "constant_speed_start", [](T& r, double v) { r.constant_speed_start = v; },
      [](const Res& m) { return m.constant_speed_start; }, [](const S& s) { return s.constant_speed_start; } },
    { "constant_speed_end", [](T& r, double v) { r.constant_speed_end = v; },
      [](const Res& m) { return m.constant_speed_end; }, [](const S& s) { return s.constant_speed_end; } },
    { "residual_linear", [](T& r, double v) { r.residual_linear = v; }, [](const Res& m) { return m.residual_linear; },
      [](const S& s) { return s.residual_linear; } },
    { "residual_angular", [](T& r, double v) { r.residual_angular = v; },
      [](const Res& m) { return m.residual_angular; }, [](const S& s) { return s.residual_angular; } },
    { "energy", [](T& r, double v) { r.figures.energy = v; }, [](const Res& m) { return m.energy; },
      [](const S& s) { return s.energy; } },
    { "joint_binding_ratio",
      [](T& r, double v) {
        r.joint_figures.binding_joint = 0;
        r.joint_figures.binding_ratio = v;
      },
      [](const Res& m) { return m.joint_binding_ratio; }, [](const S& s) { return s.joint_binding_ratio; } },
  };
}
}  // namespace

// The figures: every float64 of the response (and of ~status) is one of those checked here (a new
// figure without a check fails), each reaches the response from the result and the status from
// the response with its own value, and nothing else of the response changes.
TEST(Conversions, FiguresReachTheResponseAndTheStatus)
{
  const std::vector<Figure> list = figures();
  std::set<std::string> checked;
  for (const Figure& f : list)
    checked.insert(f.name);
  const auto response_fields = topLevelFields(ros::message_traits::Definition<GenerateTrajectory::Response>::value());
  const auto status_fields = topLevelFields(ros::message_traits::Definition<GenerationStatus>::value());
  ASSERT_GE(response_fields.size(), 8u);
  EXPECT_EQ(namesOf(response_fields, "float64"), checked);
  EXPECT_EQ(namesOf(status_fields, "float64"), checked);

  TrajectoryResult result;
  result.waypoint_times = { 1e9 };  // not a figure of the response
  for (std::size_t i = 0; i < list.size(); ++i)
    list[i].set(result, 1.5 + 10.0 * static_cast<double>(i));
  GenerateTrajectory::Response res;
  res.success = true;
  res.message = "kept";
  res.path.poses.resize(2);
  res.trajectory.points.resize(3);
  copyFigures(result, res);
  GenerationStatus status;
  status.source = "kept";
  status.waypoint_count = 9;
  copyFigures(res, status);
  for (std::size_t i = 0; i < list.size(); ++i)
  {
    EXPECT_EQ(list[i].response(res), 1.5 + 10.0 * static_cast<double>(i)) << list[i].name;
    EXPECT_EQ(list[i].status(status), 1.5 + 10.0 * static_cast<double>(i)) << list[i].name;
  }
  EXPECT_TRUE(res.success);
  EXPECT_EQ(res.message, "kept");
  EXPECT_EQ(res.path.poses.size(), 2u);
  EXPECT_EQ(res.trajectory.points.size(), 3u);
  EXPECT_EQ(status.source, "kept");
  EXPECT_EQ(status.waypoint_count, 9u);

  // A planned result's figures, read from the planner's result itself.
  std::vector<Pose<double>> waypoints;
  const TrajectoryResult planned = plannedResult("bspline", &waypoints);
  GenerateTrajectory::Response from_planner;
  copyFigures(planned, from_planner);
  EXPECT_GT(planned.figures.length, 0.0);
  EXPECT_EQ(from_planner.duration, planned.duration);
  EXPECT_EQ(from_planner.length, planned.figures.length);
  EXPECT_EQ(from_planner.rotation_length, planned.figures.rotation_length);
  EXPECT_EQ(from_planner.max_linear_speed, planned.figures.max_linear_speed);
  EXPECT_EQ(from_planner.max_angular_speed, planned.figures.max_angular_speed);
  EXPECT_EQ(from_planner.energy, planned.figures.energy);
}

// ---------------------------------------------------------------------------------------------
// rviz markers

namespace
{
void expectPoint(const geometry_msgs::Point& m, const Eigen::Vector3d& p, double tol, const std::string& where)
{
  EXPECT_NEAR(m.x, p.x(), tol) << where;
  EXPECT_NEAR(m.y, p.y(), tol) << where;
  EXPECT_NEAR(m.z, p.z(), tol) << where;
}

const visualization_msgs::Marker* findMarker(const visualization_msgs::MarkerArray& a, const std::string& ns)
{
  for (const auto& m : a.markers)
    if (m.ns == ns)
      return &m;
  return nullptr;
}

/// The markers of `result`: a DELETEALL first, waypoints, control polygon, path, one blend zone
/// per blended corner, and `axes` sample poses' axes, everything in the header's frame and stamp.
void expectMarkers(const TrajectoryResult& result, const std::vector<Pose<double>>& waypoints, int axes,
                   double axis_length)
{
  using visualization_msgs::Marker;
  std_msgs::Header header;
  header.frame_id = "map";
  header.stamp = ros::Time(12, 345);
  const visualization_msgs::MarkerArray a = toMarkerArray(result, waypoints, header, axes, axis_length);
  std::size_t zones = 0;
  for (std::size_t i = 0; i < result.blend_radii.size(); ++i)
    zones += result.blend_radii[i] > 0.0 ? 1 : 0;
  const bool with_axes = axes > 0 && !result.samples.empty();
  ASSERT_EQ(a.markers.size(), 4 + zones + (with_axes ? 1 : 0)) << "axes " << axes;
  EXPECT_EQ(a.markers[0].action, Marker::DELETEALL);
  for (const auto& m : a.markers)
  {
    EXPECT_EQ(m.header.frame_id, "map") << m.ns;
    EXPECT_EQ(m.header.stamp, header.stamp) << m.ns;
  }
  std::set<std::pair<std::string, int>> ids;
  for (std::size_t k = 1; k < a.markers.size(); ++k)
  {
    EXPECT_EQ(a.markers[k].action, Marker::ADD) << a.markers[k].ns;
    EXPECT_TRUE(ids.insert({ a.markers[k].ns, a.markers[k].id }).second) << "ns/id repeats: " << a.markers[k].ns;
    EXPECT_GT(a.markers[k].color.a, 0.0F) << a.markers[k].ns;
    EXPECT_GT(a.markers[k].scale.x, 0.0) << a.markers[k].ns;
  }

  const Marker* w = findMarker(a, "waypoints");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->type, Marker::SPHERE_LIST);
  ASSERT_EQ(w->points.size(), waypoints.size());
  for (std::size_t i = 0; i < waypoints.size(); ++i)
    expectPoint(w->points[i], waypoints[i].p, 0.0, "waypoint " + std::to_string(i));

  const Marker* polygon = findMarker(a, "control_polygon");
  ASSERT_NE(polygon, nullptr);
  EXPECT_EQ(polygon->type, Marker::LINE_STRIP);
  ASSERT_EQ(polygon->points.size(), result.control_points.size());
  for (std::size_t i = 0; i < result.control_points.size(); ++i)
    expectPoint(polygon->points[i], result.control_points[i].p, 0.0, "control point " + std::to_string(i));

  const Marker* path = findMarker(a, "path");
  ASSERT_NE(path, nullptr);
  EXPECT_EQ(path->type, Marker::LINE_STRIP);
  ASSERT_EQ(path->points.size(), result.samples.size());
  for (std::size_t i = 0; i < result.samples.size(); ++i)
    expectPoint(path->points[i], result.samples[i].pose.p, 0.0, "path " + std::to_string(i));

  std::size_t seen_zones = 0;
  for (const auto& m : a.markers)
  {
    if (m.ns != "blend_zones")
      continue;
    ++seen_zones;
    ASSERT_GE(m.id, 0);
    ASSERT_LT(static_cast<std::size_t>(m.id), result.blend_radii.size());
    const double r = result.blend_radii[static_cast<std::size_t>(m.id)];
    EXPECT_GT(r, 0.0);
    EXPECT_EQ(m.type, Marker::SPHERE);
    EXPECT_DOUBLE_EQ(m.scale.x, 2.0 * r);  // diameter
    EXPECT_DOUBLE_EQ(m.scale.y, 2.0 * r);
    EXPECT_DOUBLE_EQ(m.scale.z, 2.0 * r);
    const auto& c = m.pose.position;
    expectPoint(c, result.waypoints[static_cast<std::size_t>(m.id)].p, 0.0, "zone " + std::to_string(m.id));
  }
  EXPECT_EQ(seen_zones, zones);

  const Marker* lines = findMarker(a, "axes");
  if (!with_axes)
  {
    EXPECT_EQ(lines, nullptr);
    return;
  }
  ASSERT_NE(lines, nullptr);
  EXPECT_EQ(lines->type, Marker::LINE_LIST);
  const std::size_t n = result.samples.size();
  const std::size_t count = std::min<std::size_t>(static_cast<std::size_t>(axes), n);
  ASSERT_EQ(lines->points.size(), 6 * count);
  ASSERT_EQ(lines->colors.size(), 6 * count);
  // Evenly spaced samples from the first to the last: the k-th triad stands on the sample nearest
  // k (n - 1) / (count - 1) (the sample found by the triad's origin; within one of that place).
  std::size_t previous = 0;
  for (std::size_t k = 0; k < count; ++k)
  {
    const Eigen::Vector3d origin(lines->points[6 * k].x, lines->points[6 * k].y, lines->points[6 * k].z);
    std::size_t s = n;
    for (std::size_t j = k == 0 ? 0 : previous + 1; j < n && s == n; ++j)
      if (result.samples[j].pose.p == origin)
        s = j;
    ASSERT_LT(s, n) << "triad " << k << " is at no sample after the previous triad's";
    const double place = count == 1 ? 0.0 : static_cast<double>(k) * static_cast<double>(n - 1) / (count - 1);
    EXPECT_LE(std::abs(static_cast<double>(s) - place), 1.0) << "triad " << k;
    if (k == 0)
    {
      EXPECT_EQ(s, 0u);
    }
    if (k + 1 == count && count > 1)
    {
      EXPECT_EQ(s, n - 1) << "the last triad is not at the last sample";
    }
    previous = s;
    const Pose<double>& pose = result.samples[s].pose;
    const Eigen::Matrix3d r = matrixOf(pose.q.x(), pose.q.y(), pose.q.z(), pose.q.w());
    for (int axis = 0; axis < 3; ++axis)
    {
      const auto& from = lines->points[6 * k + 2 * axis];
      const auto& to = lines->points[6 * k + 2 * axis + 1];
      const std::string where = "triad " + std::to_string(k) + " axis " + std::to_string(axis);
      expectPoint(from, pose.p, 0.0, where);
      expectPoint(to, pose.p + axis_length * r.col(axis), 1e-12 * (1.0 + pose.p.norm()), where);
      const Eigen::Vector3d d(to.x - from.x, to.y - from.y, to.z - from.z);
      EXPECT_NEAR(d.norm(), axis_length, 1e-9 * (1.0 + pose.p.norm())) << where;
      // x red, y green, z blue.
      for (int end = 0; end < 2; ++end)
      {
        const auto& c = lines->colors[6 * k + 2 * axis + end];
        EXPECT_EQ(c.r, axis == 0 ? 1.0F : 0.0F) << where;
        EXPECT_EQ(c.g, axis == 1 ? 1.0F : 0.0F) << where;
        EXPECT_EQ(c.b, axis == 2 ? 1.0F : 0.0F) << where;
      }
    }
  }
}
}  // namespace

// Markers of planned trajectories (corner blends: blend zones; a bspline: its control polygon)
// and of random samples, with 0, 1, several and more axes than samples.
TEST(Conversions, MarkersShowTheWaypointsPathBlendsAndAxes)
{
  std::vector<Pose<double>> blended_waypoints, bspline_waypoints;
  const TrajectoryResult blended = plannedResult("piecewise_geodesic", &blended_waypoints);
  ASSERT_FALSE(blended.blend_radii.empty());
  const TrajectoryResult bspline = plannedResult("bspline", &bspline_waypoints);
  ASSERT_FALSE(bspline.control_points.empty());
  for (int axes : { 0, 1, 2, 5, 57, 1000 })
  {
    SCOPED_TRACE("axes " + std::to_string(axes));
    expectMarkers(blended, blended_waypoints, axes, 0.125);
    expectMarkers(bspline, bspline_waypoints, axes, 0.3);
  }
  const TrajectoryResult synthetic = syntheticResult(40);
  for (int axes : { 1, 3, 7, 40 })
  {
    SCOPED_TRACE("synthetic, axes " + std::to_string(axes));
    expectMarkers(synthetic, {}, axes, 2.5);
  }
  // Nothing sampled: no axes, empty strips.
  expectMarkers(TrajectoryResult(), bspline_waypoints, 10, 0.1);
}

// curve fit: the response's control_poses and knots are the result's, stamped with the response's
// header; replayed as a bspline request they give the fitted curve (its first sample's pose);
// every other curve leaves both empty.
TEST(Conversions, FittedBSplineReachesTheResponse)
{
  TrajectoryRequest r;
  for (int i = 0; i <= 40; ++i)
  {
    r.waypoints.emplace_back(so3Exp(Eigen::Vector3d(0.02 * i, 0.0, 0.01 * i)),
                             Eigen::Vector3d(0.05 * i, std::sin(0.1 * i), 0.0));
    r.times.push_back(0.05 * i);
  }
  r.curve = "fit";
  r.control_period = 0.5;
  const TrajectoryResult fit = generate(r, PlannerLimits());
  std_msgs::Header header;
  header.frame_id = "world";
  header.stamp = ros::Time(12.5);
  GenerateTrajectory::Response res;
  copyFit(fit, header, res);
  EXPECT_EQ(res.knots, fit.knots);
  EXPECT_EQ(res.control_poses.header.frame_id, "world");
  EXPECT_EQ(res.control_poses.header.stamp, ros::Time(12.5));
  ASSERT_EQ(res.control_poses.poses.size(), fit.control_points.size());
  ASSERT_EQ(res.control_poses.poses.size(), 4u + 3u);
  for (std::size_t i = 0; i < fit.control_points.size(); ++i)
  {
    const Pose<double> back = fromMsg(res.control_poses.poses[i]);
    EXPECT_LT((back.p - fit.control_points[i].p).norm(), 1e-15) << i;
    EXPECT_LT((back.q.coeffs() - fit.control_points[i].q.coeffs()).norm(), 1e-15) << i;
  }
  TrajectoryRequest replay;
  replay.curve = "bspline";
  replay.waypoints = fit.control_points;
  replay.knots = res.knots;
  replay.degree = 3;
  const TrajectoryResult again = generate(replay, PlannerLimits());
  EXPECT_LT((again.samples.front().pose.p - fit.samples.front().pose.p).norm(), 1e-12);
  EXPECT_LT((again.samples.back().pose.p - fit.samples.back().pose.p).norm(), 1e-12);

  std::vector<Pose<double>> waypoints;
  GenerateTrajectory::Response other;
  copyFit(plannedResult("bspline", &waypoints), header, other);
  EXPECT_TRUE(other.knots.empty());
  EXPECT_TRUE(other.control_poses.poses.empty());
  EXPECT_TRUE(other.control_poses.header.frame_id.empty());
}

// The response's message says what the timing did: a stretch by its factor (only when it slowed
// the curve down), the time-optimal and constant-speed timings by name, never "stretched" (their
// final correction of a few 1e-4 is no stretch the user asked for).
TEST(Conversions, GenerationMessageNamesTheTiming)
{
  TrajectoryRequest r;
  r.waypoints = { Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(0, 0, 0)),
                  Pose<double>(Quaternion<double>(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ())),
                               Eigen::Vector3d(1, 0, 0)),
                  Pose<double>(Quaternion<double>::Identity(), Eigen::Vector3d(1, 1, 0.5)) };
  r.curve = "interpolating";
  r.sample_count = 11;
  EXPECT_EQ(generationMessage(r, generate(r, PlannerLimits())), "11 samples over 2 s");
  r.max_linear_velocity = 0.5;
  r.max_linear_acceleration = 1.0;
  const TrajectoryResult stretched = generate(r, PlannerLimits());
  ASSERT_GT(stretched.time_scale, 1.0);
  std::ostringstream factor;
  factor << " (time stretched x" << stretched.time_scale << " to meet the bounds)";
  EXPECT_NE(generationMessage(r, stretched).find(factor.str()), std::string::npos) << generationMessage(r, stretched);

  r.timing = "time_optimal";
  TrajectoryResult optimal = generate(r, PlannerLimits());
  optimal.time_scale = 1.0004;  // the size of the timing's final correction
  std::string message = generationMessage(r, optimal);
  EXPECT_EQ(message.find("stretched"), std::string::npos) << message;
  EXPECT_NE(message.find(" (time-optimal within the bounds)"), std::string::npos) << message;
  r.max_linear_jerk = 10.0;
  message = generationMessage(r, generate(r, PlannerLimits()));
  EXPECT_EQ(message.find("stretched"), std::string::npos) << message;
  EXPECT_NE(message.find(" (time-optimal within the bounds, jerk-limited)"), std::string::npos) << message;

  r.timing = "constant_speed";
  r.max_linear_jerk = 0.0;
  r.speed = 0.2;
  r.curve = "blended";
  const TrajectoryResult constant = generate(r, PlannerLimits());
  message = generationMessage(r, constant);
  EXPECT_EQ(message.find("stretched"), std::string::npos) << message;
  std::ostringstream window;
  window << " (constant speed 0.2 m/s from t = " << constant.constant_speed_start << " to "
         << constant.constant_speed_end << " s)";
  EXPECT_NE(message.find(window.str()), std::string::npos) << message;
}
