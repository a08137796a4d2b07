// The work estimate (planner/work_estimate.h) against the measured time of the same request: for
// every curve family (and corner blends), both geometries, both timings (`stretch` with bounds
// that stretch the curve, `time_optimal`) and N = 100, 1000, 10⁴ waypoints (a bezier 20, 100,
// 400), the estimate in seconds, the measured CPU time of generate() (the least of three runs)
// and their ratio, which the estimate's calibration keeps within [0.5, 2] on the development
// machine (calibrated at the middle size: `--middle` runs only that one; other arguments name the
// curves to run, all by default). Prints one line per case; `--check` exits 1 when a ratio is
// outside [0.5, 2] (run on
// an idle machine: the measured times are wall-clock-free CPU times, but a loaded machine's
// caches still slow them).
//
// Waypoints: a random walk from a fixed seed, each step a rotation of 0.2 … 1 rad about a random
// axis and a translation ~ N(0, 0.5²) m per axis; chord-spaced times; 100 samples. curve fit: a
// noisy 100 Hz recording at its times (bench/recording.h), N = 10³ … 10⁵ poses.
#include <algorithm>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "se3_interpolation/planner/planner.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/planner/work_estimate.h"
#include "random_walk.h"
#include "recording.h"

namespace
{
using namespace se3_interpolation;

TrajectoryRequest request(std::size_t n)
{
  TrajectoryRequest r;
  r.waypoints = se3_bench::randomWalk(n);
  r.max_linear_velocity = 0.5;
  r.max_angular_velocity = 0.5;
  r.max_linear_acceleration = 1.0;
  r.max_angular_acceleration = 1.0;
  return r;
}

double cpuSeconds()
{
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
}  // namespace

int main(int argc, char** argv)
{
  bool check = false;
  bool middle_only = false;  // --middle: only the calibration size (1000 waypoints, a bezier 100)
  std::vector<std::string> curves;  // the curves to run (all when empty)
  for (int i = 1; i < argc; ++i)
  {
    if (std::strcmp(argv[i], "--check") == 0)
      check = true;
    else if (std::strcmp(argv[i], "--middle") == 0)
      middle_only = true;
    else
      curves.emplace_back(argv[i]);
  }
  struct Family
  {
    const char* curve;
    double blend_radius;
    std::vector<std::size_t> sizes;
  };
  const std::vector<Family> families = {
    { "piecewise_geodesic", 0.0, { 100, 1000, 10000 } }, { "piecewise_geodesic", 0.2, { 100, 1000, 10000 } },
    { "bezier", 0.0, { 20, 100, 400 } },                 { "bspline", 0.0, { 100, 1000, 10000 } },
    { "interpolating", 0.0, { 100, 1000, 10000 } },      { "hermite", 0.0, { 100, 1000, 10000 } },
    { "blended", 0.0, { 100, 1000, 10000 } },        { "fit", 0.0, { 1000, 10000, 100000 } },
  };
  PlannerLimits limits;
  limits.max_work_seconds = 1e6;
  limits.max_waypoints = 1000000;
  int outside = 0;
  std::printf("%-20s %-6s %-15s %-12s %6s %12s %12s %7s\n", "curve", "blend", "geometry", "timing", "N", "estimate_s",
              "measured_s", "ratio");
  for (const Family& f : families)
  {
    if (!curves.empty() && std::find(curves.begin(), curves.end(), f.curve) == curves.end())
      continue;
    for (const char* geometry : { "double_geodesic", "screw" })
      for (const char* timing : { "stretch", "time_optimal" })
        for (std::size_t n : f.sizes)
        {
          if (middle_only && n != f.sizes[1])
            continue;
          TrajectoryRequest r = request(n);
          if (std::string(f.curve) == "fit")
          {
            // A fit's waypoints are a recording: a noisy 100 Hz motion at its times.
            const se3_bench::Recording recording = se3_bench::noisyRecording(n);
            r.waypoints = recording.poses;
            r.times = recording.times;
          }
          r.curve = f.curve;
          r.blend_radius = f.blend_radius;
          r.geometry = geometry;
          r.timing = timing;
          const ValidatedRequest v = validateRequest(r, limits);
          const WorkShape shape = workShape(v);
          const std::vector<double> times = waypointTimes(v);
          const WorkEstimate w = estimateWork(shape, expectedSamples(shape, times.back() - times.front()));
          double best = 1e300;
          for (int run = 0; run < 3; ++run)
          {
            const double start = cpuSeconds();
            const TrajectoryResult out = generate(r, limits);
            best = std::min(best, cpuSeconds() - start);
            if (out.samples.empty())
              return 2;
          }
          const double ratio = w.seconds / best;
          const bool ok = ratio >= 0.5 && ratio <= 2.0;
          outside += ok ? 0 : 1;
          std::printf("%-20s %-6g %-15s %-12s %6zu %12.4g %12.4g %7.2f%s\n", f.curve, f.blend_radius, geometry, timing, n,
                      w.seconds, best, ratio, ok ? "" : "  outside [0.5, 2]");
          std::fflush(stdout);
        }
  }
  std::printf("%d of the ratios outside [0.5, 2]\n", outside);
  return check && outside > 0 ? 1 : 0;
}
