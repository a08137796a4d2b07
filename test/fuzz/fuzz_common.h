// Shared by the libFuzzer targets of test/fuzz/: a byte reader that turns any input into
// numbers (plausible values, edge cases, raw bits), names and requests, and the checks of a
// successful result (finite numbers, unit quaternions). A failed check prints the request
// being run and aborts, so that libFuzzer reports it. runRequestTarget() is the shared body of
// the request targets (fuzz_generate, fuzz_validate, fuzz_curves).
//
// Speed (docs/testing.md "Sanitizers and fuzzing": each per-layer target reaches 1e5 inputs in
// CI): the limits are small (kFuzzMaxWaypoints, kFuzzMaxSamples) so that inputs explore the logic, not
// bulk, and the checks build their messages only on failure.
//
// Input format (read front to back; missing bytes read as 0, so every input is valid):
// each field starts with a mode byte that picks how the value is drawn, e.g. a plausible
// value, a value from a table of edge cases (NaN, +-Inf, denormals, +-DBL_MAX, ...) or eight raw
// bytes. test/fuzz/make_corpus.py writes request seeds in this format.
//
// decode() can produce every field of the core request (TrajectoryRequest, the names of
// srv/GenerateTrajectory.srv): waypoints (0 ... 13, so one waypoint with a start state too),
// times, curve, geometry, degree, knots, continuity, end_condition, start_velocity, end_velocity,
// start_acceleration, velocities, parameterization, rotation_scale, duration,
// max_linear_velocity, max_angular_velocity, max_linear_acceleration, max_angular_acceleration,
// max_linear_jerk, max_angular_jerk, timing (constant_speed too), speed, sample_times, sample_period, sample_count,
// sample_tolerance, joint_seed, blend_radius, start_state (the service's
// from_current: on waypoints[0], near it or anywhere, at rest or moving, valid or not), and the
// response's `outputs` (parsed with names.h's table by runRequestTarget). The service's
// waypoint_frames, child_frame_id and publish belong to the node, not to the core request. The
// fields read last (blend_radius, timing, start_state, outputs, the jerk bounds, constant_speed and speed, the fit's, sample_tolerance, joint_seed) were added last, so that the
// earlier fields of the seed corpus keep their bytes.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/planner.h"

namespace se3_interpolation
{
namespace fuzz
{
class ByteReader
{
public:
  ByteReader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}

  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }

  /// An integer in [lo, hi].
  int range(int lo, int hi) { return lo + static_cast<int>(byte() % static_cast<unsigned>(hi - lo + 1)); }

  double rawDouble()
  {
    std::uint8_t b[sizeof(double)] = {};
    for (std::uint8_t& x : b)
      x = byte();
    double d;
    std::memcpy(&d, b, sizeof d);
    return d;
  }

  /// A number: mostly small multiples of 1/16, sometimes an edge case, a scaled value or raw bits.
  double number()
  {
    static const double kSpecial[] = {
      0.0,
      -0.0,
      1.0,
      -1.0,
      0.5,
      std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::infinity(),
      -std::numeric_limits<double>::infinity(),
      std::numeric_limits<double>::denorm_min(),
      -std::numeric_limits<double>::denorm_min(),
      std::numeric_limits<double>::min(),
      std::numeric_limits<double>::max(),
      -std::numeric_limits<double>::max(),
      std::numeric_limits<double>::epsilon(),
      1e-300,
      1e300,
      1e-15,
      1e-9,
      1e9,
      1e15,
      3.141592653589793,
      -3.141592653589793,
      4294967296.0,
      -9.3e18,
    };
    const std::uint8_t tag = byte();
    switch (tag % 8)
    {
      case 5:
        return kSpecial[byte() % (sizeof kSpecial / sizeof kSpecial[0])];
      case 6:
        return rawDouble();
      case 7:
        return small() * std::pow(10.0, static_cast<double>(static_cast<std::int8_t>(byte()) % 40));
      default:
        return small();
    }
  }

  /// (b − 128)/16 for the next byte b: [−8, 8) in steps of 1/16.
  double small() { return (static_cast<double>(byte()) - 128.0) / 16.0; }

  /// 0 (the field's default) most of the time, else a number.
  double optionalNumber() { return byte() % 4 == 0 ? number() : 0.0; }

