#include "se3_interpolation/execution/playback.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace se3_interpolation
{
/// One motion on the timeline, with the one it replaces until it starts.
struct Playback::Entry
{
  Motion motion;
  Nanoseconds stamp = 0;
  Nanoseconds start = 0;  ///< stamp + start_time
  /// The timeline before this motion starts (none for a hold or a stop).
  std::shared_ptr<const Entry> previous;
  /// A hold or a stop: it never loops (it plays once, then holds where it ends), and its
  /// state_at reports the time of the motion it holds or stops itself.
  bool held = false;
};

namespace
{
constexpr double kInfinity = std::numeric_limits<double>::infinity();

/// The motion time shown at `now`, and whether it moves there: wrapped into the span when
/// looping, else clamped to it (held before the start and from the end on).
struct Position
{
  double time = 0.0;
  bool moving = false;
};

/// At `t` s after the motion's stamp.
Position positionOf(const Motion& m, double t, bool loop)
{
  if (loop && m.duration > 0.0)
  {
    double u = std::fmod(t - m.start_time, m.duration);
    if (u < 0.0)
      u += m.duration;
    return { m.start_time + u, true };
  }
  const double end = m.start_time + m.duration;
  return { std::min(std::max(t, m.start_time), end), t >= m.start_time && t < end };
}

TrajectorySample atRest(TrajectorySample s)
{
  s.velocity = Twist();
  s.acceleration = Twist();
  return s;
}

Twist scaled(const Twist& a, double k)
{
  Twist r;
  r.linear = k * a.linear;
  r.angular = k * a.angular;
  return r;
}

Twist sum(const Twist& a, const Twist& b)
{
  Twist r;
  r.linear = a.linear + b.linear;
  r.angular = a.angular + b.angular;
  return r;
}

/// The motion being stopped, as it was shown: its sample `advance` s of path time after the
/// stop's start (τ = τ_c + advance, wrapped when looping).
struct StoppedMotion
{
  Motion motion;
  bool loop = false;
  bool held = false;    ///< a hold or a stop: its state_at reports its own time
  double offset = 0.0;  ///< s from the motion's stamp to the stop's start

  /// The advance at which the motion ends (infinite when it loops).
  double endAdvance() const
  {
    return loop && motion.duration > 0.0 ? kInfinity : motion.start_time + motion.duration - offset;
  }

  TrajectorySample at(double advance, bool* moving) const
  {
    // In seconds, not on the nanosecond clock: τ must not be quantised (its rate is the speed).
    const Position q = positionOf(motion, offset + advance, loop);
    TrajectorySample s = motion.state_at(q.time);
    if (!held)
      s.time = q.time;
    *moving = q.moving;
    return s;
  }
};

/// @throws std::invalid_argument for limits stop() refuses (see its comment)
bool boundsSomething(const StopLimits& l)
{
  return l.max_linear_acceleration > 0.0 || l.max_angular_acceleration > 0.0 || l.max_linear_jerk > 0.0 ||
         l.max_angular_jerk > 0.0;
}

void checkLimits(const StopLimits& limits)
{
  const auto bound = [](double a) { return a >= 0.0 && std::isfinite(a); };
  if (!bound(limits.max_linear_acceleration) || !bound(limits.max_angular_acceleration) ||
      !bound(limits.max_linear_jerk) || !bound(limits.max_angular_jerk))
    throw std::invalid_argument("playback: the stop's acceleration and jerk bounds must be finite and not negative");
  if (!boundsSomething(limits) && (!(limits.stop_time > 0.0) || !std::isfinite(limits.stop_time)))
    throw std::invalid_argument("playback: the stop ramp must be a positive time");
}

}  // namespace

Nanoseconds toNanoseconds(double seconds)
{
  constexpr double kLimit = 9.0e18;  // below 2^63 ns (292 years): far beyond any clock
  const double ns = std::round(seconds * 1e9);
  if (!(std::abs(ns) < kLimit))
    return std::isnan(ns) ? 0 : (ns > 0 ? static_cast<Nanoseconds>(kLimit) : -static_cast<Nanoseconds>(kLimit));
  return static_cast<Nanoseconds>(ns);
}

void Playback::setLoop(bool loop)
{
  std::lock_guard<std::mutex> lock(mutex_);
  loop_ = loop;
}

bool Playback::loop() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return loop_;
}

