// analysis/figures.h: measureCurve's length, rotation length, energy and peak rates against
// closed forms: a straight line, a constant screw motion (a helix), and the classical energy
// integral of a cubic Bézier in the abelian cases (pure translations, rotations about one axis).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/curves/bspline.h"
#include "test_utils.h"

using namespace se3_interpolation;
using namespace se3_interpolation::test;

template <class G>
class FiguresSe3 : public ::testing::Test
{
};
using Se3Geometries = ::testing::Types<ScrewSe3, DoubleGeodesicSe3>;
TYPED_TEST_SUITE(FiguresSe3, Se3Geometries);

TEST(Figures, StraightLineLengthIsTheDistance)
{
  std::mt19937 rng(901);
  for (int trial = 0; trial < 10; ++trial)
  {
    const Pose<double> a = randomPose(rng), b = randomPose(rng);
    // Product metric: the translation is a straight line whatever the rotations do.
    const BSplineCurve<DoubleGeodesicSe3> line({ a, b }, 1, bezierKnots(1, 0.5, 2.0));
    const double d = (b.p - a.p).norm();
    EXPECT_NEAR(measureCurve(line, 1.0).length, d, 1e-10 * d);
    // A cubic with identical rotations and collinear, increasing positions: a monotone
    // (unevenly paced) run along the segment.
    const Eigen::Vector3d dir = randomUnitVector<3>(rng);
    std::vector<Pose<double>> pts;
    for (double s : { 0.0, 0.1, 0.7, 1.3, 2.0, 2.2 })
      pts.emplace_back(a.q, a.p + s * dir);
    const BSplineCurve<ScrewSe3> run(pts, 3, randomKnots(rng, 6, 3, true));
    const CurveFigures f = measureCurve(run, 1.0);
    EXPECT_NEAR(f.length, 2.2, 1e-10 * 2.2);
    EXPECT_LT(f.rotation_length, 1e-14);
  }
}

TEST(Figures, ConstantScrewMotionIsAHelix)
{
  // g(t) = g_0 Exp(t ξ) for several turns, as a degree-1 B-spline through samples of it.
  // The body origin runs on a helix of radius r = |ω × v|/|ω|² about the screw axis, with
  // axial speed h = ω·v/|ω|: length T √((|ω| r)² + h²), rotation length T |ω|, centripetal
  // acceleration |ω|² r so energy T (|ω|² r)² (ω̇ = 0).
  std::mt19937 rng(902);
  for (int trial = 0; trial < 5; ++trial)
  {
    const Pose<double> g0 = randomPose(rng);
    Vector6<double> xi;
    xi << 2.0 * randomUnitVector<3>(rng), 1.5 * randomUnitVector<3>(rng);
    const double duration = 6.0;  // 12 rad: nearly two turns
    const std::size_t n = 25;
    std::vector<Pose<double>> pts;
    for (std::size_t k = 0; k < n; ++k)
      pts.push_back(g0 * se3Exp<double>(duration * static_cast<double>(k) / (n - 1) * xi));
    const BSplineCurve<ScrewSe3> helix(pts, 1, clampedUniformKnots(n, 1, 0.0, duration));
    const Eigen::Vector3d w = xi.head<3>(), v = xi.tail<3>();
    const double r = w.cross(v).norm() / w.squaredNorm();
    const double h = w.dot(v) / w.norm();
    const double length = duration * std::sqrt(std::pow(w.norm() * r, 2) + h * h);
    const double energy = duration * std::pow(w.squaredNorm() * r, 2);
    const CurveFigures f = measureCurve(helix, 1.7);
    EXPECT_NEAR(f.length, length, 1e-10 * length);
    EXPECT_NEAR(f.rotation_length, duration * w.norm(), 1e-10 * duration * w.norm());
    EXPECT_NEAR(f.energy, energy, 1e-10 * energy);
    EXPECT_NEAR(f.max_angular_speed, w.norm(), 1e-10 * w.norm());
  }
}

TYPED_TEST(FiguresSe3, CubicBezierEnergyIsTheClassicalIntegral)
{
  // p(t) cubic Bézier on [t0, t1], T = t1 − t0, λ = (t − t0)/T:
  // p̈ = 6/T² ((1 − λ) A + λ B), A = P_2 − 2P_1 + P_0, B = P_3 − 2P_2 + P_1, so
  // ∫ |p̈|² dt = 36/T³ ∫_0^1 |(1 − λ) A + λ B|² dλ = 12/T³ (|A|² + A·B + |B|²).
  // A rotation about one fixed axis by angles θ_i gives ρ² times the same with scalars.
  std::mt19937 rng(903);
  std::normal_distribution<double> d(0.0, 1.0);
  for (int trial = 0; trial < 10; ++trial)
  {
    const double t0 = -0.3, t1 = 1.9, T = t1 - t0, rho = 0.8;
    std::vector<Eigen::Vector3d> p(4);
    for (auto& x : p)
      x = Eigen::Vector3d(d(rng), d(rng), d(rng));
    const Eigen::Vector3d a = p[2] - 2 * p[1] + p[0], b = p[3] - 2 * p[2] + p[1];
    std::vector<Pose<double>> translation;
    for (const auto& x : p)
      translation.emplace_back(Quaternion<double>::Identity(), x);
    const double expected = 12.0 / (T * T * T) * (a.squaredNorm() + a.dot(b) + b.squaredNorm());
    const CurveFigures f = measureCurve(BSplineCurve<TypeParam>(translation, 3, bezierKnots(3, t0, t1)), rho);
    EXPECT_NEAR(f.energy, expected, 1e-10 * expected);

    const Eigen::Vector3d axis = randomUnitVector<3>(rng);
    std::vector<double> th{ d(rng) };
    for (int i = 1; i < 4; ++i)
      th.push_back(th.back() + 1.5 * d(rng) / (1.0 + std::abs(d(rng))));
    std::vector<Pose<double>> rotation;
    for (double x : th)
      rotation.emplace_back(so3Exp<double>(x * axis), Eigen::Vector3d::Zero());
    const double ra = th[2] - 2 * th[1] + th[0], rb = th[3] - 2 * th[2] + th[1];
    const double rot_expected = rho * rho * 12.0 / (T * T * T) * (ra * ra + ra * rb + rb * rb);
    const CurveFigures g = measureCurve(BSplineCurve<TypeParam>(rotation, 3, bezierKnots(3, t0, t1)), rho);
    EXPECT_NEAR(g.energy, rot_expected, 1e-10 * rot_expected);
  }
}
