#include "csv_writer.h"

#include <algorithm>
#include <charconv>
#include <deque>
#include <future>
#include <memory>
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

const char kPoseHeader[] = "t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz\n";

/// Writes `value` and then `separator`; returns one past the separator.
inline char* cell(char* first, double value, char separator)
{
  char* end = formatNumber(first, value);
  *end = separator;
  return end + 1;
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

/// The jobs of a CsvWriter: up to rows_per_job samples and the text of their rows.
template <class Sample>
struct CsvWriter<Sample>::Job
{
  std::vector<Sample> samples;  ///< rows_per_job of them, the first `rows` in use
  std::size_t rows = 0;
  std::unique_ptr<char[]> text;  ///< room for rows_per_job rows
  std::size_t size = 0;          ///< characters of text in use
};

template <class Sample>
class CsvWriter<Sample>::Impl
{
public:
  Impl(std::string header, std::size_t row_chars, Row row, CsvSink sink)
    : header_(std::move(header))
    , row_chars_(row_chars)
    , rows_per_job_(std::max<std::size_t>(1, kChunkChars / row_chars))
    , row_(std::move(row))
    , sink_(std::move(sink))
    , threads_(std::max(1u, std::thread::hardware_concurrency()))
  {
  }

  void add(const Sample* first, std::size_t count)
  {
    writeHeader();
    for (std::size_t i = 0; i < count; ++i)
    {
      if (!filling_)
        filling_ = takeJob();
      filling_->samples[filling_->rows++] = first[i];
      if (filling_->rows == rows_per_job_)
        launch();
    }
  }

  void finish()
  {
    writeHeader();
    if (filling_)
      launch();
    while (!pending_.empty())
      handOnFirst();
  }

private:
  void writeHeader()
  {
    if (header_written_)
      return;
    header_written_ = true;
    sink_(header_.data(), header_.size());
  }

  /// A spare job's memory, else a new job's.
  std::unique_ptr<Job> takeJob()
  {
    if (spare_.empty())
    {
      auto job = std::make_unique<Job>();
      job->samples.resize(rows_per_job_);
      job->text.reset(new char[rows_per_job_ * row_chars_]);
      return job;
    }
    std::unique_ptr<Job> job = std::move(spare_.back());
    spare_.pop_back();
    job->rows = 0;
    return job;
  }

  /// Formats the filling job on a thread of its own (in the caller when there is one hardware
  /// thread), after handing on the oldest job when threads_ are in flight.
  void launch()
  {
    if (pending_.size() >= threads_)
      handOnFirst();
    const std::launch policy = threads_ > 1 ? std::launch::async : std::launch::deferred;
    pending_.push_back(std::async(
        policy,
        [this](std::unique_ptr<Job> job) {
          char* p = job->text.get();
          for (std::size_t i = 0; i < job->rows; ++i)
            p = row_(job->samples[i], p);
          job->size = static_cast<std::size_t>(p - job->text.get());
          return job;
        },
        std::move(filling_)));
  }

  void handOnFirst()
  {
    std::unique_ptr<Job> job = pending_.front().get();
    pending_.pop_front();
    sink_(job->text.get(), job->size);
    spare_.push_back(std::move(job));
  }

  const std::string header_;
  const std::size_t row_chars_;
  const std::size_t rows_per_job_;
  const Row row_;
  const CsvSink sink_;
  const std::size_t threads_;
  bool header_written_ = false;
  std::unique_ptr<Job> filling_;
  std::vector<std::unique_ptr<Job>> spare_;
  /// Last, so that it is destroyed first: its futures wait for the formatting that reads the above.
  std::deque<std::future<std::unique_ptr<Job>>> pending_;
};

template <class Sample>
CsvWriter<Sample>::CsvWriter(std::string header, std::size_t row_chars, Row row, CsvSink sink)
  : impl_(std::make_unique<Impl>(std::move(header), row_chars, std::move(row), std::move(sink)))
{
}

template <class Sample>
CsvWriter<Sample>::CsvWriter(CsvWriter&&) noexcept = default;

template <class Sample>
CsvWriter<Sample>::~CsvWriter() = default;

template <class Sample>
void CsvWriter<Sample>::add(const Sample* first, std::size_t count)
{
  impl_->add(first, count);
}

template <class Sample>
void CsvWriter<Sample>::finish()
{
  impl_->finish();
}

template class CsvWriter<TrajectorySample>;
template class CsvWriter<SphereSample>;

CsvWriter<TrajectorySample> poseCsvWriter(CsvSink sink, const std::vector<std::string>& joint_names)
{
  std::string header(kPoseHeader, sizeof kPoseHeader - 2);
  for (const char* prefix : { ",q_", ",dq_", ",ddq_" })
    for (const std::string& name : joint_names)
      header += prefix + name;
  header += '\n';
  const std::size_t joints = joint_names.size();
  return CsvWriter<TrajectorySample>(
      std::move(header), (kPoseColumns + 3 * joints) * kCellChars,
      [joints](const TrajectorySample& s, char* p) {
        p = cell(p, s.time, ',');
        for (double v :
             { s.pose.p.x(), s.pose.p.y(), s.pose.p.z(), s.pose.q.x(), s.pose.q.y(), s.pose.q.z(), s.pose.q.w() })
          p = cell(p, v, ',');
        for (const Eigen::Vector3d* v : { &s.velocity.linear, &s.velocity.angular, &s.acceleration.linear })
        {
          p = cell(p, v->x(), ',');
          p = cell(p, v->y(), ',');
          p = cell(p, v->z(), ',');
        }
        p = cell(p, s.acceleration.angular.x(), ',');
        p = cell(p, s.acceleration.angular.y(), ',');
        p = cell(p, s.acceleration.angular.z(), joints > 0 ? ',' : '\n');
        // The joints' columns (an arm): positions, velocities, accelerations, each in chain order.
        for (const Eigen::VectorXd* v : { &s.joint_position, &s.joint_velocity, &s.joint_acceleration })
          for (std::size_t k = 0; k < joints; ++k)
            p = cell(p, (*v)[static_cast<Eigen::Index>(k)], v == &s.joint_acceleration && k + 1 == joints ? '\n' : ',');
        return p;
      },
      std::move(sink));
}

CsvWriter<SphereSample> sphereCsvWriter(Eigen::Index dimension, CsvSink sink)
{
  std::string header = "t";
  for (Eigen::Index j = 1; j <= dimension; ++j)
    header += ",x" + std::to_string(j);
  header += '\n';
  return CsvWriter<SphereSample>(
      std::move(header), (static_cast<std::size_t>(dimension) + 1) * kCellChars,
      [](const SphereSample& s, char* p) {
        p = cell(p, s.time, ',');
        for (Eigen::Index j = 0; j + 1 < s.point.size(); ++j)
          p = cell(p, s.point[j], ',');
        return cell(p, s.point[s.point.size() - 1], '\n');
      },
      std::move(sink));
}

void writePoseCsv(const TrajectoryResult& result, const CsvSink& sink)
{
  CsvWriter<TrajectorySample> writer = poseCsvWriter(sink, result.joint_names);
  writer.add(result.samples.data(), result.samples.size());
  writer.finish();
}

void writeSphereCsv(const SphereResult& result, const CsvSink& sink)
{
  CsvWriter<SphereSample> writer = sphereCsvWriter(result.waypoints.front().size(), sink);
  writer.add(result.samples.data(), result.samples.size());
  writer.finish();
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
