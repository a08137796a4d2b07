// The CSV text of se3_interpolate's results (docs/command_line.md "Output").
//
// Every number is written in the shortest form that parses back (strtod, std::from_chars,
// Python's float) to the same double, bit for bit: std::to_chars without a format, which picks
// fixed or scientific notation, whichever is shorter (0.1, 1e-300, 9007199254740992). -0.0 prints
// as -0; the planner passes no ∞ or NaN (planner.h). The rows are formatted in blocks of
// kChunkChars, one block per hardware thread at a time, each by a thread of its own, and handed on
// in order as they finish; a handed-on block's memory is reused for the next, so a 10⁵-sample
// file (40 MB) costs about 40 large writes and a few MiB of memory, not 40 MB of freshly mapped
// memory (whose page faults cost as much as the formatting on a virtual machine).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

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

/// Receives the CSV text in consecutive pieces, in order: the header, then blocks of rows of at
/// most kChunkChars each; called from the calling thread only; may throw, which ends the
/// formatting.
using CsvSink = std::function<void(const char* text, std::size_t size)>;

/// Writes `value` at `first` in its shortest round-trip form.
/// @param first room for at least kMaxNumberChars characters
/// @return one past the last character written
char* formatNumber(char* first, double value);

/// Writes the CSV of samples as they arrive (generate()'s SampleSink, or all at once): the header
/// before the first row, then the rows in order, formatted in blocks of kChunkChars, each by a
/// thread of its own (one per hardware thread at a time) while the caller goes on; the finished
/// blocks reach the sink from the calling thread, in order, and their memory takes the next ones.
/// Nothing reaches the sink before the first add() or finish().
template <class Sample>
class CsvWriter
{
public:
  /// Writes one row of `sample` at `first` (room for row_chars) and returns its end.
  using Row = std::function<char*(const Sample& sample, char* first)>;

  CsvWriter(std::string header, std::size_t row_chars, Row row, CsvSink sink);
  CsvWriter(CsvWriter&&) noexcept;
  /// Waits for the blocks being formatted; hands on nothing more.
  ~CsvWriter();

  /// The rows of samples first … first + count − 1, after those added before.
  void add(const Sample* first, std::size_t count);
  /// Hands on the header (if no row was added) and every row still in flight.
  void finish();

private:
  struct Job;
  class Impl;
  std::unique_ptr<Impl> impl_;
};

/// `t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz`, one row per pose sample; with an
/// arm's `joint_names`, then `q_<joint>` for each joint in chain order, `dq_<joint>`, `ddq_<joint>`
/// (the samples' joint positions, velocities and accelerations).
CsvWriter<TrajectorySample> poseCsvWriter(CsvSink sink, const std::vector<std::string>& joint_names = {});

/// `--space sphere`: `t,x1,…,x{dimension}`, one row per sample of S^{dimension − 1}.
CsvWriter<SphereSample> sphereCsvWriter(Eigen::Index dimension, CsvSink sink);

/// The pose CSV of `result`'s samples, to `sink`.
void writePoseCsv(const TrajectoryResult& result, const CsvSink& sink);

/// `--space sphere`: the CSV of `result`'s samples, to `sink`.
void writeSphereCsv(const SphereResult& result, const CsvSink& sink);

/// The whole text of writePoseCsv.
std::string poseCsv(const TrajectoryResult& result);

/// The whole text of writeSphereCsv.
std::string sphereCsv(const SphereResult& result);

}  // namespace cli
}  // namespace se3_interpolation
