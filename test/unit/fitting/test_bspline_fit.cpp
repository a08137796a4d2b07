// The least-squares B-spline fit (fitting/bspline_fit.h) against references independent of it:
// the classical least-squares spline solved densely from a Cox–de Boor basis written here,
// stationarity of the objective by finite differences, a known smooth truth under noise (the
// quality targets of docs/curves.md), outliers, quaternion signs, the smoothing's monotonicity, and
// every refusal.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/fitting/bspline_fit.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/math/quadrature.h"
#include "se3_interpolation/timing/jerk_limited.h"

namespace se3_interpolation
{
namespace
{
constexpr double kPi = 3.14159265358979323846;

// ---- References written here -----------------------------------------------------------------

/// N_{j,m}(t) by the Cox–de Boor recursion (right-continuous; the last knot interval closed).
double coxDeBoor(const std::vector<double>& u, std::size_t j, int m, double t)
{
  if (m == 0)
  {
    const double last = u.back();
    if (t == last)
      return (u[j] < t && u[j + 1] == t) ? 1.0 : 0.0;
    return (u[j] <= t && t < u[j + 1]) ? 1.0 : 0.0;
  }
  double v = 0.0;
  const double d1 = u[j + static_cast<std::size_t>(m)] - u[j];
  const double d2 = u[j + static_cast<std::size_t>(m) + 1] - u[j + 1];
  if (d1 > 0.0)
    v += (t - u[j]) / d1 * coxDeBoor(u, j, m - 1, t);
  if (d2 > 0.0)
    v += (u[j + static_cast<std::size_t>(m) + 1] - t) / d2 * coxDeBoor(u, j + 1, m - 1, t);
  return v;
}

/// A smooth truth with frequencies below 0.1 Hz: positions (m) and rotation vectors (rad).
Vector3<double> truthPosition(double t)
{
  return Vector3<double>(0.3 * std::sin(2 * kPi * 0.05 * t), 0.2 * std::cos(2 * kPi * 0.08 * t),
                         0.1 * std::sin(2 * kPi * 0.03 * t + 1.0));
}
Vector3<double> truthRotationVector(double t)
{
  return Vector3<double>(0.5 * std::sin(2 * kPi * 0.04 * t), 0.3 * std::cos(2 * kPi * 0.07 * t),
                         0.8 * std::sin(2 * kPi * 0.02 * t));
}
Pose<double> truthPose(double t)
{
  return Pose<double>(so3Exp(truthRotationVector(t)), truthPosition(t));
}
/// Linear and angular (world) velocity of the truth by central differences (h = 1e-5 s).
std::pair<Vector3<double>, Vector3<double>> truthVelocity(double t)
{
  const double h = 1e-5;
  const Pose<double> a = truthPose(t - h), b = truthPose(t + h);
  const Vector3<double> v = (b.p - a.p) / (2 * h);
  const Vector3<double> w = a.q.toRotationMatrix() * so3Log(Quaternion<double>(a.q.conjugate() * b.q)) / (2 * h);
  return { v, w };
}

struct Recording
{
  std::vector<Pose<double>> poses;
  std::vector<double> times;
};

/// 10 s at 100 Hz of the truth with noise σ_p per axis (m) and σ_r per rotation axis (rad).
Recording noisyRecording(double sigma_p, double sigma_r, unsigned seed, double duration = 10.0, double rate = 100.0)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Recording r;
  const int count = static_cast<int>(std::lround(duration * rate)) + 1;
  for (int i = 0; i < count; ++i)
  {
    const double t = i / rate;
    Pose<double> x = truthPose(t);
    x.p += sigma_p * Vector3<double>(n(rng), n(rng), n(rng));
    x.q = x.q * so3Exp(Vector3<double>(sigma_r * Vector3<double>(n(rng), n(rng), n(rng))));
    r.poses.push_back(x);
    r.times.push_back(t);
  }
  return r;
}

double angleBetween(const Quaternion<double>& a, const Quaternion<double>& b)
{
  return rotationAngle(Quaternion<double>(a.conjugate() * b));
}

template <class G>
BSplineCurve<G> curveOf(const BSplineFitResult& f)
{
  return BSplineCurve<G>(f.control, f.degree, f.knots, "control poses");
}

struct Errors
{
  double position = 0.0, rotation = 0.0, linear_velocity = 0.0, angular_velocity = 0.0;
};

/// RMS errors of the fitted curve against the truth at the recording's times.
template <class G>
Errors errorsToTruth(const BSplineFitResult& f, const std::vector<double>& times)
{
  const BSplineCurve<G> c = curveOf<G>(f);
  Errors e;
  for (double t : times)
  {
    const Kinematics k = kinematicsAt(c, t);
    const Pose<double> x = c.evaluate(t, Side::kRight);
    const Pose<double> truth = truthPose(t);
    const auto v = truthVelocity(t);
    e.position += (x.p - truth.p).squaredNorm();
    e.rotation += std::pow(angleBetween(x.q, truth.q), 2);
    e.linear_velocity += (k.velocity.linear - v.first).squaredNorm();
    e.angular_velocity += (k.velocity.angular - v.second).squaredNorm();
  }
  const double n = static_cast<double>(times.size());
  e.position = std::sqrt(e.position / n);
  e.rotation = std::sqrt(e.rotation / n);
  e.linear_velocity = std::sqrt(e.linear_velocity / n);
  e.angular_velocity = std::sqrt(e.angular_velocity / n);
  return e;
}

/// RMS of the recording's own errors to the truth.
Errors rawErrors(const Recording& r)
{
  Errors e;
  for (std::size_t i = 0; i < r.times.size(); ++i)
  {
    const Pose<double> truth = truthPose(r.times[i]);
    e.position += (r.poses[i].p - truth.p).squaredNorm();
    e.rotation += std::pow(angleBetween(r.poses[i].q, truth.q), 2);
  }
  const double n = static_cast<double>(r.times.size());
  e.position = std::sqrt(e.position / n);
  e.rotation = std::sqrt(e.rotation / n);
  return e;
}

/// ∫ |p⃛|² and ∫ |ω̈|² of a curve by 16 Gauss points per knot interval (Jet<3> derivatives).
template <class G>
std::pair<double, double> jerkIntegrals(const BSplineFitResult& f)
{
  const BSplineCurve<G> c = curveOf<G>(f);
  const std::vector<double> b = c.breakpoints();
  double lin = 0.0, ang = 0.0;
  for (std::size_t s = 0; s + 1 < b.size(); ++s)
    for (int g = 0; g < 16; ++g)
    {
      // Midpoint rule on 16 sub-intervals: the comparison needs the same rule at every λ only.
      const double t = b[s] + (b[s + 1] - b[s]) * (g + 0.5) / 16.0;
      const timing::Kinematics3 k = timing::kinematics3FromJet(jet3Of<G>(c, Jet<3>::variable(t), Side::kRight));
      const double w = (b[s + 1] - b[s]) / 16.0;
      lin += w * k.jerk.linear.squaredNorm();
      ang += w * k.jerk.angular.squaredNorm();
    }
  return { lin, ang };
}

// ---- The translation is the classical least-squares spline ----------------------------------

TEST(BSplineFit, DoubleGeodesicTranslationIsTheClassicalLeastSquaresSpline)
{
  // Uneven times (ratios up to 10³ between steps) and every degree.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<double> times;
  double t = 0.0;
  for (int i = 0; i < 120; ++i)
  {
    times.push_back(t);
    t += (i % 7 == 3) ? 0.001 : (i % 11 == 5 ? 1.0 : 0.05 + 0.05 * (uni(rng) + 1.0));
  }
  std::vector<Pose<double>> poses;
  for (std::size_t i = 0; i < times.size(); ++i)
    poses.emplace_back(so3Exp(Vector3<double>(0.3 * uni(rng), 0.3 * uni(rng), 0.3 * uni(rng))),
                       Vector3<double>(uni(rng), uni(rng), uni(rng)));
  for (int degree = 1; degree <= kMaxFitDegree; ++degree)
  {
    FitOptions o;
    o.degree = degree;
    o.control_period = 1.5;
    const BSplineFitResult f = fitBSpline<DoubleGeodesicSe3>(poses, times, o);
    // Dense normal equations of the classical problem from the Cox–de Boor basis.
    const std::size_t n = f.control.size();
    Eigen::MatrixXd a(times.size(), n);
    for (std::size_t i = 0; i < times.size(); ++i)
      for (std::size_t j = 0; j < n; ++j)
        a(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = coxDeBoor(f.knots, j, degree, times[i]);
    Eigen::MatrixXd y(times.size(), 3);
    for (std::size_t i = 0; i < times.size(); ++i)
      y.row(static_cast<Eigen::Index>(i)) = poses[i].p.transpose();
    const Eigen::MatrixXd expected = a.colPivHouseholderQr().solve(y);
    for (std::size_t j = 0; j < n; ++j)
      EXPECT_LT((f.control[j].p - expected.row(static_cast<Eigen::Index>(j)).transpose()).norm(), 1e-9)
          << "degree " << degree << ", control " << j;
    // The knots: clamped, uniform, M = ⌈T / control_period⌉ intervals.
    const std::size_t intervals = static_cast<std::size_t>(std::ceil((times.back() - times.front()) / 1.5 - 1e-9));
    EXPECT_EQ(n, intervals + static_cast<std::size_t>(degree));
    EXPECT_EQ(f.knots, clampedUniformKnots(n, degree, times.front(), times.back()));
  }
}

// ---- Exact data is recovered; the optimum is stationary -------------------------------------

template <class G>
void expectRecoversItsOwnSpline()
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<Pose<double>> control;
  for (int j = 0; j < 9; ++j)
    control.emplace_back(so3Exp(Vector3<double>(0.8 * uni(rng), 0.8 * uni(rng), 0.8 * uni(rng))),
                         Vector3<double>(uni(rng), uni(rng), uni(rng)));
  const std::vector<double> knots = clampedUniformKnots(control.size(), 3, 0.0, 3.0);
  const BSplineCurve<G> truth(control, 3, knots);
  Recording r;
  for (int i = 0; i <= 300; ++i)
  {
    r.times.push_back(i * 0.01);
    Pose<double> x = truth.evaluate(i * 0.01, Side::kRight);
    if (i % 3 == 0)
      x.q.coeffs() = -x.q.coeffs();  // the other sign of the same rotation
    r.poses.push_back(x);
  }
  FitOptions o;
  o.control_period = 0.5;
  const BSplineFitResult f = fitBSpline<G>(r.poses, r.times, o);
  ASSERT_EQ(f.control.size(), control.size());
  EXPECT_LT(f.residual_linear, 1e-10);
  EXPECT_LT(f.residual_angular, 1e-10);
  for (std::size_t j = 0; j < control.size(); ++j)
  {
    EXPECT_LT((f.control[j].p - control[j].p).norm(), 1e-8) << j;
    EXPECT_LT(angleBetween(f.control[j].q, control[j].q), 1e-8) << j;
  }
}

TEST(BSplineFit, RecoversItsOwnSplineDoubleGeodesic) { expectRecoversItsOwnSpline<DoubleGeodesicSe3>(); }
TEST(BSplineFit, RecoversItsOwnSplineScrew) { expectRecoversItsOwnSpline<ScrewSe3>(); }

/// The objective E of bspline_fit.h written here from the curve (the jerk by the same 4-point
/// Gauss rule per knot interval as the fit, of the exact Jet<3> derivatives).
template <class G>
double objectiveOf(const std::vector<Pose<double>>& control, const BSplineFitResult& f, const Recording& r,
                   const FitOptions& o)
{
  const BSplineCurve<G> c(control, f.degree, f.knots, "control poses");
  double sum = 0.0;
  for (std::size_t i = 0; i < r.times.size(); ++i)
  {
    const Pose<double> x = c.evaluate(r.times[i], Side::kRight);
    const double s = (x.p - r.poses[i].p).squaredNorm() +
                     std::pow(o.rotation_scale * angleBetween(x.q, r.poses[i].q), 2);
    const double d = o.loss_scale;
    sum += o.loss == FitLoss::kHuber && s > d * d ? 2 * d * std::sqrt(s) - d * d : s;
  }
  double jerk = 0.0;
  const std::vector<double> b = c.breakpoints();
  for (std::size_t s = 0; s + 1 < b.size() && o.smoothing > 0.0; ++s)
    for (std::size_t g = 0; g < kGauss4Nodes.size(); ++g)
    {
      const double half = 0.5 * (b[s + 1] - b[s]);
      const double t = 0.5 * (b[s] + b[s + 1]) + half * kGauss4Nodes[g];
      const timing::Kinematics3 k = timing::kinematics3FromJet(jet3Of<G>(c, Jet<3>::variable(t), Side::kRight));
      jerk += half * kGauss4Weights[g] *
              (k.jerk.linear.squaredNorm() + std::pow(o.rotation_scale, 2) * k.jerk.angular.squaredNorm());
    }
  return sum / static_cast<double>(r.times.size()) + o.smoothing * jerk;
}

/// At the fit, E does not decrease along any control pose's tangent directions (central
/// differences of E written here): the fit is a minimum of the objective it claims, whatever
/// its Jacobians.
template <class G>
void expectStationary(const FitOptions& o, unsigned seed)
{
  Recording r = noisyRecording(0.001, 0.5 * kPi / 180.0, seed, 3.0, 50.0);
  if (o.loss == FitLoss::kHuber)
    for (std::size_t i = 5; i < r.poses.size(); i += 37)
      r.poses[i].p.x() += 0.1;
  const BSplineFitResult f = fitBSpline<G>(r.poses, r.times, o);
  const double e0 = objectiveOf<G>(f.control, f, r, o);
  EXPECT_NEAR(f.objective, e0, 1e-9 * e0);
  const double h = 1e-5;
  double worst = 0.0, scale = 0.0;
  for (std::size_t j = 0; j < f.control.size(); j += 3)
    for (int x = 0; x < 6; ++x)
    {
      Vector6<double> d = Vector6<double>::Zero();
      d[x] = h;
      std::vector<Pose<double>> plus = f.control, minus = f.control;
      plus[j] = G::exp(f.control[j], d);
      minus[j] = G::exp(f.control[j], Vector6<double>(-d));
      const double ep = objectiveOf<G>(plus, f, r, o), em = objectiveOf<G>(minus, f, r, o);
      worst = std::max(worst, std::abs(ep - em) / (2 * h));
      scale = std::max(scale, std::abs(ep - e0) / h + (ep + em - 2 * e0) / (h * h) * 1e-3);
      EXPECT_GE(std::min(ep, em), e0 - 1e-12 * e0) << "control " << j << " direction " << x;
    }
  // The gradient is at the noise of the differences, far below the curvature's scale.
  EXPECT_LT(worst, 1e-6 * std::max(1.0, scale) + 1e-8) << "gradient " << worst;
}

TEST(BSplineFit, TheFitIsStationary)
{
  FitOptions o;
  o.control_period = 0.3;
  expectStationary<DoubleGeodesicSe3>(o, 1);
  expectStationary<ScrewSe3>(o, 2);
  o.smoothing = 1e-4;
  expectStationary<DoubleGeodesicSe3>(o, 3);
  expectStationary<ScrewSe3>(o, 4);
  o.smoothing = 0.0;
  o.loss = FitLoss::kHuber;
  o.loss_scale = 0.02;
  expectStationary<DoubleGeodesicSe3>(o, 5);
  expectStationary<ScrewSe3>(o, 6);
}

// ---- Quality on a noisy recording of a known truth -------------------------------------------

TEST(BSplineFit, NoiseIsReducedDoubleGeodesic)
{
  const Recording r = noisyRecording(0.001, 0.5 * kPi / 180.0, 21);
  FitOptions o;
  o.control_period = 0.25;
  const BSplineFitResult f = fitBSpline<DoubleGeodesicSe3>(r.poses, r.times, o);
  const Errors raw = rawErrors(r);
  const Errors e = errorsToTruth<DoubleGeodesicSe3>(f, r.times);
  EXPECT_LE(e.position, 0.4 * raw.position) << e.position << " vs raw " << raw.position;
  EXPECT_LE(e.rotation, 0.4 * raw.rotation) << e.rotation << " vs raw " << raw.rotation;
  double peak_linear = 0.0, peak_angular = 0.0;
  for (double t : r.times)
  {
    peak_linear = std::max(peak_linear, truthVelocity(t).first.norm());
    peak_angular = std::max(peak_angular, truthVelocity(t).second.norm());
  }
  EXPECT_LE(e.linear_velocity, 0.05 * peak_linear);
  // The angular velocity of this slow rotation (peak 0.18 rad/s) is below the 0.5° noise's
  // derivative without smoothing (measured 17 % of the peak); a little smoothing brings it in.
  FitOptions smooth = o;
  smooth.smoothing = 1e-5;
  const Errors s = errorsToTruth<DoubleGeodesicSe3>(fitBSpline<DoubleGeodesicSe3>(r.poses, r.times, smooth), r.times);
  EXPECT_LE(s.angular_velocity, 0.05 * peak_angular) << s.angular_velocity;
  EXPECT_LE(s.linear_velocity, 0.05 * peak_linear);
  EXPECT_LE(s.position, 0.4 * raw.position);
  EXPECT_LE(s.rotation, 0.4 * raw.rotation);
  // The reported residuals are those of the noise (RMS over the recording).
  EXPECT_NEAR(f.residual_linear, raw.position, 0.15 * raw.position);
  EXPECT_NEAR(f.residual_angular, raw.rotation, 0.15 * raw.rotation);
  std::cout << "double geodesic: position " << e.position / raw.position << ", rotation "
            << e.rotation / raw.rotation << " of the raw noise; velocity " << e.linear_velocity / peak_linear
            << ", angular " << e.angular_velocity / peak_angular << " of the peak; " << f.iterations
            << " LM steps\n";
}

TEST(BSplineFit, NoiseIsReducedScrew)
{
  const Recording r = noisyRecording(0.001, 0.5 * kPi / 180.0, 22);
  FitOptions o;
  o.control_period = 0.25;
  const BSplineFitResult f = fitBSpline<ScrewSe3>(r.poses, r.times, o);
  const Errors raw = rawErrors(r);
  const Errors e = errorsToTruth<ScrewSe3>(f, r.times);
  EXPECT_LE(e.position, 0.5 * raw.position) << e.position << " vs raw " << raw.position;
  EXPECT_LE(e.rotation, 0.5 * raw.rotation) << e.rotation << " vs raw " << raw.rotation;
  double peak_linear = 0.0;
  for (double t : r.times)
    peak_linear = std::max(peak_linear, truthVelocity(t).first.norm());
  EXPECT_LE(e.linear_velocity, 0.05 * peak_linear);
  std::cout << "screw: position " << e.position / raw.position << ", rotation " << e.rotation / raw.rotation
            << " of the raw noise; " << f.iterations << " LM steps\n";
}

TEST(BSplineFit, HuberResistsOutliers)
{
  Recording r = noisyRecording(0.001, 0.5 * kPi / 180.0, 23);
  std::mt19937 rng(5);
  std::uniform_int_distribution<std::size_t> pick(0, r.poses.size() - 1);
  std::uniform_real_distribution<double> dir(-1.0, 1.0);
  Recording clean = r;
  for (int k = 0; k < static_cast<int>(r.poses.size()) / 100; ++k)
  {
    const Vector3<double> d = Vector3<double>(dir(rng), dir(rng), dir(rng)).normalized();
    r.poses[pick(rng)].p += 0.1 * d;
  }
  const Errors raw = rawErrors(clean);
  FitOptions o;
  o.control_period = 0.25;
  o.rotation_scale = 0.1;
  o.loss = FitLoss::kHuber;
  o.loss_scale = 0.003;
  for (int g = 0; g < 2; ++g)
  {
    const BSplineFitResult f = g == 0 ? fitBSpline<DoubleGeodesicSe3>(r.poses, r.times, o)
                                      : fitBSpline<ScrewSe3>(r.poses, r.times, o);
    const Errors e = g == 0 ? errorsToTruth<DoubleGeodesicSe3>(f, r.times) : errorsToTruth<ScrewSe3>(f, r.times);
    EXPECT_LE(e.position, 0.6 * raw.position) << (g == 0 ? "double geodesic " : "screw ") << e.position;
    std::cout << (g == 0 ? "double geodesic" : "screw") << " huber: position " << e.position / raw.position
              << " of the raw noise\n";
  }
  // Least squares does not resist them (the test can tell the two apart).
  o.loss = FitLoss::kSquared;
  const Errors e = errorsToTruth<DoubleGeodesicSe3>(fitBSpline<DoubleGeodesicSe3>(r.poses, r.times, o), r.times);
  EXPECT_GT(e.position, 0.6 * raw.position);
}

TEST(BSplineFit, QuaternionSignsChangeNothing)
{
  const Recording r = noisyRecording(0.001, 0.5 * kPi / 180.0, 24, 3.0, 50.0);
  Recording flipped = r;
  for (std::size_t i = 0; i < flipped.poses.size(); i += 2)
    flipped.poses[i].q.coeffs() = -flipped.poses[i].q.coeffs();
  FitOptions o;
  o.control_period = 0.3;
  o.smoothing = 1e-5;
  for (int g = 0; g < 2; ++g)
  {
    const BSplineFitResult a = g == 0 ? fitBSpline<DoubleGeodesicSe3>(r.poses, r.times, o)
                                      : fitBSpline<ScrewSe3>(r.poses, r.times, o);
    const BSplineFitResult b = g == 0 ? fitBSpline<DoubleGeodesicSe3>(flipped.poses, flipped.times, o)
                                      : fitBSpline<ScrewSe3>(flipped.poses, flipped.times, o);
    ASSERT_EQ(a.control.size(), b.control.size());
    for (std::size_t j = 0; j < a.control.size(); ++j)
    {
      EXPECT_LT((a.control[j].p - b.control[j].p).norm(), 1e-10);
      EXPECT_LT(angleBetween(a.control[j].q, b.control[j].q), 1e-10);
    }
    EXPECT_NEAR(a.residual_linear, b.residual_linear, 1e-12);
    EXPECT_NEAR(a.residual_angular, b.residual_angular, 1e-12);
  }
}

TEST(BSplineFit, MoreSmoothingNeverFitsCloserNorJerksMore)
{
  const Recording r = noisyRecording(0.002, 1.0 * kPi / 180.0, 25, 4.0, 50.0);
  FitOptions o;
  o.control_period = 0.1;
  for (int g = 0; g < 2; ++g)
  {
    double last_residual = -1.0, last_jerk = std::numeric_limits<double>::infinity();
    double last_linear = -1.0, last_linear_jerk = std::numeric_limits<double>::infinity();
    for (double lambda : { 0.0, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3 })
    {
      o.smoothing = lambda;
      const BSplineFitResult f = g == 0 ? fitBSpline<DoubleGeodesicSe3>(r.poses, r.times, o)
                                        : fitBSpline<ScrewSe3>(r.poses, r.times, o);
      const auto jerk = g == 0 ? jerkIntegrals<DoubleGeodesicSe3>(f) : jerkIntegrals<ScrewSe3>(f);
      const double residual = std::pow(f.residual_linear, 2) + std::pow(o.rotation_scale * f.residual_angular, 2);
      const double total_jerk = jerk.first + o.rotation_scale * o.rotation_scale * jerk.second;
      if (g == 0)
      {
        // The double geodesic's translation alone is linear least squares: exactly monotone.
        EXPECT_GE(f.residual_linear, last_linear * (1 - 1e-12)) << "lambda " << lambda;
        EXPECT_LE(jerk.first, last_linear_jerk * (1 + 1e-12)) << "lambda " << lambda;
        last_linear = f.residual_linear;
        last_linear_jerk = jerk.first;
      }
      EXPECT_GE(residual, last_residual * (1 - 1e-6)) << "geometry " << g << ", lambda " << lambda;
      EXPECT_LE(total_jerk, last_jerk * (1 + 1e-6)) << "geometry " << g << ", lambda " << lambda;
      last_residual = residual;
      last_jerk = total_jerk;
    }
  }
}

// ---- Refusals --------------------------------------------------------------------------------

void expectRefused(const std::vector<Pose<double>>& poses, const std::vector<double>& times, const FitOptions& o,
                   const std::string& field, const std::string& detail = "")
{
  try
  {
    fitBSpline<DoubleGeodesicSe3>(poses, times, o);
    ADD_FAILURE() << "accepted; expected a refusal naming " << field;
  }
  catch (const InvalidInputError& e)
  {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(field, 0), 0u) << what;
    EXPECT_NE(what.find(detail), std::string::npos) << what;
  }
}

