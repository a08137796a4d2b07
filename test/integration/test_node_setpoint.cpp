// Integration: the setpoint never jumps (node_setpoint.test). ~command is recorded at 1 kHz
// (~command_rate 1000) through each way a motion on the moving frame starts, changes or ends — a
// goal from rest, a replacing goal, a publish: true generation and an auto-generation during a
// goal, ~clear_waypoints during a goal, cancels (accelerating, cruising, braking at the bound), an
// abort on the path tolerance — and its finite differences at the messages' own stamps (divided
// differences over four consecutive setpoints, so uneven spacing is exact) must keep the node's
// bounds: velocity, acceleration and jerk, linear and angular, hence position, velocity and
// acceleration continuous. A goal at rest starting farther from the frame than ~start_tolerance_*
// is refused whatever its own tolerances.
#include <actionlib/client/simple_action_client.h>
#include <geometry_msgs/PoseArray.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_msgs/String.h>
#include <std_srvs/Trigger.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "node_test_utils.h"
#include "se3_interpolation/FollowTrajectoryAction.h"
#include "se3_interpolation/GenerateTrajectory.h"
#include "se3_interpolation/GenerationStatus.h"

namespace
{
using se3_interpolation::FollowTrajectoryAction;
using se3_interpolation::FollowTrajectoryGoal;
using se3_interpolation::FollowTrajectoryResult;
using se3_interpolation::GenerateTrajectory;
using Client = actionlib::SimpleActionClient<FollowTrajectoryAction>;
using State = actionlib::SimpleClientGoalState;

const std::string kNode = "/se3_interpolation_node";
const std::string kChild = "tool";

/// The node's bounds (node_setpoint.test): linear, angular.
constexpr std::array<double, 2> kVelocity{ 0.5, 1.0 };
constexpr std::array<double, 2> kAcceleration{ 1.0, 2.0 };
constexpr std::array<double, 2> kJerk{ 10.0, 20.0 };
/// What the differences may show beyond a bound: velocity and acceleration 2 % (a goal's quintic
/// between 10 ms samples overshoots by up to ~0.3 %, its check lets 1 % through; the rest is the
/// differences' own error), jerk 50 % (the quintic's own jerk reaches ~1.4 times the bound where
/// the sampled motion's jerk switches sign, execution/goal_trajectory.h: the bound holds for each
/// segment's mean jerk).
constexpr double kRateSlack = 1.02;
constexpr double kJerkSlack = 1.5;
/// Setpoints closer than this (s) to the previous one are skipped: their differences would only
/// magnify the stamps' rounding.
constexpr double kMinSpacing = 5e-4;
/// The longest silence of ~command while a goal plays or holds (s): far above a loaded machine's
/// timer delays, far below the 3.8 s of a stream that stops.
constexpr double kMaxSilence = 0.5;

/// A recorded ~command setpoint: its stamp (s after the recording's origin, from integer
/// nanoseconds: a double of seconds since 1970 has only ~0.2 µs resolution) and pose.
struct Command
{
  double t;
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
};

/// `x` (the rotation R_k R_0ᵀ for angular) as coordinates of the chart at the window's first pose.
Eigen::Vector3d rotationVector(const Eigen::Quaterniond& q)
{
  Eigen::AngleAxisd aa(q.w() < 0 ? Eigen::Quaterniond(-q.coeffs()) : q);
  return aa.angle() * aa.axis();
}

class NodeSetpoint : public testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    ASSERT_TRUE(ros::service::waitForService(kNode + "/generate", ros::Duration(60.0)));
    nh_ = std::make_unique<ros::NodeHandle>();
    origin_ = ros::Time::now();
    command_sub_ = nh_->subscribe(kNode + "/command", 100000, &NodeSetpoint::onCommand);
    arm_mode_ = nh_->advertise<std_msgs::String>("/simulated_arm/mode", 1, true);
    waypoints_pub_ = nh_->advertise<geometry_msgs::PoseArray>(kNode + "/waypoints", 1, true);
    status_sub_ = nh_->subscribe(kNode + "/status", 10, &NodeSetpoint::onStatus);
    // The first goal places the frame (nothing has played on it): one point, at rest.
    FollowTrajectoryGoal home;
    home.trajectory.header.frame_id = "map";
    home.trajectory.joint_names = { kChild };
    home.trajectory.points.resize(1);
    home.trajectory.points[0].transforms.resize(1);
    home.trajectory.points[0].transforms[0].translation.z = 0.3;
    home.trajectory.points[0].transforms[0].rotation.w = 1.0;
    home.trajectory.points[0].velocities.resize(1);
    home.trajectory.points[0].accelerations.resize(1);
    auto c = client();
    c->sendGoal(home);
    ASSERT_TRUE(c->waitForResult(ros::Duration(10.0)));
    ASSERT_EQ(c->getState(), State::SUCCEEDED) << c->getState().getText();
  }

  static void onCommand(const geometry_msgs::PoseStamped::ConstPtr& m)
  {
    const Eigen::Vector3d p(m->pose.position.x, m->pose.position.y, m->pose.position.z);
    const Eigen::Quaterniond q(m->pose.orientation.w, m->pose.orientation.x, m->pose.orientation.y,
                               m->pose.orientation.z);
    std::lock_guard<std::mutex> lock(mutex_);
    commands_.push_back({ (m->header.stamp - origin_).toSec(), p, q });
  }

  static void onStatus(const se3_interpolation::GenerationStatus::ConstPtr& m)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    statuses_.push_back(*m);
  }

  static void TearDownTestSuite()
  {
    status_sub_.shutdown();
    command_sub_.shutdown();
    arm_mode_.shutdown();
    waypoints_pub_.shutdown();
    nh_.reset();
  }

  static std::unique_ptr<Client> client()
  {
    auto c = std::make_unique<Client>(kNode + "/follow_trajectory", true);
    EXPECT_TRUE(c->waitForServer(ros::Duration(30.0)));
    return c;
  }

  /// Now, on the recording's clock (s).
  static double now() { return (ros::Time::now() - origin_).toSec(); }

  /// Sleeps until `t` on the recording's clock.
  static void sleepUntil(double t) { ros::WallDuration(std::max(0.0, t - now())).sleep(); }

  /// A rest-to-rest motion from the frame's state (from_current) through `targets`, jerk-limited
  /// time_optimal within the node's bounds, sampled every 10 ms.
  static GenerateTrajectory::Response generate(const std::vector<geometry_msgs::Pose>& targets, bool publish = false)
  {
    GenerateTrajectory srv;
    srv.request.waypoints.header.frame_id = "map";
    srv.request.waypoints.poses = targets;
    srv.request.curve = "piecewise_geodesic";
    srv.request.timing = "time_optimal";
    srv.request.from_current = true;
    srv.request.publish = publish;
    srv.request.sample_period = 0.01;
    srv.request.child_frame_id = kChild;
    EXPECT_TRUE(node_test::callService(kNode + "/generate", srv));
    return srv.response;
  }

  static FollowTrajectoryGoal goalOf(const GenerateTrajectory::Response& res)
  {
    FollowTrajectoryGoal goal;
    goal.trajectory = res.trajectory;
    return goal;
  }

  /// The goal's start and end on the recording's clock.
  static double startOf(const GenerateTrajectory::Response& res) { return (res.trajectory.header.stamp - origin_).toSec(); }
  static double endOf(const GenerateTrajectory::Response& res) { return startOf(res) + res.duration; }

  /// A goal to `target` sent, and the instant it starts; waits for its acceptance.
  static GenerateTrajectory::Response sendGoal(Client& c, const geometry_msgs::Pose& target)
  {
    const GenerateTrajectory::Response res = generate({ target });
    EXPECT_TRUE(res.success) << res.message;
    c.sendGoal(goalOf(res));
    return res;
  }

  static void setArm(const std::string& mode)
  {
    std_msgs::String m;
    m.data = mode;
    arm_mode_.publish(m);
    ros::WallDuration(0.5).sleep();  // the arm echoes modes; half a second is ample for the abort below
  }

  static std::vector<Command> commandsBetween(double from, double to)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Command> out;
    for (const Command& c : commands_)
      if (c.t >= from && c.t <= to && (out.empty() || c.t - out.back().t >= kMinSpacing))
        out.push_back(c);
    return out;
  }

  /// The setpoints of [from, to] keep the bounds by their divided differences, and never fall
  /// silent for more than kMaxSilence.
  static void expectSmooth(double from, double to, const std::string& what)
  {
    SCOPED_TRACE(what);
    const std::vector<Command> c = commandsBetween(from, to);
    ASSERT_GE(c.size(), 20u) << "~command recorded on [" << from << ", " << to << "]";
    EXPECT_GE(c.front().t, from - 1e-9);
    double worst_gap = 0.0;
    std::array<double, 2> v_peak{}, a_peak{}, j_peak{};
    for (std::size_t i = 0; i + 3 < c.size(); ++i)
    {
      worst_gap = std::max(worst_gap, c[i + 1].t - c[i].t);
      const double t[4] = { c[i].t, c[i + 1].t, c[i + 2].t, c[i + 3].t };
      for (int part = 0; part < 2; ++part)
      {
        Eigen::Vector3d x[4];
        for (int k = 0; k < 4; ++k)
          x[k] = part == 0 ? Eigen::Vector3d(c[i + k].p - c[i].p) : rotationVector(c[i + k].q * c[i].q.conjugate());
        // Newton's divided differences: f[t0, t1] = velocity, 2 f[t0, t1, t2] = acceleration,
        // 6 f[t0 … t3] = jerk, each at a point inside the window.
        Eigen::Vector3d d1[3], d2[2];
        for (int k = 0; k < 3; ++k)
          d1[k] = (x[k + 1] - x[k]) / (t[k + 1] - t[k]);
        for (int k = 0; k < 2; ++k)
          d2[k] = (d1[k + 1] - d1[k]) / (t[k + 2] - t[k]);
        const Eigen::Vector3d d3 = (d2[1] - d2[0]) / (t[3] - t[0]);
        v_peak[part] = std::max(v_peak[part], d1[0].norm());
        a_peak[part] = std::max(a_peak[part], 2.0 * d2[0].norm());
        j_peak[part] = std::max(j_peak[part], 6.0 * d3.norm());
        EXPECT_LE(d1[0].norm(), kRateSlack * kVelocity[part]) << "velocity " << part << " at t = " << t[0];
        EXPECT_LE(2.0 * d2[0].norm(), kRateSlack * kAcceleration[part]) << "acceleration " << part << " at t = " << t[0];
        EXPECT_LE(6.0 * d3.norm(), kJerkSlack * kJerk[part]) << "jerk " << part << " at t = " << t[0];
      }
    }
    EXPECT_LE(worst_gap, kMaxSilence) << "~command fell silent";
    ROS_INFO_STREAM(what << ": " << c.size() << " setpoints; peaks linear v " << v_peak[0] << " a " << a_peak[0]
                         << " j " << j_peak[0] << ", angular v " << v_peak[1] << " a " << a_peak[1] << " j "
                         << j_peak[1]);
  }

  /// The last setpoint recorded.
  static Command last()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return commands_.back();
  }

  static std::unique_ptr<ros::NodeHandle> nh_;
  static ros::Time origin_;
  static ros::Subscriber command_sub_;
  static ros::Publisher arm_mode_;
  static ros::Publisher waypoints_pub_;
  static ros::Subscriber status_sub_;
  static std::vector<se3_interpolation::GenerationStatus> statuses_;
  static std::mutex mutex_;
  static std::vector<Command> commands_;
};

