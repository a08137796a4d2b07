// analysis/figures.h: measureCurve's length, rotation length, energy and peak rates against
// closed forms: a straight line, a constant screw motion (a helix), and the classical energy
// integral of a cubic Bézier in the abelian cases (pure translations, rotations about one axis);
// its peaks against brute-force searches, and its lengths and measureLengths' against chord sums.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/analysis/figures.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/curves/corner_blend.h"
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
  // acceleration |ω|² r so energy T (|ω|² r)² (ω̇ = 0). measureLengths gives the same lengths.
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
    // The timings' measure of the path (lengths alone, one Gauss rule per piece).
    const std::pair<double, double> lengths = measureLengths(helix);
    EXPECT_NEAR(lengths.first, length, 1e-10 * length);
    EXPECT_NEAR(lengths.second, duration * w.norm(), 1e-10 * duration * w.norm());
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

/// The largest local maximum of rate j of `curve`, by brute force: every local maximum of 200
/// evenly spread samples per piece (one-sided at its ends), refined by a ternary search between its
/// neighbouring samples.
template <class G>
double bruteForcePeak(const Curve<G>& curve, std::size_t j)
{
  const auto rate = [&curve, j](double t, Side side) { return rates(kinematicsAt(curve, t, side))[j]; };
  const std::vector<double> b = curve.breakpoints();
  const int samples = 200;
  double peak = 0.0;
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
  {
    if (!(b[i + 1] > b[i]))
      continue;
    const double h = (b[i + 1] - b[i]) / samples;
    std::vector<double> at(samples + 1);
    for (int k = 0; k <= samples; ++k)
      at[k] = rate(k == samples ? b[i + 1] : b[i] + k * h, k == samples ? Side::kLeft : Side::kRight);
    peak = std::max({ peak, at.front(), at.back() });
    for (int k = 1; k < samples; ++k)
    {
      if (at[k] < at[k - 1] || at[k] < at[k + 1])
        continue;
      double lo = b[i] + (k - 1) * h, hi = b[i] + (k + 1) * h;
      for (int step = 0; step < 80; ++step)
      {
        const double m1 = lo + (hi - lo) / 3.0, m2 = hi - (hi - lo) / 3.0;
        if (rate(m1, Side::kRight) < rate(m2, Side::kRight))
          lo = m1;
        else
          hi = m2;
      }
      peak = std::max({ peak, at[k], rate(0.5 * (lo + hi), Side::kRight) });
    }
  }
  return peak;
}

template <class G>
void expectPeaksOfTheCurve(const Curve<G>& curve, const std::string& what)
{
  const CurveFigures f = measureCurve(curve, 1.0);
  const Rates figure{ f.max_linear_speed, f.max_angular_speed, f.max_linear_acceleration, f.max_angular_acceleration };
  for (std::size_t j = 0; j < figure.size(); ++j)
  {
    const double peak = bruteForcePeak(curve, j);
    EXPECT_NEAR(figure[j], peak, 1e-9 * peak) << what << " rate " << j;
  }
}

// The peak rates are the curve's, not those of its best nodes: each figure equals the largest local
// maximum found by brute force (bruteForcePeak) to 1e-9, on curves of many pieces whose rates have
// many local maxima of similar heights: corner-blended polylines through 50 poses at even times whose
// legs in turn rotate by about π and translate only (each blend's angular acceleration peaks in a
// narrow bump near its start), and cubic B-splines through 30 random poses on random knots.
TYPED_TEST(FiguresSe3, PeaksAreTheCurvesAmongSimilarLocalMaxima)
{
  std::mt19937 rng(904);
  std::uniform_real_distribution<double> angle(3.0, 3.1), length(0.5, 1.5);
  for (int trial = 0; trial < 2; ++trial)
  {
    std::vector<Pose<double>> pts{ randomPose(rng) };
    std::vector<double> times{ 0.0 };
    for (int i = 1; i < 50; ++i)
    {
      const Pose<double>& last = pts.back();
      if (i % 2 == 1)
        pts.emplace_back(last.q * so3Exp<double>(angle(rng) * randomUnitVector<3>(rng)), last.p + 0.2 * randomUnitVector<3>(rng));
      else
        pts.emplace_back(last.q, last.p + length(rng) * randomUnitVector<3>(rng));
      times.push_back(i);
    }
    expectPeaksOfTheCurve(CornerBlendedGeodesic<TypeParam>(pts, times, 0.25, 1.0),
                          "corner blends trial " + std::to_string(trial));
    std::vector<Pose<double>> spline_points;
    for (int i = 0; i < 30; ++i)
      spline_points.push_back(randomPose(rng, 2.0));
    expectPeaksOfTheCurve(BSplineCurve<TypeParam>(spline_points, 3, randomKnots(rng, spline_points.size(), 3, true)),
                          "bspline trial " + std::to_string(trial));
  }
}

