#include "arrays.h"

#include <memory>

namespace se3_interpolation
{
namespace python
{
namespace
{
void appendPose(const Pose<double>& x, std::vector<double>* out)
{
  out->insert(out->end(), { x.p.x(), x.p.y(), x.p.z(), x.q.x(), x.q.y(), x.q.z(), x.q.w() });
}

void appendTwist(const Twist& v, std::vector<double>* out)
{
  out->insert(out->end(), { v.linear.x(), v.linear.y(), v.linear.z(), v.angular.x(), v.angular.y(), v.angular.z() });
}
}  // namespace

py::array_t<double> ownedArray(std::vector<double>&& data, const std::vector<py::ssize_t>& shape)
{
  auto owned = std::make_unique<std::vector<double>>(std::move(data));
  const double* first = owned->data();
  const py::capsule base(owned.get(), [](void* p) { delete static_cast<std::vector<double>*>(p); });
  owned.release();  // the capsule owns it now
  return py::array_t<double>(shape, first, base);
}

py::array_t<double> vectorArray(const std::vector<double>& values)
{
  return ownedArray(std::vector<double>(values), { static_cast<py::ssize_t>(values.size()) });
}

py::array_t<double> posesArray(const std::vector<Pose<double>>& poses)
{
  std::vector<double> rows;
  rows.reserve(7 * poses.size());
  for (const Pose<double>& x : poses)
    appendPose(x, &rows);
  return ownedArray(std::move(rows), { static_cast<py::ssize_t>(poses.size()), 7 });
}

void SampleColumns::reserve(std::size_t samples)
{
  t.reserve(samples);
  pose.reserve(7 * samples);
  velocity.reserve(6 * samples);
  acceleration.reserve(6 * samples);
}

void SampleColumns::add(double time, const Pose<double>& x, const Twist& v, const Twist& a)
{
  t.push_back(time);
  appendPose(x, &pose);
  appendTwist(v, &velocity);
  appendTwist(a, &acceleration);
}

SampleArrays::SampleArrays(SampleColumns&& columns)
{
  const auto m = static_cast<py::ssize_t>(columns.size());
  t = ownedArray(std::move(columns.t), { m });
  pose = ownedArray(std::move(columns.pose), { m, 7 });
  velocity = ownedArray(std::move(columns.velocity), { m, 6 });
  acceleration = ownedArray(std::move(columns.acceleration), { m, 6 });
}

}  // namespace python
}  // namespace se3_interpolation
