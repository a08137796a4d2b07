// The brakes of a moving start state (src/planner/start_brakes.cpp), the braked candidate's first
// part in src/planner/start_state.cpp.
#pragma once

#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "se3_interpolation/curves/braked_start.h"
#include "se3_interpolation/curves/jerk_brake.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace planner_detail
{
/// The relative excess over a bound that the jerk brake's measured rates may show (rounding).
constexpr double kRateTolerance = 1e-9;

/// The figures of a brake (B1, B2 in closed form; the jerk brake measured), and the time after
/// which every bound holds (recovery: 0 unless the start itself exceeds a bound).
struct BrakeFigures
{
  double length = 0.0;
  double rotation_length = 0.0;
  std::array<double, 2> max_speed{};
  std::array<double, 2> max_acceleration{};
  std::array<double, 2> max_jerk{};
  double energy = 0.0;  ///< ∫ |p̈|² + ρ²|ω̇|² dt
  double recovery = 0.0;
};

/// The stop of the start state without jerk bounds (B1, B2): each moving channel decelerates at its
/// acceleration bound; std::nullopt when no channel with an acceleration bound moves.
std::optional<BrakeToRest> brakeToRest(const ValidatedRequest& r);

/// B1, B2's figures in closed form, with the recovery from a start beyond a velocity bound.
BrakeFigures brakeFigures(const ValidatedRequest& r, const BrakeToRest& brake);

/// The jerk brakes to try for a start within the bounds, each with its measured figures: the
/// fastest design that holds every bound, and the acceleration ramped first in both channels.
std::vector<std::pair<JerkBrake, BrakeFigures>> jerkBrakes(const ValidatedRequest& r);
}  // namespace planner_detail
}  // namespace se3_interpolation
