// The time-optimal timing's box constraint (timing/time_optimal.h, (4) and (5)): components that
// move at w ṡ and accelerate at w s̈ + a ṡ² (an arm's joints) under limits V and A, beside the norm
// bounds. Checked against references written here: the closed-form trapezoid where one component
// decides the motion, a brute-force reference on a dense grid (the admissible accelerations of each
// band written out as intervals, forward and backward integration), and every limit at 50 points
// of every interval of the timed profile (x is linear in s on an interval: the exact motion).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/timing/time_optimal.h"

using namespace se3_interpolation;
using namespace se3_interpolation::timing;

namespace
{
/// A straight line along x at unit path speed: C′ = (1, 0, 0), C″ = 0, s ∈ [0, length].
class Line final : public PathModel
{
public:
  explicit Line(double length) : length_(length) {}
  double start() const override { return 0.0; }
  double end() const override { return length_; }
  std::vector<double> breakpoints() const override { return { 0.0, 0.5 * length_, length_ }; }
  PathJet jet(double, Side) const override
  {
    return { channelJet(Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector3d::Zero().eval()), ChannelJet() };
  }
  bool isCorner(double) const override { return false; }

private:
  double length_;
};

/// Components q_k(s) given by their derivatives: q1 = 2 sin(s) (w = 2 cos s, a = −2 sin s),
/// q2 = ½ s² (w = s, a = 1), q3 = 2 s (w = 2, a = 0): a sign change of w, a w that grows, a constant.
class Components final : public BoxConstraint
{
public:
  Components(std::vector<double> v, std::vector<double> a) : v_(std::move(v)), a_(std::move(a)) {}
  std::size_t size() const override { return v_.size(); }
  double velocityLimit(std::size_t k) const override { return v_[k]; }
  double accelerationLimit(std::size_t k) const override { return a_[k]; }
  void jet(double s, Side, double* w, double* a) const override
  {
    const double all_w[3] = { 2.0 * std::cos(s), s, 2.0 };
    const double all_a[3] = { -2.0 * std::sin(s), 1.0, 0.0 };
    for (std::size_t k = 0; k < size(); ++k)
    {
      w[k] = all_w[k];
      a[k] = all_a[k];
    }
  }

private:
  std::vector<double> v_, a_;
};

/// The largest level of every limit (line's linear speed and acceleration under v_max, a_max, the
/// components' under theirs) at 50 points of every interval: x = x_i + λ (x_{i+1} − x_i), u = u_i.
double worstLevel(const TimingProfile& p, const Components& c, double v_max, double a_max)
{
  double worst = 0.0;
  double w[3], a[3];
  for (std::size_t i = 0; i + 1 < p.s.size(); ++i)
    for (int j = 0; j <= 50; ++j)
    {
      const double lambda = j / 50.0;
      const double s = p.s[i] + lambda * (p.s[i + 1] - p.s[i]);
      const double x = p.x[i] + lambda * (p.x[i + 1] - p.x[i]);
      const double u = p.u[i];
      if (v_max > 0.0)
        worst = std::max(worst, std::sqrt(x) / v_max);
      if (a_max > 0.0)
        worst = std::max(worst, std::abs(u) / a_max);
      c.jet(s, Side::kRight, w, a);
      for (std::size_t k = 0; k < c.size(); ++k)
      {
        if (c.velocityLimit(k) > 0.0)
          worst = std::max(worst, std::abs(w[k]) * std::sqrt(x) / c.velocityLimit(k));
        if (c.accelerationLimit(k) > 0.0)
          worst = std::max(worst, std::abs(w[k] * u + a[k] * x) / c.accelerationLimit(k));
      }
    }
  return worst;
}

/// Brute force on n uniform intervals of [0, length]: the admissible u at (s, x) is the
/// intersection of |u| ≤ a_max and, per component, [(−A − a x)/w, (A − a x)/w] (ordered by the sign
/// of w; for w = 0 the condition |a| x ≤ A); the speed limit min(v_max², V²/w²); then the largest x
/// from which the slowest admissible u reaches the next point's set (backward) and the fastest
/// admissible u from rest (forward).
double bruteForceDuration(double length, const Components& c, double v_max, double a_max, std::size_t n = 20000)
{
  const double ds = length / static_cast<double>(n);
  auto controls = [&](double s, double x, double* lo, double* hi) {
    *lo = a_max > 0.0 ? -a_max : -1e300;
    *hi = a_max > 0.0 ? a_max : 1e300;
    double w[3], a[3];
    c.jet(s, Side::kRight, w, a);
    for (std::size_t k = 0; k < c.size(); ++k)
    {
      const double A = c.accelerationLimit(k);
      if (!(A > 0.0))
        continue;
      if (w[k] == 0.0)
      {
        if (std::abs(a[k]) * x > A)
          return false;
        continue;
      }
      const double e1 = (-A - a[k] * x) / w[k], e2 = (A - a[k] * x) / w[k];
      *lo = std::max(*lo, std::min(e1, e2));
      *hi = std::min(*hi, std::max(e1, e2));
    }
    return *lo <= *hi;
  };
  auto speedCap = [&](double s) {
    double cap = v_max > 0.0 ? v_max * v_max : 1e300;
    double w[3], a[3];
    c.jet(s, Side::kRight, w, a);
    for (std::size_t k = 0; k < c.size(); ++k)
      if (c.velocityLimit(k) > 0.0 && w[k] != 0.0)
        cap = std::min(cap, c.velocityLimit(k) * c.velocityLimit(k) / (w[k] * w[k]));
    return cap;
  };
  std::vector<double> beta(n + 1, 0.0);
  for (std::size_t i = n; i-- > 1;)
  {
    const double s = ds * static_cast<double>(i);
    auto ok = [&](double x) {
      double lo, hi;
      return controls(s, x, &lo, &hi) && x + 2.0 * ds * lo <= beta[i + 1] &&
             controls(s + ds, std::max(0.0, x + 2.0 * ds * lo), &lo, &hi);
    };
    double lo = 0.0, hi = speedCap(s);
    for (int k = 0; k < 80; ++k)
    {
      const double mid = 0.5 * (lo + hi);
      (ok(mid) ? lo : hi) = mid;
    }
    beta[i] = lo;
  }
  double t = 0.0, x = 0.0;
  for (std::size_t i = 0; i < n; ++i)
  {
    double lo = 0.0, hi = 0.0;
    controls(ds * static_cast<double>(i), x, &lo, &hi);
    const double next = std::max(0.0, std::min(beta[i + 1], x + 2.0 * ds * hi));
    t += 2.0 * ds / (std::sqrt(x) + std::sqrt(next));
    x = next;
  }
  return t;
}

RateBounds lineBounds(double v, double a)
{
  RateBounds b;
  b.velocity[kLinear] = v;
  b.acceleration[kLinear] = a;
  return b;
}

TimingProfile solve(double length, double v, double a, std::shared_ptr<const Components> c, double start_speed = 0.0)
{
  TimeOptimalOptions options;
  options.boxes = std::move(c);
  options.start_speed = start_speed;
  return timeOptimalProfile(Line(length), lineBounds(v, a), options);
}

}  // namespace