  std::string name(const std::vector<const char*>& valid)
  {
    static const char* kGarbage[] = { "Bezier", "bezier ", " bspline", "b-spline", "screw\n", "natural\t",
                                      "NaN",    "0",       "\xff\xfe", "a very long name that is not a curve" };
    const std::uint8_t b = byte();
    if (b < 200)
      return b % 4 == 0 ? std::string() : std::string(valid[b % valid.size()]);
    if (b < 230)
      return kGarbage[b % (sizeof kGarbage / sizeof kGarbage[0])];
    std::string s(byte() % 9, '\0');
    for (char& c : s)
      c = static_cast<char>(byte());
    return s;
  }

private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

inline Eigen::Vector3d vector3(ByteReader& in)
{
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i)
    v[i] = in.number();
  return v;
}

inline Twist twist(ByteReader& in)
{
  Twist t;
  if (in.byte() % 2 == 1)
  {
    t.linear = vector3(in);
    t.angular = vector3(in);
  }
  return t;
}

inline Quaternion<double> quaternion(ByteReader& in, const std::vector<Pose<double>>& previous)
{
  Quaternion<double> last = Quaternion<double>::Identity();
  if (!previous.empty())
    last = previous.back().q;
  switch (in.byte() % 6)
  {
    case 0:  // four numbers, normalised when possible (the common, valid case)
    case 1:
    {
      Quaternion<double> q(in.small(), in.small(), in.small(), in.small());
      const double n = q.norm();
      if (n > 0.0)
        q.coeffs() /= n;
      return q;
    }
    case 2:  // four raw numbers, not normalised
      return Quaternion<double>(in.number(), in.number(), in.number(), in.number());
    case 3:  // the previous rotation, or its negation (the same rotation)
      if (in.byte() % 2 == 1)
        last.coeffs() = -last.coeffs();
      return last;
    case 4:  // the previous rotation turned by π about an axis: the geodesic is not unique
      return last * Quaternion<double>(0.0, 1.0, 0.0, 0.0);
    default:  // the previous rotation turned by an angle near π or a tiny one, scaled slightly off unit
    {
      static const double kAngles[] = { 1e-12, 1e-6, 0.1, 3.141592653589793 - 1e-9, 3.141592653589793 - 1e-15 };
      const double angle = kAngles[in.byte() % 5];
      const Quaternion<double> r(std::cos(angle / 2), std::sin(angle / 2), 0.0, 0.0);
      Quaternion<double> q = last * r;
      q.coeffs() *= 1.0 + (static_cast<double>(in.byte()) - 128.0) / 12800.0;
      return q;
    }
  }
}

/// `count` numbers: increasing from a start (sometimes with repeats), or arbitrary.
inline std::vector<double> sequence(ByteReader& in, std::size_t count)
{
  std::vector<double> v(count);
  if (in.byte() % 3 != 0)
  {
    double t = in.small();
    for (double& x : v)
    {
      x = t;
      t += static_cast<double>(in.byte() % 32) / 8.0;
    }
  }
  else
  {
    for (double& x : v)
      x = in.number();
  }
  return v;
}

/// A start state (request.h, StartState) for the waypoints so far: none (mode 0, which missing
/// bytes give), exactly on waypoints[0] (at rest or moving), near it, or anywhere.
inline std::optional<StartState> startState(ByteReader& in, const std::vector<Pose<double>>& waypoints)
{
  const std::uint8_t mode = in.byte() % 6;
  if (mode == 0)
    return std::nullopt;
  StartState s;
  const std::vector<Pose<double>> none;
  if (mode <= 2 && !waypoints.empty())
  {
    s.pose = waypoints.front();
    if (mode == 2)  // near it: a small offset of the position and the rotation
    {
      s.pose.p += Eigen::Vector3d(in.small(), in.small(), in.small()) / 16.0;
      s.pose.q = s.pose.q * Quaternion<double>(1.0, in.small() / 16.0, in.small() / 16.0, in.small() / 16.0);
      s.pose.q.normalize();
    }
  }
  else
    s.pose = Pose<double>(quaternion(in, mode == 3 ? waypoints : none), vector3(in));
  s.velocity = twist(in);
  s.acceleration = twist(in);
  return s;
}

/// The response's `outputs`: mostly empty or valid names, sometimes repeated or unknown ones.
inline std::vector<std::string> outputs(ByteReader& in)
{
  std::vector<std::string> names;
  const std::size_t n = in.byte() % 4;
  for (std::size_t i = 0; i < n; ++i)
    names.push_back(in.name({ "path", "trajectory" }));
  return names;
}

