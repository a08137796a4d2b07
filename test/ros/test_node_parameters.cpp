// Node parameters (ros/node_parameters.h), without a roscore: the one table
// (cfg/node_parameters.yaml) against everything that must agree with it (the request's names and
// defaults, dynamic_reconfigure's generated descriptions, the docs, the config file, the launch
// files), and the checks that start-up and dynamic_reconfigure share, each against the message and
// range written here.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "se3_interpolation/InterpolationNodeConfig.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/ros/node_parameters.h"

using namespace se3_interpolation;

TEST(NodeParameters, DefaultsAreTheCoreRequestDefaults)
{
  const NodeParameters p;
  EXPECT_EQ(p.curve, "interpolating");
  EXPECT_EQ(p.geometry, "double_geodesic");
  EXPECT_EQ(p.parameterization, "chord");
  EXPECT_EQ(p.timing, "stretch");
  EXPECT_EQ(p.sample_count, 100);
  EXPECT_FALSE(p.loop);
  EXPECT_TRUE(p.replan_from_current);
  EXPECT_EQ(p.replan_lead, 0.1);
  EXPECT_EQ(p.curve, toString(RequestDefaults::kCurve));
  EXPECT_EQ(p.geometry, toString(RequestDefaults::kGeometry));
  EXPECT_EQ(p.parameterization, toString(RequestDefaults::kParameterization));
  EXPECT_EQ(p.timing, toString(RequestDefaults::kTiming));
  EXPECT_EQ(p.sample_count, static_cast<int>(RequestDefaults::kSampleCount));
  const PlannerLimits core;
  EXPECT_EQ(p.limits().max_samples, core.max_samples);
  EXPECT_EQ(p.limits().max_waypoints, core.max_waypoints);
  EXPECT_EQ(p.limits().max_work_seconds, core.max_work_seconds);
}

TEST(NodeParameters, EveryRowAcceptsItsDefaultAndNamesItself)
{
  std::set<std::string> names;
  for (const ParameterSpec& spec : kNodeParameterSpecs)
  {
    EXPECT_TRUE(names.insert(spec.name).second) << spec.name;
    EXPECT_EQ(findNodeParameter(spec.name), &spec);
    EXPECT_NE(std::string(spec.doc), "") << spec.name;
    if (spec.type == ParameterType::kInt || spec.type == ParameterType::kDouble)
    {
      EXPECT_EQ(parameterError(spec, std::stod(spec.default_text)), "") << spec.name;
      EXPECT_NE(parameterError(spec, NAN), "") << spec.name;
      EXPECT_EQ(parameterError(spec, spec.min).empty(), !spec.min_exclusive) << spec.name;
      if (std::isfinite(spec.max))
      {
        EXPECT_EQ(parameterError(spec, spec.max), "") << spec.name;
        EXPECT_EQ(parameterError(spec, std::nextafter(spec.max, INFINITY))
                      .rfind(std::string("~") + spec.name + ": refused", 0),
                  0u)
            << spec.name;
      }
    }
    else if (spec.type != ParameterType::kBool)
    {
      EXPECT_EQ(parameterError(spec, std::string(spec.default_text)), "") << spec.name;
    }
  }
  EXPECT_EQ(findNodeParameter("max_velocity"), nullptr);
}

TEST(NodeParameters, ChoicesAreTheRequestsNames)
{
  EXPECT_EQ(std::string(findNodeParameter("curve")->choices), knownNames<CurveType>());
  EXPECT_EQ(std::string(findNodeParameter("geometry")->choices), knownNames<GeometryType>());
  EXPECT_EQ(std::string(findNodeParameter("parameterization")->choices), knownNames<Parameterization>());
  EXPECT_EQ(std::string(findNodeParameter("timing")->choices), knownNames<Timing>());
  EXPECT_EQ(std::string(findNodeParameter("loss")->choices), knownNames<FitLoss>());
  std::size_t choices = 0;
  for (const ParameterSpec& spec : kNodeParameterSpecs)
    choices += spec.type == ParameterType::kChoice;
  EXPECT_EQ(choices, 5u);  // every choice parameter is compared above
}

