#include "se3_interpolation/execution/playback.h"

#include <cmath>
#include <limits>
#include <stdexcept>

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
  /// A held entry never loops: its span is a single instant.
  bool held = false;
};

namespace
{
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

std::shared_ptr<const Playback::Entry> Playback::shownAt(Nanoseconds now) const
{
  std::shared_ptr<const Entry> e = latest_;
  while (e && e->previous && now < e->start)
    e = e->previous;
  return e;
}

PlaybackState Playback::evaluate(const Entry& entry, Nanoseconds now) const
{
  const Position p = positionOf(entry.motion, secondsBetween(entry.stamp, now), loop_ && !entry.held);
  PlaybackState state;
  state.sample = entry.motion.state_at(p.time);
  state.sample.time = p.time;
  if (!p.moving)
    state.sample = atRest(state.sample);
  state.moving = p.moving;
  state.frame_id = entry.motion.frame_id;
  state.child_frame_id = entry.motion.child_frame_id;
  return state;
}

std::optional<PlaybackState> Playback::at(Nanoseconds now) const
{
  std::lock_guard<std::mutex> lock(mutex_);
  const std::shared_ptr<const Entry> e = shownAt(now);
  if (!e)
    return std::nullopt;
  return evaluate(*e, now);
}

void Playback::hold(Nanoseconds now)
{
  std::lock_guard<std::mutex> lock(mutex_);
  const std::shared_ptr<const Entry> e = shownAt(now);
  if (!e)
    return;
  const PlaybackState shown = evaluate(*e, now);
  auto held = std::make_shared<Entry>();
  const TrajectorySample pose = atRest(shown.sample);
  held->motion.state_at = [pose](double) { return pose; };
  held->motion.frame_id = e->motion.frame_id;
  held->motion.child_frame_id = e->motion.child_frame_id;
  held->stamp = now;
  held->start = now;
  held->held = true;
  latest_ = held;
}

Nanoseconds Playback::stop(Nanoseconds now, double ramp_seconds)
{
  if (!(ramp_seconds > 0.0) || !std::isfinite(ramp_seconds))
    throw std::invalid_argument("playback: the stop ramp must be a positive time");
  std::unique_lock<std::mutex> lock(mutex_);
  const std::shared_ptr<const Entry> e = shownAt(now);
  if (!e)
    return now;
  const Position p = positionOf(e->motion, secondsBetween(e->stamp, now), loop_ && !e->held);
  if (!p.moving)
  {
    lock.unlock();
    hold(now);
    return now;
  }
  // The ramp reads the stopped motion on its own clock: its time τ, wrapped as it was shown.
  const std::shared_ptr<const Entry> stopped = e;
  const bool loop = loop_ && !e->held;
  const double start_offset = secondsBetween(e->stamp, now);
  const double T = ramp_seconds;
  auto ramp = std::make_shared<Entry>();
  ramp->motion.state_at = [stopped, loop, start_offset, T](double t) {
    const double sigma = std::min(std::max(t / T, 0.0), 1.0);
    const double rate = 1.0 - 3.0 * sigma * sigma + 2.0 * sigma * sigma * sigma;
    const double rate_dot = sigma < 1.0 ? 6.0 * (sigma * sigma - sigma) / T : 0.0;
    const double advance = T * (sigma - sigma * sigma * sigma + 0.5 * sigma * sigma * sigma * sigma);
    // In seconds, not on the nanosecond clock: τ must not be quantised (its rate is the speed).
    const Position q = positionOf(stopped->motion, start_offset + advance, loop);
    TrajectorySample s = stopped->motion.state_at(q.time);
    if (!q.moving)
      return atRest(s);
    const Twist v = s.velocity;
    s.velocity = scaled(v, rate);
    s.acceleration = sum(scaled(s.acceleration, rate * rate), scaled(v, rate_dot));
    return s;
  };
  ramp->motion.start_time = 0.0;
  ramp->motion.duration = T;
  ramp->motion.frame_id = e->motion.frame_id;
  ramp->motion.child_frame_id = e->motion.child_frame_id;
  ramp->stamp = now;
  ramp->start = now;
  ramp->held = true;  // the ramp plays once, then holds where it stopped
  latest_ = ramp;
  return now + toNanoseconds(T);
}

}  // namespace se3_interpolation
