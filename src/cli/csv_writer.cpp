#include "csv_writer.h"

#include <charconv>
#include <stdexcept>
#include <system_error>
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

const char kPoseHeader[] = "t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz\n";

/// Writes `value` and then `separator`; returns one past the separator.
inline char* cell(char* first, double value, char separator)
{
  char* end = formatNumber(first, value);
  *end = separator;
  return end + 1;
}
}  // namespace

char* formatNumber(char* first, double value)
{
  const std::to_chars_result r = std::to_chars(first, first + kMaxNumberChars, value);
  if (r.ec != std::errc())
    throw std::logic_error("formatNumber: a double needed more than kMaxNumberChars characters");
  return r.ptr;
}

std::string poseCsv(const TrajectoryResult& result)
{
  std::string out;
  out.reserve(sizeof(kPoseHeader) + result.samples.size() * kPoseColumns * kCellChars);
  out += kPoseHeader;
  char row[kPoseColumns * kCellChars];
  for (const auto& s : result.samples)
  {
    char* p = cell(row, s.time, ',');
    for (double v : { s.pose.p.x(), s.pose.p.y(), s.pose.p.z(), s.pose.q.x(), s.pose.q.y(), s.pose.q.z(), s.pose.q.w() })
      p = cell(p, v, ',');
    for (const Eigen::Vector3d* v : { &s.velocity.linear, &s.velocity.angular, &s.acceleration.linear })
    {
      p = cell(p, v->x(), ',');
      p = cell(p, v->y(), ',');
      p = cell(p, v->z(), ',');
    }
    p = cell(p, s.acceleration.angular.x(), ',');
    p = cell(p, s.acceleration.angular.y(), ',');
    p = cell(p, s.acceleration.angular.z(), '\n');
    out.append(row, p);
  }
  return out;
}

std::string sphereCsv(const SphereResult& result)
{
  const Eigen::Index dim = result.waypoints.front().size();
  const std::size_t columns = static_cast<std::size_t>(dim) + 1;
  std::string out = "t";
  for (Eigen::Index j = 1; j <= dim; ++j)
    out += ",x" + std::to_string(j);
  out += '\n';
  out.reserve(out.size() + result.samples.size() * columns * kCellChars);
  std::vector<char> row(columns * kCellChars);
  for (const auto& s : result.samples)
  {
    char* p = cell(row.data(), s.time, dim > 0 ? ',' : '\n');
    for (Eigen::Index j = 0; j < dim; ++j)
      p = cell(p, s.point[j], j + 1 < dim ? ',' : '\n');
    out.append(row.data(), p);
  }
  return out;
}

}  // namespace cli
}  // namespace se3_interpolation