TEST(NodeParameters, StringParametersUseTheRequestNameTables)
{
  for (const char* curve : { "piecewise_geodesic", "bezier", "bspline", "interpolating", "hermite", "blended", "fit" })
    EXPECT_EQ(stringParameterError("curve", curve), "") << curve;
  EXPECT_EQ(stringParameterError("loss", "huber"), "");
  EXPECT_EQ(stringParameterError("loss", "cauchy").rfind("~loss: unknown value 'cauchy'", 0), 0u);
  EXPECT_EQ(stringParameterError("timing", "time_optimal"), "");
  EXPECT_EQ(stringParameterError("curve", "bspine"),
            "~curve: unknown value 'bspine' (expected one of: piecewise_geodesic, bezier, bspline, interpolating, "
            "hermite, blended, fit)");
  EXPECT_EQ(stringParameterError("timing", "fast").rfind("~timing: unknown value 'fast'", 0), 0u);
  EXPECT_EQ(stringParameterError("geometry", "").rfind("~geometry: refused (empty", 0), 0u);
  // Frame ids: tf2's rules, a bounded quote.
  EXPECT_EQ(stringParameterError("child_frame_id", "tool0"), "");
  EXPECT_EQ(stringParameterError("frame_id", "/map").rfind("~frame_id: '/map' starts with '/'", 0), 0u);
  const std::string long_id = stringParameterError("frame_id", std::string(1000, 'a'));
  EXPECT_LT(long_id.size(), 200u) << long_id;
}

TEST(NodeParameters, NumericRangesAreInclusiveWhereDocumented)
{
  EXPECT_EQ(numberParameterError("replan_lead", 0.0), "");
  EXPECT_EQ(numberParameterError("replan_lead", 10.0), "");
  EXPECT_EQ(numberParameterError("replan_lead", 10.5), "~replan_lead: refused 10.5 (must be in [0, 10] s)");
  EXPECT_EQ(numberParameterError("tf_rate", 1000.0), "");
  EXPECT_NE(numberParameterError("tf_rate", 0.0), "");  // (0, 1000]: 0 excluded
  EXPECT_NE(numberParameterError("tf_rate", NAN), "");
  EXPECT_NE(numberParameterError("service_threads", 0.0), "");
  EXPECT_EQ(numberParameterError("service_threads", 64.0), "");
  // A name without a range has nothing to refuse.
  EXPECT_EQ(numberParameterError("no_such_parameter", -1.0), "");
}

// An int parameter given as a double (`_max_samples:=1e12`, which YAML reads as one) is taken when
// it is a whole int and refused naming the value given otherwise, never overflowed.
TEST(NodeParameters, IntParametersGivenAsDoublesAreNamedAsGiven)
{
  const ParameterSpec& spec = *findNodeParameter("max_samples");
  int value = 7;
  XmlRpc::XmlRpcValue whole(2e5);
  EXPECT_EQ(intParameterFromServer(spec, whole, &value), "");
  EXPECT_EQ(value, 200000);
  XmlRpc::XmlRpcValue integer(12);
  EXPECT_EQ(intParameterFromServer(spec, integer, &value), "");
  EXPECT_EQ(value, 12);
  value = 7;
  for (const double given : { 1e12, -1e12, 2.5, static_cast<double>(NAN) })
  {
    XmlRpc::XmlRpcValue raw(given);
    const std::string why = intParameterFromServer(spec, raw, &value);
    std::ostringstream shown;
    shown << "~max_samples: refused " << given << " (must be a whole number from -2147483648 to 2147483647, >= 2)";
    EXPECT_EQ(why, shown.str());
    EXPECT_EQ(value, 7);
  }
  XmlRpc::XmlRpcValue text("many");
  EXPECT_EQ(intParameterFromServer(spec, text, &value), "~max_samples: refused (not of the expected type)");
}

