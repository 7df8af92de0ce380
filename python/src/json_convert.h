// Python objects <-> nlohmann::json, through Python's json module (exact for
// the types JSON has; NaN and infinity are refused as JSON refuses them).
#pragma once

#include <pybind11/pybind11.h>
#include <nlohmann/json.hpp>

namespace layerlab::python {

inline nlohmann::json ToJson(const pybind11::handle& value) {
  const std::string text =
      pybind11::module_::import("json").attr("dumps")(value, pybind11::arg("allow_nan") = false).cast<std::string>();
  return nlohmann::json::parse(text);
}

inline pybind11::object FromJson(const nlohmann::json& value) {
  return pybind11::module_::import("json").attr("loads")(value.dump());
}

}  // namespace layerlab::python
