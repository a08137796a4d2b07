#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "se3_interpolation/curves/bspline.h"
#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
namespace
{
using se3_interpolation::requireFinite;  // the scalar overload, beside the vector ones below

std::string indexed(const std::string& field, std::size_t i)
{
  return indexedField(field, i);
}

std::string number(double x)
{
  return formatNumber(x);
}

/// A step of at least 1 ns keeps rounded nanoseconds distinct; the margin absorbs the
/// rounding of t0 + (t1 - t0) i / (n - 1) near 1 ns spacing.
constexpr double kResolvableStep = kRosDurationResolution * (1.0 - 1e-6);

/// Generated sample times: each after the previous by at least 1 ns.
void requireResolvable(const std::vector<double>& ts, const std::string& field)
{
  for (std::size_t i = 1; i < ts.size(); ++i)
    if (!(ts[i] - ts[i - 1] >= kResolvableStep))
      throw InvalidInputError(field + ": samples " + std::to_string(i - 1) + " and " + std::to_string(i) + " are " +
                              number(ts[i] - ts[i - 1]) + " s apart, below the 1 ns resolution of time_from_start" +
                              " (fewer samples or a longer duration)");
}

void requireFinite(const Eigen::Vector3d& v, const std::string& field)
{
  static const char* kAxis[] = { ".x", ".y", ".z" };
  for (int i = 0; i < 3; ++i)
    requireFinite(v[i], field + kAxis[i]);
}

void requireFinite(const Twist& t, const std::string& field)
{
  requireFinite(t.linear, field + ".linear");
  requireFinite(t.angular, field + ".angular");
}

Quaternion<double> validQuaternion(const Quaternion<double>& q, const std::string& field)
{
  const double c[] = { q.x(), q.y(), q.z(), q.w() };
  static const char* kName[] = { ".x", ".y", ".z", ".w" };
  for (int i = 0; i < 4; ++i)
    requireFinite(c[i], field + kName[i]);
  const double n = std::sqrt(q.coeffs().squaredNorm());
  if (!(n >= 0.99 && n <= 1.01))
    throw InvalidInputError(field + ": quaternion norm " + number(n) +
                            " is outside [0.99, 1.01] (expected a unit quaternion x, y, z, w)");
  return Quaternion<double>(q.coeffs() / n);
}

template <class E>
E parseName(const std::string& value, const std::string& field, const std::vector<std::pair<const char*, E>>& names,
            E default_value)
{
  if (value.empty())
    return default_value;
  std::string known;
  for (const auto& n : names)
  {
    if (value == n.first)
      return n.second;
    known += (known.empty() ? "" : ", ") + std::string(n.first);
  }
  throw InvalidInputError(field + ": unknown value '" + value + "' (expected one of: " + known + ")");
}

const std::vector<std::pair<const char*, CurveType>> kCurves = {
  { "piecewise_geodesic", CurveType::kPiecewiseGeodesic },
  { "bezier", CurveType::kBezier },
  { "bspline", CurveType::kBspline },
  { "interpolating", CurveType::kInterpolating },
  { "hermite", CurveType::kHermite },
  { "blended", CurveType::kBlended },
};
const std::vector<std::pair<const char*, GeometryType>> kGeometries = {
  { "double_geodesic", GeometryType::kDoubleGeodesic },
  { "screw", GeometryType::kScrew },
};
const std::vector<std::pair<const char*, Timing>> kTimings = {
  { "stretch", Timing::kStretch },
  { "time_optimal", Timing::kTimeOptimal },
};
}  // namespace

const char* toString(Timing t)
{
  for (const auto& n : kTimings)
    if (n.second == t)
      return n.first;
  return "";
}

Timing parseTiming(const std::string& name)
{
  return parseName(name, "timing", kTimings, Timing::kStretch);
}

const char* toString(CurveType c)
{
  for (const auto& n : kCurves)
    if (n.second == c)
      return n.first;
  return "";
}

const char* toString(GeometryType g)
{
  for (const auto& n : kGeometries)
    if (n.second == g)
      return n.first;
  return "";
}

Pose<double> validatePose(const Pose<double>& raw, const std::string& field)
{
  requireFinite(raw.p, field + ".position");
  return Pose<double>(validQuaternion(raw.q, field + ".orientation"), raw.p);
}