TEST(NodeParameters, UnknownPrivateParametersAreNamedWithTheClosestKnownOne)
{
  const std::vector<std::string> server = {
    "/arm/node/max_velocity", "/arm/node/tf_rate",
    "/arm/node/curv",         "/arm/node/curv/nested",
    "/arm/other/x",           "/arm/node_b/y",
    "/arm/node/blend_radius", "/arm/node/joint_limits/elbow_joint/max_velocity"
  };
  const std::vector<std::string> warnings = unknownParameterWarnings(server, "/arm/node");
  ASSERT_EQ(warnings.size(), 2u);
  EXPECT_EQ(warnings[0], "~max_velocity: unknown parameter, ignored (did you mean ~max_linear_velocity?)");
  EXPECT_EQ(warnings[1], "~curv: unknown parameter, ignored (did you mean ~curve?)");
  EXPECT_EQ(closestNodeParameter("child_frame"), "child_frame_id");
  const std::string huge(100000, 'x');
  const auto long_warning = unknownParameterWarnings({ "/n/" + huge }, "/n");
  ASSERT_EQ(long_warning.size(), 1u);
  EXPECT_LT(long_warning[0].size(), 400u);
}

TEST(NodeParameters, ReconfigureTakesValidValuesAndKeepsRefusedOnes)
{
  NodeParameters p;
  // Unchanged values are no change.
  EXPECT_EQ(applyReconfigureMessage(toReconfigureMessage(p), &p), "");
  dynamic_reconfigure::Config m = toReconfigureMessage(p);
  auto set = [](auto* params, const std::string& name, auto value) {
    for (auto& x : *params)
      if (x.name == name)
        x.value = value;
  };
  set(&m.strs, "curve", std::string("bspine"));
  set(&m.strs, "timing", std::string("time_optimal"));
  set(&m.doubles, "tf_rate", 0.0);  // (0, 1000]: 0 refused
  set(&m.doubles, "max_linear_velocity", 0.5);
  set(&m.ints, "sample_count", 3);
  set(&m.bools, "loop", true);
  dynamic_reconfigure::StrParameter frame;  // not a run-time parameter: never taken
  frame.name = "frame_id";
  frame.value = "elsewhere";
  m.strs.push_back(frame);
  const std::string refused = applyReconfigureMessage(m, &p);
  EXPECT_NE(refused.find("~curve: unknown value 'bspine'"), std::string::npos) << refused;
  EXPECT_NE(refused.find("keeping 'interpolating'"), std::string::npos) << refused;
  EXPECT_NE(refused.find("~tf_rate: refused 0 (must be in (0, 1000] Hz), keeping 50"), std::string::npos) << refused;
  EXPECT_EQ(p.curve, "interpolating");
  EXPECT_EQ(p.tf_rate, 50.0);
  EXPECT_EQ(p.timing, "time_optimal");
  EXPECT_EQ(p.max_linear_velocity, 0.5);
  EXPECT_EQ(p.sample_count, 3);
  EXPECT_TRUE(p.loop);
  EXPECT_EQ(p.frame_id, "map");
  // The message carries exactly the run-time rows.
  const dynamic_reconfigure::Config back = toReconfigureMessage(p);
  std::size_t run_time = 0;
  for (const ParameterSpec& spec : kNodeParameterSpecs)
    run_time += spec.reconfigure[0] != '\0';
  EXPECT_EQ(back.bools.size() + back.ints.size() + back.doubles.size() + back.strs.size(), run_time);
}

namespace
{
std::string valueText(const dynamic_reconfigure::Config& c, const std::string& name)
{
  for (const auto& x : c.bools)
    if (x.name == name)
      return x.value ? "true" : "false";
  for (const auto& x : c.ints)
    if (x.name == name)
      return std::to_string(x.value);
  for (const auto& x : c.doubles)
    if (x.name == name)
    {
      std::ostringstream s;
      s << x.value;
      return s.str();
    }
  for (const auto& x : c.strs)
    if (x.name == name)
      return x.value;
  return "(missing)";
}

double numberOf(const dynamic_reconfigure::Config& c, const std::string& name)
{
  return std::stod(valueText(c, name));
}

std::string fileText(const std::string& path)
{
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}
}  // namespace

