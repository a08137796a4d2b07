// Integration: a node crashed (SIGKILL) and respawned (node_respawn.test, roslaunch's respawn) takes the
// setpoint up where it was: ~command resumes at the pose held before the kill, a goal at rest far
// from it is refused and one from the frame's state is accepted; killed during a goal, it refuses
// goals until it has a state (no ~actual_frame here: a ~generate publication places the frame).
#include <actionlib/client/simple_action_client.h>
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <signal.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "node_test_utils.h"
#include "se3_interpolation/FollowTrajectoryAction.h"
#include "se3_interpolation/GenerateTrajectory.h"

namespace
{
using se3_interpolation::FollowTrajectoryAction;
using se3_interpolation::FollowTrajectoryGoal;
using se3_interpolation::FollowTrajectoryResult;
using se3_interpolation::GenerateTrajectory;
using Client = actionlib::SimpleActionClient<FollowTrajectoryAction>;
using State = actionlib::SimpleClientGoalState;

const std::string kNode = "/se3_interpolation_node";

struct Command
{
  ros::Time stamp;
  Eigen::Vector3d p;
};

class NodeRespawn : public testing::Test
{
protected:
  void SetUp() override
  {
    ASSERT_TRUE(ros::service::waitForService(kNode + "/generate", ros::Duration(60.0)));
    sub_ = nh_.subscribe<geometry_msgs::PoseStamped>(kNode + "/command", 10000,
                                                     [this](const geometry_msgs::PoseStamped::ConstPtr& m) {
                                                       std::lock_guard<std::mutex> lock(mutex_);
                                                       commands_.push_back({ m->header.stamp,
                                                                             Eigen::Vector3d(m->pose.position.x,
                                                                                             m->pose.position.y,
                                                                                             m->pose.position.z) });
                                                     });
  }

  static std::unique_ptr<Client> client()
  {
    auto c = std::make_unique<Client>(kNode + "/follow_trajectory", true);
    EXPECT_TRUE(c->waitForServer(ros::Duration(30.0)));
    return c;
  }

  /// A goal of one point at rest at `p` (no rotation).
  static FollowTrajectoryGoal pointGoal(const Eigen::Vector3d& p)
  {
    FollowTrajectoryGoal goal;
    goal.trajectory.header.frame_id = "map";
    goal.trajectory.joint_names = { "tool" };
    goal.trajectory.points.resize(1);
    goal.trajectory.points[0].transforms.resize(1);
    goal.trajectory.points[0].transforms[0].translation.x = p.x();
    goal.trajectory.points[0].transforms[0].translation.y = p.y();
    goal.trajectory.points[0].transforms[0].translation.z = p.z();
    goal.trajectory.points[0].transforms[0].rotation.w = 1.0;
    goal.trajectory.points[0].velocities.resize(1);
    goal.trajectory.points[0].accelerations.resize(1);
    return goal;
  }

  /// From the frame's state (from_current) to `target`, jerk-limited time_optimal.
  static GenerateTrajectory::Response generate(const Eigen::Vector3d& target, bool from_current, bool publish)
  {
    GenerateTrajectory srv;
    srv.request.waypoints.header.frame_id = "map";
    srv.request.waypoints.poses = { node_test::pose(target.x(), target.y(), target.z(), 0.0) };
    if (!from_current)
      srv.request.waypoints.poses.insert(srv.request.waypoints.poses.begin(),
                                         node_test::pose(target.x(), target.y() - 0.1, target.z(), 0.0));
    srv.request.curve = "piecewise_geodesic";
    srv.request.timing = "time_optimal";
    srv.request.from_current = from_current;
    srv.request.publish = publish;
    srv.request.sample_period = 0.01;
    srv.request.child_frame_id = "tool";
    EXPECT_TRUE(node_test::callService(kNode + "/generate", srv));
    EXPECT_TRUE(srv.response.success) << srv.response.message;
    return srv.response;
  }

  static FollowTrajectoryGoal goalOf(const GenerateTrajectory::Response& res)
  {
    FollowTrajectoryGoal goal;
    goal.trajectory = res.trajectory;
    return goal;
  }

  /// The node's process id, from its XML-RPC API (getPid), found through the master.
  static int nodePid()
  {
    XmlRpc::XmlRpcValue args, result, payload;
    args[0] = ros::this_node::getName();
    args[1] = kNode;
    if (!ros::master::execute("lookupNode", args, result, payload, true))
      return -1;
    std::string host;
    std::uint32_t port = 0;
    if (!ros::network::splitURI(static_cast<std::string>(payload), host, port))
      return -1;
    XmlRpc::XmlRpcClient client(host.c_str(), static_cast<int>(port), "/");
    XmlRpc::XmlRpcValue request, response;
    request[0] = ros::this_node::getName();
    if (!client.execute("getPid", request, response) || response.getType() != XmlRpc::XmlRpcValue::TypeArray ||
        response.size() < 3)
      return -1;
    return static_cast<int>(response[2]);
  }

