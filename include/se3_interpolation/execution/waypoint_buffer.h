// execution/waypoint_buffer.h: the waypoints the node collects from its topics (~waypoint appends
// one, ~waypoints replaces them all, ~clear_waypoints empties them) until a request without
// waypoints of its own uses them. Safe from several threads; bounded (the node's ~max_waypoints).
// Each waypoint keeps the stamp it came with (s; 0: none, as from ~waypoints), so that a stream of
// stamped poses is a recording: curve fit takes their times from it (Snapshot::recordedTimes).
#pragma once

#include <algorithm>
#include <cstddef>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace se3_interpolation
{
/// Waypoints of type P (the node's geometry_msgs::Pose) in one frame, at most `capacity`.
template <class P>
class WaypointBuffer
{
public:
  /// The buffer's contents at one moment.
  struct Snapshot
  {
    std::vector<P> waypoints;
    std::string frame_id;
    std::vector<double> stamps;  ///< one per waypoint, s (0: the waypoint came without one)

    /// The waypoints' times as a recording: each stamp after the first one's; empty unless every
    /// waypoint has a stamp.
    std::vector<double> recordedTimes() const
    {
      if (stamps.empty() || std::find(stamps.begin(), stamps.end(), 0.0) != stamps.end())
        return {};
      std::vector<double> t(stamps.size());
      for (std::size_t i = 0; i < t.size(); ++i)
        t[i] = stamps[i] - stamps.front();
      return t;
    }
  };

  WaypointBuffer(std::size_t capacity, std::string frame_id) : capacity_(capacity), frame_id_(std::move(frame_id)) {}

  std::size_t capacity() const { return capacity_; }

  /// Appends `waypoint` recorded at `stamp` (s; 0: none); false (nothing changes) when the buffer
  /// is full.
  /// @return whether it was appended; *size is the number held afterwards
  bool append(const P& waypoint, std::size_t* size, double stamp = 0.0)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (waypoints_.size() >= capacity_)
      return false;
    waypoints_.push_back(waypoint);
    stamps_.push_back(stamp);
    *size = waypoints_.size();
    return true;
  }

  /// Replaces the contents; false (nothing changes) for more than capacity() waypoints.
  bool replace(std::vector<P> waypoints, std::string frame_id)
  {
    if (waypoints.size() > capacity_)
      return false;
    std::lock_guard<std::mutex> lock(mutex_);
    stamps_.assign(waypoints.size(), 0.0);
    waypoints_ = std::move(waypoints);
    frame_id_ = std::move(frame_id);
    return true;
  }

  /// Empties the buffer (its frame stays); returns the contents it had.
  Snapshot clear()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    Snapshot s{ std::move(waypoints_), frame_id_, std::move(stamps_) };
    waypoints_.clear();
    stamps_.clear();
    return s;
  }

  Snapshot snapshot() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return { waypoints_, frame_id_, stamps_ };
  }

  std::string frameId() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return frame_id_;
  }

  std::size_t size() const
  {
    std::lock_guard<std::mutex> lock(mutex_);
    return waypoints_.size();
  }

private:
  const std::size_t capacity_;
  mutable std::mutex mutex_;
  std::vector<P> waypoints_;
  std::string frame_id_;
  std::vector<double> stamps_;
};

}  // namespace se3_interpolation