// dynamic_reconfigure's server clamps a requested value into the generated ranges before the
// node's callback sees it, so a generated minimum of 0 would turn `dynparam set ...
// max_linear_velocity -1` into 0 ("unbounded"). Every value, in range or not, finite or not, must
// reach the node's check unchanged, which refuses it and keeps the value in effect.
TEST(NodeParameters, DynamicReconfigureHandsEveryValueToTheNodesCheck)
{
  const double values[] = { -1.0, -1e300, 1e300, NAN, INFINITY, -INFINITY, 2e9 };
  for (const ParameterSpec& spec : kNodeParameterSpecs)
  {
    if (spec.reconfigure[0] == '\0' || (spec.type != ParameterType::kDouble && spec.type != ParameterType::kInt))
      continue;
    for (double value : values)
    {
      const bool integer = spec.type == ParameterType::kInt;
      if (integer && !(std::abs(value) <= 2147483647.0))
        continue;  // (an int parameter's message carries an int)
      dynamic_reconfigure::Config request;
      if (integer)
      {
        dynamic_reconfigure::IntParameter p;
        p.name = spec.name;
        p.value = static_cast<int>(value);
        request.ints.push_back(p);
      }
      else
      {
        dynamic_reconfigure::DoubleParameter p;
        p.name = spec.name;
        p.value = value;
        request.doubles.push_back(p);
      }
      // What the server does with a request (dynamic_reconfigure/server.h, setConfigCallback).
      InterpolationNodeConfig config = InterpolationNodeConfig::__getDefault__();
      config.__fromMessage__(request);
      config.__clamp__();
      dynamic_reconfigure::Config seen;
      config.__toMessage__(seen);
      const double received = numberOf(seen, spec.name);
      if (std::isnan(value))
        EXPECT_TRUE(std::isnan(received)) << spec.name << " " << received;
      else
        EXPECT_EQ(received, integer ? static_cast<int>(value) : value) << spec.name << " clamped";
      // The node refuses what its row refuses, naming it and keeping the value in effect.
      NodeParameters p;
      const std::string refused = applyReconfigureMessage(seen, &p);
      if (parameterError(spec, received).empty())
        continue;
      EXPECT_NE(refused.find(std::string("~") + spec.name + ": refused"), std::string::npos) << refused;
      EXPECT_NE(refused.find(std::string("keeping ") + spec.default_text), std::string::npos) << refused;
      EXPECT_EQ(numberOf(toReconfigureMessage(p), spec.name), std::stod(spec.default_text)) << spec.name;
    }
  }
}

// dynamic_reconfigure's generated server is the table's run-time rows: names, types, defaults,
// ranges, groups and the choices as enums (menus in rqt_reconfigure).
TEST(NodeParameters, DynamicReconfigureIsTheTablesRunTimeRows)
{
  const auto& descriptions = InterpolationNodeConfig::__getParamDescriptions__();
  const dynamic_reconfigure::ConfigDescription& d = InterpolationNodeConfig::__getDescriptionMessage__();
  std::set<std::string> described;
  for (const auto& p : descriptions)
    described.insert(p->name);
  std::set<std::string> run_time;
  for (const ParameterSpec& spec : kNodeParameterSpecs)
  {
    if (spec.reconfigure[0] == '\0')
      continue;
    run_time.insert(spec.name);
    const auto it =
        std::find_if(descriptions.begin(), descriptions.end(), [&](const auto& p) { return p->name == spec.name; });
    ASSERT_NE(it, descriptions.end()) << spec.name;
    const std::string type = (*it)->type;
    switch (spec.type)
    {
      case ParameterType::kBool:
        EXPECT_EQ(type, "bool") << spec.name;
        break;
      case ParameterType::kInt:
        EXPECT_EQ(type, "int") << spec.name;
        break;
      case ParameterType::kDouble:
        EXPECT_EQ(type, "double") << spec.name;
        break;
      case ParameterType::kFrame:
      case ParameterType::kOptionalFrame:
      case ParameterType::kChoice:
        EXPECT_EQ(type, "str") << spec.name;
        break;
    }
    if (spec.type == ParameterType::kInt || spec.type == ParameterType::kDouble)
    {
      EXPECT_EQ(numberOf(d.dflt, spec.name), std::stod(spec.default_text)) << spec.name;
      // The generated ranges are unbounded (the server clamps to them); the node publishes the
      // table's, which reconfigureRange gives.
      const bool integer = spec.type == ParameterType::kInt;
      EXPECT_EQ(numberOf(d.min, spec.name), integer ? -2147483648.0 : -INFINITY) << spec.name;
      EXPECT_EQ(numberOf(d.max, spec.name), integer ? 2147483647.0 : INFINITY) << spec.name;
      EXPECT_EQ(numberOf(reconfigureRange(false), spec.name), std::isfinite(spec.min) ? spec.min : -2147483648.0)
          << spec.name;
      if (std::isfinite(spec.max))
        EXPECT_EQ(numberOf(reconfigureRange(true), spec.name), spec.max) << spec.name;
      else
        EXPECT_EQ(numberOf(reconfigureRange(true), spec.name), integer ? 2147483647.0 : INFINITY) << spec.name;
    }
    else
      EXPECT_EQ(valueText(d.dflt, spec.name), spec.default_text) << spec.name;
    if (spec.type == ParameterType::kChoice)
    {
      // edit_method: {'enum': [{'name': ..., 'value': ...}, ...], ...}: every choice, in order.
      const std::string edit = (*it)->edit_method;
      std::string listed;
      const std::regex value("'value': '([a-z_]+)'");
      for (auto m = std::sregex_iterator(edit.begin(), edit.end(), value); m != std::sregex_iterator(); ++m)
        listed += (listed.empty() ? "" : ", ") + (*m)[1].str();
      EXPECT_EQ(listed, spec.choices) << edit;
    }
    bool grouped = false;
    for (const auto& g : d.groups)
      for (const auto& p : g.parameters)
        grouped = grouped || (p.name == spec.name && g.name == spec.reconfigure);
    EXPECT_TRUE(grouped) << spec.name << " in group " << spec.reconfigure;
  }
  EXPECT_EQ(described, run_time);
}

