// The CSV text of se3_interpolate's results (docs/command_line.md "Output").
//
// Every number is written in the shortest form that parses back (strtod, std::from_chars,
// Python's float) to the same double, bit for bit: std::to_chars without a format, which picks
// fixed or scientific notation, whichever is shorter (0.1, 1e-300, 9007199254740992). -0.0 prints
// as -0; the planner passes no ∞ or NaN (planner.h). The rows are formatted into one buffer,
// reserved once for the longest possible text, so the caller writes the whole file at once.
#pragma once

#include <cstddef>
#include <string>

#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace cli
{
/// The longest shortest-round-trip form of a double: a sign, 17 significant digits, the decimal
/// point and a three-digit exponent, as in -2.2250738585072014e-308.
constexpr std::size_t kMaxNumberChars = 24;

/// Writes `value` at `first` in its shortest round-trip form.
/// @param first room for at least kMaxNumberChars characters
/// @return one past the last character written
char* formatNumber(char* first, double value);

/// `t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz`, one row per sample.
std::string poseCsv(const TrajectoryResult& result);

/// `--space sphere`: `t,x1,…,x{m+1}`, one row per sample.
std::string sphereCsv(const SphereResult& result);

}  // namespace cli
}  // namespace se3_interpolation
