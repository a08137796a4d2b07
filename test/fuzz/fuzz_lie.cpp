// libFuzzer target, the Lie-group layer: so3Exp/so3Log, se3Exp/se3Log and the geodesics of
// both SE(3) geometries between decoded poses (edge-case numbers, angles near 0 and pi, q and
// -q). Expected: finite unit results, exp(log) returning the rotation, the geodesic's ends at
// its endpoints, or a NonUniqueGeodesicError at angle pi; anything else is a finding.
#include "fuzz_common.h"
#include "se3_interpolation/geometry/geometry.h"

using namespace se3_interpolation;
using namespace se3_interpolation::fuzz;

namespace
{
double rotationDistance(const Quaternion<double>& a, const Quaternion<double>& b)
{
  return std::min((a.coeffs() - b.coeffs()).norm(), (a.coeffs() + b.coeffs()).norm());
}

template <class G>
void checkGeodesic(const Pose<double>& a, const Pose<double>& b, double s, const char* geometry)
{
  typename G::template Tangent<double> v;
  try
  {
    v = G::log(a, b);
  }
  catch (const NonUniqueGeodesicError&)
  {
    return;
  }
  if (!v.allFinite())
    fail(std::string(geometry) + ": log(a, b) is not finite");
  using Tangent = typename G::template Tangent<double>;
  const Pose<double> start = G::exp(a, Tangent(0.0 * v));
  const Pose<double> end = G::exp(a, v);
  const Pose<double> mid = G::exp(a, Tangent(s * v));
  checkPose(start, std::string(geometry) + " geodesic(0)");
  checkPose(end, std::string(geometry) + " geodesic(1)");
  checkPose(mid, std::string(geometry) + " geodesic(s)");
  const double scale = 1.0 + a.p.norm() + b.p.norm();
  if ((end.p - b.p).norm() > 1e-7 * scale * (1.0 + v.norm()) || rotationDistance(end.q, b.q) > 1e-8)
    fail(std::string(geometry) + ": the geodesic does not end at b");
  if ((start.p - a.p).norm() > 1e-12 * scale || rotationDistance(start.q, a.q) > 1e-12)
    fail(std::string(geometry) + ": the geodesic does not start at a");
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  g_target = "fuzz_lie";
  ByteReader in(data, size);
  std::vector<Pose<double>> poses;
  for (int i = 0; i < 2; ++i)
  {
    Eigen::Vector3d p = vector3(in);
    if (!p.allFinite() || p.norm() > 1e6)
      p = Eigen::Vector3d(in.small(), in.small(), in.small());
    const Quaternion<double> q = unitQuaternion(in, poses);
    poses.emplace_back(q, p);
  }
  double s = in.small() / 8.0;  // [-1, 1)
  try
  {
    // exp(log(q)) is q's rotation; |log q| <= pi.
    const Eigen::Vector3d w = so3Log(poses[1].q);
    if (!w.allFinite() || w.norm() > 3.141592653589794)
      fail("so3Log out of range");
    if (rotationDistance(so3Exp(w), poses[1].q) > 1e-12)
      fail("so3Exp(so3Log(q)) is not q");
    const Vector6<double> xi = se3Log(poses[0].inverseTimes(poses[1]));
    const Pose<double> back = poses[0] * se3Exp(xi);
    checkPose(back, "se3Exp(se3Log)");
    if ((back.p - poses[1].p).norm() > 1e-7 * (1.0 + poses[0].p.norm() + poses[1].p.norm()) * (1.0 + xi.norm()))
      fail("se3Exp(se3Log(a^-1 b)) is not b");
  }
  catch (const NonUniqueGeodesicError&)
  {
  }
  catch (const std::exception& e)
  {
    fail(std::string("unexpected exception: ") + e.what());
  }
  // so3Exp of any finite vector is a unit quaternion.
  const Eigen::Vector3d omega = vector3(in);
  if (omega.allFinite() && omega.norm() < 1e6)
  {
    const Quaternion<double> q = so3Exp(omega);
    if (!q.coeffs().allFinite() || std::abs(q.norm() - 1.0) > 1e-12)
      fail("so3Exp of a finite vector is not a unit quaternion");
  }
  try
  {
    checkGeodesic<ScrewSe3>(poses[0], poses[1], s, "screw");
    checkGeodesic<DoubleGeodesicSe3>(poses[0], poses[1], s, "double_geodesic");
  }
  catch (const std::exception& e)
  {
    fail(std::string("unexpected exception: ") + e.what());
  }
  return 0;
}
