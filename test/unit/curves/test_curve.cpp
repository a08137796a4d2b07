// curves/curve.h: the times rule (its messages name the field and index), findInterval's
// one-sided intervals at breakpoints, and TimeScaledCurve: c(t) = base(t0 + (t − t0)/k) has the
// base's velocity / k and acceleration / k² (checked in R^2, the classical case, by hand), and
// takes the requested side at the images of the base's breakpoints.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "se3_interpolation/curves/bezier.h"
#include "se3_interpolation/curves/curve.h"

using namespace se3_interpolation;

namespace
{
std::string timesError(const std::vector<double>& times, std::size_t n)
{
  try
  {
    requireIncreasingTimes(times, n);
  }
  catch (const InvalidInputError& e)
  {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Curve, TimesRuleNamesTheFieldAndIndex)
{
  EXPECT_EQ(timesError({ 0.0, 1.0, 2.5 }, 3), "");
  EXPECT_EQ(timesError({ 0.0, 1.0 }, 3), "times: 2 given for 3 waypoints (give one time per waypoint, or none)");
  EXPECT_EQ(timesError({ 0.0, 1.0, 1.0 }, 3),
            "times[2]: 1 is not after times[1] = 1 (times must be strictly increasing)");
  EXPECT_EQ(timesError({ 0.0, std::numeric_limits<double>::quiet_NaN(), 2.0 }, 3),
            "times[1]: nan is not a finite number");
  EXPECT_EQ(timesError({ -std::numeric_limits<double>::infinity(), 1.0 }, 2), "times[0]: -inf is not a finite number");
}

TEST(Curve, FindIntervalTakesTheRequestedSideAtBreakpoints)
{
  const std::vector<double> b{ 0.0, 1.0, 2.0, 4.0 };
  EXPECT_EQ(findInterval(b, 0.5, Side::kRight), 0u);
  EXPECT_EQ(findInterval(b, 1.0, Side::kRight), 1u);
  EXPECT_EQ(findInterval(b, 1.0, Side::kLeft), 0u);
  EXPECT_EQ(findInterval(b, 2.0, Side::kLeft), 1u);
  EXPECT_EQ(findInterval(b, 3.9, Side::kLeft), 2u);
  // Outside the span: the end intervals (extrapolation), at the ends too.
  EXPECT_EQ(findInterval(b, -1.0, Side::kRight), 0u);
  EXPECT_EQ(findInterval(b, 0.0, Side::kLeft), 0u);
  EXPECT_EQ(findInterval(b, 4.0, Side::kRight), 2u);
  EXPECT_EQ(findInterval(b, 9.0, Side::kLeft), 2u);
}

TEST(Curve, TimeScaledCurveDividesVelocityByKAndAccelerationByKSquared)
{
  // The quadratic Bézier in R^2 with control points p0, p1, p2 on [t0, t1]: with u = (t − t0)/T,
  // c(u) = (1 − u)² p0 + 2u(1 − u) p1 + u² p2, c' = 2((1 − u)(p1 − p0) + u(p2 − p1))/T,
  // c'' = 2(p2 − 2p1 + p0)/T². Stretched by k from t0: u = (t − t0)/(kT).
  const Eigen::VectorXd p0 = Eigen::Vector2d(0.0, 0.0), p1 = Eigen::Vector2d(1.0, 2.0), p2 = Eigen::Vector2d(3.0, -1.0);
  const double t0 = 0.5, t1 = 2.5, T = t1 - t0, k = 1.75;
  const auto base = std::make_shared<const BezierCurve<Euclidean>>(std::vector<Eigen::VectorXd>{ p0, p1, p2 }, t0, t1);
  const TimeScaledCurve<Euclidean> scaled(base, k);
  EXPECT_DOUBLE_EQ(scaled.startTime(), t0);
  EXPECT_DOUBLE_EQ(scaled.endTime(), t0 + k * T);
  for (double t : { t0, t0 + 0.3, t0 + 1.9, t0 + k * T })
  {
    const double u = (t - t0) / (k * T);
    const Eigen::VectorXd c = (1 - u) * (1 - u) * p0 + 2 * u * (1 - u) * p1 + u * u * p2;
    const Eigen::VectorXd v = 2.0 * ((1 - u) * (p1 - p0) + u * (p2 - p1)) / (k * T);
    const Eigen::VectorXd a = 2.0 * (p2 - 2.0 * p1 + p0) / (k * k * T * T);
    EXPECT_LT((scaled.value(t) - c).norm(), 1e-14) << t;
    const VectorX<Jet<2>> j = scaled.jet(Jet<2>::variable(t), Side::kRight);
    for (int i = 0; i < 2; ++i)
    {
      EXPECT_NEAR(j[i].value(), c[i], 1e-14);
      EXPECT_NEAR(j[i].coefficient(1), v[i], 1e-14);
      EXPECT_NEAR(2.0 * j[i].coefficient(2), a[i], 1e-14);
    }
  }
  const std::vector<double> b = scaled.breakpoints();
  ASSERT_EQ(b.size(), 2u);
  EXPECT_DOUBLE_EQ(b.back(), t0 + k * T);
}

// A scaled clock maps the image b·k of a base breakpoint b back to (b·k)/k, which rounds to
// either side of b: the one-sided jets at the scaled curve's own breakpoints must still be the
// base's one-sided jets there (velocity / k), not the neighbouring piece's. (A time-optimal motion
// from a moving start stops at such corners; the wrong side gave 3.4 times its acceleration bound.)
TEST(Curve, TimeScaledCurveTakesTheRequestedSideAtItsBreakpoints)
{
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> step(0.01, 3.0), scale(0.05, 20.0);
  const std::vector<Eigen::VectorXd> points{ Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(1.0, 0.0),
                                             Eigen::Vector2d(1.0, 1.0), Eigen::Vector2d(3.0, 1.0),
                                             Eigen::Vector2d(3.0, -2.0) };
  int checked = 0;
  for (int trial = 0; trial < 200; ++trial)
  {
    std::vector<double> times{ step(rng) };
    for (std::size_t i = 1; i < points.size(); ++i)
      times.push_back(times.back() + step(rng));
    const auto base = std::make_shared<const PiecewiseGeodesic<Euclidean>>(points, times);
    const double k = scale(rng);
    const TimeScaledCurve<Euclidean> scaled(base, k);
    const std::vector<double> b = scaled.breakpoints();
    ASSERT_EQ(b.size(), times.size());
    for (std::size_t i = 1; i + 1 < times.size(); ++i)
      for (Side side : { Side::kLeft, Side::kRight })
      {
        // Piece i−1 ends at times[i] (left), piece i starts there (right): velocity (Δp/Δt)/k.
        const std::size_t piece = side == Side::kLeft ? i - 1 : i;
        const Eigen::VectorXd v = (points[piece + 1] - points[piece]) / ((times[piece + 1] - times[piece]) * k);
        const VectorX<Jet<2>> j = scaled.jet(Jet<2>::variable(b[i]), side);
        for (int c = 0; c < 2; ++c)
          EXPECT_NEAR(j[c].coefficient(1), v[c], 1e-9 * (1.0 + v.norm())) << "trial " << trial << " breakpoint " << i;
        ++checked;
      }
  }
  EXPECT_EQ(checked, 200 * 3 * 2);
}