std::unique_ptr<ros::NodeHandle> NodeSetpoint::nh_;
ros::Time NodeSetpoint::origin_;
ros::Subscriber NodeSetpoint::command_sub_;
ros::Publisher NodeSetpoint::arm_mode_;
ros::Publisher NodeSetpoint::waypoints_pub_;
ros::Subscriber NodeSetpoint::status_sub_;
std::vector<se3_interpolation::GenerationStatus> NodeSetpoint::statuses_;
std::mutex NodeSetpoint::mutex_;
std::vector<Command> NodeSetpoint::commands_;

TEST_F(NodeSetpoint, AGoalFromRestAndAReplacingGoal)
{
  auto a = client();
  auto b = client();
  const GenerateTrajectory::Response first = sendGoal(*a, node_test::pose(1.0, 0.3, 0.5, 0.8));
  sleepUntil(startOf(first) + 0.5 * first.duration);
  GenerateTrajectory::Response second;
  for (int attempt = 0; attempt < 10 && !second.success; ++attempt)
    second = generate({ node_test::pose(0.2, 0.6, 0.3, -0.5) });
  ASSERT_TRUE(second.success) << second.message;
  b->sendGoal(goalOf(second));
  ASSERT_TRUE(b->waitForResult(ros::Duration(second.duration + 10.0)));
  EXPECT_EQ(b->getState(), State::SUCCEEDED) << b->getState().getText();
  EXPECT_EQ(a->getState(), State::PREEMPTED);
  expectSmooth(startOf(first) - 0.2, endOf(second) + 0.2, "a goal from rest, replaced half-way");
}

