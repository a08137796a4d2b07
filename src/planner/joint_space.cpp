// The planner's joint space (joint_space.h).
#include "joint_space.h"

#include <cmath>
#include <string>
#include <type_traits>
#include <utility>

#include "se3_interpolation/exceptions.h"
#include "se3_interpolation/planner/validation.h"

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

template <class Space, class G>
std::shared_ptr<const timing::BoxConstraint> jointBoxesOf(const BasicValidatedRequest<Space>& r,
                                                          const std::shared_ptr<const Curve<G>>& curve)
{
  if constexpr (std::is_same_v<Space, SphereSpace>)
    return nullptr;
  else
  {
    if (!r.joint_space)
      return nullptr;
    return std::make_shared<arm::JointBoxes>(arm::jointPathOf<G>(*r.joint_space->arm, curve, r.joint_space->seed));
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

/// The arm following m's timed motion, tracked between the waypoints' times: a timing's own
/// breakpoints (a time-optimal motion's thousands of grid times, where only s̈ jumps) would cost a
/// tracked point each, and the tracking's adaptive steps follow the motion between them anyway.
template <class Space, class G>
std::shared_ptr<arm::JointPath> followTimedMotion(const arm::ArmModel& model, const PlannedMotion<Space, G>& m,
                                                  const Eigen::VectorXd& seed)
{
  const std::shared_ptr<const Curve<G>> curve = m.curve;
  const double t0 = curve->startTime(), t1 = curve->endTime();
  std::vector<double> b{ t0 };
  for (double t : m.out.waypoint_times)
    if (t > b.back() && t < t1)
      b.push_back(t);
  b.push_back(t1);
  arm::PoseMotion motion = [curve](double t, Side side) { return kinematicsAt(*curve, t, side); };
  return std::make_shared<arm::JointPath>(model, std::move(motion), std::move(b), seed);
}
}  // namespace

template <class Space, class G>
std::shared_ptr<const arm::JointPath> followWithArm(const BasicValidatedRequest<Space>& r, PlannedMotion<Space, G>* m)
{
  if constexpr (std::is_same_v<Space, SphereSpace>)
    return nullptr;
  else
  {
    if (!r.joint_space)
      return nullptr;
    const arm::ArmModel& model = *r.joint_space->arm;
    auto joints = followTimedMotion(model, *m, r.joint_space->seed);
    arm::JointRatesCheck check = arm::checkJointRates(*joints, m->curve->breakpoints());
    if (check.stretch > 1.0)
    {
      if (r.start_state || r.timing == Timing::kConstantSpeed)
      {
        if (check.stretch > 1.0 + kJointExcessTolerance)
          throw InvalidInputError(arm::jointExcessMessage(model, check) +
                                  (r.start_state ? " (a motion from a start state keeps its start: replan from rest, "
                                                   "or lower the bounds)" :
                                                   " (timing constant_speed keeps its speed: lower `speed`)"));
      }
      else
      {
        stretchMotion(check.stretch, m);
        joints = followTimedMotion(model, *m, r.joint_space->seed);
        check = arm::checkJointRates(*joints, m->curve->breakpoints());
      }
    }
    m->out.joint_names = model.jointNames();
    m->out.joint_figures = std::move(check);
    return joints;
  }
}

void fillJoints(const arm::JointPath& joints, TrajectorySample* s, Side side)
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
    const ValidatedRequest&, const std::shared_ptr<const Curve<DoubleGeodesicSe3>>&);
template std::shared_ptr<const timing::BoxConstraint> jointBoxesOf<PoseSpace, ScrewSe3>(
    const ValidatedRequest&, const std::shared_ptr<const Curve<ScrewSe3>>&);
template std::shared_ptr<const timing::BoxConstraint> jointBoxesOf<SphereSpace, Sphere>(
    const ValidatedSphereRequest&, const std::shared_ptr<const Curve<Sphere>>&);
template std::shared_ptr<const arm::JointPath> followWithArm<PoseSpace, DoubleGeodesicSe3>(
    const ValidatedRequest&, PlannedMotion<PoseSpace, DoubleGeodesicSe3>*);
template std::shared_ptr<const arm::JointPath> followWithArm<PoseSpace, ScrewSe3>(const ValidatedRequest&,
                                                                                  PlannedMotion<PoseSpace, ScrewSe3>*);
template std::shared_ptr<const arm::JointPath> followWithArm<SphereSpace, Sphere>(const ValidatedSphereRequest&,
                                                                                  PlannedMotion<SphereSpace, Sphere>*);
}  // namespace planner_detail
}  // namespace se3_interpolation
