// The stress table of uneven times and hard rotations: `interpolating` on random waypoints with uneven times
// (neighbouring time steps differing by a ratio up to 100) and large rotation steps (up to 3 rad),
// both SE(3) geometries, end conditions natural, clamped and start, N up to 200. Every request
// must succeed, and every guarantee is checked on every curve against references computed here:
//  - every waypoint is passed at its time, from both sides (1e-12);
//  - C² at every join: one-sided velocities and accelerations (Side::kLeft / kRight) agree
//    (1e-9 relative to the size of the motion there);
//  - the end conditions: zero geodesic acceleration (natural), the given velocities (clamped),
//    the given velocity and acceleration (start);
//  - analytic derivatives: the jets' velocity and acceleration at a few times inside segments
//    against central differences of the poses;
//  - in the abelian cases (rotations about one axis, pure translations) the classical natural /
//    clamped cubic spline, solved here densely in its second-derivative form (1e-12).
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <random>

#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/geometry/geometry.h"
#include "test_utils.h"

using namespace se3_interpolation;
using test::poseDistance;

namespace
{
/// The cell values of the stress grid (docs/curves.md, "Splines through the waypoints").
const double kRatios[] = { 1.0, 3.0, 5.0, 10.0, 100.0 };
const double kRotationSteps[] = { 0.5, 1.0, 1.5, 2.0, 2.5, 3.0 };

/// Time steps whose neighbours differ by a factor between 0.81 r and r (or about 1, one step in
/// four): levels 1 and r, each jittered by at most 10 %.
std::vector<double> unevenTimes(std::mt19937& rng, std::size_t n, double ratio)
{
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<double> t{ u(rng) };
  bool high = u(rng) < 0.5;
  for (std::size_t i = 1; i < n; ++i)
  {
    if (u(rng) < 0.75)
      high = !high;
    const double h = high ? ratio * (0.9 + 0.1 * u(rng)) : 1.0 + 0.1 * u(rng);
    t.push_back(t.back() + 0.2 * h);
  }
  return t;
}

/// Consecutive relative rotations of angle in [0.8, 1] · `angle` about random axes; random
/// translation steps ~ N(0, 1) per component.
std::vector<Pose<double>> bigSteps(std::mt19937& rng, std::size_t n, double angle)
{
  std::uniform_real_distribution<double> u(0.8, 1.0);
  std::normal_distribution<double> nd(0.0, 1.0);
  std::vector<Pose<double>> x{ test::randomPose(rng) };
  for (std::size_t i = 1; i < n; ++i)
    x.push_back(x.back() * Pose<double>(so3Exp<double>(Eigen::Vector3d(angle * u(rng) * test::randomUnitVector<3>(rng))),
                                        Eigen::Vector3d(nd(rng), nd(rng), nd(rng))));
  return x;
}

Twist randomTwist(std::mt19937& rng, double scale)
{
  std::normal_distribution<double> n(0.0, scale);
  Twist v;
  v.linear = Eigen::Vector3d(n(rng), n(rng), n(rng));
  v.angular = Eigen::Vector3d(n(rng), n(rng), n(rng));
  return v;
}

double norm(const Twist& v)
{
  return std::max(v.linear.norm(), v.angular.norm());
}

double difference(const Twist& a, const Twist& b)
{
  return std::max((a.linear - b.linear).norm(), (a.angular - b.angular).norm());
}

/// The classical cubic spline through scalars y_i at t_i in second-derivative form (M_i = S''(t_i)),
/// the (N × N) system solved densely by Eigen's LU: natural M_0 = M_{N−1} = 0, or clamped end slopes.
class DenseClassicalSpline
{
public:
  DenseClassicalSpline(const std::vector<double>& t, const std::vector<double>& y, bool clamped, double v0, double v1)
    : t_(t), y_(y)
  {
    const Eigen::Index n = static_cast<Eigen::Index>(t.size());
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    Eigen::VectorXd r = Eigen::VectorXd::Zero(n);
    auto h = [&](Eigen::Index i) { return t[i + 1] - t[i]; };
    auto slope = [&](Eigen::Index i) { return (y[i + 1] - y[i]) / h(i); };
    for (Eigen::Index i = 1; i + 1 < n; ++i)
    {
      a(i, i - 1) = h(i - 1);
      a(i, i) = 2.0 * (h(i - 1) + h(i));
      a(i, i + 1) = h(i);
      r[i] = 6.0 * (slope(i) - slope(i - 1));
    }
    if (clamped)
    {
      a(0, 0) = 2.0 * h(0);
      a(0, 1) = h(0);
      r[0] = 6.0 * (slope(0) - v0);
      a(n - 1, n - 2) = h(n - 2);
      a(n - 1, n - 1) = 2.0 * h(n - 2);
      r[n - 1] = 6.0 * (v1 - slope(n - 2));
    }
    else
    {
      a(0, 0) = 1.0;
      a(n - 1, n - 1) = 1.0;
    }
    m_ = a.partialPivLu().solve(r);
  }

