// The waypoint buffer and the sequence-gap counter (execution/), without ROS.
#include <gtest/gtest.h>

#include <thread>

#include "se3_interpolation/execution/sequence_gaps.h"
#include "se3_interpolation/execution/waypoint_buffer.h"

using namespace se3_interpolation;

TEST(WaypointBuffer, AppendsUpToItsCapacityReplacesAndClears)
{
  WaypointBuffer<int> b(3, "map");
  std::size_t n = 0;
  for (int i = 0; i < 3; ++i)
  {
    EXPECT_TRUE(b.append(i, &n));
    EXPECT_EQ(n, static_cast<std::size_t>(i + 1));
  }
  EXPECT_FALSE(b.append(9, &n));  // full: nothing changes
  EXPECT_EQ(b.snapshot().waypoints, (std::vector<int>{ 0, 1, 2 }));
  EXPECT_FALSE(b.replace({ 1, 2, 3, 4 }, "odom"));
  EXPECT_EQ(b.frameId(), "map");
  EXPECT_TRUE(b.replace({ 7, 8 }, "odom"));
  EXPECT_EQ(b.snapshot().frame_id, "odom");
  const auto cleared = b.clear();
  EXPECT_EQ(cleared.waypoints, (std::vector<int>{ 7, 8 }));
  EXPECT_EQ(b.size(), 0u);
  EXPECT_EQ(b.frameId(), "odom");  // the frame stays
}

// Stamped appends are a recording: their times count from the first stamp; one waypoint without
// a stamp (or a ~waypoints replacement) and there is no recording.
TEST(WaypointBuffer, StampedAppendsAreARecording)
{
  WaypointBuffer<int> b(10, "map");
  std::size_t n = 0;
  for (int i = 0; i < 4; ++i)
    ASSERT_TRUE(b.append(i, &n, 1000.0 + 0.25 * i));
  EXPECT_EQ(b.snapshot().recordedTimes(), (std::vector<double>{ 0.0, 0.25, 0.5, 0.75 }));
  ASSERT_TRUE(b.append(4, &n));
  EXPECT_TRUE(b.snapshot().recordedTimes().empty());
  ASSERT_TRUE(b.replace({ 1, 2, 3 }, "map"));
  EXPECT_EQ(b.snapshot().stamps, (std::vector<double>{ 0.0, 0.0, 0.0 }));
  EXPECT_TRUE(b.snapshot().recordedTimes().empty());
  b.clear();
  ASSERT_TRUE(b.append(5, &n, 7.0));
  ASSERT_TRUE(b.append(6, &n, 8.5));
  EXPECT_EQ(b.snapshot().recordedTimes(), (std::vector<double>{ 0.0, 1.5 }));
}

TEST(WaypointBuffer, ConcurrentAppendsAreAllCountedUpToTheCapacity)
{
  WaypointBuffer<int> b(1500, "map");
  auto add = [&] {
    std::size_t n = 0;
    for (int i = 0; i < 1000; ++i)
      b.append(i, &n);
  };
  std::thread a(add), c(add);
  a.join();
  c.join();
  EXPECT_EQ(b.size(), 1500u);
}

TEST(SequenceGaps, CountsTheMessagesEachPublisherSkipped)
{
  SequenceGaps g;
  EXPECT_EQ(g.observe("/a", 5), 0u);   // first message
  EXPECT_EQ(g.observe("/a", 6), 0u);
  EXPECT_EQ(g.observe("/a", 10), 3u);  // 7, 8, 9 lost
  EXPECT_EQ(g.observe("/b", 100), 0u);  // another publisher
  EXPECT_EQ(g.observe("/a", 2), 0u);   // a restart
  EXPECT_EQ(g.observe("/a", 2), 0u);   // not numbered
  EXPECT_EQ(g.observe("/a", 0xFFFFFFFFu), 0xFFFFFFFFull - 3u);
}

TEST(SequenceGaps, ForgetsEveryoneRatherThanGrowWithoutBound)
{
  SequenceGaps g;
  for (std::size_t i = 0; i < 3 * SequenceGaps::kMaxTrackedPublishers; ++i)
  {
    g.observe("/p" + std::to_string(i), 1);
    EXPECT_LE(g.trackedPublishers(), SequenceGaps::kMaxTrackedPublishers);
  }
  g.observe("/p0", 1);
  EXPECT_EQ(g.observe("/p0", 5), 3u);  // a known publisher's gap still counts
}
