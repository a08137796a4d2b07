// libFuzzer target, the C^2 solve of `interpolating` (end_condition natural or clamped:
// solveC2Spline, the path-following Newton iteration of interpolating_spline.h) alone, in the
// double-geodesic and screw SE(3) and on S^2 ... S^4, with 2 ... 6 points: few enough that one
// input takes a fraction of a millisecond under ASan, enough for interior, first and last
// segments. The points are valid (unit quaternions, unit vectors; positions from [-8, 8) scaled
// by 10^-6 ... 10^6), the hostile parts are the configurations: repeated and antipodal points,
// rotations by about pi, very uneven or repeated times, clamped velocities with a normal
// component. Expected: an InterpolationError, or a curve through every point at its time (to
// 1e-9 in rotation and of the largest position) with finite values, velocities and
// accelerations that are continuous at the interior points (kContinuityTolerance,
// kQuadraticTolerance).
//
// Input format (fuzz_common.h's reader): a space byte, a count byte, the points, the times, an
// end-condition byte, the clamped velocities, a Newton-budget byte, then the evaluation times.
// test/fuzz/make_corpus.py writes the seeds (test/fuzz/corpus_c2/).
#include "fuzz_common.h"
#include "se3_interpolation/curves/interpolating_spline.h"
#include "se3_interpolation/analysis/kinematics.h"
#include "se3_interpolation/geometry/geometry.h"

using namespace se3_interpolation;
using namespace se3_interpolation::fuzz;

namespace
{
constexpr std::size_t kMaxPoints = 6;

/// The Newton budget of seven inputs in eight: three continuation steps (kIterationsPerStep
/// each), enough for the direct solves (about ten iterations), while the hard configurations
/// that would spend the default 400 (SplineSolverOptions) end in its ConvergenceError at a
/// tenth of the cost; the eighth input keeps the default, so long continuations are run too.
constexpr int kFuzzIterations = 48;

/// A tolerance for the solved spline: its residual bound is 1e-12 relative to the terms of the
/// C^2 system (SplineSolverOptions::tolerance); a thousand times that absorbs the rounding of
/// evaluating the curve at the points without hiding a wrong solution.
constexpr double kRelativeTolerance = 1e-9;

/// The continuity asked at interior points: the jump of the stacked state (velocity,
/// acceleration) within kContinuityTolerance of 1 + the size of both sides, plus
/// kQuadraticTolerance |velocity|^2. The second term is the rounding of the kinematics' terms
/// quadratic in the velocity (ω × v in the pose acceleration p̈, −|ẋ|² x on the sphere): a
/// rounding of ε |ξ| in the chart's angular velocity becomes ε |ξ| |v| in p̈ (a fuzz_c2 finding:
/// a screw step of 1e5 m in 1.25e-7 s, 8e11 m/s, whose p̈ jumped by 5.7e6 on 2.4e10, 0.04 ε |v|²,
/// while its chart state was continuous to rounding). 1e-13 is about 450 ε.
constexpr double kContinuityTolerance = 1e-6;
constexpr double kQuadraticTolerance = 1e-13;

/// A position: small, sometimes scaled by a power of ten (tiny and huge translations).
double coordinate(ByteReader& in)
{
  const double x = in.small();
  return in.byte() % 4 == 0 ? x * std::pow(10.0, static_cast<double>(in.range(-6, 6))) : x;
}

/// Times: increasing from a small start in steps of b/8 (b = 0 repeats a time), each step
/// sometimes scaled by a power of ten (very uneven intervals).
std::vector<double> times(ByteReader& in, std::size_t n)
{
  std::vector<double> t(n);
  t[0] = in.small();
  for (std::size_t i = 1; i < n; ++i)
  {
    double step = static_cast<double>(in.byte() % 32) / 8.0;
    if (in.byte() % 4 == 0)
      step *= std::pow(10.0, static_cast<double>(in.range(-6, 4)));
    t[i] = t[i - 1] + step;
  }
  return t;
}

struct Se3Data
{
  using Point = Pose<double>;
  using Tangent = Vector6<double>;