ValidatedRequest validateRequest(const TrajectoryRequest& r, const PlannerLimits& limits)
{
  ValidatedRequest v;
  const std::size_t n = r.waypoints.size();
  if (n < 2)
    throw InvalidInputError("waypoints: " + std::to_string(n) + " given; at least 2 are needed");
  if (n > limits.max_waypoints)
    throw LimitExceededError("waypoints: " + std::to_string(n) + " given; the limit (~max_waypoints) is " +
                             std::to_string(limits.max_waypoints));
  v.waypoints.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    v.waypoints.push_back(validatePose(r.waypoints[i], indexed("waypoints", i)));
  }

  v.curve = parseName(r.curve, "curve", kCurves, CurveType::kInterpolating);
  v.geometry = parseName(r.geometry, "geometry", kGeometries, GeometryType::kDoubleGeodesic);
  v.end_condition = parseName(r.end_condition, "end_condition",
                              { { "natural", EndCondition::kNatural },
                                { "clamped", EndCondition::kClamped },
                                { "start", EndCondition::kStart } },
                              EndCondition::kNatural);
  v.parameterization = parseName(r.parameterization, "parameterization",
                                 { { "chord", Parameterization::kChord },
                                   { "uniform", Parameterization::kUniform },
                                   { "centripetal", Parameterization::kCentripetal } },
                                 Parameterization::kChord);

  validateTimes(r.times, n);
  if (!r.times.empty())
  {
    v.times = r.times;
  }
  else
  {
    for (std::size_t i = 0; i + 1 < n; ++i)
      if (r.waypoints[i].p == r.waypoints[i + 1].p && v.waypoints[i].q.angularDistance(v.waypoints[i + 1].q) == 0.0)
        throw InvalidInputError(indexed("waypoints", i) + " and " + indexed("waypoints", i + 1) +
                                ": identical consecutive waypoints need explicit times (to dwell)");
  }

  // Exactly antipodal rotations: the geodesic joining two consecutive points is not unique.
  for (std::size_t i = 0; i + 1 < n; ++i)
    if (std::abs(v.waypoints[i].q.coeffs().dot(v.waypoints[i + 1].q.coeffs())) <= kAntipodalTolerance)
      throw NonUniqueGeodesicError(indexed("waypoints", i) + " and " + indexed("waypoints", i + 1) +
                                   ": the relative rotation is exactly pi, so the geodesic between them is not unique");

  if (r.degree < 0)
    throw InvalidInputError("degree: " + std::to_string(r.degree) + " must be >= 1");
  const int max_degree = static_cast<int>(n) - 1;
  v.degree = r.degree == 0 ? std::min(3, max_degree) : r.degree;
  if (v.curve == CurveType::kBspline && v.degree > max_degree)
    throw InvalidInputError("degree: " + std::to_string(v.degree) + " is too high for " + std::to_string(n) +
                            " waypoints (at most " + std::to_string(max_degree) + ")");
  if (!r.knots.empty())
  {
    if (v.curve != CurveType::kBspline)
      throw InvalidInputError("knots: only used by curve 'bspline' (curve is '" +
                              std::string(toString(v.curve)) + "')");
    validateKnots(r.knots, n, v.degree);
    for (std::size_t i = 0; i < r.knots.size(); ++i)
      requireRosDuration(r.knots[i], indexed("knots", i));
    v.knots = r.knots;
  }
  if (r.continuity < 0 || r.continuity > 8)
    throw InvalidInputError("continuity: " + std::to_string(r.continuity) + " is outside 1 ... 8");
  v.continuity = r.continuity == 0 ? 2 : r.continuity;

  requireFinite(r.start_velocity, "start_velocity");
  requireFinite(r.end_velocity, "end_velocity");
  requireFinite(r.start_acceleration, "start_acceleration");
  v.start_velocity = r.start_velocity;
  v.end_velocity = r.end_velocity;
  v.start_acceleration = r.start_acceleration;
  if (!r.velocities.empty() && r.velocities.size() != n)
    throw InvalidInputError("velocities: " + std::to_string(r.velocities.size()) + " given for " + std::to_string(n) +
                            " waypoints (give one per waypoint, or none)");
  for (std::size_t i = 0; i < r.velocities.size(); ++i)
    requireFinite(r.velocities[i], indexed("velocities", i));
  v.velocities = r.velocities;

  requireFiniteNonNegative(r.rotation_scale, "rotation_scale");
  v.rotation_scale = r.rotation_scale == 0.0 ? 1.0 : r.rotation_scale;
  requireFiniteNonNegative(r.duration, "duration");
  requireRosDuration(r.duration, "duration");
  v.duration = r.duration;
  requireFiniteNonNegative(r.max_linear_velocity, "max_linear_velocity");
  requireFiniteNonNegative(r.max_angular_velocity, "max_angular_velocity");
  requireFiniteNonNegative(r.max_linear_acceleration, "max_linear_acceleration");
  requireFiniteNonNegative(r.max_angular_acceleration, "max_angular_acceleration");
  v.max_linear_velocity = r.max_linear_velocity;
  v.max_angular_velocity = r.max_angular_velocity;
  v.max_linear_acceleration = r.max_linear_acceleration;
  v.max_angular_acceleration = r.max_angular_acceleration;
  v.timing = parseTiming(r.timing);

  requireFiniteNonNegative(r.blend_radius, "blend_radius");
  if (r.blend_radius > 0.0 && v.curve != CurveType::kPiecewiseGeodesic)
    throw InvalidInputError("blend_radius: only used by curve 'piecewise_geodesic' (curve is '" +
                            std::string(toString(v.curve)) + "')");
  v.blend_radius = r.blend_radius;

  const Sampling sampling = validateSampling(r.sample_times, r.sample_period, r.sample_count, limits);
  v.sample_times = sampling.sample_times;
  v.sample_period = sampling.sample_period;
  v.sample_count = sampling.sample_count;
  return v;
}

