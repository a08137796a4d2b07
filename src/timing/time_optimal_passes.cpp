// The passes of the time-optimal timing (timing/time_optimal.h: the backward and forward passes
// of its file comment, on the constraints (2), (3)): the pointwise caps, the admissible controls,
// the backward pass and the greedy forward pass. The solver is declared in time_optimal_solver.h.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "time_optimal_solver.h"

namespace se3_interpolation
{
namespace timing
{
namespace time_optimal_detail
{
namespace
{
/// Bisection of the controllable sets' upper ends: relative width (rounding level of x).
constexpr double kBisectionTolerance = 1e-12;
constexpr int kBisectionSteps = 200;
/// Half the relative width of the bracket the backward pass tries around brakingLimit's estimate.
constexpr double kBracketHalfWidth = 1e-10;
/// The acceleration bounds' margin while braking out of a start the bounds cannot hold.
constexpr double kRecoveryMargin = 1e-4;

/// Intersects u with {u : |a x + w u| ≤ A}, given α = |w|², β = a·w, aa = |a|², cross = |a × w|²
/// (= |a × b|² for w = b + 2Δa): α u² + 2 x β u + aa x² − A² ≤ 0.
void intersectEllipse(double alpha, double beta, double aa, double cross, double a2, double x, Interval* u)
{
  if (alpha > 0.0)
  {
    const double d = alpha * a2 - cross * x * x;
    if (d < 0.0)
    {
      u->empty = true;
      return;
    }
    const double r = std::sqrt(d);
    u->lo = std::max(u->lo, (-x * beta - r) / alpha);
    u->hi = std::min(u->hi, (-x * beta + r) / alpha);
  }
  else if (aa * x * x > a2)
  {
    u->empty = true;
  }
}
}  // namespace

void TimeOptimalSolver::updateCaps()
{
  const bool all = k_.empty();
  for (std::size_t i = 0; i < profile_.s.size(); ++i)
  {
    if (!all && !changed_[i])
      continue;
    for (PointData* p : { &right_[i], distinctLeft(i) })
    {
      if (!p)
        continue;
      p->x_max = speed_cap_.empty() ? kInf : speed_cap_[i];
      for (int c = 0; c < 2; ++c)
      {
        const ChannelJet& j = p->jet[c];
        const double v = velocityBound(i, c);
        const double a = accelerationBound(i, c);
        if (v > 0.0 && j.bb > 0.0)
          p->x_max = std::min(p->x_max, v * v / j.bb);
        if (a > 0.0)
        {
          if (j.cross > 0.0)
            p->x_max = std::min(p->x_max, a * p->extent[c]);
          else if (j.bb == 0.0 && j.aa > 0.0)
            p->x_max = std::min(p->x_max, a / p->extent[c]);
        }
      }
      if (box_count_ > 0)
        p->x_max = std::min(p->x_max, boxCap(boxJet(i, p != &right_[i]), i));
    }
  }
}

Interval TimeOptimalSolver::controls(std::size_t i, double x, double next) const
{
  return controlInterval(controlConstants(i, next), x);
}

TimeOptimalSolver::ControlConstants TimeOptimalSolver::controlConstants(std::size_t i, double next) const
{
  ControlConstants k;
  const double d = delta(i);
  k.two_delta = 2.0 * d;
  k.next = next;
  if (!u_cap_.empty())
    k.u_cap = std::min(u_cap_[i], u_cap_[i + 1]);
  const PathJet& a = right_[i].jet;
  const PathJet& b = left(i + 1).jet;
  for (int c = 0; c < 2; ++c)
  {
    if (!(bounds_.acceleration[c] > 0.0))
      continue;
    const double a0 = accelerationBound(i, c);
    k.ellipse[k.ellipses++] = { a[c].bb, a[c].ab, a[c].aa, a[c].cross, a0 * a0 };
    const ChannelJet& e = b[c];
    const double a1 = accelerationBound(i + 1, c);
    const double alpha = std::max(0.0, 4.0 * d * d * e.aa + 4.0 * d * e.ab + e.bb);
    k.ellipse[k.ellipses++] = { alpha, 2.0 * d * e.aa + e.ab, e.aa, e.cross, a1 * a1 };
  }
  if (box_count_ > 0)
    addBoxBands(i, &k);
  return k;
}

Interval TimeOptimalSolver::controlInterval(const ControlConstants& k, double x)
{
  Interval u;
  u.lo = std::max(-x / k.two_delta, -k.u_cap);
  u.hi = std::min((k.next - x) / k.two_delta, k.u_cap);
  for (int j = 0; j < k.ellipses; ++j)
  {
    const std::array<double, 5>& e = k.ellipse[j];
    intersectEllipse(e[0], e[1], e[2], e[3], e[4], x, &u);
    if (u.isEmpty())
      return u;
  }
  return u;
}

double TimeOptimalSolver::brakingLimit(const ControlConstants& k)
{
  // With r = √(α A² − cross x²) the ellipse's lowest control is u = (−x β − r)/α, and
  // x + 2Δ u = next reads x c − next = m r, c = 1 − 2Δβ/α, m = 2Δ/α: squared, the quadratic
  // (c² + m² cross) x² − 2 c next x + next² − m² α A² = 0, of which the larger root with x c ≥ next.
  double limit = kInf;
  for (int j = 0; j < k.ellipses; ++j)
  {
    const std::array<double, 5>& e = k.ellipse[j];
    const double alpha = e[0], beta = e[1], cross = e[3], a2 = e[4];
    if (!(alpha > 0.0))
      continue;
    const double m = k.two_delta / alpha;
    const double c = 1.0 - m * beta;
    const double quadratic = c * c + m * m * cross;
    const double discriminant = m * m * (c * c * alpha * a2 - cross * k.next * k.next + m * m * cross * alpha * a2);
    if (!(quadratic > 0.0) || !(discriminant >= 0.0))
      continue;
    const double root = (c * k.next + std::sqrt(discriminant)) / quadratic;
    if (root * c >= k.next)
      limit = std::min(limit, root);
  }
  return limit;
}

bool TimeOptimalSolver::admissible(const ControlConstants& k, double x)
{
  return !controlInterval(k, x).isEmpty();
}

void TimeOptimalSolver::backward()
{
  const std::size_t n = profile_.s.size();
  // Tightening only shrinks the sets: a later pass starts from the previous one's.
  const bool all = k_.empty();
  const std::vector<double> previous = all ? std::vector<double>(n, kInf) : k_;
  k_.assign(n, 0.0);
  first_change_ = all ? 0 : n - 1;
  for (std::size_t i = n - 1; i-- > 0;)
  {
    checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
    // K_0 = {0} for a start at rest; a moving start needs the whole controllable set at s_0.
    if (corner_[i] || (i == 0 && !(start_x_ > 0.0)))
      continue;
    if (!all && !changed_[i] && !changed_[i + 1] && k_[i + 1] == previous[i + 1])
    {
      // The same constraints and next set as in the pass that found previous[i], which is admissible
      // for them (or 0) and within x_max: the computation below would return it again.
      k_[i] = previous[i];
      continue;
    }
    const double next = nextLimit(i);
    const ControlConstants constants = controlConstants(i, next);
    auto admissible = [&](double x) { return TimeOptimalSolver::admissible(constants, x); };
    double hi = std::min(right_[i].x_max, previous[i]);
    if (std::isfinite(hi) && admissible(hi))
    {
      k_[i] = hi;
      continue;
    }
    if (!std::isfinite(hi))
    {
      // No pointwise cap: grow a bracket from the next set's size.
      const Interval at_rest = controls(i, 0.0, next);
      hi = std::max({ next, 2.0 * delta(i) * std::abs(at_rest.hi), std::numeric_limits<double>::min() });
      int steps = 0;
      while (admissible(hi) && steps++ < 2100)
        hi *= 4.0;
      if (!std::isfinite(hi))
        throw InvalidInputError("timing: 'time_optimal' found no bound on the speed at path time " +
                                formatNumber(profile_.s[i]) + " s (set max_linear_velocity or max_angular_velocity)");
    }
    double lo = 0.0;
    // Usually braking at an acceleration bound decides k_i: a bracket of relative width 2e-10 around
    // where it does (brakingLimit) leaves the bisection 8 steps instead of 40. Where that bracket
    // does not hold (another constraint decides), the bisection runs on what it did establish.
    const double guess = std::min(brakingLimit(constants), hi);
    if (guess > 0.0 && std::isfinite(guess))
    {
      const double below = guess * (1.0 - kBracketHalfWidth);
      const double above = guess * (1.0 + kBracketHalfWidth);
      if (admissible(below))
      {
        lo = below;
        if (above < hi && !admissible(above))
          hi = above;
      }
      else
      {
        hi = below;
      }
    }
    for (int step = 0; step < kBisectionSteps && hi - lo > kBisectionTolerance * hi; ++step)
    {
      const double mid = 0.5 * (lo + hi);
      (admissible(mid) ? lo : hi) = mid;
    }
    k_[i] = lo;
  }
  if (!all)
    for (std::size_t i = 0; i < n && i < first_change_; ++i)
      if (changed_[i] || k_[i] != previous[i])
        first_change_ = i;
  std::fill(changed_.begin(), changed_.end(), 0);
}

void TimeOptimalSolver::forward()
{
  const std::size_t n = profile_.s.size();
  std::vector<double>& x = profile_.x;
  std::vector<double>& u = profile_.u;
  std::vector<double>& t = profile_.t;
  // Step i reads x_i and the data of points i and i + 1: after a pass without a recovery, the steps
  // before the first changed point's are those of the previous pass (the same x, u and t).
  const bool again = x.size() == n && recovery_end_ == 0 && profile_.recovery_excess == 0.0;
  first_step_ = again && first_change_ > 0 ? first_change_ - 1 : 0;
  if (first_step_ == 0)
  {
    x.assign(n, 0.0);
    u.assign(n - 1, 0.0);
    t.assign(n, profile_.s.front());
    x[0] = start_x_;
    recovery_end_ = 0;
    profile_.recovery_excess = 0.0;
  }
  for (std::size_t i = first_step_; i + 1 < n; ++i)
  {
    checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
    const double d = delta(i);
    const double next = nextLimit(i);
    double chosen = 0.0;
    bool recovering = false;
    if (i == 0 && hold_start_)
    {
      recovering = x[0] > next * (1.0 + kRoundingExcess);
    }
    else
    {
      const Interval c = controls(i, x[i], next);
      if (!c.isEmpty())
      {
        chosen = c.hi;
      }
      else if (x[i] <= std::min(k_[i], right_[i].x_max) * (1.0 + kRoundingExcess))
      {
        // Rounding left x_i a hair outside K_i: hold the speed, or slow down to the next set;
        // the final check corrects what that costs.
        chosen = std::min(0.0, (next - x[i]) / (2.0 * d));
      }
      else
      {
        recovering = true;
        chosen = recoveryControl(i, x[i], next, d);
      }
    }
    double following = std::max(x[i] + 2.0 * d * chosen, 0.0);
    if (recovering)
    {
      recovery_end_ = i + 1;
      if (following > 0.0 && (corner_[i + 1] || i + 2 == n))
        throw InvalidInputError(
            "start_state: the motion starts too fast to come to rest within the bounds before path time " +
            formatNumber(profile_.s[i + 1]) + " s (" + (i + 2 == n ? "the end of the path" : "a corner") +
            "); start slower, place the first waypoint farther away, or raise the acceleration bounds");
    }
    else
    {
      following = std::min(following, next);
    }
    x[i + 1] = following;
    u[i] = (x[i + 1] - x[i]) / (2.0 * d);
    const double rate = std::sqrt(x[i]) + std::sqrt(x[i + 1]);
    if (!(rate > 0.0) && start_x_ > 0.0 && box_count_ > 0)
      throw InvalidInputError(
          "start_state: the motion starts too fast for the curve it joins: braking along it "
          "within an arm joint's acceleration limit brings it to rest at path time " +
          formatNumber(profile_.s[i]) + " s; start more slowly or farther from the first waypoint");
    if (!(rate > 0.0))
      throw InterpolationError("timing: the time-optimal profile stalls at path time " + formatNumber(profile_.s[i]) +
                               " s (the bounds are too tight for the path)");
    t[i + 1] = t[i] + 2.0 * d / rate;
  }
  profile_.recovery_end = t[checkedFrom()];
}

double TimeOptimalSolver::recoveryControl(std::size_t i, double x, double next, double d)
{
  double chosen = 0.0;
  // Braking at the acceleration bounds, which hold at the interval's ends: a margin for
  // its interior, which no later pass checks.
  for (std::size_t j : { i, i + 1 })
  {
    for (int c = 2; c < 4; ++c)
      factor_[j][c] = std::min(factor_[j][c], 1.0 - kRecoveryMargin);
    for (std::size_t q = box_count_; q < 2 * box_count_; ++q)
      box_factor_[2 * box_count_ * j + q] = std::min(box_factor_[2 * box_count_ * j + q], 1.0 - kRecoveryMargin);
    changed_[j] = 1;
  }
  const Interval free = controls(i, x, kInf);
  if (free.isEmpty())
  {
    // No braking keeps within the acceleration bounds here: the path bends too sharply
    // for this speed. The least acceleration is taken and its excess reported.
    chosen = leastAccelerationControl(i, x, d);
    const Rates r = needs(right_[i].raw, x, chosen);
    for (int c = 2; c < 4; ++c)
      profile_.recovery_excess = std::max(profile_.recovery_excess, r[c] * r[c]);
    if (box_count_ > 0)
    {
      // The boxes' acceleration levels are square roots of their ratios (boxLevel).
      std::array<double, 2 * kMaxBoxComponents> per;
      boxLevel(boxJet(i, false), x, chosen, per.data());
      for (std::size_t q = box_count_; q < 2 * box_count_; ++q)
        profile_.recovery_excess = std::max(profile_.recovery_excess, per[q] * per[q]);
    }
  }
  else
  {
    chosen = std::min(std::max((next - x) / (2.0 * d), free.lo), free.hi);
  }
  return chosen;
}

double TimeOptimalSolver::leastAccelerationControl(std::size_t i, double x, double d) const
{
  double u = 0.0;
  for (int c = 0; c < 2; ++c)
  {
    const ChannelJet& j = right_[i].jet[c];
    if (bounds_.acceleration[c] > 0.0 && j.bb > 0.0)
      u = std::min(u, -x * j.ab / j.bb);
  }
  if (box_count_ > 0)
    u = std::min(u, boxLeastControl(i, x, -x / (2.0 * d)));
  return std::max(u, -x / (2.0 * d));
}

}  // namespace time_optimal_detail
}  // namespace timing
}  // namespace se3_interpolation