void Playback::play(Motion motion, Nanoseconds stamp, Nanoseconds now)
{
  if (!motion.state_at)
    throw std::invalid_argument("playback: a motion needs its state_at");
  auto entry = std::make_shared<Entry>();
  entry->stamp = stamp;
  entry->start = stamp + toNanoseconds(motion.start_time);
  entry->motion = std::move(motion);
  std::lock_guard<std::mutex> lock(mutex_);
  // What is shown until the new motion starts: the timeline as it is, without the pending
  // motions that would start after it (never shown now) ...
  std::shared_ptr<const Entry> shown = latest_;
  while (shown && shown->previous && entry->start < shown->start)
    shown = shown->previous;
  // A motion of another moving frame replaces the timeline at once (the old frame stops being
  // broadcast).
  if (shown && shown->motion.child_frame_id != entry->motion.child_frame_id)
    shown = nullptr;
  entry->previous = withoutThePast(shown, now);
  latest_ = entry;
}

std::shared_ptr<const Playback::Entry> Playback::withoutThePast(const std::shared_ptr<const Entry>& e, Nanoseconds now)
{
  // ... and without what ended before `now`: the motion that has started by now is the oldest one
  // still shown (the chain holds only motions pending at now, a few).
  if (!e || !e->previous)
    return e;
  auto copy = std::make_shared<Entry>(*e);
  copy->previous = e->start <= now ? nullptr : withoutThePast(e->previous, now);
  return copy;
}

std::shared_ptr<const Playback::Entry> Playback::shownAt(const std::shared_ptr<const Entry>& latest, Nanoseconds now)
{
  std::shared_ptr<const Entry> e = latest;
  while (e && e->previous && now < e->start)
    e = e->previous;
  return e;
}

PlaybackState Playback::evaluate(const Entry& entry, Nanoseconds now, bool loop)
{
  const Position p = positionOf(entry.motion, secondsBetween(entry.stamp, now), loop && !entry.held);
  PlaybackState state;
  state.sample = entry.motion.state_at(p.time);
  if (!entry.held)
    state.sample.time = p.time;
  if (!p.moving)
    state.sample = atRest(state.sample);
  state.moving = p.moving;
  state.frame_id = entry.motion.frame_id;
  state.child_frame_id = entry.motion.child_frame_id;
  state.tag = entry.motion.tag;
  return state;
}

std::optional<PlaybackState> Playback::at(Nanoseconds now) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  const std::shared_ptr<const Entry> e = shownAt(latest_, now);
  if (!e)
    return std::nullopt;
  return evaluate(*e, now, loop_);
}

std::shared_ptr<const Playback::Entry> Playback::heldEntry(const Entry& shown, Nanoseconds now, bool loop)
{
  auto held = std::make_shared<Entry>();
  const TrajectorySample pose = atRest(evaluate(shown, now, loop).sample);
  held->motion.state_at = [pose](double) { return pose; };
  held->motion.frame_id = shown.motion.frame_id;
  held->motion.child_frame_id = shown.motion.child_frame_id;
  held->motion.tag = shown.motion.tag;
  held->stamp = now;
  held->start = now;
  held->held = true;
  return held;
}

void Playback::hold(Nanoseconds now)
{
  std::lock_guard<std::mutex> lock(mutex_);
  const std::shared_ptr<const Entry> e = shownAt(latest_, now);
  if (e)
    latest_ = heldEntry(*e, now, loop_);
}