/// The request (and, when `response_outputs` is given, the response's `outputs`; the bytes are
/// read either way).
inline TrajectoryRequest decode(ByteReader& in, std::vector<std::string>* response_outputs = nullptr)
{
  static const std::vector<const char*> kCurves = { "piecewise_geodesic", "bezier", "bspline",
                                                    "interpolating",      "hermite", "blended" };
  static const std::vector<const char*> kGeometries = { "double_geodesic", "screw" };
  static const std::vector<const char*> kEndConditions = { "natural", "clamped", "start" };
  static const std::vector<const char*> kParameterizations = { "chord", "uniform", "centripetal" };
  static const int kIntegers[] = { -1, -1000, std::numeric_limits<int>::min(), std::numeric_limits<int>::max(),
                                   255, 1000 };

  TrajectoryRequest r;
  const std::size_t n = in.byte() % 14;
  for (std::size_t i = 0; i < n; ++i)
  {
    const Eigen::Vector3d p = in.byte() % 8 == 0 && !r.waypoints.empty() ? r.waypoints.back().p : vector3(in);
    const Quaternion<double> q = quaternion(in, r.waypoints);
    r.waypoints.emplace_back(q, p);
  }
  r.curve = in.name(kCurves);
  r.geometry = in.name(kGeometries);
  r.end_condition = in.name(kEndConditions);
  r.parameterization = in.name(kParameterizations);

  switch (in.byte() % 4)
  {
    case 1:
      r.times = sequence(in, n);
      break;
    case 2:
      r.times = sequence(in, in.byte() % 14);
      break;
    default:
      break;
  }

  const std::uint8_t degree = in.byte();
  r.degree = degree < 240 ? degree % 10 : kIntegers[degree % 6];
  switch (in.byte() % 4)
  {
    case 1:  // the standard length N + degree + 1 when that is small
      r.knots = sequence(in, r.degree >= 0 && r.degree < 16 ? n + static_cast<std::size_t>(r.degree) + 1 : 3);
      break;
    case 2:
      r.knots = sequence(in, in.byte() % 24);
      break;
    default:
      break;
  }
  const std::uint8_t continuity = in.byte();
  r.continuity = continuity < 240 ? continuity % 12 - 1 : kIntegers[continuity % 6];

  r.start_velocity = twist(in);
  r.end_velocity = twist(in);
  r.start_acceleration = twist(in);
  switch (in.byte() % 4)
  {
    case 1:
      r.velocities.resize(n);
      break;
    case 2:
      r.velocities.resize(in.byte() % 14);
      break;
    default:
      break;
  }
  for (Twist& v : r.velocities)
    v = twist(in);

  r.rotation_scale = in.optionalNumber();
  r.duration = in.optionalNumber();
  r.max_linear_velocity = in.optionalNumber();
  r.max_angular_velocity = in.optionalNumber();
  r.max_linear_acceleration = in.optionalNumber();
  r.max_angular_acceleration = in.optionalNumber();

  if (in.byte() % 4 == 1)
    r.sample_times = sequence(in, in.byte() % 32);
  r.sample_period = in.optionalNumber();
  static const std::uint32_t kCounts[] = { 0, 1, 2, 3, 1999, 2000, 2001, std::numeric_limits<std::uint32_t>::max() };
  const std::uint8_t count = in.byte();
  r.sample_count = count < 200 ? count % 64 : kCounts[count % 8];
  // Read last, so that the earlier fields of the seed corpus keep their bytes.
  r.blend_radius = in.optionalNumber();
  r.timing = in.name({ "stretch", "time_optimal" });
  r.start_state = startState(in, r.waypoints);
  std::vector<std::string> names = outputs(in);
  if (response_outputs != nullptr)
    *response_outputs = std::move(names);
  r.max_linear_jerk = in.optionalNumber();
  r.max_angular_jerk = in.optionalNumber();
  // timing constant_speed and its speed: read after everything else, from their own bytes.
  if (in.byte() % 5 == 4)
    r.timing = "constant_speed";
  r.speed = in.optionalNumber();
  // curve fit and its fields: after everything else, from their own bytes (the fit needs times:
  // one per waypoint when the byte asks for them).
  const std::uint8_t fit = in.byte();
  if (fit % 6 == 5)
  {
    r.curve = "fit";
    if (fit % 12 == 11 && r.times.size() != r.waypoints.size())
      r.times = sequence(in, r.waypoints.size());
  }
  // The fields go to the fit, and sometimes to another curve (refused, naming the field).
  const bool fit_fields = r.curve == "fit" || fit % 16 == 15;
  const double control_period = in.optionalNumber();
  const double smoothing = in.optionalNumber();
  const std::string loss = in.name({ "squared", "huber" });
  const double loss_scale = in.optionalNumber();
  if (fit_fields)
  {
    r.control_period = control_period;
    r.smoothing = smoothing;
    r.loss = loss;
    r.loss_scale = loss_scale;
  }
  // sample_tolerance: after everything else, from its own bytes (optionalNumber: 0 most often,
  // else tiny to huge, negative, NaN or infinite).
  r.sample_tolerance = in.optionalNumber();
  // joint_seed: after sample_tolerance, from its own bytes; the fuzzed planner has no arm, so a
  // seed (one request in 16, up to 8 numbers) is refused naming joint_seed.
  if (in.byte() % 16 == 15)
    r.joint_seed.assign(static_cast<std::size_t>(in.range(0, 8)), 0.0);
  for (double& q : r.joint_seed)
    q = in.number();
  return r;
}

