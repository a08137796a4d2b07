// The CSV text of se3_interpolate's results (docs/command_line.md "Output").
//
// Every number is written in the shortest form that parses back (strtod, std::from_chars,
// Python's float) to the same double, bit for bit: std::to_chars without a format, which picks
// fixed or scientific notation, whichever is shorter (0.1, 1e-300, 9007199254740992). -0.0 prints
// as -0; the planner passes no ∞ or NaN (planner.h). The rows are formatted into one buffer of
// kChunkChars, handed on whenever it is full and reused, so a 10⁵-sample file (40 MB) costs about
// 40 large writes and no 40 MB of freshly mapped memory. Large outputs are cut into consecutive
// slices of rows formatted at the same time, one per hardware thread: the first streams through
// the buffer, each later one is formatted into a text of its own and handed on after it, in order.
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace cli
{
/// The longest shortest-round-trip form of a double: a sign, 17 significant digits, the decimal
/// point and a three-digit exponent, as in -2.2250738585072014e-308.
constexpr std::size_t kMaxNumberChars = 24;

/// The size of the text handed on at once (1 MiB: a large write, and a buffer that stays in the
/// cache while it is formatted and copied out).
constexpr std::size_t kChunkChars = std::size_t(1) << 20;

/// Receives the CSV text in consecutive pieces, in order: of about kChunkChars from the calling
/// thread's slice, then each later slice's whole text; may throw, which ends the formatting.
using CsvSink = std::function<void(const char* text, std::size_t size)>;

/// Writes `value` at `first` in its shortest round-trip form.
/// @param first room for at least kMaxNumberChars characters
/// @return one past the last character written
char* formatNumber(char* first, double value);

/// `t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz`, one row per sample, to `sink`.
void writePoseCsv(const TrajectoryResult& result, const CsvSink& sink);

/// `--space sphere`: `t,x1,…,x{m+1}`, one row per sample, to `sink`.
void writeSphereCsv(const SphereResult& result, const CsvSink& sink);

/// The whole text of writePoseCsv.
std::string poseCsv(const TrajectoryResult& result);

/// The whole text of writeSphereCsv.
std::string sphereCsv(const SphereResult& result);

}  // namespace cli
}  // namespace se3_interpolation