std::pair<std::shared_ptr<const Playback::Entry>, Nanoseconds> Playback::stopEntry(
    const std::shared_ptr<const Entry>& shown, Nanoseconds now, bool loop, const StopLimits& limits)
{
  StoppedMotion stopped;
  stopped.loop = loop && !shown->held;
  stopped.held = shown->held;
  stopped.offset = secondsBetween(shown->stamp, now);
  stopped.motion = shown->motion;
  if (!positionOf(stopped.motion, stopped.offset, stopped.loop).moving)
  {
    auto held = std::make_shared<Entry>(*heldEntry(*shown, now, loop));
    held->previous = shown;  // a stop from an instant ahead: what plays until then goes on
    return { held, now };
  }

  std::function<PathPoint(double)> law;
  double length = limits.stop_time;
  if (boundsSomething(limits))
  {
    StoppedPath path;
    path.at = [stopped](double u, bool* moving) { return stopped.at(u, moving); };
    path.end_advance = stopped.endAdvance();
    auto stop_law = std::make_shared<const StopLaw>(path, limits);
    length = stop_law->restTime();
    law = [stop_law](double t) { return stop_law->at(t); };
  }
  else
    law = [length](double t) { return smoothRamp(length, t); };

  // At rest from the first nanosecond at or after the law's end.
  Nanoseconds rest = now + toNanoseconds(length);
  if (secondsBetween(now, rest) < length)
    ++rest;
  auto entry = std::make_shared<Entry>();
  entry->motion.state_at = [stopped, law](double t) {
    const PathPoint p = law(t);
    bool moving;
    TrajectorySample s = stopped.at(p.advance, &moving);
    if (!moving)
      return atRest(s);  // the motion ended during the stop
    const Twist v = s.velocity;
    s.velocity = scaled(v, p.rate);
    s.acceleration = sum(scaled(s.acceleration, p.rate * p.rate), scaled(v, p.rate_dot));
    return s;
  };
  entry->motion.start_time = 0.0;
  entry->motion.duration = secondsBetween(now, rest);
  entry->motion.frame_id = shown->motion.frame_id;
  entry->motion.child_frame_id = shown->motion.child_frame_id;
  entry->motion.tag = shown->motion.tag;
  entry->stamp = now;
  entry->start = now;
  entry->held = true;       // the stop plays once, then holds where it stopped
  entry->previous = shown;  // a stop from an instant ahead: what plays until then goes on
  return { entry, rest };
}

Playback::Snapshot Playback::snapshot() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  return { latest_, loop_ };
}

Nanoseconds Playback::stop(Nanoseconds now, const StopLimits& limits)
{
  checkLimits(limits);
  for (;;)
  {
    const auto [latest, loop] = snapshot();
    const std::shared_ptr<const Entry> e = shownAt(latest, now);
    if (!e)
      return now;
    // The law is computed without the lock (a long stop takes milliseconds); it replaces the
    // timeline only if that is still the one it was computed from.
    const auto stopping = stopEntry(e, now, loop, limits);
    std::lock_guard<std::mutex> lock(mutex_);
    if (latest_ == latest && loop_ == loop)
    {
      latest_ = stopping.first;
      return stopping.second;
    }
  }
}

Nanoseconds Playback::stop(Nanoseconds now, double ramp_seconds)
{
  StopLimits limits;
  limits.stop_time = ramp_seconds;
  return stop(now, limits);
}

std::optional<StopPlan> Playback::planStop(Nanoseconds now, const StopLimits& limits) const
{
  checkLimits(limits);
  const auto [latest, loop] = snapshot();
  const std::shared_ptr<const Entry> e = shownAt(latest, now);
  if (!e)
    return std::nullopt;
  const auto stopping = stopEntry(e, now, loop, limits);
  StopPlan plan;
  plan.rest = stopping.second;
  plan.state = evaluate(*stopping.first, plan.rest, loop);
  return plan;
}

}  // namespace se3_interpolation
