#include "yaml_request.h"

#include <map>
#include <set>

#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
namespace cli
{
namespace
{
double toDouble(const YAML::Node& node, const std::string& field)
{
  if (!node.IsScalar())
    throw InvalidInputError(field + ": expected a number");
  try
  {
    return node.as<double>();
  }
  catch (const YAML::Exception&)
  {
    throw InvalidInputError(field + ": '" + node.Scalar() + "' is not a number");
  }
}

long toInteger(const YAML::Node& node, const std::string& field, long lo, long hi)
{
  if (!node.IsScalar())
    throw InvalidInputError(field + ": expected an integer");
  long v = 0;
  try
  {
    v = node.as<long>();
  }
  catch (const YAML::Exception&)
  {
    throw InvalidInputError(field + ": '" + node.Scalar() + "' is not an integer");
  }
  if (v < lo || v > hi)
    throw InvalidInputError(field + ": " + std::to_string(v) + " is outside " + std::to_string(lo) + " ... " +
                            std::to_string(hi));
  return v;
}

std::string toString(const YAML::Node& node, const std::string& field)
{
  if (!node.IsScalar())
    throw InvalidInputError(field + ": expected a string");
  return node.Scalar();
}

bool toBool(const YAML::Node& node, const std::string& field)
{
  try
  {
    return node.as<bool>();
  }
  catch (const YAML::Exception&)
  {
    throw InvalidInputError(field + ": expected true or false");
  }
}

std::vector<double> toDoubles(const YAML::Node& node, const std::string& field)
{
  if (!node.IsSequence())
    throw InvalidInputError(field + ": expected a list of numbers");
  std::vector<double> v;
  for (std::size_t i = 0; i < node.size(); ++i)
    v.push_back(toDouble(node[i], indexedField(field, i)));
  return v;
}

void requireKeys(const YAML::Node& node, const std::string& field, const std::set<std::string>& allowed)
{
  if (!node.IsMap())
    throw InvalidInputError(field + ": expected a mapping");
  for (const auto& kv : node)
  {
    const std::string key = kv.first.as<std::string>();
    if (allowed.count(key) == 0)
      throw InvalidInputError(field + (field.empty() ? "" : ".") + key + ": unknown field");
  }
}

/// The components of a list [x, y, ...] or of a ROS message map {x: .., y: .., ...}; in the map
/// form a missing component is 0, as when `rosservice call` fills a geometry_msgs message.
std::vector<double> toComponents(const YAML::Node& node, const std::string& field,
                                 const std::vector<std::string>& names)
{
  std::string list = "[";
  std::string map = "{";
  for (std::size_t i = 0; i < names.size(); ++i)
  {
    list += (i ? ", " : "") + names[i];
    map += (i ? ", " : "") + names[i] + ": ..";
  }
  list += "]";
  map += "}";
  if (node.IsMap())
  {
    requireKeys(node, field, std::set<std::string>(names.begin(), names.end()));
    std::vector<double> v(names.size(), 0.0);
    for (std::size_t i = 0; i < names.size(); ++i)
      if (node[names[i]])
        v[i] = toDouble(node[names[i]], field + "." + names[i]);
    return v;
  }
  if (!node.IsSequence())
    throw InvalidInputError(field + ": expected " + list + " or " + map);
  const std::vector<double> v = toDoubles(node, field);
  if (v.size() != names.size())
    throw InvalidInputError(field + ": expected " + std::to_string(names.size()) + " numbers " + list + ", got " +
                            std::to_string(v.size()));
  return v;
}

Eigen::Vector3d toVector3(const YAML::Node& node, const std::string& field)
{
  const std::vector<double> v = toComponents(node, field, { "x", "y", "z" });
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Twist toTwist(const YAML::Node& node, const std::string& field)
{
  requireKeys(node, field, { "linear", "angular" });
  Twist t;
  if (node["linear"])
    t.linear = toVector3(node["linear"], field + ".linear");
  if (node["angular"])
    t.angular = toVector3(node["angular"], field + ".angular");
  return t;
}

Pose<double> toPose(const YAML::Node& node, const std::string& field)
{
  requireKeys(node, field, { "position", "orientation" });
  Pose<double> p;
  if (!node["position"])
    throw InvalidInputError(field + ".position: missing");
  p.p = toVector3(node["position"], field + ".position");
  if (node["orientation"])
  {
    const std::vector<double> q = toComponents(node["orientation"], field + ".orientation", { "x", "y", "z", "w" });
    p.q = Quaternion<double>(q[3], q[0], q[1], q[2]);
  }
  return p;
}
/// Refuses a key given twice in one mapping, in `node` and every mapping below it: yaml-cpp keeps
/// the first value and would drop the second silently. Names the key by its field path and both
/// lines (1-based).
void rejectRepeatedKeys(const YAML::Node& node, const std::string& field)
{
  if (node.IsSequence())
  {
    for (std::size_t i = 0; i < node.size(); ++i)
      rejectRepeatedKeys(node[i], indexedField(field, i));
    return;
  }
  if (!node.IsMap())
    return;
  std::map<std::string, int> first_line;
  for (const auto& kv : node)
  {
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string("(a non-scalar key)");
    const std::string name = field + (field.empty() ? "" : ".") + key;
    const int line = kv.first.Mark().line + 1;
    const auto seen = first_line.emplace(key, line);
    if (!seen.second)
      throw InvalidInputError(name + ": repeated key at line " + std::to_string(line) + " (first given at line " +
                              std::to_string(seen.first->second) + "); give each key once");
    rejectRepeatedKeys(kv.second, name);
  }
}

/// The keys a request file may hold: the service's fields, the CLI's start_state, and the service's
/// child_frame_id, publish and from_current, which are checked and refused or ignored.
const std::set<std::string> kRequestKeys = { "waypoints",
                                             "times",
                                             "curve",
                                             "geometry",
                                             "degree",
                                             "knots",
                                             "continuity",
                                             "end_condition",
                                             "start_velocity",
                                             "end_velocity",
                                             "start_acceleration",
                                             "velocities",
                                             "parameterization",
                                             "rotation_scale",
                                             "duration",
                                             "max_linear_velocity",
                                             "max_angular_velocity",
                                             "max_linear_acceleration",
                                             "max_angular_acceleration",
                                             "max_linear_jerk",
                                             "max_angular_jerk",
                                             "timing",
                                             "speed",
                                             "control_period",
                                             "smoothing",
                                             "loss",
                                             "loss_scale",
                                             "sample_times",
                                             "sample_period",
                                             "sample_count",
                                             "sample_tolerance",
                                             "child_frame_id",
                                             "publish",
                                             "blend_radius",
                                             "from_current",
                                             "start_state",
                                             "outputs",
                                             "joint_seed" };

/// Reads the optional field `name` of the request's map into *out when it is given (the field's
/// name is the error's).
void readField(const YAML::Node& root, const char* name, double* out)
{
  if (root[name])
    *out = toDouble(root[name], name);
}
void readField(const YAML::Node& root, const char* name, std::string* out)
{
  if (root[name])
    *out = toString(root[name], name);
}
void readField(const YAML::Node& root, const char* name, std::vector<double>* out)
{
  if (root[name])
    *out = toDoubles(root[name], name);
}

/// The document check and every field the pose and sphere requests share, by name.
template <class Request>
void readCommonFields(const YAML::Node& root, Request* r)
{
  if (!root || root.IsNull())
    throw InvalidInputError("request: the YAML document is empty");
  rejectRepeatedKeys(root, "");
  // The service looks these up with tf2; the command-line tool has no TF.
  if (root.IsMap() && root["waypoint_frames"])
    throw InvalidInputError(
        "waypoint_frames: the command-line tool has no TF to look frames up in; give their "
        "poses in waypoints (the node's ~generate service takes waypoint_frames)");
  requireKeys(root, "", kRequestKeys);
  // The service's from_current starts from the motion the node plays; the CLI plays none.
  if (root["from_current"] && toBool(root["from_current"], "from_current"))
    throw InvalidInputError(
        "from_current: the CLI plays no trajectory, so there is no current motion to start "
        "from; give the state explicitly as start_state: {pose: {position: [x, y, z], "
        "orientation: [x, y, z, w]}, velocity: {linear: [..], angular: [..]}, acceleration: "
        "{linear: [..], angular: [..]}}");
  readField(root, "times", &r->times);
  readField(root, "curve", &r->curve);
  readField(root, "geometry", &r->geometry);
  if (root["degree"])
    r->degree = static_cast<int>(toInteger(root["degree"], "degree", 0, 255));
  readField(root, "knots", &r->knots);
  if (root["continuity"])
    r->continuity = static_cast<int>(toInteger(root["continuity"], "continuity", 0, 255));
  readField(root, "end_condition", &r->end_condition);
  readField(root, "parameterization", &r->parameterization);
  readField(root, "rotation_scale", &r->rotation_scale);
  readField(root, "duration", &r->duration);
  readField(root, "max_linear_velocity", &r->max_linear_velocity);
  readField(root, "max_angular_velocity", &r->max_angular_velocity);
  readField(root, "max_linear_acceleration", &r->max_linear_acceleration);
  readField(root, "max_angular_acceleration", &r->max_angular_acceleration);
  readField(root, "max_linear_jerk", &r->max_linear_jerk);
  readField(root, "max_angular_jerk", &r->max_angular_jerk);
  readField(root, "timing", &r->timing);
  readField(root, "speed", &r->speed);
  readField(root, "control_period", &r->control_period);
  readField(root, "smoothing", &r->smoothing);
  readField(root, "loss", &r->loss);
  readField(root, "loss_scale", &r->loss_scale);
  readField(root, "sample_times", &r->sample_times);
  readField(root, "sample_period", &r->sample_period);
  if (root["sample_count"])
    r->sample_count = static_cast<std::uint32_t>(toInteger(root["sample_count"], "sample_count", 0, 4294967295L));
  readField(root, "sample_tolerance", &r->sample_tolerance);
  readField(root, "joint_seed", &r->joint_seed);
  if (root["publish"])
    toBool(root["publish"], "publish");
  // The service's choice of response arrays: checked as the service does, so that one request
  // file serves both; the CLI writes its one CSV (pose, velocity, acceleration) whatever it names.
  if (root["outputs"])
  {
    const YAML::Node& outputs = root["outputs"];
    if (!outputs.IsSequence())
      throw InvalidInputError("outputs: expected a list of names");
    std::vector<std::string> names;
    for (std::size_t i = 0; i < outputs.size(); ++i)
      names.push_back(toString(outputs[i], indexedField("outputs", i)));
    parseResponseOutputs(names);
  }
  if (root["child_frame_id"])
    validateFrameId(toString(root["child_frame_id"], "child_frame_id"), "child_frame_id");
}

/// The request's waypoints: the list form or the service's PoseArray.
void readWaypoints(const YAML::Node& root, TrajectoryRequest* r)
{
  // The list form, or the service's geometry_msgs/PoseArray {header: {...}, poses: [...]}. The CLI
  // has no frames, so a header is checked for its field names only. Indices name the poses as the
  // service's messages do: waypoints[i].
  const YAML::Node given = root["waypoints"];
  YAML::Node poses = given;
  if (given && given.IsMap())
  {
    requireKeys(given, "waypoints", { "header", "poses" });
    if (given["header"])
      requireKeys(given["header"], "waypoints.header", { "seq", "stamp", "frame_id" });
    if (!given["poses"])
      throw InvalidInputError("waypoints.poses: missing (a list of poses)");
    poses.reset(given["poses"]);
  }
  if (!poses || !poses.IsSequence())
    throw InvalidInputError(
        "waypoints: missing (a list of {position: [x, y, z], orientation: [x, y, z, w]}, or "
        "{header: {frame_id: ..}, poses: [...]} as in the service)");
  for (std::size_t i = 0; i < poses.size(); ++i)
    r->waypoints.push_back(toPose(poses[i], indexedField("waypoints", i)));
}

/// The pose request of `root`; its waypoints are read only if `read_waypoints` (else they are
/// given elsewhere and left empty).
TrajectoryRequest poseRequestFromYaml(const YAML::Node& root, bool read_waypoints)
{
  TrajectoryRequest r;
  readCommonFields(root, &r);
  if (root["blend_radius"])
    r.blend_radius = toDouble(root["blend_radius"], "blend_radius");
  if (read_waypoints)
    readWaypoints(root, &r);
  if (root["start_velocity"])
    r.start_velocity = toTwist(root["start_velocity"], "start_velocity");
  if (root["end_velocity"])
    r.end_velocity = toTwist(root["end_velocity"], "end_velocity");
  if (root["start_acceleration"])
    r.start_acceleration = toTwist(root["start_acceleration"], "start_acceleration");
  if (root["velocities"])
  {
    const YAML::Node v = root["velocities"];
    if (!v.IsSequence())
      throw InvalidInputError("velocities: expected a list of twists");
    for (std::size_t i = 0; i < v.size(); ++i)
      r.velocities.push_back(toTwist(v[i], indexedField("velocities", i)));
  }
  if (root["start_state"])
  {
    const YAML::Node s = root["start_state"];
    if (!s.IsMap())
      throw InvalidInputError("start_state: expected {pose: .., velocity: .., acceleration: ..}");
    requireKeys(s, "start_state", { "pose", "velocity", "acceleration" });
    if (!s["pose"])
      throw InvalidInputError("start_state.pose: missing ({position: [x, y, z], orientation: [x, y, z, w]})");
    StartState state;
    state.pose = toPose(s["pose"], "start_state.pose");
    if (s["velocity"])
      state.velocity = toTwist(s["velocity"], "start_state.velocity");
    if (s["acceleration"])
      state.acceleration = toTwist(s["acceleration"], "start_state.acceleration");
    r.start_state = state;
  }
  return r;
}
}  // namespace

std::vector<std::vector<double>> vectorsFromYaml(const YAML::Node& node, const std::string& field)
{
  if (!node.IsSequence())
    throw InvalidInputError(field + ": expected a list of vectors");
  std::vector<std::vector<double>> out;
  for (std::size_t i = 0; i < node.size(); ++i)
    out.push_back(toDoubles(node[i], indexedField(field, i)));
  return out;
}

TrajectoryRequest requestFromYaml(const YAML::Node& root)
{
  return poseRequestFromYaml(root, true);
}

TrajectoryRequest requestFromYaml(const YAML::Node& root, std::vector<Pose<double>> waypoints,
                                  std::vector<double> times, const std::string& source)
{
  for (const char* field : { "waypoints", "times" })
    if (root && root.IsMap() && root[field])
      throw InvalidInputError(std::string(field) + ": given both in the request file and by " + source + "; with " +
                              source + " the request file carries the other fields only");
  TrajectoryRequest r = poseRequestFromYaml(root, false);
  r.waypoints = std::move(waypoints);
  r.times = std::move(times);
  return r;
}

SphereRequest sphereRequestFromYaml(const YAML::Node& root)
{
  SphereRequest r;
  readCommonFields(root, &r);
  if (root["blend_radius"])
    throw InvalidInputError("blend_radius: corner blending is for poses only (not with --space sphere)");
  if (root["start_state"])
    throw InvalidInputError("start_state: starting from a given state is for poses only (not with --space sphere)");
  auto toVectorX = [](const YAML::Node& node, const std::string& field) {
    const std::vector<double> v = toDoubles(node, field);
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
  };
  if (!root["waypoints"] || !root["waypoints"].IsSequence())
    throw InvalidInputError("waypoints: missing (a list of unit vectors [x1, ..., x{m+1}])");
  for (const auto& v : vectorsFromYaml(root["waypoints"], "waypoints"))
    r.waypoints.push_back(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
  if (root["start_velocity"])
    r.start_velocity = toVectorX(root["start_velocity"], "start_velocity");
  if (root["end_velocity"])
    r.end_velocity = toVectorX(root["end_velocity"], "end_velocity");
  if (root["start_acceleration"])
    r.start_acceleration = toVectorX(root["start_acceleration"], "start_acceleration");
  if (root["velocities"])
    for (const auto& v : vectorsFromYaml(root["velocities"], "velocities"))
      r.velocities.push_back(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
  return r;
}

}  // namespace cli
}  // namespace se3_interpolation
