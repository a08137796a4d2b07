// se3_interpolate REQUEST.yaml [-o OUT.csv] [--space pose|sphere] [--max-work-seconds S]
//                 [--waypoints FILE.csv | --bag FILE.bag --topic NAME [--frame CHILD] [--parent PARENT]]
//                 [--save-bspline FILE.yaml] [--urdf FILE --base-link NAME --tip-link NAME [--joint-limits FILE]]
//
// Generates the trajectory of a YAML request without a ROS master: CSV samples to stdout
// (or OUT.csv, written atomically: on any error no file is left; csv_writer.h formats them, every
// number in its shortest round-trip form, in pieces of 1 MiB written as they fill), the response figures
// on stderr as `name: value`. Exit status 0 on success, 2 on any error (message on stderr),
// including any error writing the output (a full disk, a closed pipe).
//
// OUT.csv is written to a temporary file created exclusively (mkstemp: O_CREAT | O_EXCL, mode
// 0600) in OUT.csv's folder, flushed with fsync and renamed over OUT.csv, so no pre-existing
// file or symbolic link is ever written through. An existing OUT.csv that is not a regular file
// (a FIFO, a device such as /dev/null) is written directly instead of being replaced.
// The request file is read up to kMaxRequestBytes before parsing: larger files are refused.
//
// --waypoints and --bag give the waypoints and times from a recording (recorded_waypoints.h);
// the request file then carries the other fields only. Recordings are long: the CLI takes up to
// kCliMaxWaypoints waypoints (the work estimate bounds what is done with them).
// --save-bspline writes the B-spline a `curve: fit` request fitted as a `curve: bspline` request
// (its control poses, knots, degree and geometry, every number in its shortest round-trip form,
// and the request file's other fields as given: timing, bounds, sampling, rotation_scale, ...),
// which replays the fitted motion sample for sample (written atomically, like OUT.csv; refused
// for other curves). --urdf and its options give the arm that follows the motion (arm_options.h):
// the CSV gains its joints' columns, stderr its joint figures.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <functional>
#include <iomanip>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "arm_options.h"
#include "csv_writer.h"
#include "recorded_waypoints.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/planner.h"
#include "yaml_request.h"

