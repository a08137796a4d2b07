// The checks of geometry/value_checks.h: finite and bounded numbers, unit quaternions, poses.
#include "se3_interpolation/geometry/value_checks.h"

#include <cmath>
#include <cstdio>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
void requireFinite(double x, const std::string& field)
{
  if (!std::isfinite(x))
    throw InvalidInputError(field + ": " + formatNumber(x) + " is not a finite number");
}

void requireBounded(double x, const std::string& field)
{
  requireFinite(x, field);
  if (!(std::abs(x) <= kMaxMagnitude))
    throw InvalidInputError(field + ": " + formatNumber(x) + " is beyond the magnitude limit " +
                            formatNumber(kMaxMagnitude) + " (larger values can overflow the curve's acceleration)");
}

void requireBounded(const Eigen::Vector3d& v, const std::string& field)
{
  static const char* kAxis[] = { ".x", ".y", ".z" };
  for (int i = 0; i < 3; ++i)
    if (!(std::abs(v[i]) <= kMaxMagnitude))
      requireBounded(v[i], field + kAxis[i]);
}

void requireUnitNorm(double norm, const std::string& field, const std::string& prefix, const char* what)
{
  if (!(norm >= kMinUnitNorm && norm <= kMaxUnitNorm))
  {
    char range[64];
    std::snprintf(range, sizeof(range), "[%g, %g]", kMinUnitNorm, kMaxUnitNorm);
    throw InvalidInputError(field + ": " + prefix + "norm " + formatNumber(norm) + " is outside " + range +
                            " (expected a unit " + what + ")");
  }
}

Quaternion<double> validateQuaternion(const Quaternion<double>& q, const std::string& field)
{
  const double c[] = { q.x(), q.y(), q.z(), q.w() };
  static const char* kName[] = { ".x", ".y", ".z", ".w" };
  for (int i = 0; i < 4; ++i)
    requireFinite(c[i], field + kName[i]);
  const double n = std::sqrt(q.coeffs().squaredNorm());
  requireUnitNorm(n, field, "quaternion ", "quaternion x, y, z, w");
  return Quaternion<double>(q.coeffs() / n);
}

Pose<double> validatePose(const Pose<double>& raw, const std::string& field)
{
  requireBounded(raw.p, field + ".position");
  return Pose<double>(validateQuaternion(raw.q, field + ".orientation"), raw.p);
}
}  // namespace se3_interpolation
