// se3_interpolate's arm (docs/joint_space.md): --urdf FILE --base-link NAME --tip-link NAME
// [--joint-limits FILE] load the chain that follows the motion (arm/arm_model.h, the MoveIt-format
// limits of arm/joint_limits.h); the CSV then has the joints' columns and the figures the joints'.
#pragma once

#include <memory>
#include <string>

#include "se3_interpolation/arm/arm_model.h"
#include "se3_interpolation/planner/request.h"

namespace se3_interpolation
{
namespace cli
{
/// The arm's command-line options.
struct ArmArguments
{
  std::string urdf;          ///< --urdf FILE
  std::string base_link;     ///< --base-link NAME
  std::string tip_link;      ///< --tip-link NAME
  std::string joint_limits;  ///< --joint-limits FILE
};

/// Reads argv[*i] (and its value, advancing *i) when it is one of the arm's options; false otherwise.
bool parseArmArgument(int argc, char** argv, int* i, ArmArguments* a);

/// The arm of the options, or null without --urdf. Throws std::invalid_argument naming the option
/// where one is given without the others, and ArmModelError naming the file, link or joint where
/// the URDF or the limits file cannot serve.
std::shared_ptr<const arm::ArmModel> loadArm(const ArmArguments& a);

/// The joints' figures on stderr: `joint_<name>: max_velocity V (limit L), max_acceleration A
/// (limit L)` per joint (limit `none` where the arm has none), then `joint_binding: <name>
/// <velocity|acceleration> <ratio to its limit>`.
void printJointFigures(const TrajectoryResult& r, const arm::ArmModel& arm);
}  // namespace cli
}  // namespace se3_interpolation