/// The request being run, printed with a failure so that a finding can be read and replayed.
inline const TrajectoryRequest* g_request = nullptr;

inline std::string list(const std::vector<double>& v)
{
  std::string s = "[";
  char buf[32];
  for (double x : v)
  {
    std::snprintf(buf, sizeof buf, "%s%.17g", s.size() > 1 ? ", " : "", x);
    s += buf;
  }
  return s + "]";
}

inline std::string list(const Eigen::Ref<const Eigen::VectorXd>& v)
{
  return list(std::vector<double>(v.data(), v.data() + v.size()));
}

inline std::string describe(const TrajectoryRequest& r)
{
  auto twist = [](const Twist& t) {
    return "{linear: " + list(t.linear) + ", angular: " + list(t.angular) + "}";
  };
  std::string s = "waypoints:\n";
  for (const Pose<double>& x : r.waypoints)
    s += "  - {position: " + list(x.p) + ", orientation: " + list(x.q.coeffs()) +
         "}\n";
  s += "times: " + list(r.times) + "\ncurve: '" + r.curve + "'\ngeometry: '" + r.geometry +
       "'\ndegree: " + std::to_string(r.degree) + "\nknots: " + list(r.knots) +
       "\ncontinuity: " + std::to_string(r.continuity) + "\nend_condition: '" + r.end_condition +
       "'\nstart_velocity: " + twist(r.start_velocity) + "\nend_velocity: " + twist(r.end_velocity) +
       "\nstart_acceleration: " + twist(r.start_acceleration) + "\nvelocities:\n";
  for (const Twist& v : r.velocities)
    s += "  - " + twist(v) + "\n";
  s += "parameterization: '" + r.parameterization + "'\nrotation_scale: " +
       list(std::vector<double>{ r.rotation_scale, r.duration, r.max_linear_velocity, r.max_angular_velocity,
              r.max_linear_acceleration, r.max_angular_acceleration }) +
       " (rotation_scale, duration, max_linear_velocity, max_angular_velocity, max_linear_acceleration, "
       "max_angular_acceleration)\nsample_times: " +
       list(r.sample_times) + "\nsample_period: " + list(std::vector<double>{ r.sample_period }) +
       "\nsample_count: " + std::to_string(r.sample_count) + "\nblend_radius: " +
       list(std::vector<double>{ r.blend_radius }) + "\nmax_linear_jerk, max_angular_jerk: " +
       list(std::vector<double>{ r.max_linear_jerk, r.max_angular_jerk }) + "\ntiming: '" + r.timing + "'\nspeed: " + list(std::vector<double>{ r.speed }) + "\ncontrol_period, smoothing, loss_scale: " +
       list(std::vector<double>{ r.control_period, r.smoothing, r.loss_scale }) + "\nloss: '" + r.loss + "'\nsample_tolerance: " + list(std::vector<double>{ r.sample_tolerance }) + "\njoint_seed: " + list(r.joint_seed) + "\n";
  if (r.start_state)
    s += "start_state: {pose: {position: " + list(r.start_state->pose.p) + ", orientation: " +
         list(r.start_state->pose.q.coeffs()) + "}, velocity: " + twist(r.start_state->velocity) +
         ", acceleration: " + twist(r.start_state->acceleration) + "}\n";
  return s;
}

/// The target's name, printed with a finding.
inline const char* g_target = "fuzz";

[[noreturn]] inline void fail(const std::string& what)
{
  std::fprintf(stderr, "%s: %s\n", g_target, what.c_str());
  if (g_request != nullptr)
    std::fprintf(stderr, "request:\n%s", describe(*g_request).c_str());
  std::fflush(stderr);
  std::abort();
}

// The field names are C strings, so that a passing check allocates nothing.
inline void checkFinite(double x, const char* field)
{
  if (!std::isfinite(x))
    fail(std::string("non-finite ") + field + " (" + list(std::vector<double>{ x }) + ") in a successful result");
}

inline void checkFinite(const Eigen::Vector3d& v, const char* field)
{
  if (!v.allFinite())
    fail(std::string("non-finite ") + field + " (" + list(v) + ") in a successful result");
}

