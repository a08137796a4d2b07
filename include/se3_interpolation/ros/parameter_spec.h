// ros/: the description of one node parameter, as cfg/node_parameters.yaml gives it. The table
// itself (kNodeParameterSpecs, and NodeParameterValues with a member per parameter) is generated
// from that file at build time into se3_interpolation/node_parameter_table.h.
#pragma once

namespace se3_interpolation
{
/// How a parameter is stored on the parameter server and in NodeParameterValues.
enum class ParameterType
{
  kBool,
  kInt,
  kDouble,
  kFrame,          ///< a TF frame id (tf2's rules, validateFrameId)
  kOptionalFrame,  ///< a TF frame id, or empty for none
  kChoice          ///< a string that must be one of ParameterSpec::choices (an enum in dynamic_reconfigure)
};

/// One row of the parameter table.
struct ParameterSpec
{
  const char* name;  ///< without "~"
  ParameterType type;
  const char* default_text;  ///< the default as the docs write it
  double min;                ///< numbers: the lower bound (-inf: none)
  bool min_exclusive;        ///< numbers: whether `min` itself is refused
  double max;                ///< numbers: the upper bound, inclusive (+inf: none)
  const char* unit;          ///< "" when none
  const char* reconfigure;   ///< the dynamic_reconfigure group; "" when read at start-up only
  const char* choices;       ///< kChoice: the names, "a, b, c"
  const char* range;         ///< numbers: the range as the docs write it ("(0, 1000]"), "" when none
  const char* doc;           ///< one line
};

}  // namespace se3_interpolation