TEST_F(NodeSetpoint, APublishedGenerationDuringAGoalLeavesItRunning)
{
  auto c = client();
  const GenerateTrajectory::Response goal = sendGoal(*c, node_test::pose(0.9, -0.2, 0.4, 0.4));
  sleepUntil(startOf(goal) + 0.4 * goal.duration);
  const GenerateTrajectory::Response published = generate({ node_test::pose(-0.5, 0.5, 0.2, -1.0) }, true);
  EXPECT_TRUE(published.success) << published.message;
  EXPECT_NE(published.message.find("not played on the moving frame"), std::string::npos) << published.message;
  ASSERT_TRUE(c->waitForResult(ros::Duration(goal.duration + 10.0)));
  EXPECT_EQ(c->getState(), State::SUCCEEDED) << c->getState().getText();
  sleepUntil(endOf(goal) + 0.5);
  expectSmooth(startOf(goal) - 0.2, endOf(goal) + 0.5, "a publish: true generation during a goal");
  EXPECT_LT((last().p - Eigen::Vector3d(0.9, -0.2, 0.4)).norm(), 1e-6) << "~command holds the goal's end";
}

TEST_F(NodeSetpoint, AnAutoGenerationDuringAGoalLeavesItRunning)
{
  auto c = client();
  const GenerateTrajectory::Response goal = sendGoal(*c, node_test::pose(0.2, 0.4, 0.3, -0.3));
  sleepUntil(startOf(goal) + 0.4 * goal.duration);
  geometry_msgs::PoseArray waypoints;
  waypoints.header.frame_id = "map";
  waypoints.poses = { node_test::pose(-0.4, -0.4, 0.3, 0.0), node_test::pose(0.6, 0.6, 0.6, 1.0) };
  waypoints_pub_.publish(waypoints);
  // The auto-generation ran, and was published but not played.
  EXPECT_TRUE(node_test::waitFor(
      [] {
        std::lock_guard<std::mutex> lock(mutex_);
        return !statuses_.empty() && statuses_.back().source == "auto_generation";
      },
      10.0));
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_FALSE(statuses_.empty());
    EXPECT_TRUE(statuses_.back().success) << statuses_.back().message;
    EXPECT_NE(statuses_.back().message.find("not played on the moving frame"), std::string::npos)
        << statuses_.back().message;
  }
  ASSERT_TRUE(c->waitForResult(ros::Duration(goal.duration + 10.0)));
  EXPECT_EQ(c->getState(), State::SUCCEEDED) << c->getState().getText();
  sleepUntil(endOf(goal) + 0.5);
  expectSmooth(startOf(goal) - 0.2, endOf(goal) + 0.5, "an auto-generation during a goal");
  EXPECT_LT((last().p - Eigen::Vector3d(0.2, 0.4, 0.3)).norm(), 1e-6) << "~command holds the goal's end";
}

