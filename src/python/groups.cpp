// The groups' exponential and logarithm (SO(3) and SE(3), math/lie_groups.h) and the geodesic
// step of both SE(3) geometries (geometry/), for single rows or (N, k) arrays of them. Rotations
// are quaternions [x, y, z, w] (validated as request quaternions are: norm within [0.99, 1.01],
// normalised); poses [x, y, z, qx, qy, qz, qw]; se(3) twists (ω, v), rotation first, the core's
// order (ScrewSe3's tangent: the body twist).
#include <string>

#include "arrays.h"
#include "bindings.h"
#include "se3_interpolation/geometry/geometry.h"
#include "se3_interpolation/planner/names.h"
#include "se3_interpolation/planner/validation.h"
#include "values.h"

namespace se3_interpolation
{
namespace python
{
namespace
{
/// `f(in, out, name)` on each row of `value`, a (In,) row or an (N, In) array, into an (Out,) row
/// or an (N, Out) array; `name` is the field of the row ("q", or "q[3]").
template <int In, int Out, class F>
py::array_t<double> mapRows(py::handle value, const std::string& field, F f)
{
  const auto a = numericArray(value, field);
  const bool single = a.ndim() == 1;
  if (!(single ? a.shape(0) == In : a.ndim() == 2 && a.shape(1) == In))
    throw InvalidInputError(field + ": expected shape (" + std::to_string(In) + ",) or (N, " + std::to_string(In) +
                            "), got " + shapeText(a));
  const py::ssize_t n = single ? 1 : a.shape(0);
  std::vector<double> out(static_cast<std::size_t>(n * Out));
  for (py::ssize_t i = 0; i < n; ++i)
    f(a.data() + i * In, out.data() + i * Out, single ? field : indexedField(field, static_cast<std::size_t>(i)));
  if (single)
    return ownedArray(std::move(out), { Out });
  return ownedArray(std::move(out), { n, Out });
}

Quaternion<double> quaternionAt(const double* q, const std::string& field)
{
  return validateQuaternion(Quaternion<double>(q[3], q[0], q[1], q[2]), field);
}

Pose<double> poseAt(const double* x, const std::string& field)
{
  return validatePose(Pose<double>(Quaternion<double>(x[6], x[3], x[4], x[5]), Eigen::Vector3d(x[0], x[1], x[2])),
                      field);
}

void writeQuaternion(const Quaternion<double>& q, double* out)
{
  out[0] = q.x();
  out[1] = q.y();
  out[2] = q.z();
  out[3] = q.w();
}

void writePose(const Pose<double>& x, double* out)
{
  out[0] = x.p.x();
  out[1] = x.p.y();
  out[2] = x.p.z();
  writeQuaternion(x.q, out + 3);
}

py::array_t<double> so3ExpOf(const py::handle& omega)
{
  return mapRows<3, 4>(omega, "omega", [](const double* w, double* out, const std::string& field) {
    const Eigen::Vector3d v(w[0], w[1], w[2]);
    requireBounded(v, field);
    writeQuaternion(so3Exp(v), out);
  });
}

py::array_t<double> so3LogOf(const py::handle& q)
{
  return mapRows<4, 3>(q, "q", [](const double* x, double* out, const std::string& field) {
    Eigen::Map<Eigen::Vector3d> row(out);
    row = so3Log(quaternionAt(x, field));
  });
}

py::array_t<double> se3ExpOf(const py::handle& xi)
{
  return mapRows<6, 7>(xi, "xi", [](const double* x, double* out, const std::string& field) {
    const Vector6<double> v = Eigen::Map<const Vector6<double>>(x);
    requireBounded(v.head<3>(), field + " (omega)");
    requireBounded(v.tail<3>(), field + " (v)");
    writePose(se3Exp(v), out);
  });
}

py::array_t<double> se3LogOf(const py::handle& pose)
{
  return mapRows<7, 6>(pose, "pose", [](const double* x, double* out, const std::string& field) {
    Eigen::Map<Vector6<double>> row(out);
    row = se3Log(poseAt(x, field));
  });
}

/// The geodesic step from a to b at each λ of `lambda` (a number: one pose; an array: (M, 7)).
py::array_t<double> geodesicOf(const py::handle& a, const py::handle& b, const py::handle& lambda,
                               const std::string& geometry_name)
{
  const GeometryType geometry = parseName(geometry_name, "geometry", RequestDefaults::kGeometry);
  const Pose<double> pa = validatePose(toPose(a, "a"), "a");
  const Pose<double> pb = validatePose(toPose(b, "b"), "b");
  const bool single = !isMapping(lambda) && !PyList_Check(lambda.ptr()) && !PyTuple_Check(lambda.ptr()) &&
                      !py::isinstance<py::array>(lambda);
  const std::vector<double> at = single ? std::vector<double>{ toDouble(lambda, "lam") } : toDoubles(lambda, "lam");
  std::vector<double> out(7 * at.size());
  for (std::size_t i = 0; i < at.size(); ++i)
  {
    requireFinite(at[i], single ? "lam" : indexedField("lam", i));
    try
    {
      writePose(geometry == GeometryType::kScrew ? geodesic<ScrewSe3, double>(pa, pb, at[i]) :
                                                   geodesic<DoubleGeodesicSe3, double>(pa, pb, at[i]),
                &out[7 * i]);
    }
    catch (const NonUniqueGeodesicError& e)
    {
      throw NonUniqueGeodesicError(std::string("a and b: ") + e.what());
    }
  }
  if (single)
    return ownedArray(std::move(out), { 7 });
  return ownedArray(std::move(out), { static_cast<py::ssize_t>(at.size()), 7 });
}
}  // namespace

void bindGroups(py::module_& m)
{
  m.def("so3_exp", &so3ExpOf, py::arg("omega"),
        "Exp: rotation vectors (3,) or (N, 3) -> unit quaternions [x, y, z, w] (4,) or (N, 4).");
  m.def("so3_log", &so3LogOf, py::arg("q"),
        "Log: quaternions [x, y, z, w] (4,) or (N, 4) -> rotation vectors of angle in [0, pi].");
  m.def("se3_exp", &se3ExpOf, py::arg("xi"),
        "Exp: twists (omega, v) (6,) or (N, 6), rotation first -> poses [x, y, z, qx, qy, qz, qw].");
  m.def("se3_log", &se3LogOf, py::arg("pose"),
        "Log: poses [x, y, z, qx, qy, qz, qw] (7,) or (N, 7) -> twists (omega, v), |omega| <= pi.");
  m.def("geodesic", &geodesicOf, py::arg("a"), py::arg("b"), py::arg("lam"),
        py::arg("geometry") = std::string(toString(RequestDefaults::kGeometry)),
        "The geodesic step from pose a to pose b at lam (a number or an array; outside [0, 1] it\n"
        "extrapolates) in the geometry 'double_geodesic' (slerp and lerp) or 'screw'\n"
        "(a Exp(lam Log(a^-1 b))): a pose (7,) or poses (M, 7).");
}

}  // namespace python
}  // namespace se3_interpolation
