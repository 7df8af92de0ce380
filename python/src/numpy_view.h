// NumPy arrays over memory a layerlab object owns: no copy, and the array's
// base is the Python object of the owner, which it keeps alive.
#pragma once

#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

namespace layerlab::python {

inline pybind11::array_t<float> FloatView(const std::vector<pybind11::ssize_t>& shape, const float* data,
                                          pybind11::handle owner) {
  return pybind11::array_t<float>(shape, data, owner);
}

// A float32 array over a vector it takes (no copy: the array's capsule frees the vector with the array).
template <typename Vector>
pybind11::array_t<float> OwningArray(Vector&& values, const std::vector<pybind11::ssize_t>& shape) {
  auto* owned = new Vector(std::move(values));
  pybind11::capsule owner(owned, [](void* p) { delete static_cast<Vector*>(p); });
  return FloatView(shape, owned->data(), owner);
}

inline std::string ShapeString(const std::vector<pybind11::ssize_t>& shape) {
  std::string s = "(";
  for (size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + (shape.size() == 1 ? ",)" : ")");
}

// A C-contiguous float32 array of exactly `shape`; a float array of another
// type or layout is converted (a copy NumPy makes); another shape raises
// ValueError naming the expected one and what the axes are.
inline pybind11::array_t<float, pybind11::array::c_style | pybind11::array::forcecast> FloatArrayOfShape(
    const pybind11::handle& value, const std::vector<pybind11::ssize_t>& shape, const std::string& what,
    const std::string& axes) {
  auto a = pybind11::array_t<float, pybind11::array::c_style | pybind11::array::forcecast>::ensure(value);
  if (!a) throw pybind11::type_error(what + ": expected a float array of shape " + ShapeString(shape) + " " + axes);
  std::vector<pybind11::ssize_t> got(a.shape(), a.shape() + a.ndim());
  if (got != shape)
    throw pybind11::value_error(what + ": expected shape " + ShapeString(shape) + " " + axes + ", got " +
                                ShapeString(got));
  return a;
}

}  // namespace layerlab::python