namespace
{
constexpr int kUsageError = 2;

/// Largest request file read (8 MiB): ~max_waypoints = 20000 waypoints take about 2 MB of YAML
/// and ~max_samples = 200000 sample_times about 4 MB; yaml-cpp needs about 60 bytes of memory
/// per input byte, so this bounds the parse to well under 1 GB.
constexpr std::size_t kMaxRequestBytes = 8u << 20;

/// The piece the request file is read in (64 KiB: a few reads for a typical request; the whole
/// limit allocated and cleared up front took 2000 page faults, a sixth of a large run's time).
constexpr std::size_t kRequestReadChars = 64u << 10;

/// The waypoints a request may have here: a recording of 10⁶ poses (about 100 MB of CSV, under 100
/// MB of memory); the node's ~max_waypoints (default 20000) bounds its buffer and messages instead.
constexpr std::size_t kCliMaxWaypoints = 1000000;

const char* const kUsage =
    "usage: se3_interpolate REQUEST.yaml [-o OUT.csv] [--space pose|sphere] [--max-work-seconds S]\n"
    "                       [--waypoints FILE.csv | --bag FILE.bag --topic NAME [--frame CHILD] [--parent PARENT]]\n"
    "                       [--save-bspline FILE.yaml]\n"
    "                       [--urdf FILE --base-link NAME --tip-link NAME [--joint-limits FILE]]\n";

struct Arguments
{
  std::string request;
  std::string output;
  std::string space = "pose";
  se3_interpolation::PlannerLimits limits;   ///< --max-work-seconds raises or lowers limits.max_work_seconds
  std::string waypoints;                     ///< --waypoints FILE.csv
  se3_interpolation::cli::BagSelection bag;  ///< --bag, --topic, --frame, --parent
  std::string save_bspline;                  ///< --save-bspline FILE.yaml
  se3_interpolation::cli::ArmArguments arm;  ///< --urdf, --base-link, --tip-link, --joint-limits
};

Arguments parseArguments(int argc, char** argv)
{
  Arguments a;
  a.limits.max_waypoints = kCliMaxWaypoints;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if ((arg == "-o" || arg == "--output") && i + 1 < argc)
      a.output = argv[++i];
    else if (arg == "--space" && i + 1 < argc)
      a.space = argv[++i];
    else if (arg == "--waypoints" && i + 1 < argc)
      a.waypoints = argv[++i];
    else if (arg == "--save-bspline" && i + 1 < argc)
      a.save_bspline = argv[++i];
    else if (arg == "--bag" && i + 1 < argc)
      a.bag.path = argv[++i];
    else if (arg == "--topic" && i + 1 < argc)
      a.bag.topic = argv[++i];
    else if (arg == "--frame" && i + 1 < argc)
      a.bag.frame = argv[++i];
    else if (arg == "--parent" && i + 1 < argc)
      a.bag.parent = argv[++i];
    else if (arg == "--max-work-seconds" && i + 1 < argc)
    {
      const std::string value = argv[++i];
      char* end = nullptr;
      a.limits.max_work_seconds = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || !(a.limits.max_work_seconds > 0.0) ||
          !std::isfinite(a.limits.max_work_seconds))
        throw std::invalid_argument("--max-work-seconds: '" + value.substr(0, 40) + "' is not a positive number");
    }
    else if (se3_interpolation::cli::parseArmArgument(argc, argv, &i, &a.arm))
      continue;
    else if (arg == "-h" || arg == "--help")
    {
      std::cout << kUsage;
      std::exit(0);
    }
    else if (!arg.empty() && arg[0] == '-')
      throw std::invalid_argument("unknown option '" + arg + "'\n" + kUsage);
    else if (a.request.empty())
      a.request = arg;
    else
      throw std::invalid_argument("more than one request file given\n" + std::string(kUsage));
  }
  if (a.request.empty())
    throw std::invalid_argument(std::string("no request file given\n") + kUsage);
  if (a.space != "pose" && a.space != "sphere")
    throw std::invalid_argument("--space: unknown value '" + a.space + "' (expected pose or sphere)");
  const bool recorded = !a.waypoints.empty() || !a.bag.path.empty();
  if (!a.waypoints.empty() && !a.bag.path.empty())
    throw std::invalid_argument("--waypoints and --bag: give the recorded waypoints from one of them");
  if (a.bag.path.empty() && !(a.bag.topic.empty() && a.bag.frame.empty() && a.bag.parent.empty()))
    throw std::invalid_argument(std::string(!a.bag.topic.empty() ? "--topic" :
                                            !a.bag.frame.empty() ? "--frame" :
                                                                   "--parent") +
                                ": reads a bag; give it with --bag FILE.bag");
  if (!a.bag.path.empty() && a.bag.topic.empty())
    throw std::invalid_argument("--topic: missing; --bag reads the poses of one topic (--topic NAME)");
  if (!a.save_bspline.empty() && a.space != "pose")
    throw std::invalid_argument("--save-bspline: writes a fitted pose B-spline; not with --space " + a.space);
  if (!a.arm.urdf.empty() && a.space != "pose")
    throw std::invalid_argument("--urdf: an arm follows pose motions; not with --space " + a.space);
  if (recorded && a.space != "pose")
    throw std::invalid_argument(std::string(a.waypoints.empty() ? "--bag" : "--waypoints") +
                                ": recorded waypoints are poses; not with --space " + a.space);
  return a;
}

/// The waypoints and times of --waypoints or --bag, if either is given.
std::optional<se3_interpolation::cli::RecordedWaypoints> readRecorded(const Arguments& args)
{
  if (!args.waypoints.empty())
    return se3_interpolation::cli::readWaypointsCsv(args.waypoints, kCliMaxWaypoints);
  if (!args.bag.path.empty())
    return se3_interpolation::cli::readWaypointsBag(args.bag);
  return std::nullopt;
}

/// A bag's frame and time origin (`frame_id: map`, `time_origin: 1700000000.000000000`), before
/// the figures.
void printRecordedFrame(const se3_interpolation::cli::RecordedWaypoints& recorded)
{
  if (recorded.first_line > 0)
    return;
  char origin[32];
  std::snprintf(origin, sizeof origin, "%lld.%09lld", static_cast<long long>(recorded.time_origin_ns / 1000000000),
                static_cast<long long>(recorded.time_origin_ns % 1000000000));
  std::cerr << "frame_id: " << recorded.frame_id << "\ntime_origin: " << origin << "\n";
}