std::string indexedField(const std::string& field, std::size_t i)
{
  return field + "[" + std::to_string(i) + "]";
}

std::string formatNumber(double x)
{
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

void requireFinite(double x, const std::string& field)
{
  if (!std::isfinite(x))
    throw InvalidInputError(field + ": " + formatNumber(x) + " is not a finite number");
}

void requireFiniteNonNegative(double x, const std::string& field)
{
  requireFinite(x, field);
  if (x < 0.0)
    throw InvalidInputError(field + ": " + formatNumber(x) + " must be >= 0");
}

void requireRosDuration(double t, const std::string& field)
{
  if (!(std::abs(t) <= kRosDurationMaxSeconds))
    throw InvalidInputError(field + ": " + formatNumber(t) + " s is outside ROS's duration range (|t| <= " +
                            formatNumber(kRosDurationMaxSeconds) + " s, signed 32-bit seconds)");
}

void validateTimeSpan(double start_time, double end_time, const std::string& cause)
{
  for (double t : { start_time, end_time })
    if (!(std::abs(t) <= kRosDurationMaxSeconds))
      throw InvalidInputError(cause + ": the trajectory would span [" + formatNumber(start_time) + ", " +
                              formatNumber(end_time) + "] s, beyond ROS's duration range (|t| <= " +
                              formatNumber(kRosDurationMaxSeconds) + " s)");
}

void validateStampedSpan(double stamp, double start_time, double end_time, const std::string& stamp_field)
{
  if (!(stamp >= 0.0 && stamp <= kRosTimeMaxSeconds))
    throw InvalidInputError(stamp_field + ": " + formatNumber(stamp) + " s is not a ROS time");
  if (!(stamp + start_time >= 0.0))
    throw InvalidInputError(stamp_field + ": the trajectory would start at " + formatNumber(stamp + start_time) +
                            " s, before time 0 (stamp + the first time < 0)");
  if (!(stamp + end_time <= kRosTimeMaxSeconds))
    throw InvalidInputError(stamp_field + ": the trajectory would end at " + formatNumber(stamp + end_time) +
                            " s, after the last ROS time " + formatNumber(kRosTimeMaxSeconds) +
                            " s (unsigned 32-bit seconds)");
}

std::string quoted(const std::string& text)
{
  static const char* kHex = "0123456789ABCDEF";
  std::string out = "'";
  const std::size_t n = std::min(text.size(), kMaxQuotedLength);
  for (std::size_t i = 0; i < n; ++i)
  {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c < 0x20 || c >= 0x7F)
    {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 0xF];
    }
    else
      out += static_cast<char>(c);
  }
  out += "'";
  if (text.size() > n)
    out += "... (" + std::to_string(text.size()) + " characters)";
  return out;
}

void validateFrameId(const std::string& id, const std::string& field)
{
  if (id.empty())
    throw InvalidInputError(field + ": is empty");
  if (id.size() > kMaxFrameIdLength)
    throw InvalidInputError(field + ": " + quoted(id) + " is longer than " + std::to_string(kMaxFrameIdLength) +
                            " characters");
  if (id.front() == '/')
    throw InvalidInputError(field + ": " + quoted(id) + " starts with '/' (tf2 frame ids have no leading slash)");
  for (std::size_t i = 0; i < id.size(); ++i)
  {
    const unsigned char c = static_cast<unsigned char>(id[i]);
    if (c < 0x20 || c == 0x7F)
      throw InvalidInputError(field + ": " + quoted(id) + " contains a control character at " + std::to_string(i));
    if (std::isspace(c))
      throw InvalidInputError(field + ": " + quoted(id) + " contains white space at " + std::to_string(i));
  }
}

