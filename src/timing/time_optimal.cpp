// The time-optimal timing (timing/time_optimal.h): the grid, its jets and the solve's loop of
// passes, and the public functions. The passes are in time_optimal_passes.cpp, the final check
// and the figures in time_optimal_check.cpp; the solver's declaration in time_optimal_solver.h.
#include "se3_interpolation/timing/time_optimal.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "se3_interpolation/deadline.h"
#include "se3_interpolation/exceptions.h"
#include "time_optimal_solver.h"

namespace se3_interpolation
{
namespace timing
{
namespace time_optimal_detail
{
namespace
{
/// Grid refinement: an interval is halved while the path's rates change too much across it for
/// the constraints at its ends to stand for its interior (channelVaries, in a bounded channel),
/// at most kMaxRefineDepth times, and the refined grid has at most kMaxRefineGrowth times the
/// intervals of the uniform one (the final check and correction keep the bounds beyond that).
constexpr int kMaxRefineDepth = 24;
constexpr std::size_t kMaxRefineGrowth = 16;
/// The first interval of a motion whose start acceleration is held (TimeOptimalOptions::hold_start):
/// this fraction of the first grid interval.
constexpr double kHoldFraction = 1e-6;

const char* const kVelocityName[2] = { "max_linear_velocity", "max_angular_velocity" };
const char* const kAccelerationName[2] = { "max_linear_acceleration", "max_angular_acceleration" };
const char* const kMotionVerb[2] = { "translates", "rotates" };
}  // namespace

TimeOptimalSolver::TimeOptimalSolver(const PathModel& path, const RateBounds& bounds, const TimeOptimalOptions& options,
                                     bool reusable)
  : path_(path), bounds_(bounds), start_x_(options.start_speed * options.start_speed), hold_start_(options.hold_start)
{
  if (!(std::isfinite(start_x_) && start_x_ >= 0.0))
    throw InvalidInputError("start_state: its speed along the path is " + formatNumber(options.start_speed) +
                            " (it must be finite)");
  buildGrid(options);
  if (reusable)
    grid_ = profile_.s;
  boxes_ = options.boxes;
  box_count_ = boxes_ ? boxes_->size() : 0;
  if (box_count_ > kMaxBoxComponents)
    throw InvalidInputError("timing: 'time_optimal' takes at most " + std::to_string(kMaxBoxComponents) +
                            " joint limits (" + std::to_string(box_count_) + " given)");
  if (box_count_ > 0)
    evaluateBoxJets();
  evaluateGrid(options);
}

void TimeOptimalSolver::reset(const TimeOptimalOptions& options)
{
  if (grid_.empty() || options.hold_start != hold_start_)
    throw InterpolationError("timing: the time-optimal timing was resolved on a grid it did not keep");
  start_x_ = options.start_speed * options.start_speed;
  if (!(std::isfinite(start_x_) && start_x_ >= 0.0))
    throw InvalidInputError("start_state: its speed along the path is " + formatNumber(options.start_speed) +
                            " (it must be finite)");
  // Everything the passes and checks change, as the constructor leaves it.
  profile_ = TimingProfile();
  profile_.s = grid_;
  recovery_end_ = 0;
  start_exceeds_ = false;
  speed_cap_.clear();
  u_cap_.clear();
  k_.clear();
  evaluateGrid(options);
}

const TimingProfile& TimeOptimalSolver::firstPassAgain(const TimeOptimalOptions& options)
{
  reset(options);
  return firstPass();
}

TimingProfile TimeOptimalSolver::solve()
{
  firstPass();
  return finish();
}

const TimingProfile& TimeOptimalSolver::firstPass()
{
  check_quarters_ = start_x_ > 0.0;
  updateCaps();
  backward();
  forward();
  return profile_;
}

TimingProfile TimeOptimalSolver::finish()
{
  localPasses(start_x_ > 0.0 || hold_start_ ? kFixedStartPasses : kLocalPasses);
  if (start_x_ > 0.0 || hold_start_)
    verifyFixedStart();
  else
    verifyAndStretch();
  return std::move(profile_);
}

const TimingProfile& TimeOptimalSolver::localPasses(int passes)
{
  const bool fixed_start = start_x_ > 0.0 || hold_start_;
  for (int pass = 0; pass < passes; ++pass)
  {
    const bool middles = tightenWhereTheMiddlesExceed();
    if (!tightenBoxesWhereTheMiddlesExceed() && !middles)
    {
      // The middles hold: a fixed start must also hold on the whole check (no stretch after it).
      const double margin = pass >= kLocalPasses ? kFixedStartMargin : 0.0;
      if (!fixed_start)
        break;
      const bool boxes = checkBoxes(margin).second;
      if (!tightenWhereTheCheckExceeds(margin) && !boxes)
        break;
    }
    updateCaps();
    backward();
    forward();
  }
  return profile_;
}

void TimeOptimalSolver::growLargest(const PathJet& j, std::array<double, 2>* largest)
{
  for (int c = 0; c < 2; ++c)
    (*largest)[c] = std::max((*largest)[c], j[c].bb);
}

bool TimeOptimalSolver::needsSplit(const PathJet& a, const PathJet& m, const PathJet& b, double d) const
{
  for (int c = 0; c < 2; ++c)
  {
    if (bounded(c) && channelVaries(a[c], m[c], b[c], d, refine_floor_[c]))
      return true;
  }
  return false;
}

void TimeOptimalSolver::refine(double sa, const PathJet& ja, double sb, const PathJet& jb, int depth)
{
  const double sm = 0.5 * (sa + sb);
  const PathJet jm = path_.jet(sm, Side::kRight);
  if (depth < kMaxRefineDepth && profile_.s.size() < grid_limit_ && sm > sa && sm < sb &&
      needsSplit(ja, jm, jb, sb - sa))
  {
    refine(sa, ja, sm, jm, depth + 1);
    addPoint(sm, jm, nullptr, false);
    refine(sm, jm, sb, jb, depth + 1);
    return;
  }
  middle_.push_back(jm);
}

void TimeOptimalSolver::addPoint(double s, const PathJet& right, const PathJet* left, bool corner)
{
  profile_.s.push_back(s);
  right_.push_back(PointData{ right, right, kInf });
  left_of_.push_back(left ? static_cast<std::int64_t>(distinct_left_.size()) : kSameAsRight);
  if (left)
    distinct_left_.push_back(PointData{ *left, *left, kInf });
  corner_.push_back(corner);
}

void TimeOptimalSolver::buildGrid(const TimeOptimalOptions& options)
{
  const std::vector<double> b = gridBreakpoints();
  const UniformGrid uniform = uniformGrid(b, options);
  refineGrid(uniform);
  if (hold_start_)
    holdStart();
}

std::vector<double> TimeOptimalSolver::gridBreakpoints() const
{
  std::vector<double> b = path_.breakpoints();
  for (double x : b)
    if (!std::isfinite(x))
      throw InvalidInputError("timing: 'time_optimal' needs a path with finite times (a breakpoint is at " +
                              formatNumber(x) + " s)");
  // (Sorted: a joined path's rounding may put a breakpoint a hair before the joint.)
  std::sort(b.begin(), b.end());
  b.erase(std::unique(b.begin(), b.end()), b.end());
  if (b.size() < 2 || !(b.back() > b.front()) || !std::isfinite(b.back() - b.front()))
    throw InvalidInputError("timing: 'time_optimal' needs a path of positive duration (this one spans " +
                            formatNumber(b.empty() ? 0.0 : b.back() - b.front()) + " s)");
  return b;
}

TimeOptimalSolver::UniformGrid TimeOptimalSolver::uniformGrid(const std::vector<double>& b,
                                                              const TimeOptimalOptions& options)
{
  const double total = b.back() - b.front();
  const std::size_t pieces = b.size() - 1;
  // The number of uniform intervals on piece j.
  const auto intervals = [&](std::size_t j) {
    const double length = b[j + 1] - b[j];
    const std::size_t share =
        static_cast<std::size_t>(std::ceil(static_cast<double>(options.min_intervals) * length / total));
    return std::max<std::size_t>({ options.intervals_per_piece, share, 2 });
  };
  std::size_t uniform = 1;
  for (std::size_t j = 0; j < pieces; ++j)
    uniform += intervals(j);
  // The uniform grid's points and their jets first: the scale of each channel's |C′|. (Reserved:
  // the grid's vectors are large, and growing them costs copies and fresh pages.)
  // (The left sides only at the pieces' inner ends, where they may differ: index and jet.)
  UniformGrid g;
  std::vector<double>& s = g.s;
  std::vector<PathJet>& right = g.right;
  std::vector<std::pair<std::size_t, PathJet>>& left = g.left;
  std::vector<bool>& corner = g.corner;
  s.reserve(uniform);
  right.reserve(uniform);
  left.reserve(pieces);
  corner.reserve(uniform);
  std::array<double, 2> largest{};
  for (std::size_t j = 0; j < pieces; ++j)
  {
    checkDeadlineEvery(j, kPointsPerDeadlineCheck / 16, kPhase);
    const double length = b[j + 1] - b[j];
    const std::size_t m = intervals(j);
    for (std::size_t k = 0; k < m; ++k)
    {
      s.push_back(b[j] + length * static_cast<double>(k) / static_cast<double>(m));
      right.push_back(path_.jet(s.back(), Side::kRight));
      growLargest(right.back(), &largest);
      const bool inner_end = k == 0 && j > 0;
      if (inner_end)
      {
        left.emplace_back(s.size() - 1, path_.jet(s.back(), Side::kLeft));
        growLargest(left.back().second, &largest);
      }
      corner.push_back(inner_end && path_.isCorner(s.back()));
    }
  }
  s.push_back(b.back());
  right.push_back(path_.jet(b.back(), Side::kLeft));
  corner.push_back(false);
  growLargest(right.back(), &largest);
  for (int c = 0; c < 2; ++c)
    refine_floor_[c] = kMoveTolerance * kMoveTolerance * largest[c];
  grid_limit_ = kMaxRefineGrowth * s.size();
  return g;
}

void TimeOptimalSolver::refineGrid(const UniformGrid& uniform)
{
  const std::vector<double>& s = uniform.s;
  const std::vector<PathJet>& right = uniform.right;
  const std::vector<std::pair<std::size_t, PathJet>>& left = uniform.left;
  const std::vector<bool>& corner = uniform.corner;
  // The refined grid (room for twice the uniform one's points; refinement rarely needs more).
  const std::size_t n = s.size();
  const std::size_t room = 2 * n + 1;
  profile_.s.reserve(room);
  right_.reserve(room);
  left_of_.reserve(room);
  distinct_left_.reserve(left.size());
  corner_.reserve(room);
  middle_.reserve(room);
  std::size_t next_left = 0;  // the first entry of `left` at or after the current point
  const auto leftAt = [&](std::size_t i) -> const PathJet* {
    return next_left < left.size() && left[next_left].first == i ? &left[next_left].second : nullptr;
  };
  for (std::size_t i = 0; i + 1 < n; ++i)
  {
    checkDeadlineEvery(i, kPointsPerDeadlineCheck, kPhase);
    const PathJet* here = leftAt(i);
    addPoint(s[i], right[i], here, corner[i]);
    if (here)
      ++next_left;
    const PathJet* next = leftAt(i + 1);
    refine(s[i], right[i], s[i + 1], next ? *next : right[i + 1], 0);
  }
  addPoint(s[n - 1], right[n - 1], nullptr, false);
}

void TimeOptimalSolver::holdStart()
{
  // The held first interval [s_0, s_0 + ε]: a new point after s_0, and new middles on both sides.
  const double s0 = profile_.s[0];
  const double held = s0 + kHoldFraction * (profile_.s[1] - s0);
  const PathJet j = path_.jet(held, Side::kRight);
  profile_.s.insert(profile_.s.begin() + 1, held);
  right_.insert(right_.begin() + 1, PointData{ j, j, kInf });
  left_of_.insert(left_of_.begin() + 1, kSameAsRight);
  corner_.insert(corner_.begin() + 1, false);
  middle_[0] = path_.jet(0.5 * (held + profile_.s[2]), Side::kRight);
  middle_.insert(middle_.begin(), path_.jet(0.5 * (s0 + held), Side::kRight));
}

void TimeOptimalSolver::evaluateGrid(const TimeOptimalOptions& options)
{
  const std::size_t n = profile_.s.size();
  factor_.assign(n, Rates{ 1.0, 1.0, 1.0, 1.0 });
  box_factor_.assign(2 * box_count_ * n, 1.0);
  changed_.assign(n, 0);
  first_change_ = first_step_ = 0;
  if (options.local_limits)
  {
    speed_cap_.assign(n, kInf);
    u_cap_.assign(n, kInf);
    for (std::size_t i = 0; i < n; ++i)
    {
      const LocalLimit l = options.local_limits(profile_.s[i]);
      factor_[i][2] = factor_[i][3] = l.acceleration_factor;
      speed_cap_[i] = l.speed_cap * l.speed_cap;
      u_cap_[i] = l.path_acceleration_cap;
    }
  }
  // The largest |C′| of each channel: the scale of "moves".
  std::array<double, 2> largest{};
  for (std::size_t i = 0; i < n; ++i)
    for (int c = 0; c < 2; ++c)
      largest[c] = std::max({ largest[c], right_[i].raw[c].bb, left(i).raw[c].bb });
  for (int c = 0; c < 2; ++c)
    largest[c] = std::sqrt(largest[c]);
  const double scale = std::max(largest[0], largest[1]);
  if (!(scale > 0.0) || !std::isfinite(scale))
    throw InvalidInputError("timing: 'time_optimal' needs a path that moves (the curve stands still)");
  bool any_bound = false;
  for (int c = 0; c < 2; ++c)
  {
    moves_[c] = largest[c] > kMoveTolerance * scale;
    floor_[c] = kMoveTolerance * largest[c] * kMoveTolerance * largest[c];
    any_bound = any_bound || bounds_.velocity[c] > 0.0 || bounds_.acceleration[c] > 0.0;
  }
  if (!any_bound && !boxesBoundTheMotion())
    throw InvalidInputError(
        "max_linear_velocity, max_angular_velocity, max_linear_acceleration, max_angular_acceleration: all 0 "
        "(unbounded); timing 'time_optimal' needs bounds (at least an acceleration bound on the motion)");
  for (std::size_t i = 0; i < n; ++i)
  {
    prepare(&right_[i], profile_.s[i]);
    if (PointData* l = distinctLeft(i))
      prepare(l, profile_.s[i]);
  }
  // A start that itself exceeds a bound (its speed, or with hold_start its acceleration): the
  // recovery from it is exempt from the checks (it is what the bounds cannot hold).
  const Rates start = needs(right_[0].raw, start_x_, 0.0);
  for (int q = 0; q < 4; ++q)
    start_exceeds_ = start_exceeds_ || (start_x_ > 0.0 && start[q] > 1.0 + kRoundingExcess && (q < 2 || hold_start_));
  start_exceeds_ = start_exceeds_ || startExceedsBoxes();
}

void TimeOptimalSolver::prepare(PointData* p, double s) const
{
  p->jet = p->raw;
  bool moving = false;
  bool limited = false;
  int unlimited = -1;
  for (int c = 0; c < 2; ++c)
  {
    if (!(moves_[c] && p->raw[c].bb > floor_[c]))
      continue;
    moving = true;
    if (bounds_.acceleration[c] > 0.0)
      limited = true;
    else if (unlimited < 0)
      unlimited = c;
  }
  if (moving && !limited && !boxesBoundTheMotion())
  {
    const int c = unlimited;
    const std::string where = "the path " + std::string(kMotionVerb[c]) + " at path time " + formatNumber(s) + " s";
    if (bounds_.velocity[c] > 0.0)
      throw InvalidInputError(std::string(kAccelerationName[c]) +
                              ": 0 (unbounded), but timing 'time_optimal' needs it: " + where +
                              " where no acceleration bound acts (the motion starts and stops at rest)");
    throw InvalidInputError(std::string(kVelocityName[c]) + " and " + kAccelerationName[c] +
                            ": 0 (unbounded), but timing 'time_optimal' needs a bound on this motion: " + where +
                            " where no other bound acts (set " + kAccelerationName[c] + ", and " + kVelocityName[c] +
                            " to cap the speed)");
  }
  if (!moving)
  {
    // A stationary point (C′ = 0 in every channel, e.g. a dwell): any speed is admissible;
    // a fictitious |C′| at the "moves" threshold keeps x and u finite there.
    for (int c = 0; c < 2; ++c)
    {
      ChannelJet& j = p->jet[c];
      if (moves_[c] && (bounds_.velocity[c] > 0.0 || bounds_.acceleration[c] > 0.0) && j.bb < floor_[c])
      {
        j.bb = floor_[c];
        j.cross = std::max(0.0, j.aa * j.bb - j.ab * j.ab);
      }
    }
  }
  // The ellipses' extents for updateCaps, once per jet instead of once per pass.
  for (int c = 0; c < 2; ++c)
  {
    const ChannelJet& j = p->jet[c];
    p->extent[c] = j.cross > 0.0 ? std::sqrt(j.bb / j.cross) : (j.bb == 0.0 && j.aa > 0.0 ? std::sqrt(j.aa) : 0.0);
  }
}

}  // namespace time_optimal_detail

double TimingProfile::timeAt(double path_parameter) const
{
  auto it = std::lower_bound(s.begin(), s.end(), path_parameter);
  if (it != s.end() && *it == path_parameter)
    return t[static_cast<std::size_t>(it - s.begin())];
  const std::size_t i = findInterval(s, path_parameter, Side::kRight);
  const double ds = path_parameter - s[i];
  const double v = std::sqrt(x[i]);
  const double v_end = std::sqrt(std::max(0.0, x[i] + 2.0 * u[i] * ds));
  const double rate = v + v_end;
  return rate > 0.0 ? t[i] + 2.0 * ds / rate : t[i];
}

TimingProfile timeOptimalProfile(const PathModel& path, const RateBounds& bounds, const TimeOptimalOptions& options)
{
  return time_optimal_detail::TimeOptimalSolver(path, bounds, options).solve();
}

}  // namespace timing
}  // namespace se3_interpolation