  double operator()(double s) const
  {
    std::size_t i = 0;
    while (i + 2 < t_.size() && s > t_[i + 1])
      ++i;
    const double h = t_[i + 1] - t_[i];
    const double l = t_[i + 1] - s;
    const double r = s - t_[i];
    const double mi = m_[static_cast<Eigen::Index>(i)], mj = m_[static_cast<Eigen::Index>(i) + 1];
    return mi * l * l * l / (6.0 * h) + mj * r * r * r / (6.0 * h) + (y_[i] / h - mi * h / 6.0) * l +
           (y_[i + 1] / h - mj * h / 6.0) * r;
  }

  /// The largest |y| and |S''| h²: the size the spline's values are rounded relative to.
  double size() const
  {
    double s = 1.0;
    for (std::size_t i = 0; i < y_.size(); ++i)
      s = std::max(s, std::abs(y_[i]));
    for (Eigen::Index i = 0; i + 1 < m_.size(); ++i)
      s = std::max(s, std::abs(m_[i]) * std::pow(t_[i + 1] - t_[i], 2));
    return s;
  }

private:
  std::vector<double> t_;
  std::vector<double> y_;
  Eigen::VectorXd m_;
};

struct Case
{
  std::vector<Pose<double>> x;
  std::vector<double> t;
  EndCondition condition;
  Twist v0, v1, a0;
};

/// Every guarantee of `interpolating` on one curve (file comment), as fatal assertions.
template <class G>
void checkGuarantees(const Case& k, const Curve<G>& c, const std::string& label)
{
  const std::size_t n = k.x.size();
  // Waypoints, from both sides.
  for (std::size_t i = 0; i < n; ++i)
  {
    const double scale = 1.0 + k.x[i].p.norm();
    ASSERT_LT(poseDistance(c.value(k.t[i]), k.x[i]), 1e-12 * scale) << label << " waypoint " << i;
    ASSERT_LT(poseDistance(kinematicsAt(c, k.t[i], Side::kLeft).pose, k.x[i]), 1e-12 * scale)
        << label << " waypoint " << i << " from the left";
  }
  // C² joins: the size of the motion at t_i is |v| / h (the acceleration the velocity makes in
  // the time steps around), |v|² (rotation rates compound), |a| and the waypoint step / h².
  for (std::size_t i = 1; i + 1 < n; ++i)
  {
    const Kinematics l = kinematicsAt(c, k.t[i], Side::kLeft);
    const Kinematics r = kinematicsAt(c, k.t[i], Side::kRight);
    const double h = std::min(k.t[i] - k.t[i - 1], k.t[i + 1] - k.t[i]);
    const double v = norm(r.velocity);
    const double step = poseDistance(k.x[i - 1], k.x[i]) + poseDistance(k.x[i], k.x[i + 1]);
    ASSERT_LT(difference(l.velocity, r.velocity), 1e-9 * (1.0 + v + step / h)) << label << " join " << i;
    const double a = 1.0 + norm(r.acceleration) + v / h + v * v + step / (h * h);
    ASSERT_LT(difference(l.acceleration, r.acceleration), 1e-9 * a) << label << " join " << i;
  }
  // End conditions, in G's tangents (T1), (T2).
  const TangentMotion<G> first = tangentMotion<G>(c, k.t.front(), Side::kRight);
  const TangentMotion<G> last = tangentMotion<G>(c, k.t.back(), Side::kLeft);
  const double h0 = k.t[1] - k.t[0], h1 = k.t[n - 1] - k.t[n - 2];
  switch (k.condition)
  {
    case EndCondition::kNatural:
      ASSERT_LT(first.acceleration.norm(), 1e-9 * (1.0 + first.velocity.norm() / h0 + first.velocity.squaredNorm()))
          << label;
      ASSERT_LT(last.acceleration.norm(), 1e-9 * (1.0 + last.velocity.norm() / h1 + last.velocity.squaredNorm()))
          << label;
      break;
    case EndCondition::kClamped:
      ASSERT_LT((first.velocity - velocityToTangent<G>(k.x.front(), k.v0)).norm(), 1e-10 * (1.0 + norm(k.v0)))
          << label;
      ASSERT_LT((last.velocity - velocityToTangent<G>(k.x.back(), k.v1)).norm(), 1e-10 * (1.0 + norm(k.v1)))
          << label;
      break;
    case EndCondition::kStart:
      ASSERT_LT((first.velocity - velocityToTangent<G>(k.x.front(), k.v0)).norm(), 1e-10 * (1.0 + norm(k.v0)))
          << label;
      ASSERT_LT((first.acceleration - accelerationToTangent<G>(k.x.front(), k.v0, k.a0)).norm(),
                1e-9 * (1.0 + norm(k.a0) + norm(k.v0) / h0))
          << label;
      break;
  }
  // Analytic derivatives against central differences (fourth order) at three times inside
  // segments, with a step short against the segment and against a turn (1e-3 of either), and
  // tolerances with the differences' own rounding error, ~ε |x| / step and ε |x| / step², and
  // that of the sample times themselves, ε |t| |v| / step and ε |t| |v| / step².
  for (std::size_t s : { std::size_t(0), (n - 1) / 2, n - 2 })
  {
    const double h = k.t[s + 1] - k.t[s];
    const double time = k.t[s] + 0.37 * h;
    const Kinematics exact = kinematicsAt(c, time);
    const double v = norm(exact.velocity);
    const double e = 1e-3 * std::min(h, 1.0 / (1.0 + exact.velocity.angular.norm()));
    const Kinematics fd = test::centralDifferences([&](double u) { return c.value(u); }, time, e);
    const double scale = 1.0 + exact.pose.p.norm() + 4.0 * std::abs(time) * v;
    ASSERT_LT(difference(fd.velocity, exact.velocity), 1e-6 * (v + scale / h) + 1e-13 * scale / e)
        << label << " segment " << s;
    ASSERT_LT(difference(fd.acceleration, exact.acceleration),
              1e-4 * (norm(exact.acceleration) + v / h + v * v + scale / (h * h)) + 1e-13 * scale / (e * e))
        << label << " segment " << s;
  }
}

template <class G>
std::shared_ptr<const Curve<G>> build(const Case& k)
{
  return makeInterpolatingSpline<G>(k.x, k.t, k.condition, velocityToTangent<G>(k.x.front(), k.v0),
                                    velocityToTangent<G>(k.x.back(), k.v1),
                                    accelerationToTangent<G>(k.x.front(), k.v0, k.a0));
}

const char* name(EndCondition c)
{
  return c == EndCondition::kNatural ? "natural" : (c == EndCondition::kClamped ? "clamped" : "start");
}

template <class G>
class InterpolatingStress : public ::testing::Test
{
};
using Se3Geometries = ::testing::Types<ScrewSe3, DoubleGeodesicSe3>;
TYPED_TEST_SUITE(InterpolatingStress, Se3Geometries);
}  // namespace

