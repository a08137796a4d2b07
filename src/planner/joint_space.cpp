// The planner's joint space (joint_space.h).
#include "joint_space.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/validation.h"
#include "se3_interpolation/timing/path_jet3.h"

namespace se3_interpolation
{
namespace planner_detail
{
namespace
{
/// A motion that may not be stretched (a moving start, constant_speed) is refused where a joint
/// exceeds its limits by more than this (relative): the rounding of the check's peak searches.
constexpr double kJointExcessTolerance = 1e-6;
}  // namespace

template <class Space>
std::optional<JointSpace> jointSpaceOf(const BasicRequest<Space>& request, std::shared_ptr<const arm::ArmModel> arm)
{
  if constexpr (std::is_same_v<Space, SphereSpace>)
  {
    if (!request.joint_seed.empty())
      throw InvalidInputError("joint_seed: an arm follows pose motions only (this request is on the sphere)");
    return std::nullopt;
  }
  else
  {
    if (!arm)
    {
      if (!request.joint_seed.empty())
        throw InvalidInputError("joint_seed: " + std::to_string(request.joint_seed.size()) +
                                " entries, but no arm is configured (the node's ~tip_link, the CLI's --tip-link)");
      return std::nullopt;
    }
    if (request.joint_seed.empty())
      throw InvalidInputError("joint_seed: empty; with an arm (chain " + quotedText(arm->baseLink()) + " → " +
                              quotedText(arm->tipLink()) + ") a request needs the arm's " + std::to_string(arm->dof()) +
                              " joint positions at the motion's start");
    JointSpace j;
    j.arm = std::move(arm);
    j.seed = Eigen::Map<const Eigen::VectorXd>(request.joint_seed.data(),
                                               static_cast<Eigen::Index>(request.joint_seed.size()));
    j.arm->checkJointVector(j.seed, "joint_seed");
    return j;
  }
}

void stretchFigures(double k, CurveFigures* fig)
{
  fig->max_linear_speed /= k;
  fig->max_angular_speed /= k;
  fig->max_linear_acceleration /= k * k;
  fig->max_angular_acceleration /= k * k;
  fig->max_linear_jerk /= k * k * k;
  fig->max_angular_jerk /= k * k * k;
  fig->energy /= k * k * k;
}

namespace
{
/// Stretches m's motion uniformly by k from its start: the curve, its figures, time_scale and the
/// waypoints' times.
template <class Space, class G>
void stretchMotion(double k, PlannedMotion<Space, G>* m)
{
  const double t0 = m->curve->startTime();
  validateTimeSpan(t0, t0 + (m->curve->endTime() - t0) * k, "the arm's joint limits");
  m->curve = std::make_shared<TimeScaledCurve<G>>(m->curve, k);
  stretchFigures(k, &m->figures);
  m->out.time_scale *= k;
  for (double& t : m->out.waypoint_times)
    t = t0 + (t - t0) * k;
}

/// The path under a timed curve: the first curve down its chain of clocks (RetimedCurve::base)
/// that runs on its own time; the curve itself where it is not retimed.
template <class G>
std::shared_ptr<const Curve<G>> pathUnder(const std::shared_ptr<const Curve<G>>& curve)
{
  std::shared_ptr<const Curve<G>> c = curve;
  while (const auto* retimed = dynamic_cast<const RetimedCurve<G>*>(c.get()))
    c = retimed->sharedBase();
  return c;
}

/// Whether `curve` and every curve down its chain of clocks give third-order jets (a timed motion
/// with a finite jerk: the jerk-limited, constant-speed and closed-form timings and stretches of
/// a C² curve; not the time-optimal timing, whose s̈ steps).
template <class G>
bool hasThirdOrderJets(const Curve<G>& curve)
{
  for (const Curve<G>* c = &curve;;)
  {
    if (!dynamic_cast<const ThirdOrderJets<G>*>(c))
      return false;
    const auto* retimed = dynamic_cast<const RetimedCurve<G>*>(c);
    if (!retimed)
      return true;
    c = &retimed->base();
  }
}

/// s(t): the path time under `curve` at its time t, as a 2-jet in t (the clocks down its chain
/// composed), and the side of s the path is evaluated from (given t's side).
template <class G>
Jet<2> pathClock(const Curve<G>& curve, double t, Side side, Side* path_side)
{
  Jet<2> s = Jet<2>::variable(t);
  *path_side = side;
  for (const Curve<G>* c = &curve; const auto* retimed = dynamic_cast<const RetimedCurve<G>*>(c); c = &retimed->base())
  {
    const Side outer = *path_side;
    s = retimed->clock(s, outer, path_side);
  }
  return s;
}

/// Where the time t lies among the waypoints' times (ascending, the waypoints' own count): "at
/// waypoints[i]" within 1e-9 of the motion's span, else "between waypoints[i] and
/// waypoints[i+1]"; empty outside them or for a count other than the request's waypoints'.
std::string waypointsAround(const std::vector<double>& times, std::size_t waypoints, double t)
{
  if (times.size() < 2 || times.size() != waypoints)
    return {};
  const double tolerance = 1e-9 * std::max(1.0, std::abs(times.back() - times.front()));
  for (std::size_t i = 0; i < times.size(); ++i)
    if (std::abs(times[i] - t) <= tolerance)
      return "at " + indexedField("waypoints", i);
  const auto after = std::upper_bound(times.begin(), times.end(), t);
  if (after == times.begin() || after == times.end())
    return {};
  const std::size_t i = static_cast<std::size_t>(after - times.begin()) - 1;
  return "between " + indexedField("waypoints", i) + " and " + indexedField("waypoints", i + 1);
}

/// `follow()`, whose refusals of the arm at a time on the path gain where among the waypoints it
/// is (their path times, `times()`, asked for only then): "between waypoints[1] and waypoints[2]:
/// the pose at t = ...".
template <class Times, class Follow>
auto namingWaypoints(const Times& times, std::size_t waypoints, Follow&& follow) -> decltype(follow())
{
  try
  {
    return follow();
  }
  catch (const arm::JointPathError& e)
  {
    const std::string where = e.time() ? waypointsAround(times(), waypoints, *e.time()) : std::string();
    if (where.empty())
      throw;
    throw arm::JointPathError(where + ": " + e.what(), *e.time());
  }
}

/// The arm's joints on `curve`'s time: the joint path of the path under it (the time-optimal
/// timing's own, which its boxes tracked, or tracked here) on the composed clocks down to it; with
/// `with_jerk` also their jerk, from the curve's third-order jets (arm::JointPath::jerk).
template <class G>
std::shared_ptr<const arm::RetimedJointPath> jointsOn(const std::shared_ptr<const Curve<G>>& curve,
                                                      std::shared_ptr<const arm::JointPath> path,
                                                      bool with_jerk = false)
{
  arm::RetimedJointPath::TipJerk tip_jerk;
  if (with_jerk)
    tip_jerk = [curve](double t, Side side) {
      const timing::Kinematics3 k = timing::kinematics3FromJet(jet3Of(*curve, Jet<3>::variable(t), side));
      arm::TipVector v;
      v << k.jerk.angular, k.jerk.linear;
      return v;
    };
  arm::RetimedJointPath::Clock clock = [curve](double t, Side side, Side* path_side) {
    return pathClock(*curve, t, side, path_side);
  };
  return std::make_shared<arm::RetimedJointPath>(std::move(path), std::move(clock), curve->startTime(),
                                                 curve->endTime(), std::move(tip_jerk));
}

/// The joint path a time-optimal timing held as its boxes, with its check; none for other curves.
template <class G>
std::optional<std::pair<std::shared_ptr<const arm::JointPath>, arm::JointRatesCheck>> heldByTiming(
    const arm::ArmModel& model, const Curve<G>& curve)
{
  const auto* timed = dynamic_cast<const timing::TimeOptimalCurve<G>*>(&curve);
  const auto boxes = timed ? std::dynamic_pointer_cast<const arm::JointBoxes>(timed->profile().boxes) : nullptr;
  if (!boxes)
    return std::nullopt;
  return std::make_pair(boxes->path(), arm::jointRatesOf(model, timed->profile().box_peaks));
}
}  // namespace

template <class Space, class G>
std::shared_ptr<const timing::BoxConstraint> jointBoxesOf(const BasicValidatedRequest<Space>& r,
                                                          const std::shared_ptr<const Curve<G>>& curve,
                                                          const std::vector<double>& waypoint_times)
{
  if constexpr (std::is_same_v<Space, SphereSpace>)
    return nullptr;
  else
  {
    if (!r.joint_space)
      return nullptr;
    return namingWaypoints([&] { return waypoint_times; }, r.waypoints.size(),
                           [&] {
                             return std::make_shared<arm::JointBoxes>(
                                 arm::jointPathOf<G>(*r.joint_space->arm, curve, r.joint_space->seed));
                           });
  }
}

template <class Space, class G>
std::shared_ptr<const arm::JointMotion> followWithArm(const BasicValidatedRequest<Space>& r, PlannedMotion<Space, G>* m)
{
  if constexpr (std::is_same_v<Space, SphereSpace>)
    return nullptr;
  else
  {
    if (!r.joint_space)
      return nullptr;
    const arm::ArmModel& model = *r.joint_space->arm;
    std::shared_ptr<const arm::JointPath> path;
    arm::JointRatesCheck check;
    if (auto held = heldByTiming(model, *m->curve))
      std::tie(path, check) = std::move(*held);
    else
    {
      const auto path_times = [&] {
        std::vector<double> s;
        for (double t : m->out.waypoint_times)
        {
          Side side = Side::kRight;
          s.push_back(pathClock(*m->curve, t, Side::kRight, &side).value());
        }
        return s;
      };
      path = namingWaypoints(path_times, r.waypoints.size(), [&] {
        return std::make_shared<arm::JointPath>(arm::jointPathOf<G>(model, pathUnder(m->curve), r.joint_space->seed));
      });
      // The jerk where the timed motion has third-order jets all along (a part of a joined motion
      // may lack them: then none).
      const auto check_with = [&](bool jerk) {
        return arm::checkJointRates(*jointsOn(m->curve, path, jerk), m->curve->breakpoints());
      };
      try
      {
        check = check_with(hasThirdOrderJets(*m->curve));
      }
      catch (const NoThirdOrderJetsError&)
      {
        check = check_with(false);
      }
    }
    if (arm::hasJerkLimits(model) && !std::isnan(check.acceleration_step_time))
    {
      const double t = check.acceleration_step_time;
      const std::string where = waypointsAround(m->out.waypoint_times, r.waypoints.size(), t);
      throw InvalidInputError("the arm's joint jerk limits: the joints' accelerations step at t = " + formatNumber(t) +
                              " s" + (where.empty() ? std::string() : " (" + where + ")") +
                              ", an unbounded jerk; a motion under jerk limits needs continuous accelerations (a "
                              "C2 curve, timing 'time_optimal', a start state the path continues)");
    }
    if (check.stretch > 1.0)
    {
      if (r.start_state || r.timing == Timing::kConstantSpeed)
      {
        const std::string where = waypointsAround(m->out.waypoint_times, r.waypoints.size(), check.binding_time);
        if (check.stretch > 1.0 + kJointExcessTolerance)
          throw InvalidInputError((where.empty() ? std::string() : where + ": ") +
                                  arm::jointExcessMessage(model, check) +
                                  (r.start_state ? " (a motion from a start state keeps its start: replan from rest, "
                                                   "or lower the bounds)" :
                                                   " (timing constant_speed keeps its speed: lower `speed`)"));
      }
      else
      {
        const double k = check.stretch;
        stretchMotion(k, m);
        check = arm::stretchJointRates(model, check, k, m->curve->startTime());
      }
    }
    m->out.joint_names = model.jointNames();
    m->out.joint_figures = std::move(check);
    return jointsOn(m->curve, std::move(path));
  }
}

void fillJoints(const arm::JointMotion& joints, TrajectorySample* s, Side side)
{
  arm::JointState q = joints.at(s->time, side);
  s->joint_position = std::move(q.position);
  s->joint_velocity = std::move(q.velocity);
  s->joint_acceleration = std::move(q.acceleration);
}

template std::optional<JointSpace> jointSpaceOf<PoseSpace>(const TrajectoryRequest&,
                                                           std::shared_ptr<const arm::ArmModel>);
template std::optional<JointSpace> jointSpaceOf<SphereSpace>(const SphereRequest&,
                                                             std::shared_ptr<const arm::ArmModel>);
template std::shared_ptr<const timing::BoxConstraint> jointBoxesOf<PoseSpace, DoubleGeodesicSe3>(
    const ValidatedRequest&, const std::shared_ptr<const Curve<DoubleGeodesicSe3>>&, const std::vector<double>&);
template std::shared_ptr<const timing::BoxConstraint> jointBoxesOf<PoseSpace, ScrewSe3>(
    const ValidatedRequest&, const std::shared_ptr<const Curve<ScrewSe3>>&, const std::vector<double>&);
template std::shared_ptr<const timing::BoxConstraint> jointBoxesOf<SphereSpace, Sphere>(
    const ValidatedSphereRequest&, const std::shared_ptr<const Curve<Sphere>>&, const std::vector<double>&);
template std::shared_ptr<const arm::JointMotion> followWithArm<PoseSpace, DoubleGeodesicSe3>(
    const ValidatedRequest&, PlannedMotion<PoseSpace, DoubleGeodesicSe3>*);
template std::shared_ptr<const arm::JointMotion> followWithArm<PoseSpace, ScrewSe3>(
    const ValidatedRequest&, PlannedMotion<PoseSpace, ScrewSe3>*);
template std::shared_ptr<const arm::JointMotion> followWithArm<SphereSpace, Sphere>(
    const ValidatedSphereRequest&, PlannedMotion<SphereSpace, Sphere>*);
}  // namespace planner_detail
}  // namespace se3_interpolation