/// `waypoint_times: t0, t1, ...`: when the trajectory passes (or is controlled by) each waypoint,
/// after any stretch; scripts/plot_trajectory.py --figures marks them.
void printWaypointTimes(const std::vector<double>& times)
{
  std::cerr << "waypoint_times: ";
  for (std::size_t i = 0; i < times.size(); ++i)
    std::cerr << (i ? ", " : "") << times[i];
  std::cerr << "\n";
}

void printSphereFigures(const se3_interpolation::SphereResult& r)
{
  std::cerr << std::setprecision(12) << "duration: " << r.duration << "\nlength: " << r.figures.rotation_length
            << "\nmax_speed: " << r.figures.max_angular_speed
            << "\nmax_acceleration: " << r.figures.max_angular_acceleration
            << "\npeak_jerk: " << r.figures.max_angular_jerk << "\nenergy: " << r.figures.energy << "\n";
  printWaypointTimes(r.waypoint_times);
}

void printFigures(const se3_interpolation::TrajectoryResult& r)
{
  std::cerr << std::setprecision(12) << "duration: " << r.duration << "\nlength: " << r.figures.length
            << "\nrotation_length: " << r.figures.rotation_length
            << "\nmax_linear_speed: " << r.figures.max_linear_speed
            << "\nmax_angular_speed: " << r.figures.max_angular_speed
            << "\npeak_linear_acceleration: " << r.figures.max_linear_acceleration
            << "\npeak_angular_acceleration: " << r.figures.max_angular_acceleration
            << "\npeak_linear_jerk: " << r.figures.max_linear_jerk
            << "\npeak_angular_jerk: " << r.figures.max_angular_jerk << "\nenergy: " << r.figures.energy << "\n";
  if (r.recovery_time > 0.0)
    std::cerr << "recovery_time: " << r.recovery_time << "\n";
  if (r.stop_time > 0.0)
    std::cerr << "stop_time: " << r.stop_time << "\n";
  if (r.constant_speed_end > r.constant_speed_start)
    std::cerr << "constant_speed_start: " << r.constant_speed_start << "\nconstant_speed_end: " << r.constant_speed_end
              << "\n";
  if (!r.knots.empty())
    std::cerr << "residual_linear: " << r.residual_linear << "\nresidual_angular: " << r.residual_angular
              << "\ncontrol_poses: " << r.control_points.size() << "\n";
  printWaypointTimes(r.waypoint_times);
}

/// The fields of a fit request that the fitted B-spline replaces: the curve and its data and
/// options. Every other field (timing, bounds, speed, sampling, rotation_scale, start state, ...)
/// shapes the timed motion or its samples and goes into the replay as given.
const char* const kFitOnlyFields[] = { "curve", "geometry",       "degree",    "knots", "waypoints",
                                       "times", "control_period", "smoothing", "loss",  "loss_scale" };

/// The fields of `root` (the request file) other than kFitOnlyFields, as YAML; "" when none.
std::string replayedFields(const YAML::Node& root)
{
  YAML::Node kept(YAML::NodeType::Map);
  if (root.IsMap())
    for (const auto& field : root)
    {
      const std::string& name = field.first.Scalar();
      if (std::find(std::begin(kFitOnlyFields), std::end(kFitOnlyFields), name) == std::end(kFitOnlyFields))
        kept[name] = field.second;
    }
  if (kept.size() == 0)
    return "";
  YAML::Emitter out;
  out << kept;
  return std::string(out.c_str()) + "\n";
}

