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
/// Fraction of an acceleration bound the bounded stop aims at: the 5 % left absorbs the
/// variation of a(τ), v(τ) and τ̇ within one step (checked at the step's middle and end).
constexpr double kStopBoundFraction = 0.95;
/// The bounded stop's step (s): fine against the motions' own time scales (their segments last
/// tenths of seconds), and 10⁵ steps (kMaxStopSteps) still cover a 100 s stop.
constexpr double kStopStep = 1e-3;
/// The shortest step: ten halvings of kStopStep (~1 µs), where a step is accepted as it is.
constexpr double kMinStopStep = kStopStep / 1024.0;
/// A bounded stop longer than this (s) or of more steps falls back to the smooth ramp (a table
/// of 10⁵ steps is 3.2 MB and a few tens of ms to compute).
constexpr double kMaxStopSeconds = 60.0;
constexpr std::size_t kMaxStopSteps = 100000;
/// Relative rounding allowed on the norms compared with a bound (a motion braking at exactly A
/// computes |a| = A to ~1e-16).
constexpr double kBoundRounding = 1e-9;
/// The smooth ramp's peak |τ̈| T: |6 (σ² − σ)| at σ = 1/2.
constexpr double kRampPeakRateDot = 1.5;

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

/// The path time law at one instant of a stop: τ − τ_c, τ̇, τ̈.
struct PathPoint
{
  double advance = 0.0;
  double rate = 0.0;
  double rate_dot = 0.0;
};

/// The smooth ramp of T s at t s after its start (file comment of playback.h).
PathPoint smoothRamp(double T, double t)
{
  const double sigma = std::min(std::max(t / T, 0.0), 1.0);
  PathPoint p;
  p.rate = 1.0 - 3.0 * sigma * sigma + 2.0 * sigma * sigma * sigma;
  p.rate_dot = sigma < 1.0 ? 6.0 * (sigma * sigma - sigma) / T : 0.0;
  p.advance = T * (sigma - sigma * sigma * sigma + 0.5 * sigma * sigma * sigma * sigma);
  return p;
}

/// The bounded stop's law: τ̈ constant per step, hence τ̇ linear and τ quadratic in each, exact.
class StopTable
{
public:
  struct Step
  {
    double time = 0.0;  ///< s after the stop's start
    double advance = 0.0;
    double rate = 0.0;
    double rate_dot = 0.0;
  };

  std::vector<Step> steps;
  double end_time = 0.0;     ///< s after the stop's start: at rest from here on
  double end_advance = 0.0;  ///< τ − τ_c at rest

  PathPoint at(double t) const
  {
    if (!(t < end_time) || steps.empty())
      return { end_advance, 0.0, 0.0 };
    const auto after =
        std::upper_bound(steps.begin(), steps.end(), t, [](double time, const Step& s) { return time < s.time; });
    const Step& k = after == steps.begin() ? steps.front() : *(after - 1);
    const double s = std::max(t - k.time, 0.0);
    return { k.advance + k.rate * s + 0.5 * k.rate_dot * s * s, k.rate + k.rate_dot * s, k.rate_dot };
  }
};

/// The fallback bound of one step for a part whose own played term |c| = |a τ̇²| leaves no
/// braking within kStopBoundFraction A (file comment of playback.h): A in the band up to A (a
/// motion braking at the bound keeps its rate), |c| + kStopBoundFraction A beyond (the stop still
/// brakes on top of the motion's own excess). Always ≥ |c|, so that x = 0 is admissible.
double fallbackBound(double own, double bound)
{
  const double target = kStopBoundFraction * bound;
  if (own <= target)
    return target;
  if (own <= bound * (1.0 + kBoundRounding))
    return std::max(bound, own);
  return own + target;
}