  static std::vector<Point> points(ByteReader& in, std::size_t n)
  {
    std::vector<Point> x;
    for (std::size_t i = 0; i < n; ++i)
    {
      // sometimes the previous position again (a pure rotation between the two)
      Eigen::Vector3d p;
      if (!x.empty() && in.byte() % 4 == 0)
        p = x.back().p;
      else
        for (int j = 0; j < 3; ++j)
          p[j] = coordinate(in);  // one at a time: the reads in order
      const Quaternion<double> q = unitQuaternion(in, x);
      x.emplace_back(q, p);
    }
    return x;
  }
  template <class G>
  static Tangent velocity(ByteReader& in, const Point& x)
  {
    Twist v;
    for (int j = 0; j < 3; ++j)
      v.linear[j] = in.small();
    for (int j = 0; j < 3; ++j)
      v.angular[j] = in.small();
    return velocityToTangent<G>(x, v);
  }
  /// The size the rounding of a position is relative to: 1 + the largest waypoint position (the
  /// curve reaches x_{i+1} as x_i Exp(L_i), rounded on the scale of both; a fuzz_c2 finding
  /// measured a miss of 1.9e-9 m at a waypoint at 0.3 m reached from one at 7.9e6 m, 2.4e-16 of
  /// the step, against the waypoint's own size).
  static double scale(const std::vector<Point>& x)
  {
    double largest = 0.0;
    for (const Point& p : x)
      largest = std::max(largest, p.p.norm());
    return 1.0 + largest;
  }
  static double distance(const Point& a, const Point& b, double scale)
  {
    const double rotation = std::min((a.q.coeffs() - b.q.coeffs()).norm(), (a.q.coeffs() + b.q.coeffs()).norm());
    return std::max(rotation, (a.p - b.p).norm() / scale);
  }
  /// Pose, velocity and acceleration stacked (position first), for the continuity check.
  template <class G>
  static Eigen::VectorXd state(const Curve<G>& curve, double t, Side side)
  {
    const Kinematics k = kinematicsAt(curve, t, side);
    checkPose(k.pose, "kinematics(t).pose");
    Eigen::VectorXd s(12);
    s << k.velocity.linear, k.velocity.angular, k.acceleration.linear, k.acceleration.angular;
    return s;
  }
};

struct SphereData
{
  using Point = Eigen::VectorXd;
  using Tangent = Eigen::VectorXd;