/// The fitted B-spline of `r` as a `curve: bspline` request in `geometry` (--save-bspline), with the
/// other fields of the fit's request file `root` (replayedFields) and its waypoints' header, so
/// that the replay gives the fit's samples.
std::string bsplineRequest(const se3_interpolation::TrajectoryResult& r, const std::string& geometry,
                           const std::string& source, const YAML::Node& root)
{
  char cell[se3_interpolation::cli::kMaxNumberChars];
  auto number = [&cell](double v) { return std::string(cell, se3_interpolation::cli::formatNumber(cell, v)); };
  auto list = [&number](std::initializer_list<double> values) {
    std::string s = "[";
    for (double v : values)
      s += (s.size() > 1 ? ", " : "") + number(v);
    return s + "]";
  };
  std::string text = "# The B-spline se3_interpolate fitted to " + source + " (curve fit, residual_linear " +
                     number(r.residual_linear) + " m, residual_angular " + number(r.residual_angular) +
                     " rad): replays the fitted motion.\ncurve: bspline\ngeometry: " + geometry +
                     "\ndegree: " + std::to_string(r.knots.size() - r.control_points.size() - 1) + "\nknots: [";
  for (std::size_t i = 0; i < r.knots.size(); ++i)
    text += (i ? ", " : "") + number(r.knots[i]);
  text += "]\nwaypoints:\n";
  // A PoseArray's header (its frame) stays with the poses.
  const YAML::Node waypoints = root.IsMap() && root["waypoints"] ? root["waypoints"] : YAML::Node();
  const bool header = waypoints.IsMap() && waypoints["header"];
  if (header)
  {
    YAML::Emitter flow;
    flow << YAML::Flow << waypoints["header"];
    text += "  header: " + std::string(flow.c_str()) + "\n  poses:\n";
  }
  for (const se3_interpolation::Pose<double>& x : r.control_points)
    text += std::string(header ? "    " : "  ") + "- {position: " + list({ x.p.x(), x.p.y(), x.p.z() }) +
            ", orientation: " + list({ x.q.x(), x.q.y(), x.q.z(), x.q.w() }) + "}\n";
  return text + replayedFields(root);
}

std::string systemError(const std::string& what)
{
  return what + ": " + std::strerror(errno);
}

/// Writes all of `text` to `fd`; throws naming `what` on any error.
void writeAll(int fd, const char* text, std::size_t size, const std::string& what)
{
  std::size_t done = 0;
  while (done < size)
  {
    const ssize_t n = ::write(fd, text + done, size - done);
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0)
      throw std::runtime_error(systemError("cannot write " + what));
    done += static_cast<std::size_t>(n);
  }
}

/// Produces the output: hands the text, in pieces, to the sink it is given.
using Producer = std::function<void(const se3_interpolation::cli::CsvSink&)>;

/// Writes everything `produce` hands on to `fd`; throws naming `what` on any error.
void writeProduced(int fd, const Producer& produce, const std::string& what)
{
  produce([fd, &what](const char* text, std::size_t size) { writeAll(fd, text, size, what); });
}

/// Writes the text of `produce` to `path` through an exclusively created temporary file renamed
/// into place (see the file comment); an existing non-regular `path` is written directly.
void writeAtomically(const std::string& path, const Producer& produce)
{
  const std::string what = "'" + path + "'";
  struct stat existing;
  if (::stat(path.c_str(), &existing) == 0 && !S_ISREG(existing.st_mode))
  {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0)
      throw std::runtime_error(systemError("cannot open " + what));
    try
    {
      writeProduced(fd, produce, what);
    }
    catch (...)
    {
      ::close(fd);
      throw;
    }
    if (::close(fd) != 0)
      throw std::runtime_error(systemError("cannot write " + what));
    return;
  }
  const std::size_t slash = path.rfind('/');
  const std::string folder = slash == std::string::npos ? "" : path.substr(0, slash + 1);
  const std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  std::string tmp = folder + "." + name + ".XXXXXX";
  const int fd = ::mkstemp(&tmp[0]);
  if (fd < 0)
    throw std::runtime_error(systemError("cannot create a temporary file beside " + what));
  try
  {
    // mkstemp's 0600, widened to what a plain creation would give (0666 less the umask).
    const mode_t mask = ::umask(0);
    ::umask(mask);
    if (::fchmod(fd, 0666 & ~mask) != 0)
      throw std::runtime_error(systemError("cannot set the mode of " + what));
    writeProduced(fd, produce, what);
    if (::fsync(fd) != 0)
      throw std::runtime_error(systemError("cannot write " + what));
  }
  catch (...)
  {
    ::close(fd);
    ::unlink(tmp.c_str());
    throw;
  }
  if (::close(fd) != 0)
  {
    ::unlink(tmp.c_str());
    throw std::runtime_error(systemError("cannot write " + what));
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0)
  {
    const std::string error = systemError("cannot write " + what);
    ::unlink(tmp.c_str());
    throw std::runtime_error(error);
  }
}

