// The rules of ROS's conventions that requests meet (validation.h): durations within ROS's signed
// 32-bit seconds, stamped spans within its unsigned ones, and tf2 frame ids.
#include <cctype>
#include <cmath>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/validation.h"

namespace se3_interpolation
{
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
      throw InvalidInputError(
          cause + ": the trajectory would span [" + formatNumber(start_time) + ", " + formatNumber(end_time) +
          "] s, beyond ROS's duration range (|t| <= " + formatNumber(kRosDurationMaxSeconds) + " s)");
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

void validateFrameId(const std::string& id, const std::string& field)
{
  if (id.empty())
    throw InvalidInputError(field + ": is empty");
  if (id.size() > kMaxFrameIdLength)
    throw InvalidInputError(field + ": " + quotedText(id) + " is longer than " + std::to_string(kMaxFrameIdLength) +
                            " characters");
  if (id.front() == '/')
    throw InvalidInputError(field + ": " + quotedText(id) + " starts with '/' (tf2 frame ids have no leading slash)");
  for (std::size_t i = 0; i < id.size(); ++i)
  {
    const unsigned char c = static_cast<unsigned char>(id[i]);
    if (c < 0x20 || c == 0x7F)
      throw InvalidInputError(field + ": " + quotedText(id) + " contains a control character at " + std::to_string(i));
    if (std::isspace(c))
      throw InvalidInputError(field + ": " + quotedText(id) + " contains white space at " + std::to_string(i));
  }
}

}  // namespace se3_interpolation
