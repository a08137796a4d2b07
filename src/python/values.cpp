#include "values.h"

#include <algorithm>

#include "se3_interpolation/exceptions.h"

namespace se3_interpolation
{
namespace python
{
namespace
{
std::string typeName(py::handle value)
{
  return Py_TYPE(value.ptr())->tp_name;
}

/// "[x, y, z]" of `names`.
std::string listText(const std::vector<std::string>& names)
{
  std::string text = "[";
  for (std::size_t i = 0; i < names.size(); ++i)
    text += (i ? ", " : "") + names[i];
  return text + "]";
}

/// A list, tuple or array: what a list field may be given as (a string is a sequence, not a list).
bool isListLike(py::handle value)
{
  return PyList_Check(value.ptr()) || PyTuple_Check(value.ptr()) || py::isinstance<py::array>(value);
}

/// A list or tuple of two vectors: the (position, orientation) and (linear, angular) spellings (two
/// numbers are a row of the wrong length instead).
bool isPair(py::handle value)
{
  if (!(PyList_Check(value.ptr()) || PyTuple_Check(value.ptr())) || PySequence_Size(value.ptr()) != 2)
    return false;
  const py::handle first = PySequence_Fast_GET_ITEM(value.ptr(), 0);
  return isListLike(first) || isMapping(first);
}

/// mapping[key], or a null object when the key is absent or None (None means "not given").
py::object item(py::handle mapping, const char* key)
{
  py::object value = mapping.attr("get")(key);
  return value.is_none() ? py::object() : value;
}

/// Exactly `names.size()` numbers in a list or array (the list spelling of a vector or pose).
std::vector<double> fixedNumbers(py::handle value, const std::string& field, const std::vector<std::string>& names)
{
  const std::vector<double> v = toDoubles(value, field);
  if (v.size() != names.size())
    throw InvalidInputError(field + ": expected " + std::to_string(names.size()) + " numbers " + listText(names) +
                            ", got " + std::to_string(v.size()));
  return v;
}

/// The components of a list [x, y, ...] or of a mapping {x: .., y: .., ...} (a missing one is 0).
std::vector<double> components(py::handle value, const std::string& field, const std::vector<std::string>& names)
{
  if (isMapping(value))
  {
    requireKeys(value, field, names);
    std::vector<double> v(names.size(), 0.0);
    for (std::size_t i = 0; i < names.size(); ++i)
      if (py::object c = item(value, names[i].c_str()))
        v[i] = toDouble(c, field + "." + names[i]);
    return v;
  }
  if (!isListLike(value))
  {
    std::string map = "{";
    for (std::size_t i = 0; i < names.size(); ++i)
      map += (i ? ", " : "") + names[i] + ": ..";
    throw py::type_error(field + ": expected " + listText(names) + " or " + map + "}, got " + typeName(value));
  }
  return fixedNumbers(value, field, names);
}

Eigen::Vector3d toVector3(py::handle value, const std::string& field)
{
  const std::vector<double> v = components(value, field, { "x", "y", "z" });
  return Eigen::Vector3d(v[0], v[1], v[2]);
}

Quaternion<double> toQuaternion(py::handle value, const std::string& field)
{
  const std::vector<double> q = components(value, field, { "x", "y", "z", "w" });
  return Quaternion<double>(q[3], q[0], q[1], q[2]);
}

/// The rows of an (N, columns) array `value`, refused with its shape otherwise.
py::array_t<double, py::array::c_style | py::array::forcecast> rowsArray(py::handle value, const std::string& field,
                                                                         const std::vector<std::string>& names)
{
  auto a = numericArray(value, field);
  if (a.ndim() != 2 || a.shape(1) != static_cast<py::ssize_t>(names.size()))
    throw InvalidInputError(field + ": expected an (N, " + std::to_string(names.size()) + ") array " + listText(names) +
                            ", got shape " + shapeText(a));
  return a;
}

const std::vector<std::string> kPoseColumns = { "x", "y", "z", "qx", "qy", "qz", "qw" };
const std::vector<std::string> kTwistColumns = { "vx", "vy", "vz", "wx", "wy", "wz" };
}  // namespace

bool isMapping(py::handle value)
{
  if (PyDict_Check(value.ptr()))
    return true;
  // collections.abc.Mapping, looked up once and kept for the life of the process.
  static PyObject* const mapping = py::object(py::module_::import("collections.abc").attr("Mapping")).release().ptr();
  return py::isinstance(value, py::handle(mapping));
}

py::dict copyMapping(py::handle mapping)
{
  py::dict copy;
  if (PyDict_Merge(copy.ptr(), mapping.ptr(), 1) != 0)
    throw py::error_already_set();
  return copy;
}

void requireKeys(py::handle mapping, const std::string& field, const std::vector<std::string>& allowed)
{
  for (py::handle key : mapping)
  {
    if (!PyUnicode_Check(key.ptr()))
      throw py::type_error(field + (field.empty() ? "" : ": ") + "keys must be strings, got " + typeName(key));
    const std::string name = toString(key, field);
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
      throw InvalidInputError(field + (field.empty() ? "" : ".") + name + ": unknown field");
  }
}

std::string shapeText(const py::array& a)
{
  std::string text = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i)
    text += (i ? ", " : "") + std::to_string(a.shape(i));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

py::array_t<double, py::array::c_style | py::array::forcecast> numericArray(py::handle value, const std::string& field)
{
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  if (PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr()) || isMapping(value))
    throw py::type_error(field + ": expected numbers, got " + typeName(value));
  if (py::isinstance<py::array>(value))
  {
    const char kind = py::reinterpret_borrow<py::array>(value).dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u')
      throw py::type_error(field + ": expected a numeric array, got dtype " +
                           py::str(py::reinterpret_borrow<py::array>(value).dtype()).cast<std::string>());
  }
  Array a = Array::ensure(value);
  if (!a)
    throw py::type_error(field + ": expected numbers, got " + typeName(value));
  return a;
}

double toDouble(py::handle value, const std::string& field)
{
  PyObject* o = value.ptr();
  if (PyBool_Check(o) || PyUnicode_Check(o) || PyBytes_Check(o) || PyComplex_Check(o) || !PyNumber_Check(o))
    throw py::type_error(field + ": expected a number, got " + typeName(value));
  const double x = PyFloat_AsDouble(o);
  if (x == -1.0 && PyErr_Occurred())
  {
    const bool overflow = PyErr_ExceptionMatches(PyExc_OverflowError);
    PyErr_Clear();
    if (overflow)
      throw InvalidInputError(field + ": " + quotedText(py::str(value).cast<std::string>()) + " does not fit a double");
    throw py::type_error(field + ": expected a number, got " + typeName(value));
  }
  return x;
}

long long toInteger(py::handle value, const std::string& field, long long lo, long long hi)
{
  PyObject* o = value.ptr();
  if (PyBool_Check(o) || !PyIndex_Check(o))
    throw py::type_error(field + ": expected an integer, got " + typeName(value));
  const py::object index = py::reinterpret_steal<py::object>(PyNumber_Index(o));
  if (!index)
    throw py::error_already_set();
  int overflow = 0;
  const long long v = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (overflow != 0 || v < lo || v > hi)
    throw InvalidInputError(field + ": " + py::str(index).cast<std::string>() + " is outside " + std::to_string(lo) +
                            " ... " + std::to_string(hi));
  return v;
}

std::string toString(py::handle value, const std::string& field)
{
  if (!PyUnicode_Check(value.ptr()))
    throw py::type_error(field + ": expected a string, got " + typeName(value));
  Py_ssize_t size = 0;
  const char* text = PyUnicode_AsUTF8AndSize(value.ptr(), &size);
  if (text == nullptr)
  {
    PyErr_Clear();
    throw InvalidInputError(field + ": not encodable as UTF-8");
  }
  return std::string(text, static_cast<std::size_t>(size));
}

bool toBool(py::handle value, const std::string& field)
{
  if (!PyBool_Check(value.ptr()))
    throw py::type_error(field + ": expected True or False, got " + typeName(value));
  return value.ptr() == Py_True;
}

std::vector<double> toDoubles(py::handle value, const std::string& field)
{
  if (!isListLike(value))
    throw py::type_error(field + ": expected a list of numbers, got " + typeName(value));
  py::array_t<double, py::array::c_style | py::array::forcecast> a;
  try
  {
    a = numericArray(value, field);
  }
  catch (const py::type_error&)
  {
    // Name the first item that is not a number, as the CLI does (field[i]).
    if (!py::isinstance<py::array>(value))
    {
      const py::sequence items = py::reinterpret_borrow<py::sequence>(value);
      for (std::size_t i = 0; i < items.size(); ++i)
        toDouble(items[i], indexedField(field, i));
    }
    throw;
  }
  if (a.ndim() != 1)
    throw InvalidInputError(field + ": expected a 1-D list of numbers, got shape " + shapeText(a));
  return std::vector<double>(a.data(), a.data() + a.size());
}

std::vector<std::string> toStrings(py::handle value, const std::string& field)
{
  if (!PyList_Check(value.ptr()) && !PyTuple_Check(value.ptr()))
    throw py::type_error(field + ": expected a list of names, got " + typeName(value));
  std::vector<std::string> names;
  const py::sequence items = py::reinterpret_borrow<py::sequence>(value);
  for (std::size_t i = 0; i < items.size(); ++i)
    names.push_back(toString(items[i], indexedField(field, i)));
  return names;
}

Pose<double> toPose(py::handle value, const std::string& field)
{
  Pose<double> p;
  if (isMapping(value))
  {
    requireKeys(value, field, { "position", "orientation" });
    const py::object position = item(value, "position");
    if (!position)
      throw InvalidInputError(field + ".position: missing");
    p.p = toVector3(position, field + ".position");
    if (const py::object orientation = item(value, "orientation"))
      p.q = toQuaternion(orientation, field + ".orientation");
    return p;
  }
  if (isPair(value))
  {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(value);
    p.p = toVector3(pair[0], field + ".position");
    p.q = toQuaternion(pair[1], field + ".orientation");
    return p;
  }
  if (!isListLike(value))
    throw py::type_error(field +
                         ": expected [x, y, z, qx, qy, qz, qw], (position, orientation) or {position: .., "
                         "orientation: ..}, got " +
                         typeName(value));
  const std::vector<double> v = fixedNumbers(value, field, kPoseColumns);
  p.p = Eigen::Vector3d(v[0], v[1], v[2]);
  p.q = Quaternion<double>(v[6], v[3], v[4], v[5]);
  return p;
}

Twist toTwist(py::handle value, const std::string& field)
{
  Twist t;
  if (isMapping(value))
  {
    requireKeys(value, field, { "linear", "angular" });
    if (const py::object linear = item(value, "linear"))
      t.linear = toVector3(linear, field + ".linear");
    if (const py::object angular = item(value, "angular"))
      t.angular = toVector3(angular, field + ".angular");
    return t;
  }
  if (isPair(value))
  {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(value);
    t.linear = toVector3(pair[0], field + ".linear");
    t.angular = toVector3(pair[1], field + ".angular");
    return t;
  }
  if (!isListLike(value))
    throw py::type_error(field +
                         ": expected [vx, vy, vz, wx, wy, wz], (linear, angular) or {linear: .., angular: ..}, "
                         "got " +
                         typeName(value));
  const std::vector<double> v = fixedNumbers(value, field, kTwistColumns);
  t.linear = Eigen::Vector3d(v[0], v[1], v[2]);
  t.angular = Eigen::Vector3d(v[3], v[4], v[5]);
  return t;
}

std::vector<Pose<double>> toPoses(py::handle value, const std::string& field)
{
  py::handle poses = value;
  py::object inner;
  if (isMapping(value))
  {
    // geometry_msgs/PoseArray: the module has no frames, so a header is checked for its keys only.
    requireKeys(value, field, { "header", "poses" });
    if (const py::object header = item(value, "header"))
      requireKeys(header, field + ".header", { "seq", "stamp", "frame_id" });
    inner = item(value, "poses");
    if (!inner)
      throw InvalidInputError(field + ".poses: missing (a list of poses)");
    poses = inner;
  }
  std::vector<Pose<double>> out;
  if (py::isinstance<py::array>(poses))
  {
    const auto a = rowsArray(poses, field, kPoseColumns);
    const double* row = a.data();
    for (py::ssize_t i = 0; i < a.shape(0); ++i, row += 7)
      out.emplace_back(Quaternion<double>(row[6], row[3], row[4], row[5]), Eigen::Vector3d(row[0], row[1], row[2]));
    return out;
  }
  if (!PyList_Check(poses.ptr()) && !PyTuple_Check(poses.ptr()))
    throw py::type_error(field + ": expected an (N, 7) array or a list of poses, got " + typeName(poses));
  const py::sequence items = py::reinterpret_borrow<py::sequence>(poses);
  out.reserve(items.size());
  for (std::size_t i = 0; i < items.size(); ++i)
    out.push_back(toPose(items[i], indexedField(field, i)));
  return out;
}

std::vector<Twist> toTwists(py::handle value, const std::string& field)
{
  std::vector<Twist> out;
  if (py::isinstance<py::array>(value))
  {
    const auto a = rowsArray(value, field, kTwistColumns);
    const double* row = a.data();
    for (py::ssize_t i = 0; i < a.shape(0); ++i, row += 6)
    {
      Twist t;
      t.linear = Eigen::Vector3d(row[0], row[1], row[2]);
      t.angular = Eigen::Vector3d(row[3], row[4], row[5]);
      out.push_back(t);
    }
    return out;
  }
  if (!PyList_Check(value.ptr()) && !PyTuple_Check(value.ptr()))
    throw py::type_error(field + ": expected an (N, 6) array or a list of twists, got " + typeName(value));
  const py::sequence items = py::reinterpret_borrow<py::sequence>(value);
  for (std::size_t i = 0; i < items.size(); ++i)
    out.push_back(toTwist(items[i], indexedField(field, i)));
  return out;
}

}  // namespace python
}  // namespace se3_interpolation