/// The request file's text, refused above kMaxRequestBytes before anything is parsed. Read in
/// pieces of kRequestReadChars, so that the text takes the memory of the file, not of the limit.
std::string readRequestFile(const std::string& path)
{
  std::ifstream f(path, std::ios::binary);
  if (!f)
    throw std::invalid_argument("cannot read request file '" + path + "'");
  std::string text;
  char piece[kRequestReadChars];
  while (text.size() <= kMaxRequestBytes && f.read(piece, sizeof piece).gcount() > 0)
    text.append(piece, static_cast<std::size_t>(f.gcount()));
  if (f.bad())
    throw std::invalid_argument("cannot read request file '" + path + "'");
  if (text.size() > kMaxRequestBytes)
    throw std::invalid_argument("request file '" + path + "' is larger than " + std::to_string(kMaxRequestBytes) +
                                " bytes (the limit of se3_interpolate's input)");
  return text;
}

/// The request file parsed as YAML.
YAML::Node loadRequestFile(const std::string& path)
{
  const std::string text = readRequestFile(path);
  try
  {
    return YAML::Load(text);
  }
  catch (const YAML::Exception& e)
  {
    throw std::invalid_argument("request file '" + path + "' is not valid YAML: " + e.what());
  }
}
}  // namespace

int main(int argc, char** argv)
{
  std::optional<se3_interpolation::cli::RecordedWaypoints> recorded;
  try
  {
    const Arguments args = parseArguments(argc, argv);
    const YAML::Node root = loadRequestFile(args.request);
    const auto output = [&args](const Producer& csv) {
      if (args.output.empty())
        writeProduced(STDOUT_FILENO, csv, "the standard output");
      else
        writeAtomically(args.output, csv);
    };
    namespace se3 = se3_interpolation;
    if (args.space == "sphere")
    {
      const se3::SphereRequest request = se3::cli::sphereRequestFromYaml(root);
      se3::SphereResult result;
      output([&](const se3::cli::CsvSink& sink) {
        se3::cli::CsvWriter<se3::SphereSample> writer =
            se3::cli::sphereCsvWriter(request.waypoints.empty() ? 0 : request.waypoints.front().size(), sink);
        result = se3::generate(request, args.limits,
                               se3::SampleSink<se3::SphereSpace>(
                                   [&writer](const se3::SphereSample* first, std::size_t count) {
                                     writer.add(first, count);
                                   }));
        writer.finish();
      });
      printSphereFigures(result);
    }
    else
    {
      recorded = readRecorded(args);
      const se3::TrajectoryRequest request =
          recorded ? se3::cli::requestFromYaml(root, recorded->waypoints, recorded->times, recorded->source) :
                     se3::cli::requestFromYaml(root);
      const std::shared_ptr<const se3::arm::ArmModel> arm = se3::cli::loadArm(args.arm);
      se3::TrajectoryResult result;
      if (args.save_bspline.empty())
        // The samples go to the output as they are computed (planner.h, SampleSink).
        output([&](const se3::cli::CsvSink& sink) {
          se3::cli::CsvWriter<se3::TrajectorySample> writer =
              se3::cli::poseCsvWriter(sink, arm ? arm->jointNames() : std::vector<std::string>());
          result = se3::generate(request, args.limits, arm,
                                 se3::SampleSink<se3::PoseSpace>(
                                     [&writer](const se3::TrajectorySample* first, std::size_t count) {
                                       writer.add(first, count);
                                     }));
          writer.finish();
        });
      else
      {
        // The fitted B-spline first, then the samples: neither is written if the fit fails.
        if (request.curve != se3::FitFamily::kName)
          throw std::invalid_argument("--save-bspline: writes the B-spline of curve 'fit'; the request's curve is '" +
                                      request.curve + "'");
        result = se3::generate(request, args.limits, arm);
        const std::string geometry =
            se3::toString(se3::parseName(request.geometry, "geometry", se3::RequestDefaults::kGeometry));
        const std::string text =
            bsplineRequest(result, geometry, recorded ? recorded->source : "'" + args.request + "'", root);
        writeAtomically(args.save_bspline, [&text](const se3::cli::CsvSink& sink) { sink(text.data(), text.size()); });
        output([&result](const se3::cli::CsvSink& sink) { se3::cli::writePoseCsv(result, sink); });
      }
      if (recorded)
        printRecordedFrame(*recorded);
      printFigures(result);
      if (arm)
        se3::cli::printJointFigures(result, *arm);
    }
    return 0;
  }
  catch (const std::exception& e)
  {
    std::cerr << "se3_interpolate: error: "
              << (recorded ? se3_interpolation::cli::withRecordedOrigin(e.what(), *recorded) : std::string(e.what()))
              << "\n";
    return kUsageError;
  }
}