TEST(BSplineFit, RefusesWhatItCannotFit)
{
  const Recording r = noisyRecording(0.001, 0.01, 26, 2.0, 50.0);
  FitOptions o;
  o.control_period = 0.0;
  expectRefused(r.poses, r.times, o, "control_period");
  o.control_period = -1.0;
  expectRefused(r.poses, r.times, o, "control_period");
  o.control_period = 1e-300;
  expectRefused(r.poses, r.times, o, "control_period", "at most one per waypoint");
  o.control_period = 0.25;
  o.smoothing = -1.0;
  expectRefused(r.poses, r.times, o, "smoothing");
  o.smoothing = 1.0;
  o.degree = 2;
  expectRefused(r.poses, r.times, o, "smoothing", "degree");
  o.degree = 3;
  o.smoothing = 0.0;
  o.loss = FitLoss::kHuber;
  expectRefused(r.poses, r.times, o, "loss_scale");
  o.loss = FitLoss::kSquared;
  o.degree = kMaxFitDegree + 1;
  expectRefused(r.poses, r.times, o, "degree");
  o.degree = 3;
  expectRefused(r.poses, std::vector<double>(r.times.begin(), r.times.end() - 1), o, "times");
  std::vector<double> backwards = r.times;
  std::swap(backwards[4], backwards[5]);
  expectRefused(r.poses, backwards, o, "times[5]");

  // A gap in the recording from 0.8 s to 1.6 s leaves control poses undetermined without
  // smoothing; the message names the gap's time. With smoothing the fit bridges it.
  Recording gap;
  for (std::size_t i = 0; i < r.times.size(); ++i)
    if (r.times[i] < 0.8 || r.times[i] > 1.6)
    {
      gap.times.push_back(r.times[i]);
      gap.poses.push_back(r.poses[i]);
    }
  o.control_period = 0.2;
  expectRefused(gap.poses, gap.times, o, "control_period", "t = 1");
  o.smoothing = 1e-6;
  EXPECT_NO_THROW(fitBSpline<DoubleGeodesicSe3>(gap.poses, gap.times, o));
  EXPECT_NO_THROW(fitBSpline<ScrewSe3>(gap.poses, gap.times, o));

  // A recording that turns half a turn between two knots: neighbouring control poses would be half
  // a turn apart (no unique geodesic): refused naming control_period, in both geometries.
  const std::vector<Pose<double>> flip = { Pose<double>(),
                                           Pose<double>(so3Exp(Vector3<double>(0.0, 0.0, kPi)), Vector3<double>(1, 0, 0)),
                                           Pose<double>(Quaternion<double>::Identity(), Vector3<double>(2, 0, 0)) };
  FitOptions linear;
  linear.degree = 1;
  linear.control_period = 1.0;
  expectRefused(flip, { 0.0, 1.0, 2.0 }, linear, "control_period", "half a turn");
  try
  {
    fitBSpline<ScrewSe3>(flip, { 0.0, 1.0, 2.0 }, linear);
    ADD_FAILURE() << "the screw fit of a half turn was accepted";
  }
  catch (const InvalidInputError& e)
  {
    EXPECT_EQ(std::string(e.what()).rfind("control_period:", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace se3_interpolation
