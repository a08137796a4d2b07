// The se3_interpolate command line: happy paths with checked CSV, and errors with exit
// status 2, a message on stderr and no output file. The CSV's numbers parse back to the planner's
// samples bit for bit (csv_writer.h), checked on hard values and on large outputs. Recorded
// waypoints (--waypoints, --bag) read back exactly, from CSV files and from bags the tests write.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <rosbag/bag.h>
#include <std_msgs/String.h>
#include <tf2_msgs/TFMessage.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include "csv_writer.h"
#include "recorded_waypoints.h"
#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/arm/joint_limits.h"
#include "se3_interpolation/planner/planner.h"
#include "yaml_request.h"

namespace
{
struct CliRun
{
  int status = -1;
  std::string out;
  std::string err;
};

std::string slurp(const std::string& path)
{
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

bool exists(const std::string& path)
{
  return std::ifstream(path).good();
}

CliRun run(const std::string& args)
{
  const std::string out = testing::TempDir() + "cli_stdout.txt";
  const std::string err = testing::TempDir() + "cli_stderr.txt";
  const std::string cmd = std::string(SE3_INTERPOLATE_BIN) + " " + args + " >" + out + " 2>" + err;
  CliRun r;
  const int raw = std::system(cmd.c_str());
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

std::string data(const std::string& name)
{
  return std::string(SE3_TEST_DATA) + "/" + name;
}

/// Writes `text` to a file in the test's temporary directory and returns its path.
std::string writeTemp(const std::string& name, const std::string& text)
{
  const std::string path = testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

std::uint64_t bits(double v)
{
  std::uint64_t b;
  std::memcpy(&b, &v, sizeof b);
  return b;
}

/// The rows of a CSV text, every cell parsed with std::from_chars (which must consume the whole
/// cell); `*malformed` counts the cells that did not parse.
std::vector<std::vector<double>> parseCsvExactly(const std::string& text, std::string* header, int* malformed)
{
  std::vector<std::vector<double>> rows;
  const std::size_t header_end = text.find('\n');
  *header = text.substr(0, header_end);
  *malformed = 0;
  const char* p = text.data() + header_end + 1;
  const char* const end = text.data() + text.size();
  while (p < end)
  {
    std::vector<double> row;
    for (;;)
    {
      const char* cell_end = p;
      while (cell_end < end && *cell_end != ',' && *cell_end != '\n')
        ++cell_end;
      double v = 0.0;
      const std::from_chars_result r = std::from_chars(p, cell_end, v);
      if (r.ec != std::errc() || r.ptr != cell_end)
        ++*malformed;
      row.push_back(v);
      p = cell_end + 1;
      if (cell_end == end || *cell_end == '\n')
        break;
    }
    rows.push_back(row);
  }
  return rows;
}

/// The request file at `path` with its sample_count replaced, written to the test's temporary
/// directory (yaml-cpp keeps each scalar's text, so the numbers are those of `path`).
std::string withSampleCount(const std::string& path, const std::string& name, int sample_count)
{
  YAML::Node root = YAML::LoadFile(path);
  root["sample_count"] = sample_count;
  std::ostringstream text;
  text << root << "\n";
  return writeTemp(name, text.str());
}

/// Compares the CSV's rows with the expected rows bit for bit; returns the number of differing
/// values (the first few are reported).
int countBitDifferences(const std::vector<std::vector<double>>& rows, const std::vector<std::vector<double>>& expected)
{
  int differences = 0;
  EXPECT_EQ(rows.size(), expected.size());
  for (std::size_t i = 0; i < std::min(rows.size(), expected.size()); ++i)
  {
    EXPECT_EQ(rows[i].size(), expected[i].size()) << "row " << i;
    for (std::size_t j = 0; j < std::min(rows[i].size(), expected[i].size()); ++j)
    {
      if (bits(rows[i][j]) != bits(expected[i][j]) && ++differences <= 5)
      {
        ADD_FAILURE() << "row " << i << ", column " << j << ": " << std::hexfloat << rows[i][j] << " read, "
                      << expected[i][j] << " sampled";
      }
    }
  }
  return differences;
}

std::vector<std::vector<double>> parseCsv(const std::string& text, std::string* header)
{
  std::istringstream in(text);
  std::getline(in, *header);
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line))
  {
    std::vector<double> row;
    std::istringstream l(line);
    std::string cell;
    while (std::getline(l, cell, ','))
      row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}
}  // namespace

TEST(Cli, PureTranslationCsvIsTheClassicalPolygon)
{
  const CliRun r = run(data("translation.yaml"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::string header;
  const auto rows = parseCsv(r.out, &header);
  EXPECT_EQ(header, "t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz");
  ASSERT_EQ(rows.size(), 5U);
  // t, x, y, vx, vy on the polygon (0,0) → (2,0) in 1 s → (2,4) in 2 s
  const double expected[5][5] = {
    { 0, 0, 0, 2, 0 }, { 0.5, 1, 0, 2, 0 }, { 1, 2, 0, 0, 2 }, { 2, 2, 2, 0, 2 }, { 3, 2, 4, 0, 2 }
  };
  for (int i = 0; i < 5; ++i)
  {
    ASSERT_EQ(rows[i].size(), 20U);
    EXPECT_NEAR(rows[i][0], expected[i][0], 1e-15);
    EXPECT_NEAR(rows[i][1], expected[i][1], 1e-14);
    EXPECT_NEAR(rows[i][2], expected[i][2], 1e-14);
    EXPECT_NEAR(rows[i][8], expected[i][3], 1e-14);
    EXPECT_NEAR(rows[i][9], expected[i][4], 1e-14);
    EXPECT_NEAR(rows[i][7], 1.0, 1e-15);  // qw
  }
  EXPECT_NE(r.err.find("length: 6"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("duration: 3"), std::string::npos) << r.err;
}

TEST(Cli, TimeOptimalPolylineIsTheSumOfTheTrapezoids)
{
  const CliRun r = run(data("time_optimal.yaml"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::string header;
  const auto rows = parseCsv(r.out, &header);
  ASSERT_EQ(rows.size(), 401U);
  // Closed form: rest at the corner, 2 m and 4 m at 1 m/s cruise and 2 m/s^2: 2.5 s + 4.5 s.
  const double duration = rows.back()[0] - rows.front()[0];
  EXPECT_NEAR(duration, 7.0, 0.005 * 7.0);
  const std::size_t at = r.err.find("duration: ");
  ASSERT_NE(at, std::string::npos) << r.err;
  EXPECT_NEAR(std::stod(r.err.substr(at + 10)), duration, 1e-9);
  for (const auto& row : rows)
  {
    EXPECT_LE(Eigen::Vector3d(row[8], row[9], row[10]).norm(), 1.0 * (1 + 1e-9)) << row[0];
    EXPECT_LE(Eigen::Vector3d(row[14], row[15], row[16]).norm(), 2.0 * (1 + 1e-9)) << row[0];
  }
  EXPECT_EQ(Eigen::Vector3d(rows.front()[8], rows.front()[9], rows.front()[10]).norm(), 0.0);
  EXPECT_EQ(Eigen::Vector3d(rows.back()[8], rows.back()[9], rows.back()[10]).norm(), 0.0);
  // Cruising at the bound on the long segment.
  EXPECT_NEAR(rows[300][9], 1.0, 1e-6);

  const CliRun bad = run(data("unknown_timing.yaml"));
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("timing: unknown value 'fastest' (expected one of: stretch, time_optimal, constant_speed)"),
            std::string::npos)
      << bad.err;
}

TEST(Cli, ScrewBezierCsvToFile)
{
  const std::string out = testing::TempDir() + "bezier.csv";
  std::remove(out.c_str());
  const CliRun r = run(data("bezier_screw.yaml") + " -o " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  std::string header;
  const auto rows = parseCsv(slurp(out), &header);
  ASSERT_EQ(rows.size(), 11U);
  // Ends are the first and last waypoints; quaternions are unit and sign-continuous, w ≥ 0 first.
  EXPECT_NEAR(rows.front()[1], 0.0, 1e-15);
  EXPECT_NEAR(rows.back()[1], 0.0, 1e-14);
  EXPECT_NEAR(rows.back()[2], 1.0, 1e-14);
  EXPECT_NEAR(rows.back()[3], 0.5, 1e-14);
  EXPECT_NEAR(std::abs(rows.back()[6]), 1.0, 1e-14);
  EXPECT_GE(rows.front()[7], 0.0);
  for (std::size_t i = 0; i < rows.size(); ++i)
  {
    const Eigen::Vector4d q(rows[i][4], rows[i][5], rows[i][6], rows[i][7]);
    EXPECT_NEAR(q.norm(), 1.0, 1e-14);
    if (i > 0)
    {
      EXPECT_GT(q.dot(Eigen::Vector4d(rows[i - 1][4], rows[i - 1][5], rows[i - 1][6], rows[i - 1][7])), 0.0);
    }
  }
  for (const char* figure :
       { "duration: 2", "length: ", "rotation_length: ", "max_linear_speed: ", "max_angular_speed: ", "energy: " })
    EXPECT_NE(r.err.find(figure), std::string::npos) << figure;
}

/// The classical quintic Hermite interpolant on [0, h] (basis polynomials in u = t/h).
double quinticHermite(double t, double h, double p0, double v0, double a0, double p1, double v1, double a1)
{
  const double u = t / h, u3 = u * u * u, u4 = u3 * u, u5 = u4 * u;
  return (1 - 10 * u3 + 15 * u4 - 6 * u5) * p0 + (u - 6 * u3 + 8 * u4 - 3 * u5) * h * v0 +
         0.5 * (u * u - 3 * u3 + 3 * u4 - u5) * h * h * a0 + 0.5 * (u3 - 2 * u4 + u5) * h * h * a1 +
         (-4 * u3 + 7 * u4 - 3 * u5) * h * v1 + (10 * u3 - 15 * u4 + 6 * u5) * p1;
}

// start_state: the motion starts in the given state and joins the geodesic to the waypoint by the
// classical quintic Hermite polynomial (pure translation); from_current is refused.
TEST(Cli, StartStateIsTheClassicalQuinticAndFromCurrentIsRefused)
{
  const CliRun r = run(data("start_state.yaml"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::string header;
  const auto rows = parseCsv(r.out, &header);
  ASSERT_EQ(rows.size(), 4U);
  // The geodesic start -> (2, 1) over 2 s has velocity (1, 0.5) and no acceleration.
  for (const auto& row : rows)
  {
    const double t = row[0];
    EXPECT_NEAR(row[1], quinticHermite(t, 2.0, 0.0, 1.0, 0.0, 2.0, 1.0, 0.0), 1e-12) << t;
    EXPECT_NEAR(row[2], quinticHermite(t, 2.0, 0.0, 0.0, 2.0, 1.0, 0.5, 0.0), 1e-12) << t;
  }
  EXPECT_NEAR(rows[0][8], 1.0, 1e-12);   // vx at the start
  EXPECT_NEAR(rows[0][15], 2.0, 1e-12);  // ay at the start

  const std::string text = slurp(data("start_state.yaml"));
  const CliRun refused = run(writeTemp("from_current.yaml", text + "from_current: true\n"));
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("from_current: the CLI plays no trajectory"), std::string::npos) << refused.err;
  const CliRun sphere =
      run(writeTemp("start_sphere.yaml",
                    "waypoints: [[1, 0, 0], [0, 1, 0]]\nstart_state: {pose: {position: [0, 0, 0]}}\n") +
          " --space sphere");
  EXPECT_EQ(sphere.status, 2);
  EXPECT_NE(sphere.err.find("start_state:"), std::string::npos) << sphere.err;
}

TEST(Cli, ErrorsExitTwoWithoutOutputFile)
{
  const std::string out = testing::TempDir() + "must_not_exist.csv";
  const std::pair<const char*, const char*> cases[] = {
    { "nan.yaml", "waypoints[0].position.y" },
    { "unknown_curve.yaml", "curve: unknown value 'catmull_rom'" },
    { "bad_syntax.yaml", "not valid YAML" },
    { "does_not_exist.yaml", "cannot read request file" },
  };
  for (const auto& c : cases)
  {
    std::remove(out.c_str());
    const CliRun r = run(data(c.first) + " -o " + out);
    EXPECT_EQ(r.status, 2) << c.first;
    EXPECT_NE(r.err.find(c.second), std::string::npos) << c.first << ": " << r.err;
    EXPECT_FALSE(exists(out)) << c.first;
    EXPECT_FALSE(exists(out + ".tmp")) << c.first;
    EXPECT_TRUE(r.out.empty()) << c.first;
  }
  const CliRun usage = run("");
  EXPECT_EQ(usage.status, 2);
  EXPECT_NE(usage.err.find("usage:"), std::string::npos);
}

TEST(Cli, BlendRadiusCutsTheCornerWithTheEuclideanQuartic)
{
  const CliRun r = run(data("blend_translation.yaml"));
  ASSERT_EQ(r.status, 0) << r.err;
  std::string header;
  const auto rows = parseCsv(r.out, &header);
  ASSERT_EQ(rows.size(), 5U);
  // Outside [0.75, 1.25] s the polygon of translation.yaml at the same times; at t = 1 the
  // quartic Bezier (1.5,0) (1.75,0) (2,0) (2,0.25) (2,0.5) at lambda = 1/2 and its velocity
  // B'(1/2) d(lambda)/dt = (0.5, 0.5) * 2.
  const double expected[5][5] = {
    { 0, 0, 0, 2, 0 }, { 0.5, 1, 0, 2, 0 }, { 1, 30.5 / 16, 1.5 / 16, 1, 1 }, { 2, 2, 2, 0, 2 }, { 3, 2, 4, 0, 2 }
  };
  for (int i = 0; i < 5; ++i)
  {
    ASSERT_EQ(rows[i].size(), 20U);
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(rows[i][k], expected[i][k], 1e-14) << i << " " << k;
    EXPECT_NEAR(rows[i][8], expected[i][3], 1e-13) << i;
    EXPECT_NEAR(rows[i][9], expected[i][4], 1e-13) << i;
  }
  EXPECT_NE(r.err.find("duration: 3"), std::string::npos) << r.err;

  const std::string out = testing::TempDir() + "must_not_exist.csv";
  std::remove(out.c_str());
  const CliRun bad = run(data("blend_other_curve.yaml") + " -o " + out);
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("blend_radius: only used by curve 'piecewise_geodesic'"), std::string::npos) << bad.err;
  EXPECT_FALSE(exists(out));
}

TEST(Cli, SphereSpaceBlendedCircleAndErrors)
{
  // --space sphere: points on the circle of angular radius 1 rad about x3 at times equal to their
  // angles; the blended spline is that circle at unit rate, x(t) = (sin 1 cos t, sin 1 sin t, cos 1),
  // with speed sin 1, covariant acceleration sin 1 cos 1 and energy (eq. 32) 2.9 sin²1 cos²1.
  const std::string out = testing::TempDir() + "sphere.csv";
  std::remove(out.c_str());
  const CliRun r = run(data("sphere_circle_blended.yaml") + " --space sphere -o " + out);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  std::string header;
  const auto rows = parseCsv(slurp(out), &header);
  EXPECT_EQ(header, "t,x1,x2,x3");
  ASSERT_EQ(rows.size(), 30U);
  const double s1 = std::sin(1.0), c1 = std::cos(1.0);
  for (std::size_t i = 0; i < rows.size(); ++i)
  {
    ASSERT_EQ(rows[i].size(), 4U);
    const double t = rows[i][0];
    EXPECT_NEAR(t, 0.1 * static_cast<double>(i), 1e-14);
    EXPECT_NEAR(rows[i][1], s1 * std::cos(t), 1e-12) << t;
    EXPECT_NEAR(rows[i][2], s1 * std::sin(t), 1e-12) << t;
    EXPECT_NEAR(rows[i][3], c1, 1e-12) << t;
  }
  auto figure = [&r](const std::string& name) {
    const std::size_t at = r.err.find(name + ": ");
    return at == std::string::npos ? -1.0 : std::stod(r.err.substr(at + name.size() + 2));
  };
  EXPECT_NEAR(figure("duration"), 2.9, 1e-10) << r.err;
  EXPECT_NEAR(figure("length"), 2.9 * s1, 1e-10) << r.err;
  EXPECT_NEAR(figure("max_speed"), s1, 1e-10) << r.err;
  EXPECT_NEAR(figure("max_acceleration"), s1 * c1, 1e-10) << r.err;
  EXPECT_NEAR(figure("energy"), 2.9 * s1 * s1 * c1 * c1, 1e-10) << r.err;

  const std::string bad = testing::TempDir() + "sphere_must_not_exist.csv";
  const std::pair<const char*, const char*> cases[] = {
    { "sphere_non_unit.yaml", "waypoints[2]: norm 0.5 is outside [0.99, 1.01]" },
    { "sphere_antipodal.yaml", "waypoints[1] and waypoints[2]" },
  };
  for (const auto& c : cases)
  {
    std::remove(bad.c_str());
    const CliRun e = run(data(c.first) + " --space sphere -o " + bad);
    EXPECT_EQ(e.status, 2) << c.first;
    EXPECT_NE(e.err.find(c.second), std::string::npos) << c.first << ": " << e.err;
    EXPECT_FALSE(exists(bad)) << c.first;
    EXPECT_FALSE(exists(bad + ".tmp")) << c.first;
    EXPECT_TRUE(e.out.empty()) << c.first;
  }
  // A pose request is not a sphere request, and the space must be known.
  EXPECT_EQ(run(data("bezier_screw.yaml") + " --space sphere").status, 2);
  const CliRun unknown = run(data("sphere_circle_blended.yaml") + " --space torus");
  EXPECT_EQ(unknown.status, 2);
  EXPECT_NE(unknown.err.find("--space: unknown value 'torus'"), std::string::npos) << unknown.err;
}

// Every number the CSV prints parses back to the same double: the hard cases of shortest
// round-trip printing, and many random doubles of every exponent.
TEST(CsvWriter, EveryNumberParsesBackBitForBit)
{
  using Limits = std::numeric_limits<double>;
  const double two53 = 9007199254740992.0;
  std::vector<double> values = { 0.0,
                                 -0.0,
                                 Limits::denorm_min(),
                                 -Limits::denorm_min(),
                                 std::nextafter(Limits::min(), 0.0),  // the largest subnormal
                                 Limits::min(),
                                 -Limits::min(),
                                 1e-300,
                                 -1e-300,
                                 two53,
                                 two53 - 1.0,
                                 two53 + 2.0,
                                 -(two53 + 2.0),
                                 9223372036854775808.0,
                                 1e22,
                                 1e23,
                                 5e-324 * 3,
                                 Limits::max(),
                                 Limits::lowest(),
                                 0.1,
                                 0.1 + 0.2,
                                 1.0 / 3.0,
                                 -2.0 / 3.0,
                                 M_PI,
                                 std::nextafter(1.0, 2.0),
                                 std::nextafter(1.0, 0.0),
                                 -123456789012345680.0,
                                 100000.0,
                                 1e-7 };
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> typical(-10.0, 10.0);
  for (int i = 0; i < 100000; ++i)
  {
    const std::uint64_t pattern = rng();
    double v;
    std::memcpy(&v, &pattern, sizeof v);
    if (std::isfinite(v))
      values.push_back(v);
    values.push_back(typical(rng));
  }
  int failures = 0;
  for (double v : values)
  {
    char text[se3_interpolation::cli::kMaxNumberChars + 1];
    char* const end = se3_interpolation::cli::formatNumber(text, v);
    *end = '\0';
    double read = 0.0;
    const std::from_chars_result r = std::from_chars(text, end, read);
    const bool exact =
        r.ec == std::errc() && r.ptr == end && bits(read) == bits(v) && bits(std::strtod(text, nullptr)) == bits(v);
    if (!exact && ++failures <= 5)
    {
      ADD_FAILURE() << std::hexfloat << v << " printed as '" << text << "'";
    }
  }
  EXPECT_EQ(failures, 0);

  // The shortest form: what a reader expects, not the 17 digits of iostreams.
  auto printed = [](double v) {
    char text[se3_interpolation::cli::kMaxNumberChars];
    return std::string(text, se3_interpolation::cli::formatNumber(text, v));
  };
  EXPECT_EQ(printed(0.1), "0.1");
  EXPECT_EQ(printed(-0.0), "-0");
  EXPECT_EQ(printed(0.0), "0");
  EXPECT_EQ(printed(2.0), "2");
  EXPECT_EQ(printed(0.1 + 0.2), "0.30000000000000004");
  EXPECT_EQ(printed(1e-300), "1e-300");
  EXPECT_EQ(printed(two53), "9007199254740992");
  EXPECT_EQ(printed(-Limits::min()), "-2.2250738585072014e-308");
  EXPECT_EQ(printed(-Limits::min()).size(), se3_interpolation::cli::kMaxNumberChars);
}

// A large CLI output is the planner's samples for the same request file, bit for bit: poses
// (three curves, screw and double geodesic, time-optimal with rests) and a sphere. 2 × 10⁴ rows
// are two slices formatted at once (csv_writer.cpp) on a machine of two or more cores, and
// several 1 MiB pieces each.
TEST(Cli, LargeCsvIsTheSamplesBitForBit)
{
  using namespace se3_interpolation;
  constexpr int kSamples = 20000;
  const std::string csv = testing::TempDir() + "large.csv";
  for (const std::string& source : { data("bezier_screw.yaml"), data("time_optimal.yaml"),
                                     std::string(SE3_TEST_DATA) + "/../../../config/example_request.yaml" })
  {
    const std::string request = withSampleCount(source, "large_request.yaml", kSamples);
    const CliRun r = run(request + " -o " + csv);
    ASSERT_EQ(r.status, 0) << source << ": " << r.err;
    const TrajectoryResult result = generate(cli::requestFromYaml(YAML::LoadFile(request)), PlannerLimits());
    std::vector<std::vector<double>> expected;
    for (const auto& s : result.samples)
      expected.push_back({ s.time,
                           s.pose.p.x(),
                           s.pose.p.y(),
                           s.pose.p.z(),
                           s.pose.q.x(),
                           s.pose.q.y(),
                           s.pose.q.z(),
                           s.pose.q.w(),
                           s.velocity.linear.x(),
                           s.velocity.linear.y(),
                           s.velocity.linear.z(),
                           s.velocity.angular.x(),
                           s.velocity.angular.y(),
                           s.velocity.angular.z(),
                           s.acceleration.linear.x(),
                           s.acceleration.linear.y(),
                           s.acceleration.linear.z(),
                           s.acceleration.angular.x(),
                           s.acceleration.angular.y(),
                           s.acceleration.angular.z() });
    ASSERT_EQ(expected.size(), static_cast<std::size_t>(kSamples)) << source;
    const std::string text = slurp(csv);
    EXPECT_EQ(text, cli::poseCsv(result)) << source;
    std::string header;
    int malformed = 0;
    const auto rows = parseCsvExactly(text, &header, &malformed);
    EXPECT_EQ(header, "t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz");
    EXPECT_EQ(malformed, 0) << source;
    EXPECT_EQ(countBitDifferences(rows, expected), 0) << source;
  }

  const std::string request = withSampleCount(data("sphere_circle_blended.yaml"), "large_sphere.yaml", kSamples);
  const CliRun r = run(request + " --space sphere -o " + csv);
  ASSERT_EQ(r.status, 0) << r.err;
  const SphereResult result = generate(cli::sphereRequestFromYaml(YAML::LoadFile(request)), PlannerLimits());
  std::vector<std::vector<double>> expected;
  for (const auto& s : result.samples)
    expected.push_back({ s.time, s.point[0], s.point[1], s.point[2] });
  std::string header;
  int malformed = 0;
  const auto rows = parseCsvExactly(slurp(csv), &header, &malformed);
  EXPECT_EQ(header, "t,x1,x2,x3");
  EXPECT_EQ(malformed, 0);
  EXPECT_EQ(countBitDifferences(rows, expected), 0);
}

// The same request in the list spelling and in the service's (rosservice call) spelling: a
// PoseArray with {x, y, z(, w)} maps whose missing components are 0, and map twists.
TEST(Cli, ServiceSpellingEqualsListSpelling)
{
  const std::string tail =
      "times: [0, 1.5, 3, 4]\ncurve: interpolating\ngeometry: screw\nend_condition: clamped\nsample_count: 9\n";
  const std::string list = writeTemp("list_spelling.yaml",
                                     "waypoints:\n"
                                     "  - {position: [0, 0, 0.5], orientation: [0, 0, 0, 1]}\n"
                                     "  - {position: [1, 0, 1], orientation: [0, 0, 0.7071068, 0.7071068]}\n"
                                     "  - {position: [1, 1, 1], orientation: [0.5, 0.5, 0.5, 0.5]}\n"
                                     "  - {position: [0, 1, 0.5], orientation: [0, 0, 1, 0]}\n"
                                     "start_velocity: {linear: [0.2, 0, 0], angular: [0, 0, 0]}\n"
                                     "end_velocity: {linear: [0, 0, 0], angular: [0, 0, 0.5]}\n" +
                                         tail);
  const std::string service =
      writeTemp("service_spelling.yaml",
                "waypoints:\n"
                "  header: {seq: 0, stamp: {secs: 0, nsecs: 0}, frame_id: map}\n"
                "  poses:\n"
                "    - {position: {x: 0, y: 0, z: 0.5}, orientation: {w: 1}}\n"
                "    - {position: {x: 1, z: 1}, orientation: {z: 0.7071068, w: 0.7071068}}\n"
                "    - {position: {x: 1, y: 1, z: 1}, orientation: {x: 0.5, y: 0.5, z: 0.5, w: 0.5}}\n"
                "    - {position: {y: 1, z: 0.5}, orientation: {z: 1}}\n"
                "start_velocity: {linear: {x: 0.2}, angular: {}}\n"
                "end_velocity: {angular: {z: 0.5}}\n"
                "publish: true\nchild_frame_id: moving\noutputs: [trajectory]\n" +
                    tail);
  const CliRun a = run(list);
  const CliRun b = run(service);
  ASSERT_EQ(a.status, 0) << a.err;
  ASSERT_EQ(b.status, 0) << b.err;
  EXPECT_EQ(a.out, b.out);
  EXPECT_EQ(a.err, b.err);
  // The file the README shows for both the CLI and `rosservice call` is this request.
  const CliRun readme = run(std::string(SE3_TEST_DATA) + "/../../../config/example_request.yaml");
  ASSERT_EQ(readme.status, 0) << readme.err;
  EXPECT_EQ(readme.out, a.out);
  // Independent of the spelling: the clamped ends carry the given twists, and the curve passes
  // through the waypoints at their times (rows at t = 0, 0.5, ..., 4: waypoint 1 is row 3).
  std::string header;
  const auto rows = parseCsv(b.out, &header);
  ASSERT_EQ(rows.size(), 9U);
  EXPECT_NEAR(rows[0][8], 0.2, 1e-12);
  EXPECT_NEAR(rows[0][9], 0.0, 1e-12);
  EXPECT_NEAR(rows[8][13], 0.5, 1e-12);
  EXPECT_NEAR(rows[3][1], 1.0, 1e-12);
  EXPECT_NEAR(rows[3][2], 0.0, 1e-12);
  EXPECT_NEAR(rows[3][3], 1.0, 1e-12);
  EXPECT_NEAR(std::abs(rows[8][6]), 1.0, 1e-12);
  EXPECT_NE(b.err.find("waypoint_times: 0, 1.5, 3, 4\n"), std::string::npos) << b.err;
}

TEST(Cli, ServiceSpellingRefusals)
{
  const std::string two = "  - {position: [1, 0, 0]}\n";
  const std::pair<std::string, const char*> cases[] = {
    // {} is the zero quaternion (every component 0), refused as from the service.
    { "waypoints:\n  - {position: {x: 0}, orientation: {}}\n" + two,
      "waypoints[0].orientation: quaternion norm 0 is outside [0.99, 1.01]" },
    { "waypoints:\n  - {position: {x: 0}, orientation: {x: 0, y: 0, z: 0.5}}\n" + two,
      "waypoints[0].orientation: quaternion norm 0.5 is outside" },
    { "waypoints:\n  - {position: {x: 0, q: 1}}\n" + two, "waypoints[0].position.q: unknown field" },
    { "waypoints:\n  - {position: {x: 0}, orientation: {x: 0, w: one}}\n" + two,
      "waypoints[0].orientation.w: 'one' is not a number" },
    { "waypoints:\n  - {position: [0, 0]}\n" + two, "waypoints[0].position: expected 3 numbers [x, y, z], got 2" },
    { "waypoints:\n  - {position: 3}\n" + two, "waypoints[0].position: expected [x, y, z] or {x: .., y: .., z: ..}" },
    { "waypoints:\n  - {position: {x: .nan}}\n" + two, "waypoints[0].position.x: nan is not a finite number" },
    { "waypoints: {header: {frame_id: map}}\n", "waypoints.poses: missing" },
    { "waypoints: {frame_id: map, poses: []}\n", "waypoints.frame_id: unknown field" },
    { "waypoints: {header: {frame: map}, poses: []}\n", "waypoints.header.frame: unknown field" },
    { "waypoints: {poses: []}\n", "waypoints: 0 given; at least 2 are needed" },
    { "waypoints: {poses: [{position: {}}, {position: {x: 1}}]}\nstart_velocity: {linear: {x: 1, w: 0}}\n",
      "start_velocity.linear.w: unknown field" },
    { "waypoints: {poses: [{position: {}}, {position: {x: 1}}]}\nvelocities: [{angular: [1, 2]}, {}]\n",
      "velocities[0].angular: expected 3 numbers" },
    // A service field the CLI cannot serve (no TF): refused by name, not as an unknown field.
    { "waypoints: {poses: [{position: {}}, {position: {x: 1}}]}\nwaypoint_frames: [taught_1]\n",
      "waypoint_frames: the command-line tool has no TF" },
    // The service's outputs, checked as the service checks them.
    { "waypoints: {poses: [{position: {}}, {position: {x: 1}}]}\noutputs: [path, markers]\n",
      "outputs[1]: unknown value 'markers' (expected one of: path, trajectory, joint_trajectory)" },
    { "waypoints: {poses: [{position: {}}, {position: {x: 1}}]}\noutputs: path\n",
      "outputs: expected a list of names" },
  };
  const std::string out = testing::TempDir() + "spelling_must_not_exist.csv";
  for (const auto& c : cases)
  {
    std::remove(out.c_str());
    const CliRun r = run(writeTemp("refused.yaml", c.first) + " -o " + out);
    EXPECT_EQ(r.status, 2) << c.first;
    EXPECT_NE(r.err.find(c.second), std::string::npos) << c.first << "\n" << r.err;
    EXPECT_FALSE(exists(out)) << c.first;
  }
  // {w: 1} is the identity, a position map with missing components is 0: the origin, at rest.
  const CliRun identity = run(writeTemp("identity.yaml",
                                        "waypoints: {poses: [{position: {}, orientation: {w: 1}}, {position: {x: 2}, "
                                        "orientation: {w: 1}}]}\ntimes: [0, 1]\nsample_count: 2\n"));
  ASSERT_EQ(identity.status, 0) << identity.err;
  std::string header;
  const auto rows = parseCsv(identity.out, &header);
  ASSERT_EQ(rows.size(), 2U);
  const std::vector<double> first = { 0, 0, 0, 0, 0, 0, 0, 1 };
  const std::vector<double> last = { 1, 2, 0, 0, 0, 0, 0, 1 };
  for (std::size_t j = 0; j < first.size(); ++j)
  {
    EXPECT_EQ(rows[0][j], first[j]) << j;
    EXPECT_EQ(rows[1][j], last[j]) << j;
  }
}

// A key given twice in one mapping, at any depth: yaml-cpp keeps the first value, so the second
// would be dropped silently. The error names the key's field path and both lines.
TEST(Cli, RepeatedKeysAreErrorsNamingTheKeyAndLine)
{
  const std::string two = "  - {position: [0, 0, 0]}\n  - {position: [1, 0, 0]}\n";
  const std::pair<std::string, const char*> cases[] = {
    { "waypoints:\n" + two + "duration: 1\nduration: 5\n", "duration: repeated key at line 5 (first given at line 4)" },
    { "waypoints:\n  - position: [0, 0, 0]\n    position: [2, 0, 0]\n  - {position: [1, 0, 0]}\n",
      "waypoints[0].position: repeated key at line 3 (first given at line 2)" },
    { "waypoints:\n  - position: [0, 0, 0]\n  - position: [1, 0, 0]\n    orientation: [0, 0, 0, 1]\n"
      "    orientation: [0, 0, 1, 0]\n",
      "waypoints[1].orientation: repeated key at line 5 (first given at line 4)" },
    { "waypoints:\n  - {position: {x: 0, y: 1, x: 2}}\n  - {position: [1, 0, 0]}\n",
      "waypoints[0].position.x: repeated key at line 2" },
    { "waypoints:\n" + two +
          "start_state:\n  pose: {position: [0, 0, 0]}\n  velocity: {linear: [1, 0, 0]}\n"
          "  velocity: {linear: [0, 1, 0]}\n",
      "start_state.velocity: repeated key at line 7 (first given at line 6)" },
    { "waypoints: {poses: [{position: {}}, {position: {x: 1}}], header: {frame_id: a, frame_id: b}}\n",
      "waypoints.header.frame_id: repeated key at line 1" },
  };
  const std::string out = testing::TempDir() + "repeated_must_not_exist.csv";
  for (const auto& c : cases)
  {
    std::remove(out.c_str());
    const CliRun r = run(writeTemp("repeated.yaml", c.first) + " -o " + out);
    EXPECT_EQ(r.status, 2) << c.first;
    EXPECT_NE(r.err.find(c.second), std::string::npos) << c.first << "\n" << r.err;
    EXPECT_FALSE(exists(out)) << c.first;
    EXPECT_FALSE(exists(out + ".tmp")) << c.first;
  }
  // To the standard output: nothing written there either.
  const CliRun stdout_run = run(writeTemp("repeated.yaml", "waypoints:\n" + two + "curve: bezier\ncurve: bspline\n"));
  EXPECT_EQ(stdout_run.status, 2);
  EXPECT_NE(stdout_run.err.find("curve: repeated key at line 5"), std::string::npos) << stdout_run.err;
  EXPECT_TRUE(stdout_run.out.empty()) << stdout_run.out;
  // The sphere space reads the same document check.
  const CliRun sphere = run(writeTemp("repeated_sphere.yaml",
                                      "waypoints: [[1, 0, 0], [0, 1, 0]]\ntimes: [0, 1]\n"
                                      "times: [0, 2]\n") +
                            " --space sphere");
  EXPECT_EQ(sphere.status, 2);
  EXPECT_NE(sphere.err.find("times: repeated key at line 3 (first given at line 2)"), std::string::npos) << sphere.err;
}

namespace
{
std::string writeFile(const std::string& name, const std::string& text)
{
  const std::string path = testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

int shell(const std::string& cmd)
{
  const int raw = std::system(cmd.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

/// Entries of `folder` whose names start with `prefix`.
int countEntries(const std::string& folder, const std::string& prefix)
{
  return shell("exit $(ls -a '" + folder + "' | grep -c '^" + prefix + "')");
}
}  // namespace

// Jerk bounds from a request file: a straight move under v = 0.5 m/s, a = 1 m/s², j = 5 m/s³ is the
// double S of L = 2 m: T_j = a/j = 0.2 s, T_a = T_j + v/a = 0.7 s, T = T_a + L/v = 4.7 s (Biagiotti
// & Melchiorri §3.4); the figures carry the peaks; bad jerk values exit 2 naming the field.
TEST(Cli, JerkBoundsGiveTheDoubleSAndItsPeaks)
{
  const std::string base =
      "waypoints:\n  - {position: [0, 0, 0], orientation: [0, 0, 0, 1]}\n"
      "  - {position: [2, 0, 0], orientation: [0, 0, 0, 1]}\ncurve: piecewise_geodesic\n"
      "timing: time_optimal\nmax_linear_velocity: 0.5\nmax_linear_acceleration: 1.0\n"
      "sample_period: 0.001\n";
  const CliRun r = run(writeFile("cli_jerk.yaml", base + "max_linear_jerk: 5.0\n"));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string figures = "\n" + r.err;  // one `name: value` per line
  const auto figure = [&figures](const std::string& name) {
    const std::size_t at = figures.find("\n" + name + ": ");
    return at == std::string::npos ? -1.0 : std::stod(figures.substr(at + name.size() + 3));
  };
  EXPECT_NEAR(figure("duration"), 4.7, 0.01 * 4.7) << r.err;
  EXPECT_NEAR(figure("peak_linear_acceleration"), 1.0, 1e-4) << r.err;
  EXPECT_NEAR(figure("peak_linear_jerk"), 5.0, 5e-4) << r.err;
  EXPECT_NEAR(figure("max_linear_speed"), 0.5, 5e-5) << r.err;
  // The jerk from the CSV's accelerations (column ax) stays within the bound.
  std::string header;
  const auto rows = parseCsv(r.out, &header);
  ASSERT_GT(rows.size(), 4000U);
  for (std::size_t i = 1; i < rows.size(); ++i)
    EXPECT_LE(std::abs(rows[i][14] - rows[i - 1][14]) / (rows[i][0] - rows[i - 1][0]), 5.0 * (1 + 1e-6)) << rows[i][0];
  const std::string out = testing::TempDir() + "must_not_exist_jerk.csv";
  for (const char* bad : { "max_linear_jerk: -1\n", "max_angular_jerk: .nan\n", "max_linear_jerk: .inf\n" })
  {
    std::remove(out.c_str());
    const CliRun e = run(writeFile("cli_jerk_bad.yaml", base + bad) + " -o " + out);
    EXPECT_EQ(e.status, 2) << bad;
    EXPECT_NE(e.err.find(std::string(bad).substr(0, std::string(bad).find(':') + 1)), std::string::npos) << e.err;
    EXPECT_FALSE(exists(out)) << bad;
  }
}

// timing constant_speed from a request file: a straight move of L = 2 m at V = 0.5 m/s under
// a = 1 m/s² has ramps of T = 15/8 V/a = 0.9375 s (the smoothstep's peak slope 15/8), so it lasts
// L/V + T = 4.9375 s with the window [T, L/V] = [0.9375, 4]; the CSV's speed is V inside it; bad
// speeds and a missing ramp bound exit 2 naming the field.
TEST(Cli, ConstantSpeedHoldsItsSpeedInItsWindow)
{
  const std::string base =
      "waypoints:\n  - {position: [0, 0, 0], orientation: [0, 0, 0, 1]}\n"
      "  - {position: [2, 0, 0], orientation: [0, 0, 0, 1]}\ncurve: piecewise_geodesic\n"
      "timing: constant_speed\nsample_period: 0.001\n";
  const CliRun r = run(writeFile("cli_constant_speed.yaml", base + "speed: 0.5\nmax_linear_acceleration: 1.0\n"));
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string figures = "\n" + r.err;
  const auto figure = [&figures](const std::string& name) {
    const std::size_t at = figures.find("\n" + name + ": ");
    return at == std::string::npos ? -1.0 : std::stod(figures.substr(at + name.size() + 3));
  };
  EXPECT_NEAR(figure("duration"), 4.9375, 1e-9) << r.err;
  EXPECT_NEAR(figure("constant_speed_start"), 0.9375, 1e-9) << r.err;
  EXPECT_NEAR(figure("constant_speed_end"), 4.0, 1e-9) << r.err;
  EXPECT_NEAR(figure("peak_linear_acceleration"), 1.0, 1e-9) << r.err;
  std::string header;
  const auto rows = parseCsv(r.out, &header);
  ASSERT_GT(rows.size(), 4900U);
  std::size_t inside = 0;
  for (const auto& row : rows)
    if (row[0] > 0.9375 && row[0] < 4.0)
    {
      ++inside;
      EXPECT_NEAR(std::hypot(row[8], row[9], row[10]), 0.5, 1e-9) << row[0];
    }
  EXPECT_GT(inside, 3000U);
  const std::string out = testing::TempDir() + "must_not_exist_constant_speed.csv";
  for (const std::string& bad : { std::string("speed: -1\nmax_linear_acceleration: 1\n"),
                                  std::string("speed: .nan\nmax_linear_acceleration: 1\n"),
                                  std::string("speed: .inf\nmax_linear_acceleration: 1\n"),
                                  std::string("max_linear_acceleration: 1\n"), std::string("speed: 0.5\n") })
  {
    std::remove(out.c_str());
    const CliRun e = run(writeFile("cli_constant_speed_bad.yaml", base + bad) + " -o " + out);
    EXPECT_EQ(e.status, 2) << bad;
    const std::string field = bad.rfind("speed: 0.5", 0) == 0 ? "max_linear_acceleration:" : "speed:";
    EXPECT_NE(e.err.find(field), std::string::npos) << bad << e.err;
    EXPECT_FALSE(exists(out)) << bad;
  }
}

// The output goes through a temporary file created exclusively, never through
// a planted file or symbolic link, and nothing is left beside the target.
TEST(CliHostile, OutputNeverWritesThroughAPlantedLink)
{
  const std::string folder = testing::TempDir() + "cli_planted/";
  ASSERT_EQ(shell("rm -rf '" + folder + "' && mkdir -p '" + folder + "'"), 0);
  const std::string victim = folder + "victim.txt";
  std::ofstream(victim) << "precious\n";
  for (const char* planted : { "out.csv.tmp", ".out.csv.tmp" })
    ASSERT_EQ(shell("ln -s '" + victim + "' '" + folder + planted + "'"), 0);
  const CliRun r = run(data("translation.yaml") + " -o " + folder + "out.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(slurp(victim), "precious\n");
  std::string header;
  EXPECT_EQ(parseCsv(slurp(folder + "out.csv"), &header).size(), 5u);
  // Only the planted links and the output: no temporary file left.
  EXPECT_EQ(countEntries(folder, "\\.out\\.csv\\."), 1);
  EXPECT_EQ(countEntries(folder, "out\\.csv"), 2);
  // The output has a plain file's mode (mkstemp's 0600 widened by the umask), here 0644.
  EXPECT_EQ(shell("umask 022 && " + std::string(SE3_INTERPOLATE_BIN) + " " + data("translation.yaml") + " -o " +
                  folder + "mode.csv 2>/dev/null && test \"$(stat -c %a '" + folder + "mode.csv')\" = 644"),
            0);
}

// Row 6: an existing FIFO is written into, not replaced.
TEST(CliHostile, FifoOutputIsWrittenNotReplaced)
{
  const std::string fifo = testing::TempDir() + "cli_fifo";
  const std::string captured = testing::TempDir() + "cli_fifo_captured.csv";
  ASSERT_EQ(shell("rm -f '" + fifo + "' && mkfifo '" + fifo + "'"), 0);
  ASSERT_EQ(shell("cat '" + fifo + "' > '" + captured + "' & " + SE3_INTERPOLATE_BIN + " " + data("translation.yaml") +
                  " -o '" + fifo + "' 2>/dev/null; status=$?; wait; exit $status"),
            0);
  EXPECT_EQ(shell("test -p '" + fifo + "'"), 0) << "the FIFO was replaced";
  std::string header;
  EXPECT_EQ(parseCsv(slurp(captured), &header).size(), 5u);
}

// Row 7: any write error is exit status 2, on the standard output as for -o.
TEST(CliHostile, WriteErrorsExitTwo)
{
  const std::string err = testing::TempDir() + "cli_full_err.txt";
  EXPECT_EQ(shell(std::string(SE3_INTERPOLATE_BIN) + " " + data("translation.yaml") + " >/dev/full 2>" + err), 2);
  EXPECT_NE(slurp(err).find("cannot write the standard output"), std::string::npos) << slurp(err);
  const CliRun full = run(data("translation.yaml") + " -o /dev/full");
  EXPECT_EQ(full.status, 2);
  EXPECT_NE(full.err.find("cannot write '/dev/full'"), std::string::npos) << full.err;
  const CliRun missing = run(data("translation.yaml") + " -o " + testing::TempDir() + "no_such_folder/out.csv");
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("cannot create a temporary file"), std::string::npos) << missing.err;
}

// Row 12: a request file above 8 MiB is refused before it is parsed.
TEST(CliHostile, OversizedRequestFileIsRefusedBeforeParsing)
{
  const std::string path = testing::TempDir() + "cli_huge.yaml";
  {
    std::ofstream f(path);
    f << "waypoints:\n";
    const std::string line = "  - {position: [0, 0, 0]}\n";
    for (std::size_t written = 11; written <= (8u << 20); written += line.size())
      f << line;
  }
  const CliRun r = run(path);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("is larger than 8388608 bytes"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty());
}

// Row 14: durations ROS cannot carry and unbounded frame ids are refused by the CLI too.
TEST(CliHostile, HugeDurationAndLongFrameIdNameTheField)
{
  const std::string waypoints = "waypoints:\n  - {position: [0, 0, 0]}\n  - {position: [1, 0, 0]}\n";
  const std::pair<std::string, const char*> cases[] = {
    { waypoints + "duration: 3e9\n", "error: duration: " },
    { waypoints + "duration: 1e300\n", "error: duration: " },
    { waypoints + "max_linear_velocity: 1e-300\n", "error: max_linear_velocity: " },
    { waypoints + "child_frame_id: " + std::string(300, 'c') + "\n", "error: child_frame_id: " },
    { waypoints + "sample_period: 1e300\n", "" },
  };
  for (const auto& c : cases)
  {
    const CliRun r = run(writeFile("cli_hostile.yaml", c.first));
    if (*c.second == '\0')
    {
      // Row 13: both ends, whatever the period.
      ASSERT_EQ(r.status, 0) << r.err;
      std::string header;
      const auto rows = parseCsv(r.out, &header);
      ASSERT_EQ(rows.size(), 2u);
      EXPECT_EQ(rows[0][0], 0.0);
      EXPECT_EQ(rows[1][0], 1.0);
      continue;
    }
    EXPECT_EQ(r.status, 2) << c.first.substr(0, 100);
    EXPECT_NE(r.err.find(c.second), std::string::npos) << r.err;
    EXPECT_LT(r.err.size(), 300u);
  }
}

// The CLI's work bound is ~max_work_seconds' default (1 s), adjustable with --max-work-seconds.
TEST(CliHostile, MaxWorkSecondsBoundsTheRequest)
{
  const CliRun tight = run(data("bezier_screw.yaml") + " --max-work-seconds 1e-6");
  EXPECT_EQ(tight.status, 2);
  EXPECT_NE(tight.err.find("the limit (max_work_seconds) is 9.9999999999999995e-07 s"), std::string::npos) << tight.err;
  EXPECT_EQ(run(data("bezier_screw.yaml") + " --max-work-seconds 100").status, 0);
  const CliRun bad = run(data("bezier_screw.yaml") + " --max-work-seconds -3");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("--max-work-seconds: '-3' is not a positive number"), std::string::npos) << bad.err;
  // On the sphere too.
  const std::string sphere = data("sphere_circle_blended.yaml") + " --space sphere";
  const CliRun tight_sphere = run(sphere + " --max-work-seconds 1e-6");
  EXPECT_EQ(tight_sphere.status, 2);
  EXPECT_NE(tight_sphere.err.find("the limit (max_work_seconds) is 9.9999999999999995e-07 s"), std::string::npos)
      << tight_sphere.err;
  EXPECT_EQ(run(sphere + " --max-work-seconds 100").status, 0);
}

// --- Recorded waypoints: --waypoints FILE.csv and --bag FILE.bag (recorded_waypoints.h) -------

namespace
{
using se3_interpolation::Pose;
using se3_interpolation::cli::RecordedWaypoints;

/// Pose k of a test recording: a screw-like walk, rotated 0.3 k rad about a tilted axis, shifted by
/// `offset` (so that each frame of a bag has poses of its own).
Pose<double> recordedPose(int k, double offset)
{
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, -0.3, 1.0).normalized();
  const Eigen::Quaterniond q(Eigen::AngleAxisd(0.3 * k + offset, axis));
  return Pose<double>(se3_interpolation::Quaternion<double>(q.w(), q.x(), q.y(), q.z()),
                      Eigen::Vector3d(k + offset, 0.5 * k, -0.2 * k * k));
}

/// The poses 0 … n-1 of recordedPose(k, offset).
std::vector<Pose<double>> recordedPoses(int n, double offset)
{
  std::vector<Pose<double>> poses;
  for (int k = 0; k < n; ++k)
    poses.push_back(recordedPose(k, offset));
  return poses;
}

/// Expects `pose` to be `expected` to `tolerance` (the quaternion up to its sign).
void expectPose(const Pose<double>& pose, const Pose<double>& expected, double tolerance, const std::string& what)
{
  EXPECT_LT((pose.p - expected.p).norm(), tolerance) << what;
  EXPECT_NEAR(std::abs(pose.q.coeffs().dot(expected.q.coeffs())), 1.0, tolerance) << what;
}

/// Expects the recording to be exactly `poses` at `times`.
void expectRecorded(const RecordedWaypoints& r, const std::vector<Pose<double>>& poses,
                    const std::vector<double>& times)
{
  ASSERT_EQ(r.waypoints.size(), poses.size());
  ASSERT_EQ(r.times.size(), times.size());
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    EXPECT_EQ(r.times[i], times[i]) << i;
    EXPECT_EQ(r.waypoints[i].p, poses[i].p) << i;
    EXPECT_EQ(r.waypoints[i].q.coeffs(), poses[i].q.coeffs()) << i;
  }
}

/// Runs the CLI with `recording` (the options that give the waypoints) on a request of `curve`
/// sampled at `times`, and expects its samples to pass through `poses` at `times` (to 1e-9);
/// returns its standard error.
std::string expectCliPassesThrough(const std::string& recording, const std::string& curve,
                                   const std::vector<Pose<double>>& poses, const std::vector<double>& times)
{
  std::string sample_times;
  for (std::size_t i = 0; i < times.size(); ++i)
    sample_times += (i ? ", " : "") + std::string(se3_interpolation::formatNumber(times[i]));
  const std::string options =
      writeTemp("recorded_options.yaml", "curve: " + curve + "\nsample_times: [" + sample_times + "]\n");
  const std::string out = testing::TempDir() + "recorded_out.csv";
  std::remove(out.c_str());
  const CliRun r = run(options + " " + recording + " -o " + out);
  EXPECT_EQ(r.status, 0) << recording << ": " << r.err;
  std::string header;
  const auto rows = parseCsv(slurp(out), &header);
  EXPECT_EQ(rows.size(), poses.size()) << recording;
  for (std::size_t i = 0; i < std::min(rows.size(), poses.size()); ++i)
  {
    EXPECT_NEAR(rows[i][0], times[i], 1e-12) << recording << " row " << i;
    const Pose<double> sampled(se3_interpolation::Quaternion<double>(rows[i][7], rows[i][4], rows[i][5], rows[i][6]),
                               Eigen::Vector3d(rows[i][1], rows[i][2], rows[i][3]));
    expectPose(sampled, poses[i], 1e-9, recording + " row " + std::to_string(i));
  }
  return r.err;
}

/// Expects the CLI run with `args` to exit 2 without writing its output, with every one of `needles`
/// in its message.
void expectRefused(const std::string& args, const std::vector<std::string>& needles)
{
  const std::string out = testing::TempDir() + "refused_out.csv";
  std::remove(out.c_str());
  const CliRun r = run(args + " -o " + out);
  EXPECT_EQ(r.status, 2) << args << ": " << r.err;
  for (const std::string& needle : needles)
    EXPECT_NE(r.err.find(needle), std::string::npos) << args << ": '" << needle << "' not in " << r.err;
  EXPECT_FALSE(exists(out)) << args;
}
}  // namespace

// The CLI's own output reads back: its t and pose columns (of 20) are the waypoints and times, and
// an interpolating spline through them passes through the read poses at the read times.
TEST(RecordedCsv, OwnOutputReadsBackAndIsInterpolated)
{
  const std::string first = testing::TempDir() + "recorded_first.csv";
  ASSERT_EQ(run(data("bezier_screw.yaml") + " -o " + first).status, 0);
  // The brute-force expectation: the output's cells by std::stod, columns by their known place.
  std::string header;
  const auto rows = parseCsv(slurp(first), &header);
  ASSERT_EQ(rows.size(), 11u);
  std::vector<Pose<double>> poses;
  std::vector<double> times;
  for (const auto& row : rows)
  {
    times.push_back(row[0]);
    poses.emplace_back(se3_interpolation::Quaternion<double>(row[7], row[4], row[5], row[6]),
                       Eigen::Vector3d(row[1], row[2], row[3]));
  }
  const RecordedWaypoints read = se3_interpolation::cli::readWaypointsCsv(first);
  expectRecorded(read, poses, times);
  EXPECT_TRUE(read.frame_id.empty());
  for (const char* curve : { "interpolating", "piecewise_geodesic" })
  {
    const std::string err = expectCliPassesThrough("--waypoints " + first, curve, poses, times);
    EXPECT_EQ(err.find("frame_id:"), std::string::npos) << err;
  }
}

// Columns are found by name in any order; other columns, spaces around cells, CRLF line ends and
// a missing final newline are accepted.
TEST(RecordedCsv, ColumnsByNameInAnyOrder)
{
  const std::vector<Pose<double>> poses = recordedPoses(4, 0.0);
  const std::vector<double> times = { 0.0, 0.5, 1.25, 2.0 };
  std::string text = "note,qw, z ,y,x,t,extra,qz,qy,qx\r\n";
  char number[se3_interpolation::cli::kMaxNumberChars];
  const auto cell = [&number](double v) {
    return std::string(number, se3_interpolation::cli::formatNumber(number, v));
  };
  for (std::size_t i = 0; i < poses.size(); ++i)
  {
    const Pose<double>& p = poses[i];
    text += "n" + std::to_string(i) + "," + cell(p.q.w()) + ", " + cell(p.p.z()) + " ," + cell(p.p.y()) + "," +
            cell(p.p.x()) + "," + cell(times[i]) + ",not a number," + cell(p.q.z()) + "," + cell(p.q.y()) + "," +
            cell(p.q.x()) + (i + 1 < poses.size() ? "\r\n" : "");
  }
  expectRecorded(se3_interpolation::cli::parseWaypointsCsv(text, "shuffled.csv"), poses, times);
  const std::string path = writeTemp("recorded_shuffled.csv", text);
  expectCliPassesThrough("--waypoints " + path, "interpolating", poses, times);
}

// Each malformed file is refused naming the file, its line (1-based), column (1-based, in bytes)
// and byte offset (0-based) where the fault starts, exit 2, no output; a cell is quoted with its
// control bytes (a NUL too) as \xHH, so that the message goes on after it.
TEST(RecordedCsv, MalformedFilesNameTheLineColumnAndByte)
{
  const std::string options = writeTemp("recorded_plain.yaml", "curve: piecewise_geodesic\n");
  const std::string head = "t,x,y,z,qx,qy,qz,qw\n";  // 20 bytes
  const std::string row0 = "0,0,0,0,0,0,0,1\n";      // 16 bytes
  const std::string row1 = "1,1,0,0,0,0,0,1\n";
  const struct
  {
    const char* name;
    std::string text;
    std::vector<std::string> needles;
  } cases[] = {
    { "empty.csv", "", { "line 1, column 1 (byte offset 0): the file is empty" } },
    { "no_qw.csv",
      "t,x,y,z,qx,qy,qz\n0,0,0,0,0,0,0\n",
      { "line 1, column 1 (byte offset 0): column 'qw': missing from the header",
        "its cells: 't', 'x', 'y', 'z', 'qx', 'qy', 'qz')" } },
    { "twice.csv",
      "t,x,y,x,z,qx,qy,qz,qw\n",
      { "line 1, column 7 (byte offset 6): column 'x' named twice (cells 2 and 4)" } },
    { "header_only.csv", head, { "line 2, column 1 (byte offset 20): no rows" } },
    { "short_row.csv",
      head + row0 + "1,1,0,0,0,0,1\n",
      { "line 3, column 14 (byte offset 49): 7 cells, but the header (line 1) has 8" } },
    { "long_row.csv", head + row0 + row1 + "2,1,0,0,0,0,0,1,9\n", { "line 4, column 17 (byte offset 68): 9 cells" } },
    { "blank_line.csv", head + row0 + "\n" + row1, { "line 3, column 1 (byte offset 36): 1 cell," } },
    { "word.csv",
      head + row0 + row1 + "2,1,1,0,zero,0,0,1\n",
      { "line 4, column 9 (byte offset 60): cell 5 (column 'qx'): 'zero' is not a finite number" } },
    { "nan.csv",
      head + row0 + "1,nan,0,0,0,0,0,1\n",
      { "line 3, column 3 (byte offset 38): cell 2 (column 'x'): 'nan' is not a finite number" } },
    { "empty_cell.csv",
      head + row0 + "1,1,0,,0,0,0,1\n",
      { "line 3, column 7 (byte offset 42): cell 4 (column 'z'): ''" } },
    { "nul.csv",
      head + row0 + std::string("1,1,0,0,\0x,0,0,1\n", 17),
      { "line 3, column 9 (byte offset 44): cell 5 (column 'qx'): '\\x00x' is not a finite number" } },
    { "nul_header.csv",
      std::string("t,x,y,z,q\0x,qy,qz,qw\n", 21) + row0,
      { "line 1, column 1 (byte offset 0): column 'qx': missing", "'q\\x00x', 'qy'" } },
    { "utf16.csv",
      std::string("\xFF\xFEt\0,\0x\0\n\0", 10),
      { "line 1, column 1 (byte offset 0): the file starts with a UTF-16 byte order mark (FF FE)" } },
    { "bom_word.csv",
      "\xEF\xBB\xBF" + head + "0,0,0,0,0,0,0,one\n",
      { "line 2, column 15 (byte offset 37): cell 8 (column 'qw'): 'one'" } },
    { "cr_word.csv",
      "t,x,y,z,qx,qy,qz,qw\r0,0,0,0,0,0,0,1\r1,one,0,0,0,0,0,1\r",
      { "line 3, column 3 (byte offset 38): cell 2 (column 'x'): 'one'" } },
    { "long_line.csv",
      head + std::string((std::size_t(1) << 20) + 1, '0'),
      { "line 2, column 1 (byte offset 20): the line is longer than 1048576 bytes" } },
    // The request validation's checks, with the line they came from.
    { "not_unit.csv",
      head + row0 + "1,1,0,0,0,0,0,2\n",
      { "waypoints[1]", "line 3, column 1 (byte offset 36) of --waypoints" } },
    { "not_increasing.csv",
      head + row0 + row1 + "1,2,0,0,0,0,0,1\n",
      { "times[2]", "line 4, column 1 (byte offset 52) of --waypoints" } },
  };
  for (const auto& c : cases)
  {
    const std::string path = writeTemp(c.name, c.text);
    std::vector<std::string> needles = c.needles;
    needles.push_back("--waypoints '" + path + "' line ");
    if (c.needles.front().rfind("line ", 0) != 0)
      needles.pop_back();
    expectRefused(options + " --waypoints " + path, needles);
    if (c.needles.front().rfind("line ", 0) == 0)
    {
      try
      {
        se3_interpolation::cli::parseWaypointsCsv(c.text, c.name);
        ADD_FAILURE() << c.name << " parsed";
      }
      catch (const se3_interpolation::InvalidInputError& e)
      {
        EXPECT_NE(std::string(e.what()).find(c.needles.front()), std::string::npos) << e.what();
      }
    }
  }
  expectRefused(options + " --waypoints " + testing::TempDir() + "no_such.csv", { "--waypoints", "cannot be read" });
  // A recording longer than the CLI takes is refused at the first line too many.
  try
  {
    se3_interpolation::cli::parseWaypointsCsv(head + row0 + row1 + "2,2,0,0,0,0,0,1\n", "capped.csv", 2);
    ADD_FAILURE() << "3 rows taken with a limit of 2";
  }
  catch (const se3_interpolation::InvalidInputError& e)
  {
    EXPECT_EQ(std::string(e.what()),
              "--waypoints 'capped.csv' line 4, column 1 (byte offset 52): more than 2 "
              "waypoints, the most se3_interpolate takes");
  }
}

// A UTF-8 byte order mark (a spreadsheet's export) is skipped, and lines may end in '\n', "\r\n"
// or a lone '\r' (old Mac files), also where a read piece of 64 KiB ends between the '\r' and the
// '\n' of a "\r\n", or right after a lone '\r'.
TEST(RecordedCsv, ByteOrderMarkAndEveryLineEndAreRead)
{
  const std::vector<Pose<double>> poses = recordedPoses(5, 0.5);
  const std::vector<double> times = { 0.0, 0.5, 1.0, 1.75, 2.0 };
  char number[se3_interpolation::cli::kMaxNumberChars];
  const auto cell = [&number](double v) {
    return std::string(number, se3_interpolation::cli::formatNumber(number, v));
  };
  const auto text = [&](const std::string& bom, const std::string& end, std::size_t pad) {
    std::string t = bom + "t,x,y,z,qx,qy,qz,qw,pad" + end;
    for (std::size_t i = 0; i < poses.size(); ++i)
    {
      const Pose<double>& p = poses[i];
      t += cell(times[i]) + "," + cell(p.p.x()) + "," + cell(p.p.y()) + "," + cell(p.p.z()) + "," + cell(p.q.x()) +
           "," + cell(p.q.y()) + "," + cell(p.q.z()) + "," + cell(p.q.w()) + ",";
      // Row 1's pad puts its line end's first byte at 65535, the last of the first piece read.
      if (i == 1)
        t += std::string(pad > t.size() ? pad - t.size() : 0, 'p');
      t += end;
    }
    return t;
  };
  for (const std::string bom : { "", "\xEF\xBB\xBF" })
    for (const std::string end : { "\n", "\r\n", "\r" })
    {
      SCOPED_TRACE("BOM " + std::to_string(bom.size()) + ", line end of " + std::to_string(end.size()) + " bytes" +
                   (end == "\r" ? " (CR)" : ""));
      const std::string csv = text(bom, end, 65535);
      ASSERT_EQ(csv[65535], end[0]);
      expectRecorded(se3_interpolation::cli::parseWaypointsCsv(csv, "ends.csv"), poses, times);
      const std::string path = writeTemp("recorded_ends.csv", csv);
      expectRecorded(se3_interpolation::cli::readWaypointsCsv(path), poses, times);
      // Without the last line end too.
      expectRecorded(se3_interpolation::cli::parseWaypointsCsv(csv.substr(0, csv.size() - end.size()), "ends.csv"),
                     poses, times);
    }
  const std::string path = writeTemp("recorded_cr.csv", text("\xEF\xBB\xBF", "\r", 0));
  expectCliPassesThrough("--waypoints " + path, "interpolating", poses, times);
}

// A bad header is refused as soon as it is read, before the rest of the file (so that a 2 GB
// recording with a bad header costs no 2 GB of memory). Read from a FIFO, the writer learns how
// far: it is stopped (EPIPE) once the reader has refused and closed it.
TEST(RecordedCsv, ABadHeaderIsRefusedBeforeTheRowsAreRead)
{
  const std::string fifo = testing::TempDir() + "recording.fifo";
  std::remove(fifo.c_str());
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0) << std::strerror(errno);
  std::signal(SIGPIPE, SIG_IGN);
  constexpr std::size_t kOffered = std::size_t(64) << 20;
  std::size_t written = 0;
  std::thread writer([&] {
    const int fd = ::open(fifo.c_str(), O_WRONLY | O_CLOEXEC);
    if (fd < 0)
      return;
    std::string block = "x,y,z,qx,qy,qz,qw\n";  // no t
    while (block.size() < (std::size_t(64) << 10))
      block += "0,0,0,0,0,0,1\n";
    while (written < kOffered)
    {
      const ssize_t n = ::write(fd, block.data(), block.size());
      if (n <= 0)
        break;
      written += static_cast<std::size_t>(n);
    }
    ::close(fd);
  });
  std::string message;
  try
  {
    se3_interpolation::cli::readWaypointsCsv(fifo);
  }
  catch (const se3_interpolation::InvalidInputError& e)
  {
    message = e.what();
  }
  writer.join();
  std::remove(fifo.c_str());
  EXPECT_NE(message.find("line 1, column 1 (byte offset 0): column 't': missing from the header"), std::string::npos)
      << message;
  EXPECT_LT(written, std::size_t(1) << 20) << "bytes taken from the FIFO before the refusal";
}

// With --waypoints the request file gives the other fields only; the options are checked together.
TEST(RecordedCsv, ConflictsAreRefusedNamingBoth)
{
  const std::string csv = writeTemp("recorded_conflict.csv", "t,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n1,1,0,0,0,0,0,1\n");
  const std::string with_times = writeTemp("recorded_with_times.yaml", "curve: interpolating\ntimes: [0, 1]\n");
  expectRefused(with_times + " --waypoints " + csv, { "times: given both in the request file and by --waypoints" });
  expectRefused(data("bezier_screw.yaml") + " --waypoints " + csv,
                { "waypoints: given both in the request file and by --waypoints '" + csv + "'" });
  const std::string options = writeTemp("recorded_plain.yaml", "curve: piecewise_geodesic\n");
  expectRefused(options + " --waypoints " + csv + " --bag x.bag --topic /tf", { "--waypoints and --bag" });
  expectRefused(options + " --waypoints " + csv + " --space sphere", { "--waypoints", "--space sphere" });
  expectRefused(options + " --bag x.bag --topic /tf --space sphere", { "--bag", "--space sphere" });
  expectRefused(options + " --topic /tf", { "--topic", "--bag FILE.bag" });
  expectRefused(options + " --bag x.bag", { "--topic: missing" });
  EXPECT_EQ(run(options + " --waypoints " + csv).status, 0);
}

// 10⁵ rows parse with std::from_chars, bit for bit (the time is printed, not asserted).
TEST(RecordedCsv, LargeFileParsesBitForBit)
{
  constexpr int kRows = 100000;
  std::mt19937_64 random(30);
  std::uniform_real_distribution<double> value(-10.0, 10.0);
  std::vector<double> cells(static_cast<std::size_t>(kRows) * 8);
  std::string text = "t,x,y,z,qx,qy,qz,qw,vx\n";
  char number[se3_interpolation::cli::kMaxNumberChars];
  for (int i = 0; i < kRows; ++i)
  {
    for (int c = 0; c < 8; ++c)
    {
      double& v = cells[static_cast<std::size_t>(i) * 8 + c];
      v = c == 0 ? i * 0.01 : value(random);
      text.append(number, se3_interpolation::cli::formatNumber(number, v));
      text += ',';
    }
    text += "0\n";
  }
  const auto start = std::chrono::steady_clock::now();
  const RecordedWaypoints r = se3_interpolation::cli::parseWaypointsCsv(text, "large.csv");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "[ timing   ] " << kRows << " rows (" << text.size() / 1000000.0 << " MB) parsed in " << seconds
            << " s\n";
  ASSERT_EQ(r.waypoints.size(), static_cast<std::size_t>(kRows));
  int differences = 0;
  for (std::size_t i = 0; i < r.waypoints.size(); ++i)
  {
    const double* row = &cells[i * 8];
    const Pose<double>& p = r.waypoints[i];
    const double read[8] = { r.times[i], p.p.x(), p.p.y(), p.p.z(), p.q.x(), p.q.y(), p.q.z(), p.q.w() };
    for (int c = 0; c < 8; ++c)
      differences += bits(read[c]) != bits(row[c]);
  }
  EXPECT_EQ(differences, 0);
}

namespace
{
/// The message of pose k of recordedPose(k, offset) from `parent` to `child` at `stamp`.
geometry_msgs::TransformStamped recordedTransform(int k, double offset, const std::string& parent,
                                                  const std::string& child, const ros::Time& stamp)
{
  const Pose<double> p = recordedPose(k, offset);
  geometry_msgs::TransformStamped t;
  t.header.frame_id = parent;
  t.header.stamp = stamp;
  t.child_frame_id = child;
  t.transform.translation.x = p.p.x();
  t.transform.translation.y = p.p.y();
  t.transform.translation.z = p.p.z();
  t.transform.rotation.x = p.q.x();
  t.transform.rotation.y = p.q.y();
  t.transform.rotation.z = p.q.z();
  t.transform.rotation.w = p.q.w();
  return t;
}

/// The test bag's stamp of pose k: 100.5 s + k/4 s.
ros::Time recordedStamp(int k)
{
  return ros::Time(100, 500000000) + ros::Duration(0.25 * k);
}

constexpr int kBagPoses = 4;

/// A bag with the topics: /pose (PoseStamped in map, offset 0), /tool (TransformStamped world →
/// tool0, offset 1), /tf (tool0 in world, offset 2, flange in base, offset 3, and a distractor
/// camera in world, alone in one more message), /tf_mixed (tool0 in world at even k and in base at
/// odd k, offset 4) and /chatter (std_msgs/String).
std::string writeTestBag()
{
  const std::string path = testing::TempDir() + "recorded.bag";
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  for (int k = 0; k < kBagPoses; ++k)
  {
    const ros::Time stamp = recordedStamp(k);
    const geometry_msgs::TransformStamped pose = recordedTransform(k, 0.0, "map", "", stamp);
    geometry_msgs::PoseStamped ps;
    ps.header = pose.header;
    ps.pose.position.x = pose.transform.translation.x;
    ps.pose.position.y = pose.transform.translation.y;
    ps.pose.position.z = pose.transform.translation.z;
    ps.pose.orientation = pose.transform.rotation;
    bag.write("/pose", stamp, ps);
    bag.write("/tool", stamp, recordedTransform(k, 1.0, "world", "tool0", stamp));
    tf2_msgs::TFMessage tf;
    tf.transforms = { recordedTransform(k, 2.0, "world", "tool0", stamp),
                      recordedTransform(k, 3.0, "base", "flange", stamp),
                      recordedTransform(k, 9.0, "world", "camera", stamp) };
    bag.write("/tf", stamp, tf);
    tf2_msgs::TFMessage camera_only;
    camera_only.transforms = { recordedTransform(k + 1, 9.0, "world", "camera", stamp + ros::Duration(0.1)) };
    bag.write("/tf", stamp + ros::Duration(0.1), camera_only);
    tf2_msgs::TFMessage mixed;
    mixed.transforms = { recordedTransform(k, 4.0, k % 2 ? "base" : "world", "tool0", stamp) };
    bag.write("/tf_mixed", stamp, mixed);
    std_msgs::String chatter;
    chatter.data = "pose " + std::to_string(k);
    bag.write("/chatter", stamp, chatter);
  }
  bag.close();
  return path;
}
}  // namespace

// Each message type gives exactly the recorded poses, at their stamps after the first one, in the
// recorded frame; the CLI passes through them and reports the frame and the time origin.
TEST(RecordedBag, ReadsEachTypeExactly)
{
  const std::string bag = writeTestBag();
  std::vector<double> times;
  for (int k = 0; k < kBagPoses; ++k)
    times.push_back(0.25 * k);
  const struct
  {
    const char* topic;
    const char* frame;
    const char* parent;
    double offset;
    const char* frame_id;
  } cases[] = {
    { "/pose", "", "", 0.0, "map" },
    { "/tool", "", "", 1.0, "world" },
    { "/tool", "tool0", "world", 1.0, "world" },
    { "/tf", "tool0", "", 2.0, "world" },
    { "/tf", "flange", "", 3.0, "base" },
    { "/tf", "flange", "base", 3.0, "base" },
  };
  for (const auto& c : cases)
  {
    SCOPED_TRACE(std::string(c.topic) + " --frame " + c.frame + " --parent " + c.parent);
    const RecordedWaypoints r = se3_interpolation::cli::readWaypointsBag({ bag, c.topic, c.frame, c.parent });
    const std::vector<Pose<double>> poses = recordedPoses(kBagPoses, c.offset);
    expectRecorded(r, poses, times);
    EXPECT_EQ(r.frame_id, c.frame_id);
    EXPECT_EQ(r.time_origin_ns, 100500000000LL);
    std::string args = "--bag " + bag + " --topic " + c.topic;
    args += std::string(c.frame).empty() ? "" : std::string(" --frame ") + c.frame;
    args += std::string(c.parent).empty() ? "" : std::string(" --parent ") + c.parent;
    const std::string err = expectCliPassesThrough(args, "interpolating", poses, times);
    EXPECT_NE(err.find(std::string("frame_id: ") + c.frame_id + "\ntime_origin: 100.500000000\n"), std::string::npos)
        << err;
  }
  // --parent picks one parent of a child recorded in two.
  const RecordedWaypoints base = se3_interpolation::cli::readWaypointsBag({ bag, "/tf_mixed", "tool0", "base" });
  expectRecorded(base, { recordedPose(1, 4.0), recordedPose(3, 4.0) }, { 0.0, 0.5 });
  EXPECT_EQ(base.frame_id, "base");
  EXPECT_EQ(base.time_origin_ns, 100750000000LL);
}

// Each refusal names its option, exit 2, no output file.
TEST(RecordedBag, RefusalsNameTheOption)
{
  const std::string bag = writeTestBag();
  const std::string options = writeTemp("recorded_plain.yaml", "curve: piecewise_geodesic\n");
  const std::string not_a_bag = writeTemp("not_a.bag", "t,x,y,z,qx,qy,qz,qw\n");
  const std::pair<std::string, std::vector<std::string>> cases[] = {
    { "--bag " + testing::TempDir() + "no_such.bag --topic /tf --frame tool0", { "--bag '", "cannot be opened" } },
    { "--bag " + not_a_bag + " --topic /tf --frame tool0", { "--bag '" + not_a_bag + "'", "cannot be opened" } },
    { "--bag " + bag + " --topic /odom",
      { "--topic '/odom': no message on it", "'/chatter (std_msgs/String)'", "'/pose (geometry_msgs/PoseStamped)'",
        "'/tf (tf2_msgs/TFMessage)'" } },
    { "--bag " + bag + " --topic /chatter", { "--topic '/chatter': carries std_msgs/String; expected" } },
    { "--bag " + bag + " --topic /tf",
      { "--frame: --topic '/tf' carries tf2_msgs/TFMessage", "'camera', 'flange', 'tool0'" } },
    { "--bag " + bag + " --topic /tf --frame gripper",
      { "--frame 'gripper': no transform of it", "'camera', 'flange', 'tool0'" } },
    { "--bag " + bag + " --topic /tool --frame flange", { "--frame 'flange': no transform of it", "'tool0'" } },
    { "--bag " + bag + " --topic /pose --frame tool0", { "--frame 'tool0'", "PoseStamped, which has no child frame" } },
    { "--bag " + bag + " --topic /tf_mixed --frame tool0",
      { "--parent: the transforms of 'tool0'", "'base', 'world'", "choose one with --parent" } },
    { "--bag " + bag + " --topic /tf --frame tool0 --parent base",
      { "--parent 'base': none of the transforms of "
        "'tool0'",
        "(their frames: 'world')" } },
    { "--bag " + bag + " --topic /pose --parent world", { "--parent 'world': none of the poses on '/pose'", "'map'" } },
  };
  for (const auto& c : cases)
  {
    expectRefused(options + " " + c.first, c.second);
  }
  const std::string with_waypoints = data("bezier_screw.yaml");
  expectRefused(with_waypoints + " --bag " + bag + " --topic /pose",
                { "waypoints: given both", "--bag '" + bag + "'" });
}

// A bag cut short (a recording killed, a copy interrupted) has lost its index: rosbag says only
// "wanted 4 bytes"; the message suggests `rosbag reindex`, which rebuilds the index from the data.
TEST(RecordedBag, ATruncatedBagSuggestsReindex)
{
  const std::string bag = writeTestBag();
  const std::string whole = slurp(bag);
  const std::string options = writeTemp("recorded_plain.yaml", "curve: piecewise_geodesic\n");
  for (const std::size_t size : { whole.size() / 2, whole.size() - 3 })
  {
    const std::string truncated = writeTemp("truncated.bag", whole.substr(0, size));
    expectRefused(options + " --bag " + truncated + " --topic /pose",
                  { "--bag '" + truncated + "'", "cut short", "rosbag reindex " + truncated });
  }
  const std::string not_a_bag = writeTemp("not_a.bag", "t,x,y,z,qx,qy,qz,qw\n");
  const CliRun r = run(options + " --bag " + not_a_bag + " --topic /pose");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.find("reindex"), std::string::npos) << r.err;
}

// curve fit from a CSV recording: the residuals among the figures; --save-bspline writes a bspline
// request that replays the fitted motion (the same CSV to 1e-12); refused for other curves and
// for the sphere, writing nothing.
TEST(CliFit, SaveBsplineReplaysTheFit)
{
  std::mt19937 rng(12);
  std::normal_distribution<double> noise(0.0, 0.001);
  std::string csv = "t,x,y,z,qx,qy,qz,qw\n";
  char number[se3_interpolation::cli::kMaxNumberChars];
  auto cell = [&](double v) { return std::string(number, se3_interpolation::cli::formatNumber(number, v)); };
  for (int i = 0; i <= 300; ++i)
  {
    const double t = 0.01 * i;
    const se3_interpolation::Quaternion<double> q =
        se3_interpolation::so3Exp(Eigen::Vector3d(0.2 * t, -0.1 * t, 0.3 * std::sin(t)));
    csv += cell(t) + "," + cell(0.2 * t + noise(rng)) + "," + cell(std::sin(t) + noise(rng)) + "," + cell(noise(rng)) +
           "," + cell(q.x()) + "," + cell(q.y()) + "," + cell(q.z()) + "," + cell(q.w()) + "\n";
  }
  const std::string recording = writeTemp("fit_recording.csv", csv);
  for (const char* geometry : { "double_geodesic", "screw" })
  {
    const std::string options = writeTemp("fit_options.yaml", std::string("curve: fit\ngeometry: ") + geometry +
                                                                  "\ncontrol_period: 0.5\nsample_count: 41\n");
    const std::string saved = testing::TempDir() + "fitted_bspline.yaml";
    std::remove(saved.c_str());
    const CliRun fit = run(options + " --waypoints " + recording + " --save-bspline " + saved);
    ASSERT_EQ(fit.status, 0) << fit.err;
    EXPECT_NE(fit.err.find("residual_linear: "), std::string::npos) << fit.err;
    EXPECT_NE(fit.err.find("residual_angular: "), std::string::npos) << fit.err;
    EXPECT_NE(fit.err.find("control_poses: 9"), std::string::npos) << fit.err;  // ⌈3 / 0.5⌉ + 3
    const double residual = std::stod(fit.err.substr(fit.err.find("residual_linear: ") + 17));
    EXPECT_GT(residual, 0.0008);  // the noise: 1 mm per axis in x, y, z
    EXPECT_LT(residual, 0.0025);
    const std::string text = slurp(saved);
    ASSERT_NE(text.find("curve: bspline"), std::string::npos) << text;
    EXPECT_NE(text.find(std::string("geometry: ") + geometry), std::string::npos) << text;
    // The saved request keeps the sampling: it replays the fitted samples.
    EXPECT_NE(text.find("sample_count: 41"), std::string::npos) << text;
    const std::string replay = writeTemp("fit_replay.yaml", text);
    const CliRun again = run(replay);
    ASSERT_EQ(again.status, 0) << again.err;
    std::string header_a, header_b;
    const auto a = parseCsv(fit.out, &header_a);
    const auto b = parseCsv(again.out, &header_b);
    ASSERT_EQ(a.size(), 41u);
    ASSERT_EQ(b.size(), a.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      for (std::size_t j = 0; j < 8; ++j)
        worst = std::max(worst, std::abs(a[i][j] - b[i][j]));
    EXPECT_LT(worst, 1e-12) << geometry;
  }
  // Refusals: another curve, the sphere; nothing written.
  const std::string saved = testing::TempDir() + "not_written.yaml";
  std::remove(saved.c_str());
  const std::string interpolating = writeTemp("fit_other.yaml", "curve: interpolating\n");
  const CliRun other = run(interpolating + " --waypoints " + recording + " --save-bspline " + saved);
  EXPECT_EQ(other.status, 2);
  EXPECT_NE(other.err.find("--save-bspline: writes the B-spline of curve 'fit'"), std::string::npos) << other.err;
  EXPECT_FALSE(exists(saved));
  const CliRun sphere = run(interpolating + " --space sphere --save-bspline " + saved);
  EXPECT_EQ(sphere.status, 2);
  EXPECT_FALSE(exists(saved));
}

// The saved B-spline request keeps every field of the fit's request that shapes the samples
// (timing, bounds, speed, sampling, rotation_scale, the waypoints' header): run as it is, its CSV
// is the fit's, row for row.
TEST(CliFit, SavedBsplineReplaysTheSamplesAsTheyAre)
{
  std::string csv = "t,x,y,z,qx,qy,qz,qw\n";
  char number[se3_interpolation::cli::kMaxNumberChars];
  auto cell = [&](double v) { return std::string(number, se3_interpolation::cli::formatNumber(number, v)); };
  for (int i = 0; i <= 200; ++i)
  {
    const double t = 0.01 * i;
    const se3_interpolation::Quaternion<double> q =
        se3_interpolation::so3Exp(Eigen::Vector3d(0.3 * t, -0.2 * t, 0.4 * std::sin(t)));
    csv += cell(t) + "," + cell(0.2 * t) + "," + cell(0.3 * std::sin(2.0 * t)) + "," + cell(0.05 * t * t) + "," +
           cell(q.x()) + "," + cell(q.y()) + "," + cell(q.z()) + "," + cell(q.w()) + "\n";
  }
  const std::string recording = writeTemp("fit_replay_recording.csv", csv);
  // The same poses in the request file, as a PoseArray with a header (its frame goes into the replay).
  std::string in_file = "waypoints:\n  header: {frame_id: odom}\n  poses:\n";
  std::string times = "times: [";
  for (int i = 0; i <= 200; i += 4)
  {
    const double t = 0.01 * i;
    const se3_interpolation::Quaternion<double> q =
        se3_interpolation::so3Exp(Eigen::Vector3d(0.3 * t, -0.2 * t, 0.4 * std::sin(t)));
    in_file += "    - {position: [" + cell(0.2 * t) + ", " + cell(0.3 * std::sin(2.0 * t)) + ", " + cell(0.05 * t * t) +
               "], orientation: [" + cell(q.x()) + ", " + cell(q.y()) + ", " + cell(q.z()) + ", " + cell(q.w()) +
               "]}\n";
    times += (i ? ", " : "") + cell(t);
  }
  in_file += times + "]\n";
  const std::string common =
      "curve: fit\ngeometry: screw\ncontrol_period: 0.4\nrotation_scale: 2.5\n"
      "sample_period: 0.0125\nmax_linear_acceleration: 1\nmax_angular_acceleration: 2\n";
  for (const std::string& timing :
       std::vector<std::string>{ "timing: time_optimal\nmax_linear_velocity: 0.3\nmax_angular_velocity: 0.5\n",
                                 "timing: constant_speed\nspeed: 0.1\n", "max_linear_velocity: 0.05\n" + in_file })
  {
    SCOPED_TRACE(timing.substr(0, 60));
    const bool header = timing.find("header") != std::string::npos;
    const std::string options = writeTemp("fit_replay_options.yaml", common + timing);
    const std::string saved = testing::TempDir() + "fit_replay_saved.yaml";
    std::remove(saved.c_str());
    const CliRun fit = run(options + (header ? "" : " --waypoints " + recording) + " --save-bspline " + saved);
    ASSERT_EQ(fit.status, 0) << fit.err;
    const std::string text = slurp(saved);
    for (const char* field : { "rotation_scale: 2.5", "sample_period: 0.0125", "max_linear_acceleration: 1" })
      EXPECT_NE(text.find(field), std::string::npos) << field << " missing from\n" << text;
    EXPECT_EQ(text.find("control_period"), std::string::npos) << text;
    if (header)
    {
      EXPECT_NE(text.find("waypoints:\n  header: {frame_id: odom}\n  poses:\n    - {position: ["), std::string::npos)
          << text;
    }
    const CliRun again = run(saved);
    ASSERT_EQ(again.status, 0) << again.err;
    std::string header_a, header_b;
    const auto a = parseCsv(fit.out, &header_a);
    const auto b = parseCsv(again.out, &header_b);
    EXPECT_EQ(header_b, header_a);
    ASSERT_GT(a.size(), 100u);
    ASSERT_EQ(b.size(), a.size());
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i)
      for (std::size_t j = 0; j < a[i].size(); ++j)
        worst = std::max(worst, std::abs(a[i][j] - b[i][j]) / (1.0 + std::abs(a[i][j])));
    EXPECT_LT(worst, 1e-9);
  }
}

// 10⁵ recorded poses through the CLI: accepted by the default limits (waypoints and work) and
// fitted; the time is printed, not asserted (docs/performance.md gives the measurement).
TEST(CliFit, HundredThousandPosesFromCsv)
{
  std::string csv = "t,x,y,z,qx,qy,qz,qw\n";
  char number[se3_interpolation::cli::kMaxNumberChars];
  auto cell = [&](double v) { return std::string(number, se3_interpolation::cli::formatNumber(number, v)); };
  std::mt19937 rng(13);
  std::normal_distribution<double> noise(0.0, 0.001);
  for (int i = 0; i < 100000; ++i)
  {
    const double t = 0.01 * i;
    const se3_interpolation::Quaternion<double> q =
        se3_interpolation::so3Exp(Eigen::Vector3d(0.5 * std::sin(0.25 * t), 0.0, 0.3 * std::cos(0.1 * t)));
    csv += cell(t) + "," + cell(0.3 * std::sin(0.3 * t) + noise(rng)) + "," +
           cell(0.2 * std::cos(0.5 * t) + noise(rng)) + "," + cell(noise(rng)) + "," + cell(q.x()) + "," + cell(q.y()) +
           "," + cell(q.z()) + "," + cell(q.w()) + "\n";
  }
  const std::string recording = writeTemp("fit_large.csv", csv);
  const std::string options = writeTemp("fit_large.yaml", "curve: fit\nsample_count: 1000\n");
  const auto start = std::chrono::steady_clock::now();
  const CliRun fit = run(options + " --waypoints " + recording);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "[ timing   ] 10^5 poses fitted through se3_interpolate in " << seconds << " s\n";
  ASSERT_EQ(fit.status, 0) << fit.err;
  EXPECT_NE(fit.err.find("control_poses: 4003"), std::string::npos) << fit.err;  // ⌈999.99 / 0.25⌉ + 3
}

namespace
{
/// docs/examples/ and config/robots/ of the source tree.
std::string sourceFile(const std::string& relative)
{
  return std::string(SE3_TEST_DATA) + "/../../../" + relative;
}

/// The UR5e options of docs/joint_space.md's command, with `extra` after them.
std::string ur5eOptions(const std::string& extra = "")
{
  return " --urdf " + sourceFile("config/robots/ur5e.urdf") + " --base-link base_link --tip-link tool0" +
         " --joint-limits " + sourceFile("config/robots/ur5e_joint_limits.yaml") + extra;
}
}  // namespace

TEST(Cli, ArmColumnsAreThePlannersJointSamples)
{
  const std::string request = sourceFile("docs/examples/ur5e_joint_space.yaml");
  const CliRun r = run(request + ur5eOptions());
  ASSERT_EQ(r.status, 0) << r.err;
  std::string header;
  const std::vector<std::vector<double>> rows = parseCsv(r.out, &header);
  std::string joints;
  for (const char* prefix : { "q_", "dq_", "ddq_" })
    for (const char* name : { "shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
                              "wrist_2_joint", "wrist_3_joint" })
      joints += std::string(",") + prefix + name;
  EXPECT_EQ(header, "t,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz,ax,ay,az,alx,aly,alz" + joints);
  auto model = std::make_shared<se3_interpolation::arm::ArmModel>(
      se3_interpolation::arm::ArmModel::fromUrdfFile(sourceFile("config/robots/ur5e.urdf"), "base_link", "tool0"));
  model->applyLimits(se3_interpolation::arm::readJointLimitsFile(sourceFile("config/robots/ur5e_joint_limits.yaml")));
  const se3_interpolation::TrajectoryResult expected =
      se3_interpolation::generate(se3_interpolation::cli::requestFromYaml(YAML::LoadFile(request)),
                                  se3_interpolation::PlannerLimits(), model);
  ASSERT_EQ(rows.size(), expected.samples.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
  {
    ASSERT_EQ(rows[i].size(), 38u);
    const se3_interpolation::TrajectorySample& s = expected.samples[i];
    for (Eigen::Index k = 0; k < 6; ++k)
    {
      EXPECT_EQ(bits(rows[i][20 + static_cast<std::size_t>(k)]), bits(s.joint_position[k])) << i;
      EXPECT_EQ(bits(rows[i][26 + static_cast<std::size_t>(k)]), bits(s.joint_velocity[k])) << i;
      EXPECT_EQ(bits(rows[i][32 + static_cast<std::size_t>(k)]), bits(s.joint_acceleration[k])) << i;
    }
  }
  EXPECT_NE(r.err.find("joint_shoulder_pan_joint: max_velocity "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("joint_binding: "), std::string::npos) << r.err;
}

TEST(Cli, ArmErrorsExitTwoWithoutOutput)
{
  const std::string request = sourceFile("docs/examples/ur5e_joint_space.yaml");
  const std::string out = testing::TempDir() + "arm_must_not_exist.csv";
  const std::string urdf = " --urdf " + sourceFile("config/robots/ur5e.urdf");
  const std::string bad_limits =
      writeTemp("bad_limits.yaml", "joint_limits:\n  no_such_joint: {has_velocity_limits: true, max_velocity: 1.0}\n");
  const std::pair<std::string, std::string> cases[] = {
    { request + " --urdf /no/such/file.urdf --base-link base_link --tip-link tool0", "/no/such/file.urdf" },
    { request + urdf + " --base-link base_link", "--tip-link" },
    { request + " --tip-link tool0", "--urdf" },
    { request + urdf + " --base-link base_link --tip-link no_such_link", "no_such_link" },
    { request + urdf + " --base-link base_link --tip-link tool0 --joint-limits " + bad_limits, "no_such_joint" },
    { request, "joint_seed" },
    { request + urdf + " --base-link base_link --tip-link tool0 --space sphere", "--urdf" },
  };
  for (const auto& c : cases)
  {
    std::remove(out.c_str());
    const CliRun r = run(c.first + " -o " + out);
    EXPECT_EQ(r.status, 2) << c.first;
    EXPECT_NE(r.err.find(c.second), std::string::npos) << c.first << ": " << r.err;
    EXPECT_FALSE(exists(out)) << c.first;
  }
}
