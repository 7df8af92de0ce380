// Python arguments as C++ values, refused at the boundary with the argument's
// name: a wrong type raises TypeError naming the type expected, a value out
// of range ValueError (layerlab.ArgumentError) naming the range, never
// pybind11's "Unable to cast Python instance to C++ type". Checks made by the
// core (the same the command line makes) raise layerlab.ArgumentError too.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <pybind11/pybind11.h>

#include "layerlab/framework/error.h"
#include "layerlab/framework/lightfield_checks.h"

namespace layerlab::python {

// Raises layerlab.ArgumentError (a layerlab.Error and a ValueError) with `message`.
[[noreturn]] inline void RaiseArgumentError(const std::string& message) {
  pybind11::object type = pybind11::module_::import("layerlab.errors").attr("ArgumentError");
  pybind11::object value = type(message);
  PyErr_SetObject(type.ptr(), value.ptr());
  throw pybind11::error_already_set();
}

// Runs a check of the core (which throws layerlab::Error) on an argument and
// raises what it refuses as layerlab.ArgumentError.
template <typename Check>
void CheckArgument(Check&& check) {
  try {
    check();
  } catch (const Error& e) {
    RaiseArgumentError(e.what());
  }
}

inline std::string TypeName(const pybind11::handle& value) {
  return pybind11::str(pybind11::type::of(value).attr("__name__")).cast<std::string>();
}

inline std::string Repr(const pybind11::handle& value) { return pybind11::repr(value).cast<std::string>(); }

// An integer (a Python int or anything with __index__, such as a NumPy
// integer; not a bool, not a float): TypeError otherwise. Outside [lo, hi]:
// ArgumentError "<name>: <value>: must be in [lo, hi]" (or `range` when given).
inline long long IntegerArg(const pybind11::handle& value, const std::string& name, long long lo, long long hi,
                            const std::string& range = "") {
  if (PyBool_Check(value.ptr()) || !PyIndex_Check(value.ptr()))
    throw pybind11::type_error(name + ": expected an int, got " + TypeName(value) + " " + Repr(value));
  pybind11::object index = pybind11::reinterpret_steal<pybind11::object>(PyNumber_Index(value.ptr()));
  if (!index) throw pybind11::error_already_set();
  int overflow = 0;
  const long long x = PyLong_AsLongLongAndOverflow(index.ptr(), &overflow);
  if (PyErr_Occurred()) throw pybind11::error_already_set();
  if (overflow != 0 || x < lo || x > hi)
    RaiseArgumentError(name + ": " + Repr(value) + ": " +
                       (range.empty() ? "must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" : range));
  return x;
}

// An unsigned 64-bit integer (a seed): TypeError for another type, ArgumentError outside [0, 2^64 - 1].
inline unsigned long long Unsigned64Arg(const pybind11::handle& value, const std::string& name) {
  if (PyBool_Check(value.ptr()) || !PyIndex_Check(value.ptr()))
    throw pybind11::type_error(name + ": expected an int, got " + TypeName(value) + " " + Repr(value));
  pybind11::object index = pybind11::reinterpret_steal<pybind11::object>(PyNumber_Index(value.ptr()));
  if (!index) throw pybind11::error_already_set();
  const unsigned long long x = PyLong_AsUnsignedLongLong(index.ptr());
  if (PyErr_Occurred()) {
    PyErr_Clear();
    RaiseArgumentError(name + ": " + Repr(value) + ": must be in [0, 2^64 - 1]");
  }
  return x;
}

// A real number (int, float, NumPy scalar; not a bool, str or bytes): TypeError otherwise.
inline double RealArg(const pybind11::handle& value, const std::string& name) {
  if (!PyBool_Check(value.ptr()) && !PyUnicode_Check(value.ptr()) && !PyBytes_Check(value.ptr())) {
    const double x = PyFloat_AsDouble(value.ptr());
    if (!PyErr_Occurred()) return x;
    PyErr_Clear();
  }
  throw pybind11::type_error(name + ": expected a number, got " + TypeName(value) + " " + Repr(value));
}

// A bool (not an int): TypeError otherwise.
inline bool BoolArg(const pybind11::handle& value, const std::string& name) {
  if (!PyBool_Check(value.ptr()))
    throw pybind11::type_error(name + ": expected a bool, got " + TypeName(value) + " " + Repr(value));
  return value.ptr() == Py_True;
}

// A str: TypeError otherwise.
inline std::string StringArg(const pybind11::handle& value, const std::string& name) {
  if (!PyUnicode_Check(value.ptr()))
    throw pybind11::type_error(name + ": expected a str, got " + TypeName(value) + " " + Repr(value));
  return value.cast<std::string>();
}

// A list, tuple or 1-D array of real numbers (a str is not one): TypeError naming the argument or the item.
inline std::vector<double> RealListArg(const pybind11::handle& value, const std::string& name) {
  if (PyUnicode_Check(value.ptr()) || PyBytes_Check(value.ptr()) || !PySequence_Check(value.ptr()))
    throw pybind11::type_error(name + ": expected a list of numbers, got " + TypeName(value) + " " + Repr(value));
  std::vector<double> values;
  const auto items = pybind11::reinterpret_borrow<pybind11::sequence>(value);
  for (size_t i = 0; i < items.size(); ++i) values.push_back(RealArg(items[i], name + "[" + std::to_string(i) + "]"));
  return values;
}

// The C++ object of a layerlab class `T` (`python_name` in messages): TypeError for anything else.
template <typename T>
std::shared_ptr<T> HolderArg(const pybind11::handle& value, const std::string& name, const std::string& python_name) {
  if (!pybind11::isinstance<T>(value))
    throw pybind11::type_error(name + ": expected a " + python_name + ", got " + TypeName(value));
  return value.cast<std::shared_ptr<T>>();
}

// A geometry held to the limits a light-field manifest is held to
// (CheckLightFieldGeometry): ArgumentError "<what>: cols: must be in [1, 16384], got 0".
inline void CheckGeometryArgument(const LightFieldGeometry& g, const std::string& what) {
  CheckLightFieldGeometry(g, [&](const std::string& field, const std::string& why) {
    RaiseArgumentError(what + ": " + field + ": " + why);
  });
}

}  // namespace layerlab::python