// Two corners of a screw polyline whose blends peak at 69.496 and 68.827 rad/s² (the request-space
// grid's waypoints 0-2 and 35-37 of a 50-waypoint polyline, blend_radius 0.25): the nodes sampled the
// lower peak higher, and refining only the best node gave 68.830, 0.96 % low; the stretch then scaled
// the motion to that figure and its angular acceleration exceeded max_angular_acceleration by 1 %.
TEST(Figures, APeakSampledLowerThanAnotherIsFound)
{
  const std::vector<Pose<double>> pts{
    { Quaternion<double>(0.99659711473087298, 0.057151243306832647, -0.033519166860894178, 0.049034597495379334),
      Eigen::Vector3d(-0.8720537330684871, 0.82279799911566887, 1.6568125621666239) },
    { Quaternion<double>(0.044637708554197367, -0.10057217643449909, -0.26185330128435852, -0.95881466452528852),
      Eigen::Vector3d(0.39645112016958073, 0.62260740459242991, 1.8257303949677042) },
    { Quaternion<double>(0.044637708149474618, -0.10057217638190503, -0.26185330101282878, -0.95881466462380216),
      Eigen::Vector3d(0.54628435426576638, 0.40563115225003638, 1.4748494355492845) },
    { Quaternion<double>(-0.23894908680342897, 0.26423109876893758, -0.3573222909912338, -0.86336900611496559),
      Eigen::Vector3d(19.186585880950251, -1.6842253934112432, 3.1759250640058618) },
    { Quaternion<double>(-0.42711477757706617, 0.0071283074397643365, 0.87149436192195029, -0.24087285265589894),
      Eigen::Vector3d(19.007485925847249, 0.18048543473481105, 2.6148921909740741) },
    { Quaternion<double>(-0.42711477770550649, 0.0071283072423472702, 0.87149436198140784, -0.24087285221886989),
      Eigen::Vector3d(19.143438543257769, -0.29370188005956965, 2.4159677920362728) },
  };
  const CornerBlendedGeodesic<ScrewSe3> curve(pts, { 0.0, 1.0, 2.0, 35.0, 36.0, 37.0 }, 0.25, 1.0);
  const double peak = bruteForcePeak(curve, kAngularAcceleration);
  EXPECT_NEAR(peak, 69.4963, 1e-4);
  EXPECT_NEAR(measureCurve(curve, 1.0).max_angular_acceleration, peak, 1e-9 * peak);
}

/// The curve's lengths (∫|ṗ|, ∫|ω|) as limits of polygon lengths: the sums of the chords |Δp| and
/// the rotation angles between m points per piece (graded toward the piece's ends), extrapolated
/// from m and 2m (the sums converge as 1/m²). Shares no rule with measureCurve or measureLengths.
template <class G>
std::pair<double, double> chordLengths(const Curve<G>& curve, int m)
{
  const auto sums = [&curve](int points) {
    std::pair<double, double> sum{ 0.0, 0.0 };
    const std::vector<double> b = curve.breakpoints();
    for (std::size_t i = 0; i + 1 < b.size(); ++i)
    {
      Pose<double> prev = curve.value(b[i]);
      for (int k = 1; k <= points; ++k)
      {
        const double w = 0.5 - 0.5 * std::cos(M_PI * static_cast<double>(k) / points);
        const Pose<double> x = curve.value(b[i] + w * (b[i + 1] - b[i]));
        sum.first += (x.p - prev.p).norm();
        sum.second += x.q.angularDistance(prev.q);
        prev = x;
      }
    }
    return sum;
  };
  const std::pair<double, double> coarse = sums(m), fine = sums(2 * m);
  return { fine.first + (fine.first - coarse.first) / 3.0, fine.second + (fine.second - coarse.second) / 3.0 };
}