TEST(TimeOptimalBoxes, OneComponentThatDecidesGivesItsTrapezoid)
{
  // q3 = 2 s over s ∈ [0, 1.5]: 3 units at V = 1, A = 1 (closed form 3/1 + 1/1 = 4 s); the line's
  // own bounds (speed 0.6, acceleration 0.6) allow ṡ = 0.6 > V/2 and s̈ = 0.6 > A/2, so they do not bind.
  auto c = std::make_shared<Components>(std::vector<double>{ 0, 0, 1.0 }, std::vector<double>{ 0, 0, 1.0 });
  const TimingProfile p = solve(1.5, 0.6, 0.6, c);
  EXPECT_NEAR(p.duration(), 4.0, 4.0 * 1e-3);
  EXPECT_LE(worstLevel(p, *c, 0.6, 0.6), 1.0 + 1e-9);
}

TEST(TimeOptimalBoxes, WithTheNormBoundsBindingTooTheTrapezoidOfTheTighterOfEach)
{
  // Speed: the line allows ṡ ≤ 0.4, q3 ṡ ≤ 0.5: the line binds. Acceleration: the line s̈ ≤ 1,
  // q3 s̈ ≤ 0.5: q3 binds. Trapezoid in s over 1: 1/0.4 + 0.4/0.5 = 3.3 s.
  auto c = std::make_shared<Components>(std::vector<double>{ 0, 0, 1.0 }, std::vector<double>{ 0, 0, 1.0 });
  const TimingProfile p = solve(1.0, 0.4, 1.0, c);
  EXPECT_NEAR(p.duration(), 3.3, 3.3 * 1e-3);
  EXPECT_LE(worstLevel(p, *c, 0.4, 1.0), 1.0 + 1e-9);
}

