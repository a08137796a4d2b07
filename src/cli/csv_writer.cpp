#include "csv_writer.h"

#include <algorithm>
#include <charconv>
#include <future>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <vector>

namespace se3_interpolation
{
namespace cli
{
namespace
{
/// The numbers of a pose row: t, position (3), quaternion (4), velocity (6), acceleration (6).
constexpr std::size_t kPoseColumns = 20;

/// Room for one number and the comma or newline after it.
constexpr std::size_t kCellChars = kMaxNumberChars + 1;

/// The fewest rows a thread of their own formats: about 10 ms of work (1 µs a pose row), against
/// the 0.1 ms of starting the thread.
constexpr std::size_t kMinRowsPerSlice = 10000;

const char kPoseHeader[] = "t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz\n";

/// Writes `value` and then `separator`; returns one past the separator.
inline char* cell(char* first, double value, char separator)
{
  char* end = formatNumber(first, value);
  *end = separator;
  return end + 1;
}

/// `header`, then `row(i, first)` for i = begin … end − 1 (each writes at most row_chars
/// characters at first and returns their end), through one reused buffer handed to `sink` when full.
template <class Row>
void streamRows(const std::string& header, std::size_t begin, std::size_t end, std::size_t row_chars, const Row& row,
                const CsvSink& sink)
{
  std::vector<char> buffer(std::max(kChunkChars, header.size() + row_chars));
  char* const first = buffer.data();
  char* const last_row_start = first + buffer.size() - row_chars;
  char* p = std::copy(header.begin(), header.end(), first);
  for (std::size_t i = begin; i < end; ++i)
  {
    if (p > last_row_start)
    {
      sink(first, static_cast<std::size_t>(p - first));
      p = first;
    }
    p = row(i, p);
  }
  sink(first, static_cast<std::size_t>(p - first));
}

/// streamRows for rows 0 … count − 1, cut into consecutive slices formatted at the same time, one
/// per hardware thread (of at least kMinRowsPerSlice rows): the first streams to `sink` in the
/// calling thread, each later one is formatted into a text of its own, handed on in order.
template <class Row>
void writeRows(const std::string& header, std::size_t count, std::size_t row_chars, const Row& row,
               const CsvSink& sink)
{
  const std::size_t threads = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t slices = std::max<std::size_t>(1, std::min(threads, count / kMinRowsPerSlice));
  const std::size_t per_slice = (count + slices - 1) / slices;
  // A thread for each later slice where one can be started, else formatted when it is collected.
  std::vector<std::future<std::string>> later;
  for (std::size_t begin = per_slice; begin < count; begin += per_slice)
    later.push_back(std::async(std::launch::async | std::launch::deferred, [&, begin] {
      const std::size_t end = std::min(count, begin + per_slice);
      std::string text;
      text.reserve((end - begin) * row_chars);
      streamRows(std::string(), begin, end, row_chars, row,
                 [&text](const char* piece, std::size_t size) { text.append(piece, size); });
      return text;
    }));
  streamRows(header, 0, std::min(count, per_slice), row_chars, row, sink);
  for (auto& slice : later)
  {
    const std::string text = slice.get();
    sink(text.data(), text.size());
  }
}

/// The whole text a write*Csv function hands to its sink.
template <class Result>
std::string collect(void (*write)(const Result&, const CsvSink&), const Result& result)
{
  std::string text;
  write(result, [&text](const char* piece, std::size_t size) { text.append(piece, size); });
  return text;
}
}  // namespace

char* formatNumber(char* first, double value)
{
  const std::to_chars_result r = std::to_chars(first, first + kMaxNumberChars, value);
  if (r.ec != std::errc())
    throw std::logic_error("formatNumber: a double needed more than kMaxNumberChars characters");
  return r.ptr;
}

void writePoseCsv(const TrajectoryResult& result, const CsvSink& sink)
{
  const auto& samples = result.samples;
  writeRows(kPoseHeader, samples.size(), kPoseColumns * kCellChars,
            [&samples](std::size_t i, char* p) {
              const TrajectorySample& s = samples[i];
              p = cell(p, s.time, ',');
              for (double v : { s.pose.p.x(), s.pose.p.y(), s.pose.p.z(), s.pose.q.x(), s.pose.q.y(), s.pose.q.z(),
                                s.pose.q.w() })
                p = cell(p, v, ',');
              for (const Eigen::Vector3d* v : { &s.velocity.linear, &s.velocity.angular, &s.acceleration.linear })
              {
                p = cell(p, v->x(), ',');
                p = cell(p, v->y(), ',');
                p = cell(p, v->z(), ',');
              }
              p = cell(p, s.acceleration.angular.x(), ',');
              p = cell(p, s.acceleration.angular.y(), ',');
              return cell(p, s.acceleration.angular.z(), '\n');
            },
            sink);
}

void writeSphereCsv(const SphereResult& result, const CsvSink& sink)
{
  const Eigen::Index dim = result.waypoints.front().size();
  std::string header = "t";
  for (Eigen::Index j = 1; j <= dim; ++j)
    header += ",x" + std::to_string(j);
  header += '\n';
  const auto& samples = result.samples;
  writeRows(header, samples.size(), (static_cast<std::size_t>(dim) + 1) * kCellChars,
            [&samples, dim](std::size_t i, char* p) {
              const SphereSample& s = samples[i];
              p = cell(p, s.time, ',');
              for (Eigen::Index j = 0; j + 1 < dim; ++j)
                p = cell(p, s.point[j], ',');
              return cell(p, s.point[dim - 1], '\n');
            },
            sink);
}

std::string poseCsv(const TrajectoryResult& result)
{
  return collect(&writePoseCsv, result);
}

std::string sphereCsv(const SphereResult& result)
{
  return collect(&writeSphereCsv, result);
}

}  // namespace cli
}  // namespace se3_interpolation
