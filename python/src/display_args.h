// Arguments that name a display's layers and rays, read one way wherever a
// function takes them (synthesize, DisplayOperator, RetinaOperator, patterns_as_seen).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "layerlab/python/src/arguments.h"
#include "layerlab/python/src/numpy_view.h"
#include "layerlab/systems/display_model.h"

namespace layerlab::python {

// One (rows, cols, 3) float array per layer of `system`, copied into patterns (a pattern owns its buffer),
// each named "<prefix>pattern k (layer)" in errors and handed to `check(pattern, name)`; a count other than
// the layers' raises ValueError naming `function`.
template <class Check>
Patterns PatternArrays(const DisplaySystem& system, const pybind11::sequence& arrays, const std::string& function,
                       const std::string& prefix, Check check) {
  if (arrays.size() != system.layers.size())
    throw pybind11::value_error(function + ": expected " + std::to_string(system.layers.size()) +
                                " patterns (one per layer), got " + std::to_string(arrays.size()));
  Patterns patterns;
  for (size_t k = 0; k < system.layers.size(); ++k) {
    const VirtualLayer& layer = system.layers[k];
    const std::string name = prefix + "pattern " + std::to_string(k) + " (" + layer.name + ")";
    const auto a = FloatArrayOfShape(arrays[k], {layer.rows, layer.cols, 3}, name, "(rows, cols, RGB)");
    LayerPattern& p = patterns.emplace_back(layer.cols, layer.rows, 0.0f);
    std::copy(a.data(), a.data() + p.rgb.size(), p.rgb.begin());
    check(p, name);
  }
  return patterns;
}

// The rays and sampling a display model is bound to: `geometry` (held to a manifest's limits, named
// "<function>: geometry") or else the one the display suggests, and `sampling` ("nearest" or "bilinear").
struct ModelRays {
  LightFieldGeometry geometry;
  Sampling sampling = Sampling::kNearest;
};
inline ModelRays ModelRaysArg(const DisplaySystem& system, const std::optional<LightFieldGeometry>& geometry,
                              const std::string& sampling, const std::string& function) {
  ModelRays rays{geometry ? *geometry : DisplayLightFieldGeometry(system)};
  if (geometry) CheckGeometryArgument(rays.geometry, function + ": geometry");
  CheckArgument([&] { rays.sampling = SamplingFromString(sampling); });
  return rays;
}

}  // namespace layerlab::python