TEST_F(NodeSetpoint, ClearWaypointsDuringAGoalStopsWithinTheBounds)
{
  auto c = client();
  const GenerateTrajectory::Response goal = sendGoal(*c, node_test::pose(1.4, 0.4, 0.3, 0.0));
  sleepUntil(startOf(goal) + 0.5 * goal.duration);
  std_srvs::Trigger clear;
  ASSERT_TRUE(node_test::callService(kNode + "/clear_waypoints", clear));
  const double cleared = now();
  ASSERT_TRUE(c->waitForResult(ros::Duration(5.0)));
  EXPECT_EQ(c->getState(), State::PREEMPTED);
  sleepUntil(cleared + 2.0);
  expectSmooth(startOf(goal) - 0.2, cleared + 2.0, "~clear_waypoints during a goal");
  const std::vector<Command> held = commandsBetween(cleared + 1.5, cleared + 2.0);
  ASSERT_GE(held.size(), 2u);
  EXPECT_LT((held.back().p - held.front().p).norm(), 1e-12) << "at rest after the stop";
  EXPECT_GT((held.back().p - Eigen::Vector3d(1.4, 0.4, 0.3)).norm(), 1e-3) << "stopped before the goal's end";
}

TEST_F(NodeSetpoint, CancelsKeepTheBoundsWhateverTheGoalWasDoing)
{
  // Accelerating, cruising, and braking at the acceleration bound (the last 0.3 s of a
  // straight 1.4 m: at 0.5 m/s it brakes at 1 m/s² during its last ~0.6 s).
  const double x_end[3] = { 0.2, 1.4, 0.2 };
  for (int k = 0; k < 3; ++k)
  {
    auto c = client();
    const GenerateTrajectory::Response goal = sendGoal(*c, node_test::pose(x_end[k], 0.4, 0.3, 0.0));
    const double cancel_at[3] = { startOf(goal) + 0.25, startOf(goal) + 0.5 * goal.duration, endOf(goal) - 0.3 };
    sleepUntil(cancel_at[k]);
    c->cancelGoal();
    ASSERT_TRUE(c->waitForResult(ros::Duration(5.0)));
    EXPECT_EQ(c->getState(), State::PREEMPTED);
    sleepUntil(cancel_at[k] + 2.0);
    expectSmooth(startOf(goal) - 0.2, cancel_at[k] + 2.0, "cancel " + std::to_string(k));
  }
}

