// Fault: the ROS master killed and restarted on the same port (issue 15, row 10). roscpp never
// registers again with a new master, so the node's watchdog must notice that the master no
// longer knows it and exit with status 1 (to be respawned by roslaunch). This test runs its own
// master on a free port (never 11311) and the node as a child process, without rostest.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#include <xmlrpcpp/XmlRpc.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

namespace
{
int freePort()
{
  const int s = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = 0;
  socklen_t len = sizeof(a);
  if (s < 0 || bind(s, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0 ||
      getsockname(s, reinterpret_cast<sockaddr*>(&a), &len) != 0)
    return 0;
  const int port = ntohs(a.sin_port);
  close(s);
  return port;
}

/// Starts `argv` with its output in `log`; returns the child's pid.
pid_t spawn(const std::vector<std::string>& argv, const std::string& log)
{
  const pid_t pid = fork();
  if (pid == 0)
  {
    std::freopen(log.c_str(), "w", stdout);
    dup2(fileno(stdout), fileno(stderr));
    std::vector<char*> args;
    for (const auto& a : argv)
      args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    _exit(127);
  }
  return pid;
}

/// Does the master at `port` list `node` as a subscriber of `topic` (getSystemState)?
bool masterHasSubscriber(int port, const std::string& topic, const std::string& node)
{
  XmlRpc::XmlRpcClient client("127.0.0.1", port, "/");
  XmlRpc::XmlRpcValue args, result;
  args[0] = "/test_master_restart";
  if (!client.execute("getSystemState", args, result) || result.getType() != XmlRpc::XmlRpcValue::TypeArray ||
      static_cast<int>(result[0]) != 1)
    return false;
  XmlRpc::XmlRpcValue& subscribers = result[2][1];
  for (int i = 0; i < subscribers.size(); ++i)
    if (static_cast<std::string>(subscribers[i][0]) == topic)
      for (int j = 0; j < subscribers[i][1].size(); ++j)
        if (static_cast<std::string>(subscribers[i][1][j]) == node)
          return true;
  return false;
}

bool masterUp(int port)
{
  XmlRpc::XmlRpcClient client("127.0.0.1", port, "/");
  XmlRpc::XmlRpcValue args, result;
  args[0] = "/test_master_restart";
  return client.execute("getUri", args, result) && result.getType() == XmlRpc::XmlRpcValue::TypeArray &&
         static_cast<int>(result[0]) == 1;
}

template <class F>
bool waitFor(F done, double seconds)
{
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < deadline)
  {
    if (done())
      return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return done();
}

std::string slurp(const std::string& path)
{
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
}  // namespace

TEST(MasterRestart, NodeExitsToBeRespawnedWhenTheMasterForgetsIt)
{
  const int port = freePort();
  ASSERT_GT(port, 0);
  const std::string uri = "http://127.0.0.1:" + std::to_string(port) + "/";
  setenv("ROS_MASTER_URI", uri.c_str(), 1);
  setenv("ROS_IP", "127.0.0.1", 1);
  const std::string dir = testing::TempDir();
  const std::vector<std::string> master = { "rosmaster", "--core", "-p", std::to_string(port) };
  pid_t master_pid = spawn(master, dir + "master_restart_master1.log");
  ASSERT_TRUE(waitFor([&] { return masterUp(port); }, 30.0));

  const std::string node_log = dir + "master_restart_node.log";
  const pid_t node = spawn({ SE3_NODE_BIN, "__name:=watched_node", "_master_check_period:=0.2", "_tf_rate:=10" },
                           node_log);
  // Its last registration (the ~waypoint subscriber): the node is fully up.
  ASSERT_TRUE(waitFor([&] { return masterHasSubscriber(port, "/watched_node/waypoint", "/watched_node"); }, 30.0))
      << slurp(node_log);

  // While the master is away the node waits; once a new master answers without knowing it, it exits.
  kill(master_pid, SIGKILL);
  waitpid(master_pid, nullptr, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  int status = 0;
  EXPECT_EQ(waitpid(node, &status, WNOHANG), 0) << "the node exited while the master was down";
  master_pid = spawn(master, dir + "master_restart_master2.log");

  bool exited = waitFor([&] { return waitpid(node, &status, WNOHANG) == node; }, 30.0);
  if (!exited)
  {
    kill(node, SIGKILL);
    waitpid(node, &status, 0);
  }
  kill(master_pid, SIGKILL);
  waitpid(master_pid, nullptr, 0);
  ASSERT_TRUE(exited) << "the node lives on unregistered:\n" << slurp(node_log);
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_NE(slurp(node_log).find("no longer knows /watched_node"), std::string::npos) << slurp(node_log);
}