  static std::vector<Point> points(ByteReader& in, std::size_t n)
  {
    const Eigen::Index dim = 3 + in.byte() % 3;
    std::vector<Point> x;
    for (std::size_t i = 0; i < n; ++i)
    {
      const std::uint8_t mode = in.byte() % 8;
      if (mode == 0 && !x.empty())
      {
        x.push_back(-x.back());  // antipodal: no unique geodesic
        continue;
      }
      if (mode == 1 && !x.empty())
      {
        // the previous point turned by a tiny angle or one near pi
        static const double kAngles[] = { 1e-12, 1e-7, 3.141592653589793 - 1e-6, 3.141592653589793 - 1e-12 };
        const double a = kAngles[in.byte() % 4];
        Eigen::VectorXd u = Eigen::VectorXd::Zero(dim);
        u[in.byte() % dim] = 1.0;
        u -= u.dot(x.back()) * x.back();
        if (u.norm() > 0.5)
        {
          x.push_back(std::cos(a) * x.back() + std::sin(a) * u.normalized());
          continue;
        }
      }
      Eigen::VectorXd p(dim);
      for (Eigen::Index j = 0; j < dim; ++j)
        p[j] = in.small();
      if (!(p.norm() > 0.0))
        p[0] = 1.0;
      x.push_back(p.normalized());
    }
    return x;
  }
  template <class G>
  static Tangent velocity(ByteReader& in, const Point& x)
  {
    Eigen::VectorXd v(x.size());
    for (Eigen::Index j = 0; j < v.size(); ++j)
      v[j] = in.small();
    if (in.byte() % 8 != 0)
      v -= v.dot(x) * x;  // else a normal component: an InvalidInputError naming the velocity
    return v;
  }
  static double scale(const std::vector<Point>&) { return 1.0; }
  static double distance(const Point& a, const Point& b, double) { return (a - b).norm(); }
  static Eigen::VectorXd state(const Curve<Sphere>& curve, double t, Side side)
  {
    const SphereKinematics k = kinematicsAt(curve, t, side);
    if (!k.point.allFinite() || std::abs(k.point.norm() - 1.0) > 1e-9)
      fail("a point of the sphere spline is not a unit vector");
    Eigen::VectorXd s(2 * k.velocity.size());
    s << k.velocity, k.acceleration;
    return s;
  }
};

template <class G, class Space>
void solve(ByteReader& in)
{
  const std::size_t n = 2 + in.byte() % (kMaxPoints - 1);
  const std::vector<typename Space::Point> x = Space::points(in, n);
  const std::vector<double> t = times(in, n);
  const EndCondition condition = in.byte() % 2 == 0 ? EndCondition::kNatural : EndCondition::kClamped;
  const typename Space::Tangent v0 = Space::template velocity<G>(in, x.front());
  const typename Space::Tangent v1 = Space::template velocity<G>(in, x.back());
  SplineSolverOptions options;
  if (in.byte() % 8 != 0)
    options.max_iterations = kFuzzIterations;
  const std::shared_ptr<const ChartCubicSpline<G>> curve = solveC2Spline<G>(x, t, condition, v0, v1, options);
  if (!(curve->startTime() == t.front()) || !(curve->endTime() == t.back()))
    fail("the C2 spline's span is not [times.front(), times.back()]");
  const double scale = Space::scale(x);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!(Space::distance(curve->value(t[i]), x[i], scale) <= kRelativeTolerance))
      fail("the C2 spline misses waypoint " + std::to_string(i) + " at its time " + list(std::vector<double>{ t[i] }));
    const Eigen::VectorXd right = Space::state(*curve, t[i], Side::kRight);
    const Eigen::VectorXd left = Space::state(*curve, t[i], Side::kLeft);
    if (!right.allFinite() || !left.allFinite())
      fail("non-finite velocity or acceleration of the C2 spline at waypoint " + std::to_string(i));
    const Eigen::Index m = right.size() / 2;  // velocity first, then acceleration
    const double speed2 = std::max(right.head(m).squaredNorm(), left.head(m).squaredNorm());
    if (i > 0 && i + 1 < n &&
        !((right - left).norm() <=
          kContinuityTolerance * (1.0 + right.norm() + left.norm()) + kQuadraticTolerance * speed2))
      fail("the C2 spline's velocity or acceleration jumps at waypoint " + std::to_string(i) + ": left " +
           list(left) + ", right " + list(right));
  }
  const int evaluations = in.byte() % 4;
  for (int k = 0; k < evaluations; ++k)
  {
    const double u = static_cast<double>(in.byte()) / 255.0;
    const Eigen::VectorXd s = Space::state(*curve, t.front() + (t.back() - t.front()) * u, Side::kRight);
    if (!s.allFinite())
      fail("non-finite velocity or acceleration of the C2 spline inside its span");
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  g_target = "fuzz_c2";
  ByteReader in(data, size);
  try
  {
    switch (in.byte() % 3)
    {
      case 0:
        solve<DoubleGeodesicSe3, Se3Data>(in);
        break;
      case 1:
        solve<ScrewSe3, Se3Data>(in);
        break;
      default:
        solve<Sphere, SphereData>(in);
        break;
    }
  }
  catch (const InterpolationError&)
  {
    // The expected rejection: repeated times, antipodal points, a non-tangent velocity, or a
    // ConvergenceError where the solve has no solution it can follow.
  }
  catch (const std::exception& e)
  {
    fail(std::string("an exception other than InterpolationError escaped: ") + e.what());
  }
  return 0;
}
