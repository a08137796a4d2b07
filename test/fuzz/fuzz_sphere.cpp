// libFuzzer target, the sphere space S^m (m = 2 ... 4) end to end: bytes -> SphereRequest ->
// generate (sphere space: validation, curve, figures, timing, sampling) with up to 6 waypoints
// and 32 samples. Expected: an InterpolationError, or samples on the unit sphere with
// finite velocities and accelerations tangent to it. Input format: fuzz_common.h's reader.
#include "fuzz_common.h"
#include "se3_interpolation/planner/planner.h"

using namespace se3_interpolation;
using namespace se3_interpolation::fuzz;

namespace
{
/// Small limits (fuzz_common.h, "Speed"): the figures' quadrature and the samples dominate the
/// cost of an input, in proportion to the waypoints and the samples.
constexpr std::size_t kMaxWaypoints = 6;
constexpr std::size_t kMaxSamples = 32;

Eigen::VectorXd vectorX(ByteReader& in, Eigen::Index dim, bool normalise)
{
  Eigen::VectorXd v(dim);
  for (Eigen::Index j = 0; j < dim; ++j)
    v[j] = normalise ? in.small() : in.number();
  const double n = v.norm();
  if (normalise && n > 0.0)
    v /= n;
  return v;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  g_target = "fuzz_sphere";
  static const std::vector<const char*> kCurves = { "piecewise_geodesic", "bezier", "bspline",
                                                    "interpolating",      "hermite", "blended" };
  static const std::vector<const char*> kEndConditions = { "natural", "clamped", "start" };
  static const std::vector<const char*> kParameterizations = { "chord", "uniform", "centripetal" };
  ByteReader in(data, size);
  SphereRequest r;
  const Eigen::Index dim = 3 + in.byte() % 3;
  const std::size_t n = in.byte() % (kMaxWaypoints + 2);  // one more than the limit: its error
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint8_t mode = in.byte() % 8;
    if (mode == 0 && !r.waypoints.empty())
      r.waypoints.push_back(-r.waypoints.back());  // antipodal
    else if (mode == 1 && !r.waypoints.empty())
      r.waypoints.push_back(r.waypoints.back());  // repeated
    else if (mode == 2 && in.byte() % 4 == 0)
      r.waypoints.push_back(vectorX(in, dim + 1, true));  // mixed dimensions
    else
      r.waypoints.push_back(vectorX(in, dim, mode != 3));
  }
  r.curve = in.name(kCurves);
  r.end_condition = in.name(kEndConditions);
  r.parameterization = in.name(kParameterizations);
  if (in.byte() % 3 == 1)
    r.times = sequence(in, n);
  const std::uint8_t degree = in.byte();
  r.degree = degree % 10;
  if (in.byte() % 4 == 1)
    r.knots = sequence(in, n + static_cast<std::size_t>(r.degree) + 1);
  r.continuity = in.byte() % 10;
  if (in.byte() % 2 == 1)
    r.start_velocity = vectorX(in, dim, false);
  if (in.byte() % 2 == 1)
    r.end_velocity = vectorX(in, dim, false);
  if (in.byte() % 4 == 1)
    for (std::size_t i = 0; i < n; ++i)
      r.velocities.push_back(vectorX(in, dim, false));
  r.duration = in.optionalNumber();
  r.max_angular_velocity = in.optionalNumber();
  r.max_angular_acceleration = in.optionalNumber();
  r.sample_period = in.optionalNumber();
  r.sample_count = in.byte() % (kMaxSamples + 8);
  r.max_angular_jerk = in.optionalNumber();
  // Last, so that the seed corpus keeps its bytes: the timing (constant_speed is refused on the
  // sphere, naming timing) and the speed.
  r.timing = in.name({ "stretch", "time_optimal", "constant_speed" });
  r.speed = in.optionalNumber();
  // curve fit (refused on the sphere, naming curve) and its fields.
  const std::uint8_t fit = in.byte();
  if (fit % 8 == 7)
    r.curve = "fit";
  const double control_period = in.optionalNumber();
  const double smoothing = in.optionalNumber();
  const std::string loss = in.name({ "squared", "huber" });
  if (fit % 16 == 15)
  {
    r.control_period = control_period;
    r.smoothing = smoothing;
    r.loss = loss;
  }
  // sample_tolerance: for poses only, refused on the sphere when positive.
  r.sample_tolerance = in.optionalNumber();
  PlannerLimits limits;
  limits.max_samples = kMaxSamples;
  limits.max_waypoints = kMaxWaypoints;
  try
  {
    const SphereResult out = generate(r, limits);
    if (r.sample_tolerance > 0.0)
      fail("a sphere request with sample_tolerance > 0 is served");
    if (out.samples.empty() || out.samples.size() > limits.max_samples)
      fail("a successful sphere result has " + std::to_string(out.samples.size()) + " samples");
    for (const SphereSample& s : out.samples)
    {
      if (!s.point.allFinite() || std::abs(s.point.norm() - 1.0) > 1e-9)
        fail("a sample off the unit sphere");
      if (!s.velocity.allFinite() || !s.acceleration.allFinite())
        fail("a non-finite sample velocity or acceleration");
      if (std::abs(s.point.dot(s.velocity)) > 1e-6 * (1.0 + s.velocity.norm()))
        fail("a sample velocity not tangent to the sphere");
    }
    for (double f : { out.duration, out.figures.rotation_length, out.figures.max_angular_speed, out.figures.max_angular_acceleration, out.figures.energy })
      checkFinite(f, "sphere figures");
  }
  catch (const InterpolationError&)
  {
    // The expected rejection of a bad request.
  }
  catch (const std::exception& e)
  {
    fail(std::string("an exception other than InterpolationError escaped: ") + e.what());
  }
  return 0;
}
