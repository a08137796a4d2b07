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
//  - stop(): the frame comes to rest along the rest of its path: its path time τ (the stopped
//    motion's own time) is slowed from τ̇ = 1 to τ̇ = 0, so that the frame shows the pose of the
//    motion at τ(t), with (chain rule; the spatial angular velocity is linear in the path rate too)
//        velocity      v(τ) τ̇,              ω(τ) τ̇,
//        acceleration  a(τ) τ̇² + v(τ) τ̈,    ω̇(τ) τ̇² + ω(τ) τ̈,
//    v, a, ω, ω̇ being the stopped motion's velocity and acceleration at τ. Two laws τ(t)
//    (StopLimits):
//    * Without any bound (StopLimits), a smooth ramp of T = stop_time seconds: with
//      σ = (t − t_c)/T ∈ [0, 1],
//        τ̇ = 1 − 3σ² + 2σ³,   τ = τ_c + T (σ − σ³ + σ⁴/2),   τ̈ = 6 (σ² − σ)/T,
//      so τ̇ falls from 1 to 0 with τ̈ = 0 at both ends: velocity and acceleration are continuous
//      at t_c and reach rest at t_c + T, having gone on by T/2 of path time.
//    * With acceleration and/or jerk bounds, the law of execution/stop_law.h: a jerk-limited fall
//      of τ̇ (after the motion has gone on for a delay where that is needed), chosen so that the
//      played acceleration and jerk stay within each bound, or within what the motion itself does
//      where it exceeds one, whatever the motion was doing at t_c; acceleration continuous at t_c
//      and at rest. On a straight line at constant speed v: rest after v/A + A/J s. A motion
//      that reaches its end during the stop ends there at rest, as it would have.
//    With loop, the stopped motion's time wraps as it was shown. planStop() tells, without
//    changing anything, when and where the frame would be at rest.
// Motions carry a tag (Motion::tag, opaque to the playback: e.g. which goal a motion executes);
// hold() and stop() keep the tag of what they hold or stop, and PlaybackState::tag reports the
// tag of what is shown.
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
#include <utility>

#include "se3_interpolation/execution/stop_law.h"
#include "se3_interpolation/geometry/trajectory_sample.h"

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
  double start_time = 0.0;     ///< s after the stamp
  double duration = 0.0;       ///< s
  std::string frame_id;        ///< the frame the poses are in (world)
  std::string child_frame_id;  ///< the moving frame (body)
  /// An opaque label of the caller's (e.g. "goal 3", "service"), kept by hold() and stop() and
  /// reported by PlaybackState::tag while this motion, or its held or stopped continuation, is
  /// shown.
  std::string tag;
};

/// What the moving frame shows at one instant.
struct PlaybackState
{
  /// world_T_body, the spatial twist and its derivative (zero while held); sample.time is the
  /// motion's own time: during a stop and while held after hold() or stop(), the time τ of the
  /// motion that was stopped or held (so that its pose there is state_at(τ).pose).
  TrajectorySample sample;
  /// false while the pose is held: before a motion's start, after its end, after hold() or a
  /// finished stop().
  bool moving = false;
  std::string frame_id;
  std::string child_frame_id;
  std::string tag;  ///< Motion::tag of the motion shown (or held, or stopped)
};

/// Where and when a stop would bring the frame to rest.
struct StopPlan
{
  Nanoseconds rest = 0;  ///< the first instant at rest (the stop's instant when already at rest)
  PlaybackState state;   ///< what at(rest) shows: the rest pose (moving false), its τ, frame and tag
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

  /// Brings the motion shown at `now` to rest along its path (see the file comment) and holds
  /// where it stops; a motion already at rest is held. Pending motions are dropped. `now` may lie
  /// ahead of the present (the law takes time to compute: a caller on a live clock stops from an
  /// instant ahead, so that the stop starts after it is in place): until then what is shown at
  /// `now` plays on. The law is
  /// computed from a snapshot outside the lock; should the timeline change meanwhile, it is
  /// computed again from the new one.
  /// @return the first instant at which the frame is at rest
  /// @throws std::invalid_argument for a negative or non-finite bound, or, when neither is
  /// bounded, a stop_time that is not a positive finite time
  Nanoseconds stop(Nanoseconds now, const StopLimits& limits);

  /// The smooth ramp of `ramp_seconds`: stop(now, limits) with no bound and stop_time = ramp_seconds.
  Nanoseconds stop(Nanoseconds now, double ramp_seconds);

  /// Where and when stop(now, limits) would bring the frame to rest, changing nothing; empty
  /// before the first play(). Same law, same rest: at(rest) after that stop() shows plan.state.
  /// @throws std::invalid_argument as stop()
  std::optional<StopPlan> planStop(Nanoseconds now, const StopLimits& limits) const;

  /// What the frame shows at `now`; empty before the first play().
  std::optional<PlaybackState> at(Nanoseconds now) const;

private:
  struct Entry;
  /// The entry of `latest` shown at `now`.
  static std::shared_ptr<const Entry> shownAt(const std::shared_ptr<const Entry>& latest, Nanoseconds now);
  static std::shared_ptr<const Entry> withoutThePast(const std::shared_ptr<const Entry>& e, Nanoseconds now);
  /// What `entry` shows at `now`, `loop` being the playback's setting.
  static PlaybackState evaluate(const Entry& entry, Nanoseconds now, bool loop);
  /// The entry holding what `shown` shows at `now`, at rest.
  static std::shared_ptr<const Entry> heldEntry(const Entry& shown, Nanoseconds now, bool loop);
  /// The entry that stops `shown` from `now` (a held one when it is at rest there), and its rest
  /// instant; pure (no lock needed).
  static std::pair<std::shared_ptr<const Entry>, Nanoseconds> stopEntry(const std::shared_ptr<const Entry>& shown,
                                                                        Nanoseconds now, bool loop,
                                                                        const StopLimits& limits);

  /// The timeline and the loop setting, read together under the lock.
  struct Snapshot
  {
    std::shared_ptr<const Entry> latest;
    bool loop = false;
  };
  Snapshot snapshot() const;

  mutable std::mutex mutex_;
  std::shared_ptr<const Entry> latest_;
  bool loop_ = false;
};

}  // namespace se3_interpolation