inline void checkPose(const Pose<double>& x, const char* field)
{
  if (!x.p.allFinite() || !x.q.coeffs().allFinite())
    fail(std::string("non-finite ") + field + " (position " + list(x.p) + ", orientation " + list(x.q.coeffs()) +
         ") in a successful result");
  if (std::abs(x.q.norm() - 1.0) > 1e-9)
    fail(std::string("non-unit quaternion in ") + field + " of a successful result");
}

inline void checkPose(const Pose<double>& x, const std::string& field)
{
  checkPose(x, field.c_str());
}

inline void checkResult(const TrajectoryResult& out, const PlannerLimits& limits)
{
  if (out.samples.empty() || out.samples.size() > limits.max_samples)
    fail("a successful result has " + std::to_string(out.samples.size()) + " samples");
  checkFinite(out.start_time, "start_time");
  checkFinite(out.duration, "duration");
  checkFinite(out.time_scale, "time_scale");
  checkFinite(out.figures.length, "length");
  checkFinite(out.figures.rotation_length, "rotation_length");
  checkFinite(out.figures.max_linear_speed, "max_linear_speed");
  checkFinite(out.figures.max_angular_speed, "max_angular_speed");
  checkFinite(out.figures.max_linear_acceleration, "max_linear_acceleration");
  checkFinite(out.figures.max_angular_acceleration, "max_angular_acceleration");
  checkFinite(out.figures.energy, "energy");
  if (!(out.time_scale >= 1.0))
    fail("time_scale below 1");
  for (double t : out.waypoint_times)
    checkFinite(t, "waypoint_times");
  for (const Pose<double>& x : out.waypoints)
    checkPose(x, "waypoints");
  for (const Pose<double>& x : out.control_points)
    checkPose(x, "control_points");
  for (const TrajectorySample& s : out.samples)
  {
    checkFinite(s.time, "samples.time");
    checkPose(s.pose, "samples.pose");
    checkFinite(s.velocity.linear, "samples.velocity.linear");
    checkFinite(s.velocity.angular, "samples.velocity.angular");
    checkFinite(s.acceleration.linear, "samples.acceleration.linear");
    checkFinite(s.acceleration.angular, "samples.acceleration.angular");
  }
  if (!out.point_at)
    fail("a successful result has no point_at");
  checkPose(out.point_at(out.start_time), "point_at(start_time)");
  checkPose(out.point_at(out.start_time + out.duration), "point_at(end)");
}
/// The planner limits of the request targets: a few waypoints and samples are enough to reach
/// every branch (the limits' own checks included: decode() also draws counts beyond them), and
/// keep one input in the order of 0.1 ms under ASan.
constexpr std::size_t kFuzzMaxWaypoints = 12;
constexpr std::size_t kFuzzMaxSamples = 256;

/// The body of a request target: decodes the input, keeps the request for a finding's report
/// and runs `layer(request, limits, in)` (`in` positioned after the request, for further
/// choices), expecting it to return or to throw an InterpolationError; any other exception is
/// a finding. Returns libFuzzer's 0.
template <class Layer>
int runRequestTarget(const char* target, const std::uint8_t* data, std::size_t size, Layer&& layer)
{
  g_target = target;
  ByteReader in(data, size);
  std::vector<std::string> response_outputs;
  const TrajectoryRequest request = decode(in, &response_outputs);
  g_request = &request;
  PlannerLimits limits;
  limits.max_samples = kFuzzMaxSamples;
  limits.max_waypoints = kFuzzMaxWaypoints;
  try
  {
    // The response's outputs are checked by the same name table as the node's and the CLI's.
    parseResponseOutputs(response_outputs);
    layer(request, limits, in);
  }
  catch (const InterpolationError&)
  {
    // The expected rejection of a bad request.
  }
  catch (const std::exception& e)
  {
    fail(std::string("an exception other than InterpolationError escaped: ") + e.what());
  }
  catch (...)
  {
    fail("a non-standard exception escaped");
  }
  g_request = nullptr;
  return 0;
}

/// A unit quaternion from the reader: quaternion()'s cases, normalised; the identity when they
/// are not normalisable (the layers below validation take unit quaternions only).
inline Quaternion<double> unitQuaternion(ByteReader& in, const std::vector<Pose<double>>& previous)
{
  Quaternion<double> q = quaternion(in, previous);
  const double n = q.norm();
  if (!(n > 0.5 && n < 2.0) || !q.coeffs().allFinite())
    return Quaternion<double>::Identity();
  q.coeffs() /= n;
  return q;
}
}  // namespace fuzz
}  // namespace se3_interpolation