TYPED_TEST(InterpolatingStress, EveryCellOfTheTableSucceedsWithEveryGuarantee)
{
  // Per cell (time-step ratio × rotation step) and end condition: N = 3, 12 and 200 for natural
  // and clamped; N = 3 and 4 for start, whose forward recursion amplifies its data from segment
  // to segment (interpolating_spline.h): longer random sequences spin so fast (10⁶ rad/s and
  // more at ratio 100) that central differences can no longer resolve them, and beyond about a
  // dozen waypoints they leave double range.
  std::mt19937 rng(1200);
  int requests = 0;
  for (double ratio : kRatios)
    for (double angle : kRotationSteps)
      for (EndCondition condition : { EndCondition::kNatural, EndCondition::kClamped, EndCondition::kStart })
        for (std::size_t n : condition == EndCondition::kStart ? std::vector<std::size_t>{ 3, 4 } :
                                                                 std::vector<std::size_t>{ 3, 12, 200 })
        {
          Case k{ bigSteps(rng, n, angle), unevenTimes(rng, n, ratio), condition, randomTwist(rng, 1.0),
                  randomTwist(rng, 1.0), randomTwist(rng, 1.0) };
          const std::string label = std::string(name(condition)) + " ratio " + std::to_string(ratio) + " angle " +
                                    std::to_string(angle) + " N " + std::to_string(n);
          std::shared_ptr<const Curve<TypeParam>> c;
          try
          {
            c = build<TypeParam>(k);
          }
          catch (const InterpolationError& e)
          {
            FAIL() << label << ": refused: " << e.what();
          }
          checkGuarantees<TypeParam>(k, *c, label);
          ++requests;
        }
  EXPECT_EQ(requests, 5 * 6 * (3 + 3 + 2));
}

