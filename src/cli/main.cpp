// se3_interpolate REQUEST.yaml [-o OUT.csv] [--space sphere]
//
// Generates the trajectory of a YAML request without a ROS master: CSV samples to stdout
// (or OUT.csv, written atomically: on any error no file is left), the response figures
// on stderr as `name: value`. Exit status 0 on success, 2 on any error (message on stderr).
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "se3_interpolation/planner.h"
#include "se3_interpolation/sphere_planner.h"
#include "yaml_request.h"

namespace
{
constexpr int kUsageError = 2;

const char* const kUsage = "usage: se3_interpolate REQUEST.yaml [-o OUT.csv] [--space pose|sphere]\n";

struct Arguments
{
  std::string request;
  std::string output;
  std::string space = "pose";
};

Arguments parseArguments(int argc, char** argv)
{
  Arguments a;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if ((arg == "-o" || arg == "--output") && i + 1 < argc)
      a.output = argv[++i];
    else if (arg == "--space" && i + 1 < argc)
      a.space = argv[++i];
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
  return a;
}

std::string poseCsv(const se3_interpolation::TrajectoryResult& result)
{
  std::ostringstream out;
  out << std::setprecision(17);
  out << "t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz\n";
  for (const auto& s : result.samples)
  {
    out << s.time;
    for (double v : { s.pose.p.x(), s.pose.p.y(), s.pose.p.z(), s.pose.q.x(), s.pose.q.y(), s.pose.q.z(), s.pose.q.w() })
      out << ',' << v;
    for (const Eigen::Vector3d* v : { &s.velocity.linear, &s.velocity.angular, &s.acceleration.linear,
                                      &s.acceleration.angular })
      out << ',' << v->x() << ',' << v->y() << ',' << v->z();
    out << '\n';
  }
  return out.str();
}

/// `--space sphere`: t,x1,…,x{m+1}.
std::string sphereCsv(const se3_interpolation::SphereResult& result)
{
  std::ostringstream out;
  out << std::setprecision(17) << 't';
  const Eigen::Index dim = result.waypoints.front().size();
  for (Eigen::Index j = 1; j <= dim; ++j)
    out << ",x" << j;
  out << '\n';
  for (const auto& s : result.samples)
  {
    out << s.time;
    for (Eigen::Index j = 0; j < dim; ++j)
      out << ',' << s.point[j];
    out << '\n';
  }
  return out.str();
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
  std::cerr << std::setprecision(12) << "duration: " << r.duration << "\nlength: " << r.length
            << "\nmax_speed: " << r.max_speed << "\nmax_acceleration: " << r.max_acceleration
            << "\nenergy: " << r.energy << "\n";
  printWaypointTimes(r.waypoint_times);
}

void printFigures(const se3_interpolation::TrajectoryResult& r)
{
  std::cerr << std::setprecision(12) << "duration: " << r.duration << "\nlength: " << r.length
            << "\nrotation_length: " << r.rotation_length << "\nmax_linear_speed: " << r.max_linear_speed
            << "\nmax_angular_speed: " << r.max_angular_speed << "\nenergy: " << r.energy << "\n";
  printWaypointTimes(r.waypoint_times);
}

/// Writes `text` to `path` through a temporary file renamed into place.
void writeAtomically(const std::string& path, const std::string& text)
{
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f << text;
    f.flush();
    if (!f)
    {
      std::remove(tmp.c_str());
      throw std::runtime_error("cannot write '" + path + "'");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot write '" + path + "'");
  }
}
}  // namespace

int main(int argc, char** argv)
{
  try
  {
    const Arguments args = parseArguments(argc, argv);
    YAML::Node root;
    try
    {
      root = YAML::LoadFile(args.request);
    }
    catch (const YAML::BadFile&)
    {
      throw std::invalid_argument("cannot read request file '" + args.request + "'");
    }
    catch (const YAML::Exception& e)
    {
      throw std::invalid_argument("request file '" + args.request + "' is not valid YAML: " + e.what());
    }
    std::string csv;
    if (args.space == "sphere")
    {
      const se3_interpolation::SphereResult result =
          se3_interpolation::generateSphereTrajectory(se3_interpolation::cli::sphereRequestFromYaml(root), {});
      csv = sphereCsv(result);
      printSphereFigures(result);
    }
    else
    {
      const se3_interpolation::TrajectoryResult result =
          se3_interpolation::generateTrajectory(se3_interpolation::cli::requestFromYaml(root), {});
      csv = poseCsv(result);
      printFigures(result);
    }
    if (args.output.empty())
      std::cout << csv << std::flush;
    else
      writeAtomically(args.output, csv);
    return 0;
  }
  catch (const std::exception& e)
  {
    std::cerr << "se3_interpolate: error: " << e.what() << "\n";
    return kUsageError;
  }
}
