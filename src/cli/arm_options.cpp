// se3_interpolate's arm options (arm_options.h).
#include "arm_options.h"

#include <cmath>
#include <iomanip>
#include <iostream>
#include <stdexcept>

#include "se3_interpolation/arm/joint_limits.h"

namespace se3_interpolation
{
namespace cli
{
bool parseArmArgument(int argc, char** argv, int* i, ArmArguments* a)
{
  const std::string arg = argv[*i];
  std::string* value = arg == "--urdf"         ? &a->urdf :
                       arg == "--base-link"    ? &a->base_link :
                       arg == "--tip-link"     ? &a->tip_link :
                       arg == "--joint-limits" ? &a->joint_limits :
                                                 nullptr;
  if (!value || *i + 1 >= argc)
    return false;
  *value = argv[++*i];
  return true;
}

std::shared_ptr<const arm::ArmModel> loadArm(const ArmArguments& a)
{
  if (a.urdf.empty())
  {
    if (!a.base_link.empty() || !a.tip_link.empty() || !a.joint_limits.empty())
      throw std::invalid_argument(std::string(!a.base_link.empty() ? "--base-link" :
                                              !a.tip_link.empty()  ? "--tip-link" :
                                                                     "--joint-limits") +
                                  ": an option of the arm; give its URDF with --urdf FILE");
    return nullptr;
  }
  if (a.base_link.empty() || a.tip_link.empty())
    throw std::invalid_argument(std::string(a.base_link.empty() ? "--base-link" : "--tip-link") +
                                ": missing; --urdf follows the motion with the chain from --base-link NAME to "
                                "--tip-link NAME");
  auto model = std::make_shared<arm::ArmModel>(arm::ArmModel::fromUrdfFile(a.urdf, a.base_link, a.tip_link));
  if (!a.joint_limits.empty())
    model->applyLimits(arm::readJointLimitsFile(a.joint_limits));
  return model;
}

void printJointFigures(const TrajectoryResult& r, const arm::ArmModel& arm)
{
  const arm::JointRatesCheck& c = r.joint_figures;
  const auto limit = [](double l) { return std::isfinite(l) ? std::to_string(l) : std::string("none"); };
  std::cerr << std::setprecision(12);
  for (std::size_t k = 0; k < r.joint_names.size() && k < c.peaks.size(); ++k)
  {
    const arm::JointLimits& l = arm.joints()[k].limits;
    std::cerr << "joint_" << r.joint_names[k] << ": max_velocity " << c.peaks[k].velocity << " (limit "
              << limit(l.max_velocity) << "), max_acceleration " << c.peaks[k].acceleration << " (limit "
              << limit(l.max_acceleration) << ")";
    if (c.has_jerk)
      std::cerr << ", max_jerk " << c.peaks[k].jerk << " (limit " << limit(l.max_jerk) << ")";
    std::cerr << "\n";
  }
  if (c.binding_joint >= 0)
    std::cerr << "joint_binding: " << r.joint_names[static_cast<std::size_t>(c.binding_joint)] << " "
              << c.binding_quantity << " " << c.binding_ratio << "\n";
}
}  // namespace cli
}  // namespace se3_interpolation
