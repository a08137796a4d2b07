// planner/: the request, written once over the space: request.h (request, validated request,
// result, defaults, limits), names.h (the request's name tables), validation.h (one function per
// rule), work_estimate.h (the bounded work per request), curve_factory.h (curve name →
// construction), planner.h (this header: generate<Space>).
//
// The trajectory planner: request → validation → timing → curve → stretch → samples, written
// once over the space (planner/request.h): poses in either SE(3) geometry, and the sphere S^m.
//
// This is the ROS-free heart of the `~generate` service and the `se3_interpolate` CLI:
// both translate their input into a request (same field names as srv/GenerateTrajectory.srv)
// and call generate(). Every bad input is rejected by validateRequest() (validation.h) before
// anything is computed, with an InterpolationError whose message names the field and index;
// the work a request asks for is bounded before the curve is built (work_estimate.h), and no
// figure or sample leaves as ∞ or NaN.
//
// The sphere (the CLI's `--space sphere`, docs/command_line.md) takes the same fields, with
//  - waypoints: unit vectors x_i ∈ R^{m+1}, m ≥ 2, all of one dimension;
//  - start_velocity, end_velocity, start_acceleration, velocities: vectors of R^{m+1} tangent to
//    the sphere at their waypoint (empty = zero), projected onto the tangent space (a normal
//    component above kMaxNormalFraction of the length is an error); start_acceleration is the
//    covariant acceleration D²x/dt² (Crouch Case 2);
//  - curves: piecewise_geodesic, bezier, bspline (great-circle de Casteljau / de Boor),
//    interpolating (chart cubics, every end condition), hermite (Crouch Case 1), blended
//    (Pobegailo's C^n circle splines);
//  - timing: `chord` spacing by the great-circle angle (rad), `centripetal` its square root;
//    max_angular_velocity bounds the speed |ẋ| (rad/s) and max_angular_acceleration the covariant
//    acceleration |D²x/dt²| (rad/s²), by stretch or time_optimal as for poses; `geometry`,
//    `rotation_scale`, `blend_radius` and the max_linear_* bounds are refused when set.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>

#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
/// The most samples generate() hands to a SampleSink at once (a few hundred kB of poses).
constexpr std::size_t kSamplesPerBlock = 2048;

/// Receives generate()'s samples instead of BasicResult::samples: consecutive blocks of at most
/// kSamplesPerBlock, in time order, on the calling thread, each valid only during the call (the
/// memory is reused for the next). Its time does not count against the request's work limit.
template <class Space>
using SampleSink = std::function<void(const typename Space::Sample* first, std::size_t count)>;

/// Validates, builds the curve, applies the bounds and samples it (Space: PoseSpace or
/// SphereSpace): the whole of a `~generate` call or a CLI run, without ROS.
/// @param request the request, field for field as in srv/GenerateTrajectory.srv (empty strings and
///        zeros select the defaults of RequestDefaults)
/// @param limits the resource bounds (the node's ~max_samples, ~max_waypoints, ~max_work_seconds)
/// @return the samples, the waypoints' final times, the figures and the timed curve
/// @throws InvalidInputError for a bad field, naming the field and index
/// @throws NonUniqueGeodesicError for two points to be joined that are half a turn apart
/// @throws ConvergenceError if a C² solve cannot continue to the data
/// @throws LimitExceededError if the request would take longer than limits.max_work_seconds, or
///         ran past its deadline
template <class Space>
BasicResult<Space> generate(const BasicRequest<Space>& request, const PlannerLimits& limits);

/// generate(), handing the samples to `sink` as they are computed instead of keeping them: a large
/// output (the CLI's 10⁵ samples) then needs a block's memory, not all of it (16 MB of fresh memory
/// at 160 bytes a pose sample). The result is the same with `samples` empty. Every error that
/// validation, the work estimate, the curve or the timing finds is thrown before the first block;
/// only a sample that is not finite, or the deadline passing while sampling, is thrown after some.
/// @throws what generate() throws, and what `sink` throws
template <class Space>
BasicResult<Space> generate(const BasicRequest<Space>& request, const PlannerLimits& limits,
                            const SampleSink<Space>& sink);

/// generate() with an arm following the motion (docs/joint_space.md; arm/joint_path.h,
/// arm/joint_timing.h): the request's joint_seed is required (the arm's joint positions at the
/// motion's start); every timing holds the arm's joint velocity and acceleration limits together
/// with the request's bounds (time_optimal in its passes; the others by a uniform stretch of the
/// motion; a motion from a start state and constant_speed are refused naming the joint and time
/// where a joint would exceed its limits); every sample carries the joints' positions, velocities
/// and accelerations, and the result the joint names and figures.
/// @throws what generate() throws, and InvalidInputError naming joint_seed, or the time and pose
///         where the arm cannot follow the motion (out of reach, singular, past a position limit)
TrajectoryResult generate(const TrajectoryRequest& request, const PlannerLimits& limits,
                          std::shared_ptr<const arm::ArmModel> arm);

/// The arm's generate() handing its samples to `sink` (as generate() with a sink).
TrajectoryResult generate(const TrajectoryRequest& request, const PlannerLimits& limits,
                          std::shared_ptr<const arm::ArmModel> arm, const SampleSink<PoseSpace>& sink);

/// Waypoint times: the explicit ones, else spaced by the parameterisation (docs/timing.md): chord
/// steps are √(|Δp|² + (ρ Δθ)²) for poses and the great-circle angle on the sphere.
/// @param request a validated request (validateRequest())
/// @return one time per waypoint, strictly increasing (s)
template <class Space>
std::vector<double> waypointTimes(const BasicValidatedRequest<Space>& request);

}  // namespace se3_interpolation