  /// Crashes the node (SIGKILL: no shutdown of its own; roslaunch respawns it) and waits for the
  /// new instance's action server.
  void killAndWaitForTheRespawn()
  {
    const int pid = nodePid();
    ASSERT_GT(pid, 0) << "the node's pid";
    ASSERT_EQ(kill(pid, SIGKILL), 0);
    ASSERT_TRUE(node_test::waitFor([] { return !ros::service::exists(kNode + "/generate", false); }, 30.0));
    ASSERT_TRUE(ros::service::waitForService(kNode + "/generate", ros::Duration(60.0)));
    killed_ = ros::Time::now();
    client();
  }

  std::vector<Command> commandsAfter(const ros::Time& t)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<Command> out;
    for (const Command& c : commands_)
      if (c.stamp > t)
        out.push_back(c);
    return out;
  }

  ros::NodeHandle nh_;
  ros::Subscriber sub_;
  std::mutex mutex_;
  std::vector<Command> commands_;
  ros::Time killed_;
};

TEST_F(NodeRespawn, TheHeldSetpointSurvivesARespawn)
{
  auto c = client();
  c->sendGoal(pointGoal(Eigen::Vector3d(0.0, 0.0, 0.3)));  // places the frame (nothing has played)
  ASSERT_TRUE(c->waitForResult(ros::Duration(10.0)));
  ASSERT_EQ(c->getState(), State::SUCCEEDED) << c->getState().getText();
  const Eigen::Vector3d held(0.8, 0.2, 0.3);
  const GenerateTrajectory::Response res = generate(held, true, false);
  ASSERT_TRUE(res.success) << res.message;
  c->sendGoal(goalOf(res));
  ASSERT_TRUE(c->waitForResult(ros::Duration(res.duration + 10.0)));
  ASSERT_EQ(c->getState(), State::SUCCEEDED) << c->getState().getText();
  ros::WallDuration(0.5).sleep();

  killAndWaitForTheRespawn();
  EXPECT_TRUE(node_test::waitFor([&] { return commandsAfter(killed_).size() >= 10; }, 10.0))
      << "~command resumes after the respawn";
  for (const Command& cmd : commandsAfter(killed_))
    EXPECT_LT((cmd.p - held).norm(), 1e-9) << "~command resumes at the held pose";

  // A goal at rest 3.4 m away is refused (the start rule against the held pose) ...
  auto far = client();
  far->sendGoal(pointGoal(held + Eigen::Vector3d(3.4, 0.0, 0.0)));
  ASSERT_TRUE(far->waitForResult(ros::Duration(10.0)));
  EXPECT_EQ(far->getState(), State::REJECTED);
  EXPECT_EQ(far->getResult()->error_code, FollowTrajectoryResult::INVALID_GOAL) << far->getResult()->error_string;
  // ... and one from the frame's state runs.
  const GenerateTrajectory::Response back = generate(Eigen::Vector3d(0.2, 0.2, 0.3), true, false);
  ASSERT_TRUE(back.success) << back.message;
  EXPECT_LT((Eigen::Vector3d(back.trajectory.points[0].transforms[0].translation.x,
                             back.trajectory.points[0].transforms[0].translation.y,
                             back.trajectory.points[0].transforms[0].translation.z) -
             held)
                .norm(),
            1e-9)
      << "from_current starts at the held pose";
  auto d = client();
  d->sendGoal(goalOf(back));
  ASSERT_TRUE(d->waitForResult(ros::Duration(back.duration + 10.0)));
  EXPECT_EQ(d->getState(), State::SUCCEEDED) << d->getState().getText();
}

TEST_F(NodeRespawn, KilledDuringAGoalItRefusesGoalsUntilItHasAState)
{
  auto c = client();
  const GenerateTrajectory::Response res = generate(Eigen::Vector3d(1.2, -0.4, 0.3), true, false);
  ASSERT_TRUE(res.success) << res.message;
  c->sendGoal(goalOf(res));
  ros::WallDuration(res.trajectory.header.stamp.toSec() - ros::Time::now().toSec() + 0.5 * res.duration).sleep();
  killAndWaitForTheRespawn();

  auto d = client();
  d->sendGoal(pointGoal(Eigen::Vector3d(0.0, 0.0, 0.3)));
  ASSERT_TRUE(d->waitForResult(ros::Duration(10.0)));
  EXPECT_EQ(d->getState(), State::REJECTED);
  EXPECT_NE(d->getResult()->error_string.find("restarted while a goal moved the frame"), std::string::npos)
      << d->getResult()->error_string;
  // A ~generate publication places the frame: goals from it are taken.
  const GenerateTrajectory::Response placed = generate(Eigen::Vector3d(0.5, 0.5, 0.3), false, true);
  ASSERT_TRUE(placed.success) << placed.message;
  ros::WallDuration(placed.trajectory.header.stamp.toSec() - ros::Time::now().toSec() + placed.duration + 0.2).sleep();
  const GenerateTrajectory::Response from_there = generate(Eigen::Vector3d(0.3, 0.3, 0.3), true, false);
  ASSERT_TRUE(from_there.success) << from_there.message;
  auto e = client();
  e->sendGoal(goalOf(from_there));
  ASSERT_TRUE(e->waitForResult(ros::Duration(from_there.duration + 10.0)));
  EXPECT_EQ(e->getState(), State::SUCCEEDED) << e->getState().getText();
}

}  // namespace

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_node_respawn");
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