/// {x : |c + v x| ≤ B}: the roots of |v|² x² + 2 (c·v) x + |c|² − B² ≤ 0, an interval [lo, hi]
/// (the whole line when v = 0 and |c| ≤ B); false when empty. Roots in the cancellation-free
/// form q/|v|², (|c|² − B²)/q.
bool admissibleRateDots(const Eigen::Vector3d& c, const Eigen::Vector3d& v, double B, double* lo, double* hi)
{
  const double vv = v.squaredNorm();
  const double k = c.squaredNorm() - B * B;
  if (vv == 0.0)
  {
    *lo = -kInfinity;
    *hi = kInfinity;
    return k <= 0.0;
  }
  const double cv = c.dot(v);
  const double discriminant = cv * cv - vv * k;
  if (discriminant < 0.0)
    return false;
  const double q = -(cv + std::copysign(std::sqrt(discriminant), cv));
  if (q == 0.0)
  {
    *lo = 0.0;
    *hi = 0.0;
    return true;
  }
  const double r1 = q / vv, r2 = k / q;
  *lo = std::min(r1, r2);
  *hi = std::max(r1, r2);
  return true;
}

/// One bounded part of the played acceleration: own term c = a τ̇², path term v τ̈.
struct Part
{
  const Eigen::Vector3d& (*acceleration)(const TrajectorySample&);
  const Eigen::Vector3d& (*velocity)(const TrajectorySample&);
  double bound;
};

const Eigen::Vector3d& linearAcceleration(const TrajectorySample& s)
{
  return s.acceleration.linear;
}
const Eigen::Vector3d& linearVelocity(const TrajectorySample& s)
{
  return s.velocity.linear;
}
const Eigen::Vector3d& angularAcceleration(const TrajectorySample& s)
{
  return s.acceleration.angular;
}
const Eigen::Vector3d& angularVelocity(const TrajectorySample& s)
{
  return s.velocity.angular;
}

/// @throws std::invalid_argument for limits stop() refuses (see its comment)
void checkLimits(const StopLimits& limits)
{
  const auto bound = [](double a) { return a >= 0.0 && std::isfinite(a); };
  if (!bound(limits.max_linear_acceleration) || !bound(limits.max_angular_acceleration))
    throw std::invalid_argument("playback: the stop's acceleration bounds must be finite and not negative");
  const bool ramp = limits.max_linear_acceleration == 0.0 && limits.max_angular_acceleration == 0.0;
  if (ramp && (!(limits.stop_time > 0.0) || !std::isfinite(limits.stop_time)))
    throw std::invalid_argument("playback: the stop ramp must be a positive time");
}