// docs/ros_interface.md's table and config/se3_interpolation.yaml are the table's, as
// cfg/node_parameter_table.py writes them (it prints the difference).
TEST(NodeParameters, DocsAndConfigFileAreGeneratedFromTheTable)
{
  const std::string command = "/usr/bin/python3 " SE3_SOURCE_DIR "/cfg/node_parameter_table.py check 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string out;
  char chunk[4096];
  while (std::fgets(chunk, sizeof chunk, pipe))
    out += chunk;
  EXPECT_EQ(pclose(pipe), 0) << out;
  // And the check can fail: the docs name every parameter in the generated table's form.
  const std::string docs = fileText(SE3_SOURCE_DIR "/docs/ros_interface.md");
  for (const ParameterSpec& spec : kNodeParameterSpecs)
    EXPECT_NE(docs.find(std::string("| `") + spec.name + "` |"), std::string::npos) << spec.name;
}

// The launch files set only parameters of the table, and only when their argument is given, so
// that the config file's values take effect.
TEST(NodeParameters, LaunchFilesSetOnlyTableParametersAndOnlyWhenGiven)
{
  for (const char* file : { "launch/se3_interpolation.launch", "launch/se3_interpolation_nodelet.launch" })
  {
    const std::string text = fileText(std::string(SE3_SOURCE_DIR "/") + file);
    ASSERT_FALSE(text.empty()) << file;
    const std::regex param("<param ([^>]*)name=\"([a-z_]+)\"");
    int count = 0;
    for (auto m = std::sregex_iterator(text.begin(), text.end(), param); m != std::sregex_iterator(); ++m, ++count)
    {
      const std::string name = (*m)[2];
      EXPECT_NE(findNodeParameter(name), nullptr) << file << ": " << name;
      EXPECT_NE((*m)[1].str().find("if="), std::string::npos) << file << ": " << name << " is set unconditionally";
    }
    EXPECT_GE(count, 2) << file;
    const std::regex arg("<arg name=\"([a-z_]+)\" default=\"([^\"]*)\"");
    for (auto m = std::sregex_iterator(text.begin(), text.end(), arg); m != std::sregex_iterator(); ++m)
      if (findNodeParameter((*m)[1]))
      {
        EXPECT_EQ((*m)[2].str(), "") << file << ": argument " << (*m)[1] << " overrides the config file";
      }
  }
}