void validateTimes(const std::vector<double>& times, std::size_t num_waypoints)
{
  if (times.empty())
    return;
  if (times.size() != num_waypoints)
    throw InvalidInputError("times: " + std::to_string(times.size()) + " given for " + std::to_string(num_waypoints) +
                            " waypoints (give one time per waypoint, or none)");
  for (std::size_t i = 0; i < times.size(); ++i)
  {
    requireFinite(times[i], indexedField("times", i));
    requireRosDuration(times[i], indexedField("times", i));
    if (i > 0 && !(times[i] > times[i - 1]))
      throw InvalidInputError(indexedField("times", i) + ": " + formatNumber(times[i]) + " is not after times[" +
                              std::to_string(i - 1) + "] = " + formatNumber(times[i - 1]) +
                              " (times must be strictly increasing)");
  }
}

Sampling validateSampling(const std::vector<double>& sample_times, double sample_period, std::uint32_t sample_count,
                          const PlannerLimits& limits)
{
  if (sample_times.size() > limits.max_samples)
    throw LimitExceededError("sample_times: " + std::to_string(sample_times.size()) +
                             " samples requested; the limit (~max_samples) is " + std::to_string(limits.max_samples));
  for (std::size_t i = 0; i < sample_times.size(); ++i)
  {
    requireFinite(sample_times[i], indexedField("sample_times", i));
    requireRosDuration(sample_times[i], indexedField("sample_times", i));
    if (i > 0 && sample_times[i] < sample_times[i - 1])
      throw InvalidInputError(indexedField("sample_times", i) + ": " + formatNumber(sample_times[i]) +
                              " is before the previous sample time (sample_times must be non-decreasing)");
  }
  requireFiniteNonNegative(sample_period, "sample_period");
  if (sample_period > 0.0 && sample_period < kRosDurationResolution)
    throw InvalidInputError("sample_period: " + formatNumber(sample_period) +
                            " s is below the 1 ns resolution of time_from_start");
  if (sample_count == 1)
    throw InvalidInputError("sample_count: 1 is too few (at least 2: both ends)");
  Sampling s;
  s.sample_times = sample_times;
  s.sample_period = sample_period;
  s.sample_count = sample_count == 0 ? 100 : sample_count;
  if (sample_times.empty() && sample_period == 0.0 && s.sample_count > limits.max_samples)
    throw LimitExceededError("sample_count: " + std::to_string(s.sample_count) +
                             " samples requested; the limit (~max_samples) is " + std::to_string(limits.max_samples));
  return s;
}

std::vector<double> sampleTimes(const Sampling& r, double t0, double t1, const PlannerLimits& limits)
{
  std::vector<double> ts;
  if (!r.sample_times.empty())
  {
    const double tol = 1e-9 * std::max(1.0, std::abs(t1));
    for (std::size_t i = 0; i < r.sample_times.size(); ++i)
    {
      const double t = r.sample_times[i];
      if (t < t0 - tol || t > t1 + tol)
        throw InvalidInputError(indexedField("sample_times", i) + ": " + formatNumber(t) +
                                " s is outside the trajectory [" + formatNumber(t0) + ", " + formatNumber(t1) + "] s");
      ts.push_back(std::min(std::max(t, t0), t1));
      const double step = i > 0 ? ts[i] - ts[i - 1] : 0.0;
      if (step > 0.0 && step < kResolvableStep)
        throw InvalidInputError(indexedField("sample_times", i) + ": " + formatNumber(t) + " s is only " +
                                formatNumber(step) + " s after the previous sample (time_from_start resolves 1 ns)");
    }
    return ts;
  }
  if (r.sample_period > 0.0)
  {
    if (r.sample_period < kRosDurationResolution)
      throw InvalidInputError("sample_period: " + formatNumber(r.sample_period) +
                              " s is below the 1 ns resolution of time_from_start");
    const double count = std::floor((t1 - t0) / r.sample_period) + 2.0;
    if (!(count <= static_cast<double>(limits.max_samples)))
      throw LimitExceededError("sample_period: " + formatNumber(r.sample_period) + " s gives " + formatNumber(count) +
                               " samples; the limit (~max_samples) is " + std::to_string(limits.max_samples));
    // Both ends always; a regular sample closer to t1 than the tolerance merges into t1.
    const double tol = std::max(1e-9 * r.sample_period, kRosDurationResolution);
    ts.push_back(t0);
    for (std::size_t i = 1;; ++i)
    {
      const double t = t0 + static_cast<double>(i) * r.sample_period;
      if (!(t < t1 - tol))
        break;
      ts.push_back(t);
    }
    ts.push_back(t1);
    requireResolvable(ts, "sample_period");
    return ts;
  }
  ts.resize(r.sample_count);
  for (std::size_t i = 0; i < ts.size(); ++i)
    ts[i] = t0 + (t1 - t0) * static_cast<double>(i) / static_cast<double>(ts.size() - 1);
  ts.back() = t1;
  requireResolvable(ts, "sample_count");
  return ts;
}

}  // namespace se3_interpolation