TYPED_TEST(InterpolatingStress, AbelianCasesAreTheClassicalSplineOnTheSameData)
{
  // Rotations about one fixed axis with the table's steps (many turns in all) and uneven times,
  // then pure translations: the classical natural / clamped spline in the angle / the position.
  std::mt19937 rng(1201);
  for (double ratio : kRatios)
    for (double angle : kRotationSteps)
      for (bool clamped : { false, true })
      {
        const std::size_t n = 40;
        const std::vector<double> t = unevenTimes(rng, n, ratio);
        const Eigen::Vector3d axis = test::randomUnitVector<3>(rng);
        std::uniform_real_distribution<double> u(0.8, 1.0);
        std::vector<double> theta{ 0.0 };
        for (std::size_t i = 1; i < n; ++i)
          theta.push_back(theta.back() + (u(rng) < 0.9 ? 1.0 : -1.0) * angle * u(rng));
        std::vector<Pose<double>> x;
        for (double a : theta)
          x.emplace_back(so3Exp<double>(Eigen::Vector3d(a * axis)), Eigen::Vector3d::Zero());
        Case k{ x, t, clamped ? EndCondition::kClamped : EndCondition::kNatural, Twist(), Twist(), Twist() };
        k.v0.angular = 0.7 * axis;
        k.v1.angular = -1.3 * axis;
        const auto c = build<TypeParam>(k);
        const DenseClassicalSpline ref(t, theta, clamped, 0.7, -1.3);
        for (int s = 0; s <= 400; ++s)
        {
          const double time = t.front() + (t.back() - t.front()) * s / 400.0;
          const Pose<double> expected(so3Exp<double>(Eigen::Vector3d(ref(time) * axis)), Eigen::Vector3d::Zero());
          ASSERT_LT(poseDistance(c->value(time), expected), 1e-12 * ref.size())
              << "ratio " << ratio << " angle " << angle << " clamped " << clamped << " t " << time;
        }

        // Pure translations: each coordinate is its own classical spline.
        std::normal_distribution<double> nd(0.0, angle);
        std::vector<std::vector<double>> y(3);
        Case p{ {}, t, k.condition, randomTwist(rng, 1.0), randomTwist(rng, 1.0), Twist() };
        p.v0.angular.setZero();
        p.v1.angular.setZero();
        for (std::size_t i = 0; i < n; ++i)
        {
          const Eigen::Vector3d q(nd(rng), nd(rng), nd(rng));
          p.x.emplace_back(Quaternion<double>::Identity(), q);
          for (int d = 0; d < 3; ++d)
            y[d].push_back(q[d]);
        }
        const auto e = build<TypeParam>(p);
        for (int d = 0; d < 3; ++d)
        {
          const DenseClassicalSpline refd(t, y[d], clamped, p.v0.linear[d], p.v1.linear[d]);
          for (int s = 0; s <= 200; ++s)
          {
            const double time = t.front() + (t.back() - t.front()) * s / 200.0;
            ASSERT_LT(std::abs(e->value(time).p[d] - refd(time)), 1e-12 * refd.size())
                << "translation ratio " << ratio << " clamped " << clamped << " t " << time;
            ASSERT_LT(rotationAngle(e->value(time).q), 1e-12);
          }
        }
      }
}