TEST(TimeOptimalBoxes, VaryingComponentsMatchTheBruteForceReferenceAndHoldEverywhere)
{
  // w of q1 changes sign at s = π/2 (its velocity limit does not bind there), q2's w grows with s
  // and its a = 1 acts at every speed.
  const struct
  {
    double length, v, a;
    std::vector<double> vk, ak;
  } cases[] = {
    { 3.0, 2.0, 3.0, { 1.0, 1.2, 0 }, { 1.5, 2.0, 0 } },
    { 3.0, 0.5, 3.0, { 1.0, 1.2, 0 }, { 0.8, 2.0, 0 } },
    { 2.0, 0, 0, { 0.7, 0.9, 2.0 }, { 1.0, 1.0, 3.0 } },  // the components alone bound the motion
  };
  for (const auto& k : cases)
  {
    auto c = std::make_shared<Components>(k.vk, k.ak);
    const TimingProfile p = solve(k.length, k.v, k.a, c);
    const double reference = bruteForceDuration(k.length, *c, k.v, k.a);
    EXPECT_NEAR(p.duration() / reference, 1.0, 0.01) << k.length << " " << k.v;
    EXPECT_GE(p.duration() / reference, 1.0 - 2e-3);
    EXPECT_LE(worstLevel(p, *c, k.v, k.a), 1.0 + 1e-9);
  }
}

TEST(TimeOptimalBoxes, LimitsThatDoNotBindLeaveTheTimingAsItIs)
{
  auto loose = std::make_shared<Components>(std::vector<double>{ 50, 50, 50 }, std::vector<double>{ 50, 50, 50 });
  const TimingProfile with = solve(3.0, 0.5, 1.0, loose);
  const TimingProfile without = timeOptimalProfile(Line(3.0), lineBounds(0.5, 1.0));
  EXPECT_NEAR(with.duration(), without.duration(), 1e-9 * without.duration());
}

TEST(TimeOptimalBoxes, AMovingStartHoldsTheLimitsAfterIt)
{
  // Starting at ṡ = 0.2 (within every limit): the motion keeps it exactly and stays within all.
  auto c = std::make_shared<Components>(std::vector<double>{ 1.0, 1.2, 0 }, std::vector<double>{ 1.5, 2.0, 0 });
  const TimingProfile p = solve(3.0, 2.0, 3.0, c, 0.2);
  EXPECT_DOUBLE_EQ(p.x.front(), 0.04);
  EXPECT_LE(worstLevel(p, *c, 2.0, 3.0), 1.0 + 1e-7);
}

TEST(TimeOptimalBoxes, AComponentWithoutAnAccelerationLimitNeedsTheNormBounds)
{
  auto c = std::make_shared<Components>(std::vector<double>{ 1.0, 1.0, 1.0 }, std::vector<double>{ 1.0, 0, 1.0 });
  EXPECT_THROW(solve(2.0, 0, 0, c), InvalidInputError);
}
