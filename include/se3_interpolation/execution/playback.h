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
//    * Without acceleration bounds, a smooth ramp of T seconds: with σ = (t − t_c)/T ∈ [0, 1],
//        τ̇ = 1 − 3σ² + 2σ³,   τ = τ_c + T (σ − σ³ + σ⁴/2),   τ̈ = 6 (σ² − σ)/T,
//      so τ̇ falls from 1 to 0 with τ̈ = 0 at both ends: velocity and acceleration are continuous
//      at t_c and reach rest at t_c + T, having gone on by T/2 of path time.
//    * With a bound on |played linear acceleration| ≤ A_lin and/or |played angular acceleration|
//      ≤ A_ang (a bound of 0 bounds nothing), the quickest stop: τ(t) is integrated forward in
//      steps of kStopStep (1 ms, halved where needed) with, in each step, the most negative
//      constant τ̈ that the bounds admit,
//        τ̈ = min { x ≤ 0 : |a τ̇² + v x| ≤ B_lin and |ω̇ τ̇² + ω x| ≤ B_ang },
//      each set solved exactly as a quadratic inequality in x. B is kStopBoundFraction (0.95) of
//      the bound: the 5 % left absorbs the variation of a(τ), v(τ) and τ̇ within a step (the
//      step is halved, down to ~1 µs, while the played acceleration at its middle or end exceeds
//      the bound). τ̇ falls from 1 to 0 continuously (the velocity is continuous, the
//      acceleration jumps at the start and between steps, within the bounds), the last step
//      ending exactly at τ̇ = 0. On a straight line at constant speed v this is constant
//      deceleration B: rest after v/B s and v²/(2B) m. Where no bounded part moves (v = 0, and
//      ω = 0 where bounded: e.g. a pure rotation with only a linear bound) nothing limits τ̈ and
//      the frame comes to rest within one step.
//      The set is empty when the motion itself brakes, or turns, harder than 0.95 A; then, per
//      part, B = A while |a τ̇²| ≤ A (a motion braking at the bound keeps its own rate: it stops
//      no later than it would itself), and B = |a τ̇²| + 0.95 A beyond (a motion not made under
//      the bounds: the stop adds at most the bound to the motion's own excess, and still ends).
//      A motion that reaches its end during the stop ends there at rest, as it would have. A law
//      longer than kMaxStopSeconds (60 s) or kMaxStopSteps (10⁵) falls back to the smooth ramp
//      of the length the bounds need for the stopped velocity (T = 1.5 |v|/B, the ramp's peak
//      |τ̈| being 1.5/T; the motion's own acceleration is not counted).
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

/// How stop() brings the frame to rest (file comment). A bound of 0 is no bound on that part.
struct StopLimits
{
  double max_linear_acceleration = 0.0;   ///< A_lin (m/s²) on the played |p̈|; 0 = not bounded
  double max_angular_acceleration = 0.0;  ///< A_ang (rad/s²) on the played |ω̇|; 0 = not bounded
  double stop_time = 1.0;                 ///< T (s) of the smooth ramp used when neither is bounded
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
  /// where it stops; a motion already at rest is held. Pending motions are dropped. The law is
  /// computed from a snapshot outside the lock; should the timeline change meanwhile, it is
  /// computed again from the new one.
  /// @return the first instant at which the frame is at rest
  /// @throws std::invalid_argument for a negative or non-finite bound, or, when neither is
  /// bounded, a stop_time that is not a positive finite time
  Nanoseconds stop(Nanoseconds now, const StopLimits& limits);

  /// The smooth ramp of `ramp_seconds`: stop(now, StopLimits{ 0, 0, ramp_seconds }).
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
