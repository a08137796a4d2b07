// execution/: what the node does with a trajectory once it has one, without ROS: playback.h
// (this header: the motion a moving frame shows over time), waypoint_buffer.h (the buffered
// waypoints), sequence_gaps.h (messages lost between numbered ones).
//
// Playback: the timeline of the moving frame. It shows one motion at a time, on a clock of int64
// nanoseconds (ROS time: a double of seconds since 1970 has only ~0.2 µs resolution, and a
// ros::Duration throws beyond 2³¹ s). A motion is a trajectory stamped at some instant: its time t
// counts from the stamp, and it spans [start_time, start_time + duration]. Before its start and
// after its end the pose is held at rest (or, with loop, the span repeats forever).
//  - play(): the new motion replaces the one shown at its start instant (stamp + start_time); until
//    then the old one goes on. A replan computed from the state at that instant
//    (from_current, docs/timing.md) is therefore spliced without a jump (C²).
//  - hold(): the frame stays where it is now, at rest.
//  - stop(): the frame comes to rest along the rest of its path. Its path time τ is slowed by a
//    ramp of T seconds: with σ = (t − t_c)/T ∈ [0, 1],
//        τ̇ = 1 − 3σ² + 2σ³,   τ = τ_c + T (σ − σ³ + σ⁴/2),   τ̈ = 6 (σ² − σ)/T,
//    so τ̇ falls from 1 to 0 with τ̈ = 0 at both ends: velocity v τ̇ and acceleration a τ̇² + v τ̈ of
//    the motion (chain rule; the spatial angular velocity is linear in the path rate too) are
//    continuous at t_c and reach rest at t_c + T, having gone on by T/2 of path time.
// Every operation is safe from several threads (the node's TF timer, service threads and, later,
// an action server): the timeline is replaced as a whole under a mutex and read as an immutable
// snapshot.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
/// Instants and stamps: nanoseconds of the playback clock (ROS time's toNSec()).
using Nanoseconds = std::int64_t;

/// Seconds from `from` to `to`, from their integer difference.
inline double secondsBetween(Nanoseconds from, Nanoseconds to)
{
  return static_cast<double>(to - from) * 1e-9;
}

/// `seconds` as nanoseconds, rounded (saturated far beyond any clock).
Nanoseconds toNanoseconds(double seconds);

/// A trajectory to play.
struct Motion
{
  /// The state at trajectory time t (s after the stamp), for t in [start_time, start_time + duration].
  std::function<TrajectorySample(double)> state_at;
  double start_time = 0.0;  ///< s after the stamp
  double duration = 0.0;    ///< s
  std::string frame_id;        ///< the frame the poses are in (world)
  std::string child_frame_id;  ///< the moving frame (body)
};

/// What the moving frame shows at one instant.
struct PlaybackState
{
  /// world_T_body, the spatial twist and its derivative (zero while held); sample.time is the
  /// motion's own time.
  TrajectorySample sample;
  /// false while the pose is held: before a motion's start, after its end, after hold() or a
  /// finished stop().
  bool moving = false;
  std::string frame_id;
  std::string child_frame_id;
};

class Playback
{
public:
  /// Whether motions repeat their span forever instead of holding their last pose.
  void setLoop(bool loop);
  bool loop() const;

  /// Plays `motion` stamped `stamp`, at `now`: what is shown goes on until stamp + start_time,
  /// when the new motion replaces it (a pending motion that would start later is dropped); a
  /// motion of another child frame replaces everything at once.
  /// @throws std::invalid_argument for a motion without state_at
  void play(Motion motion, Nanoseconds stamp, Nanoseconds now);

  /// Holds the pose shown at `now` (at rest); nothing to do when nothing plays.
  void hold(Nanoseconds now);

  /// Brings the motion shown at `now` to rest along its path with a ramp of `ramp_seconds` (> 0)
  /// (see the file comment) and holds where it stops; a motion already at rest is held.
  /// @return the instant at which the frame is at rest
  /// @throws std::invalid_argument for a ramp that is not a positive finite time
  Nanoseconds stop(Nanoseconds now, double ramp_seconds);

  /// What the frame shows at `now`; empty before the first play().
  std::optional<PlaybackState> at(Nanoseconds now) const;

private:
  struct Entry;
  std::shared_ptr<const Entry> shownAt(Nanoseconds now) const;
  static std::shared_ptr<const Entry> withoutThePast(const std::shared_ptr<const Entry>& e, Nanoseconds now);
  PlaybackState evaluate(const Entry& entry, Nanoseconds now) const;

  mutable std::mutex mutex_;
  std::shared_ptr<const Entry> latest_;
  bool loop_ = false;
};

}  // namespace se3_interpolation
