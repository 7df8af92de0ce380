// The compiled system in words (a table with units) and for machines (JSON).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/systems/display_model.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

std::string FormatSystemTable(const DisplaySystem& system);

// The highest frequency every layer can show: the coarsest layer's Nyquist
// (system.max_cpd is the finest layer's).
double EveryLayerMaxCpd(const DisplaySystem& system);

// Keys carry their unit (depth_m, fov_deg, ...); infinities are written as
// the strings "inf" / "-inf", since JSON has no infinity.
nlohmann::json SystemToJson(const DisplaySystem& system);

// The light field a display is bound to and, per layer, how many of its
// pixels some ray reads (solvers touch only those).
struct LayerCoverage {
  std::string name;
  size_t reached = 0, total = 0;
};
std::vector<LayerCoverage> Coverage(const DisplayModel& model);
std::string FormatCoverage(const DisplayModel& model, const std::vector<LayerCoverage>& coverage);
nlohmann::json CoverageToJson(const DisplayModel& model, const std::vector<LayerCoverage>& coverage);

// A finite number as itself, an infinite one as "inf" / "-inf".
nlohmann::json JsonNumber(double value);

}  // namespace layerlab
