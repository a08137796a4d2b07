// A time limit for one request, checked inside the core's long loops (cooperative cancellation).
//
// The planner refuses a request whose estimated cost exceeds its limit before computing anything
// (planner/work_estimate.h); the estimate is a model, so the loops whose length grows with the
// request (the C² solve's sweeps and Newton steps, the time-optimal passes and checks, the figures'
// quadrature, the sampling) also check a deadline and stop with a LimitExceededError naming the
// phase when it has passed. The deadline is the current thread's (ScopedDeadline), so that curves
// and timing keep their interfaces and a call without a deadline (a unit test, a library user)
// checks nothing.
#pragma once

#include <chrono>
#include <cstdint>
#include <sstream>
#include <string>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
/// A point in time after which the current request is abandoned.
class Deadline
{
public:
  using Clock = std::chrono::steady_clock;

  /// `seconds` from now (> 0); `limit_seconds` is the limit it enforces, for the message.
  Deadline(double seconds, double limit_seconds)
    : end_(Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds)))
    , limit_seconds_(limit_seconds)
  {
  }

  bool expired() const { return Clock::now() > end_; }
  bool before(const Deadline& other) const { return end_ < other.end_; }
  double limitSeconds() const { return limit_seconds_; }
  /// Moves the end `by` later (ScopedDeadlinePause).
  void postpone(Clock::duration by) { end_ += by; }

private:
  Clock::time_point end_;
  double limit_seconds_;
};

namespace detail
{
inline Deadline*& currentDeadline()
{
  thread_local Deadline* deadline = nullptr;
  return deadline;
}
}  // namespace detail

/// Makes `deadline` the current thread's for its lifetime, unless the current one is earlier
/// (a request inside a caller's deadline keeps the caller's); the previous one is restored after.
class ScopedDeadline
{
public:
  explicit ScopedDeadline(Deadline& deadline) : previous_(detail::currentDeadline())
  {
    if (previous_ == nullptr || deadline.before(*previous_))
      detail::currentDeadline() = &deadline;
  }
  ~ScopedDeadline() { detail::currentDeadline() = previous_; }
  ScopedDeadline(const ScopedDeadline&) = delete;
  ScopedDeadline& operator=(const ScopedDeadline&) = delete;

private:
  Deadline* previous_;
};

/// Suspends the current thread's deadline for its lifetime and then postpones it by that time:
/// for the caller's own work inside a request (generate()'s sample sink, where the CLI formats and
/// writes its output and waits for a slow reader), which is not the request's.
class ScopedDeadlinePause
{
public:
  ScopedDeadlinePause() : paused_(detail::currentDeadline()), start_(Deadline::Clock::now())
  {
    detail::currentDeadline() = nullptr;
  }
  ~ScopedDeadlinePause()
  {
    detail::currentDeadline() = paused_;
    if (paused_ != nullptr)
      paused_->postpone(Deadline::Clock::now() - start_);
  }
  ScopedDeadlinePause(const ScopedDeadlinePause&) = delete;
  ScopedDeadlinePause& operator=(const ScopedDeadlinePause&) = delete;

private:
  Deadline* paused_;
  Deadline::Clock::time_point start_;
};

/// Throws LimitExceededError naming `phase` when the current thread's deadline has passed; does
/// nothing without one. Costs one clock read (~25 ns): call it every few hundred steps of a loop.
/// @throws LimitExceededError "timing/… : the request ran past its work limit of … s"
inline void checkDeadline(const char* phase)
{
  const Deadline* d = detail::currentDeadline();
  if (d != nullptr && d->expired())
  {
    std::ostringstream limit;
    limit << d->limitSeconds();
    throw LimitExceededError(std::string(phase) + ": the request ran past its work limit of " + limit.str() +
                             " s (max_work_seconds; the estimate of its cost was too low: fewer waypoints or "
                             "samples, or a larger limit)");
  }
}

/// checkDeadline every `period` calls of `counter` (a loop index): the cheap form for hot loops.
inline void checkDeadlineEvery(std::uint64_t counter, std::uint64_t period, const char* phase)
{
  if (counter % period == 0)
    checkDeadline(phase);
}

}  // namespace se3_interpolation