/// The bounded stop of `m` from τ̇ = 1 (file comment of playback.h); empty beyond kMaxStopSeconds
/// or kMaxStopSteps.
std::optional<StopTable> boundedStop(const StoppedMotion& m, const std::vector<Part>& parts)
{
  StopTable table;
  const double end = m.endAdvance();
  double t = 0.0, u = 0.0, r = 1.0;
  bool moving = true;
  TrajectorySample s = m.at(0.0, &moving);
  std::vector<double> bounds(parts.size());
  for (;;)
  {
    if (table.steps.size() >= kMaxStopSteps || t >= kMaxStopSeconds)
      return std::nullopt;
    // The most negative admissible τ̈ ≤ 0 at the step's start: within kStopBoundFraction of
    // every bound if possible, else within the fallback bounds (which admit 0).
    const auto brake = [&](bool fallback, double* x) {
      double lo = -kInfinity, hi = 0.0;
      for (std::size_t i = 0; i < parts.size(); ++i)
      {
        const Eigen::Vector3d c = parts[i].acceleration(s) * (r * r);
        bounds[i] = fallback ? fallbackBound(c.norm(), parts[i].bound) : kStopBoundFraction * parts[i].bound;
        double part_lo, part_hi;
        if (!admissibleRateDots(c, parts[i].velocity(s), bounds[i], &part_lo, &part_hi))
          return false;
        lo = std::max(lo, part_lo);
        hi = std::min(hi, part_hi);
      }
      *x = lo;
      return lo <= hi;
    };
    double x = 0.0;
    if (!brake(false, &x) && !brake(true, &x))
      x = 0.0;  // the fallback admits 0 but for rounding: the motion's own rate
    // No bounded part moves (v = ω = 0 where bounded): rest within one step.
    if (!std::isfinite(x))
      x = -r / kStopStep;
    // Within the bounds at `sample` moving at rate `rate`, the stop braking at x?
    const auto within = [&](const TrajectorySample& sample, double rate) {
      for (std::size_t i = 0; i < parts.size(); ++i)
      {
        const Eigen::Vector3d own = parts[i].acceleration(sample) * (rate * rate);
        const double allowed = std::max({ parts[i].bound, bounds[i], own.norm() }) * (1.0 + kBoundRounding);
        if ((own + parts[i].velocity(sample) * x).norm() > allowed)
          return false;
      }
      return true;
    };
    double h = kStopStep, step = h, u1 = u, r1 = r;
    bool rests = false, ends = false;
    TrajectorySample s1;
    for (;;)
    {
      step = h;
      rests = x < 0.0 && r + x * step <= 0.0;
      if (rests)
        step = r / -x;  // the last step ends exactly at τ̇ = 0
      double advance = r * step + 0.5 * x * step * step;
      ends = u + advance >= end;
      if (ends)
      {
        // The motion ends first: the step ends there (r t + x t²/2 = end − u, its first root).
        const double remaining = end - u;
        step = 2.0 * remaining / (r + std::sqrt(std::max(r * r + 2.0 * x * remaining, 0.0)));
        advance = remaining;
        rests = false;
      }
      u1 = ends ? end : u + advance;
      r1 = rests ? 0.0 : std::max(r + x * step, 0.0);
      const double half = 0.5 * step;
      const TrajectorySample middle = m.at(u + r * half + 0.5 * x * half * half, &moving);
      s1 = m.at(u1, &moving);
      if (h <= kMinStopStep || (within(middle, r + x * half) && within(s1, r1)))
        break;
      h *= 0.5;
    }
    table.steps.push_back({ t, u, r, x });
    t += step;
    u = u1;
    r = r1;
    s = s1;
    if (rests || ends || r == 0.0)
      break;
  }
  table.end_time = t;
  table.end_advance = u;
  return table;
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

std::pair<std::shared_ptr<const Playback::Entry>, Nanoseconds>
Playback::stopEntry(const std::shared_ptr<const Entry>& shown, Nanoseconds now, bool loop, const StopLimits& limits)
{
  StoppedMotion stopped;
  stopped.loop = loop && !shown->held;
  stopped.held = shown->held;
  stopped.offset = secondsBetween(shown->stamp, now);
  stopped.motion = shown->motion;
  if (!positionOf(stopped.motion, stopped.offset, stopped.loop).moving)
    return { heldEntry(*shown, now, loop), now };

  std::vector<Part> parts;
  if (limits.max_linear_acceleration > 0.0)
    parts.push_back({ linearAcceleration, linearVelocity, limits.max_linear_acceleration });
  if (limits.max_angular_acceleration > 0.0)
    parts.push_back({ angularAcceleration, angularVelocity, limits.max_angular_acceleration });

  std::function<PathPoint(double)> law;
  double length = limits.stop_time;
  std::optional<StopTable> table;
  if (!parts.empty())
    table = boundedStop(stopped, parts);
  if (table)
  {
    length = table->end_time;
    law = [table = std::make_shared<const StopTable>(std::move(*table))](double t) { return table->at(t); };
  }
  else
  {
    if (!parts.empty())
    {
      // Too long a table: the smooth ramp whose path term 1.5 |v|/T meets the bounds at τ_c.
      bool moving;
      const TrajectorySample s = stopped.at(0.0, &moving);
      length = kStopStep;
      for (const Part& part : parts)
        length = std::max(length, kRampPeakRateDot * part.velocity(s).norm() / (kStopBoundFraction * part.bound));
    }
    law = [length](double t) { return smoothRamp(length, t); };
  }

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
  entry->held = true;  // the stop plays once, then holds where it stopped
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
