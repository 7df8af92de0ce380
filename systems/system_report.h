// The compiled system in words (a table with units) and for machines (JSON).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "systems/display_system.h"

namespace layerlab {

std::string FormatSystemTable(const DisplaySystem& system);

// Keys carry their unit (depth_m, fov_deg, ...); infinities are written as
// the strings "inf" / "-inf", since JSON has no infinity.
nlohmann::json SystemToJson(const DisplaySystem& system);

// A finite number as itself, an infinite one as "inf" / "-inf".
nlohmann::json JsonNumber(double value);

}  // namespace layerlab
