// Python objects <-> nlohmann::json, through Python's json module (exact for
// the types JSON has). A value JSON cannot hold (NaN, infinity, an object of
// another type) is refused naming its place: layerlab.SceneError with the
// file and the JSON pointer of the key ("<dict>: /elements/2/distance: NaN
// ..."), a ValueError, or TypeError for a type JSON has no counterpart of.
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <utility>

#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

#include "layerlab/framework/error.h"

namespace layerlab::python {

// The JSON pointer (below `pointer`) of the first value in `value` that JSON
// cannot hold, and why; nullopt when there is none. Why starts with "type:"
// for a type JSON lacks.
inline std::optional<std::pair<std::string, std::string>> FindNonJson(const pybind11::handle& value,
                                                                      const std::string& pointer) {
  namespace py = pybind11;
  if (value.is_none() || py::isinstance<py::bool_>(value) || py::isinstance<py::int_>(value) ||
      py::isinstance<py::str>(value))
    return std::nullopt;
  if (py::isinstance<py::float_>(value)) {
    const double x = value.cast<double>();
    if (std::isfinite(x)) return std::nullopt;
    return std::make_pair(pointer, std::string(std::isnan(x) ? "NaN"
                                               : x > 0       ? "+inf"
                                                             : "-inf") +
                                       " is not a number JSON holds (a finite number is expected)");
  }
  if (py::isinstance<py::dict>(value)) {
    for (const auto& [key, item] : value.cast<py::dict>()) {
      const std::string name = py::str(key).cast<std::string>();
      if (auto found = FindNonJson(item, pointer + "/" + EscapePointerToken(name))) return found;
    }
    return std::nullopt;
  }
  if (py::isinstance<py::list>(value) || py::isinstance<py::tuple>(value)) {
    size_t k = 0;
    for (const py::handle& item : value)
      if (auto found = FindNonJson(item, pointer + "/" + std::to_string(k++))) return found;
    return std::nullopt;
  }
  return std::make_pair(pointer, "type: a " + py::str(py::type::of(value).attr("__name__")).cast<std::string>() +
                                     " is not a JSON value (dict, list, str, int, float, bool or None)");
}

// The JSON text of `value`; a value JSON cannot hold raises as above, named
// by `file` and its place below `pointer`.
inline std::string JsonText(const pybind11::handle& value, const std::string& file, const std::string& pointer = "") {
  namespace py = pybind11;
  if (auto found = FindNonJson(value, pointer)) {
    const Location where{file, found->first};
    if (found->second.rfind("type: ", 0) == 0) throw py::type_error(where.str() + ": " + found->second.substr(6));
    const std::string what = where.str() + ": " + found->second;
    py::object type = py::module_::import("layerlab.errors").attr("SceneError");
    py::object error = type(what, where.file, where.pointer, found->second);
    PyErr_SetObject(type.ptr(), error.ptr());
    throw py::error_already_set();
  }
  return py::module_::import("json").attr("dumps")(value, py::arg("allow_nan") = false).cast<std::string>();
}

inline nlohmann::json ToJson(const pybind11::handle& value, const std::string& file, const std::string& pointer = "") {
  return nlohmann::json::parse(JsonText(value, file, pointer));
}

inline pybind11::object FromJson(const nlohmann::json& value) {
  return pybind11::module_::import("json").attr("loads")(value.dump());
}

}  // namespace layerlab::python