// measureLengths, the timings' measure of the path (one Gauss–Legendre rule per piece where
// measureCurve uses four), and measureCurve's lengths, against the chord sums (chordLengths): corner
// blends between uneven times (steps of 1e-3 s, 1 s and 10³ s: pieces whose speed changes by orders
// of magnitude in a sliver, where a halving rule floored at 1 % of the peak speed left both 0.4 %
// short) and cubic B-splines on random knots.
TYPED_TEST(FiguresSe3, LengthsAloneAgreeWithTheChordSums)
{
  std::mt19937 rng(905);
  for (int trial = 0; trial < 4; ++trial)
  {
    std::vector<Pose<double>> pts{ randomPose(rng, 2.0) };
    std::vector<double> times{ 0.0 };
    for (int i = 1; i < 12; ++i)
    {
      pts.push_back(pts.back() * Pose<double>(so3Exp<double>(2.5 * randomUnitVector<3>(rng)), randomUnitVector<3>(rng)));
      times.push_back(times.back() + (i % 3 == 0 ? 1e3 : (i % 3 == 1 ? 1.0 : 1e-3 * (trial + 1))));
    }
    const CornerBlendedGeodesic<TypeParam> blended(pts, times, 0.3, 1.0);
    const BSplineCurve<TypeParam> spline(pts, 3, randomKnots(rng, pts.size(), 3, true));
    for (const Curve<TypeParam>* curve : { static_cast<const Curve<TypeParam>*>(&blended),
                                           static_cast<const Curve<TypeParam>*>(&spline) })
    {
      const std::string what = (curve == &blended ? "corner blends, trial " : "cubic B-spline, trial ") + std::to_string(trial);
      const std::pair<double, double> reference = chordLengths(*curve, 5000);
      // Within 1e-6 on the blends (measured: 5e-7 at worst), 1e-8 on the splines (measured: 1.5e-9
      // at worst, a rotation length in clang's sanitized build; the reference itself is good to 1e-10).
      const double tolerance = curve == &blended ? 1e-6 : 1e-8;
      const std::pair<double, double> lengths = measureLengths(*curve);
      const CurveFigures full = measureCurve(*curve, 1.0);
      EXPECT_NEAR(lengths.first, reference.first, tolerance * reference.first) << what;
      EXPECT_NEAR(lengths.second, reference.second, tolerance * reference.second) << what;
      EXPECT_NEAR(full.length, reference.first, tolerance * reference.first) << what;
      EXPECT_NEAR(full.rotation_length, reference.second, tolerance * reference.second) << what;
    }
  }
}

TYPED_TEST(FiguresSe3, SpeedsFromFirstOrderJetsAreTheKinematicsSpeeds)
{
  // speedsAt (measureLengths' evaluation: the curve's first-order jets, or the second-order ones
  // truncated for a curve without them, here a time-scaled wrapper) against |ṗ| and |ω| of
  // kinematicsAt, on both sides of every breakpoint and between them.
  using G = TypeParam;
  std::mt19937 rng(906);
  std::vector<Pose<double>> pts{ randomPose(rng, 2.0) };
  std::vector<double> times{ 0.0 };
  for (int i = 1; i < 8; ++i)
  {
    pts.push_back(pts.back() * Pose<double>(so3Exp<double>(1.5 * randomUnitVector<3>(rng)), randomUnitVector<3>(rng)));
    times.push_back(times.back() + (i % 2 == 0 ? 2.0 : 0.01));
  }
  const auto blended = std::make_shared<CornerBlendedGeodesic<G>>(pts, times, 0.4, 0.7);
  const auto spline = std::make_shared<BSplineCurve<G>>(pts, 3, randomKnots(rng, pts.size(), 3, true));
  const TimeScaledCurve<G> scaled(spline, 2.5);
  for (const Curve<G>* curve : { static_cast<const Curve<G>*>(blended.get()), static_cast<const Curve<G>*>(spline.get()),
                                 static_cast<const Curve<G>*>(&scaled) })
  {
    std::vector<double> ts = curve->breakpoints();
    for (std::size_t i = 0; i + 1 < curve->breakpoints().size(); ++i)
      for (double f : { 0.1, 0.5, 0.93 })
        ts.push_back(curve->breakpoints()[i] + f * (curve->breakpoints()[i + 1] - curve->breakpoints()[i]));
    for (double t : ts)
      for (const Side side : { Side::kLeft, Side::kRight })
      {
        const Rates fast = speedsAt(*curve, t, side);
        const Rates full = rates(kinematicsAt(*curve, t, side));
        EXPECT_NEAR(fast[kLinearSpeed], full[kLinearSpeed], 1e-12 * (1.0 + full[kLinearSpeed])) << "t " << t;
        EXPECT_NEAR(fast[kAngularSpeed], full[kAngularSpeed], 1e-12 * (1.0 + full[kAngularSpeed])) << "t " << t;
      }
  }
}