TEST_F(NodeSetpoint, AnAbortOnThePathToleranceStopsWithinTheBounds)
{
  setArm("freeze");
  auto c = client();
  const GenerateTrajectory::Response res = generate({ node_test::pose(1.2, -0.3, 0.4, 0.6) });
  ASSERT_TRUE(res.success) << res.message;
  FollowTrajectoryGoal goal = goalOf(res);
  goal.path_tolerance_linear = 0.05;
  c->sendGoal(goal);
  ASSERT_TRUE(c->waitForResult(ros::Duration(res.duration + 10.0)));
  const double aborted = now();
  setArm("follow");
  EXPECT_EQ(c->getState(), State::ABORTED);
  EXPECT_EQ(c->getResult()->error_code, FollowTrajectoryResult::PATH_TOLERANCE_VIOLATED)
      << c->getResult()->error_string;
  sleepUntil(aborted + 2.0);
  expectSmooth(startOf(res) - 0.2, aborted + 2.0, "an abort on the path tolerance");
}

TEST_F(NodeSetpoint, AGoalAtRestMustStartAtTheFrameWhateverItsTolerance)
{
  const Command held = last();
  FollowTrajectoryGoal goal;
  goal.trajectory.header.frame_id = "map";
  goal.trajectory.joint_names = { kChild };
  goal.trajectory.points.resize(1);
  goal.trajectory.points[0].transforms.resize(1);
  goal.trajectory.points[0].transforms[0].translation.x = held.p.x() + 0.5;
  goal.trajectory.points[0].transforms[0].translation.y = held.p.y();
  goal.trajectory.points[0].transforms[0].translation.z = held.p.z();
  goal.trajectory.points[0].transforms[0].rotation.x = held.q.x();
  goal.trajectory.points[0].transforms[0].rotation.y = held.q.y();
  goal.trajectory.points[0].transforms[0].rotation.z = held.q.z();
  goal.trajectory.points[0].transforms[0].rotation.w = held.q.w();
  goal.trajectory.points[0].velocities.resize(1);
  goal.trajectory.points[0].accelerations.resize(1);
  goal.path_tolerance_linear = 10.0;
  auto c = client();
  c->sendGoal(goal);
  ASSERT_TRUE(c->waitForResult(ros::Duration(5.0)));
  EXPECT_EQ(c->getState(), State::REJECTED);
  EXPECT_EQ(c->getResult()->error_code, FollowTrajectoryResult::INVALID_GOAL);
  EXPECT_NE(c->getResult()->error_string.find("tolerance 0.001 m"), std::string::npos)
      << c->getResult()->error_string;
}

// Every transition above and the handovers between the tests, in one stream.
TEST_F(NodeSetpoint, TheWholeStreamNeverJumps)
{
  ros::WallDuration(0.2).sleep();
  double from = 0.0, to = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_FALSE(commands_.empty());
    from = commands_.front().t;
    to = commands_.back().t;
  }
  expectSmooth(from, to, "the whole recording");
}

}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_setpoint");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
