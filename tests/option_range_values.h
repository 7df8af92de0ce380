// Values just inside and just outside an option table's range
// (framework/option_table.h), at either end: what an option's consumers
// must accept and refuse. `step`: how far inside an open end (0: the next
// double; integers step by 1). And a value as a scene file writes it.
#pragma once

#include <cmath>
#include <sstream>

#include <nlohmann/json.hpp>

#include "layerlab/framework/option_table.h"

namespace layerlab::testing {

inline double InsideRange(const OptionRange& r, bool integer, bool at_min, double step = 0) {
  const double end = at_min ? r.min : r.max, toward = at_min ? r.max : r.min;
  if (!(at_min ? r.min_open : r.max_open)) return end;
  if (integer) return end + (at_min ? 1 : -1);
  return step > 0 ? end + (at_min ? step : -step) : std::nextafter(end, toward);
}

inline double OutsideRange(const OptionRange& r, bool integer, bool at_min, double step = 0) {
  const double end = at_min ? r.min : r.max, away = at_min ? -INFINITY : INFINITY;
  if (at_min ? r.min_open : r.max_open) return end;
  if (integer) return end + (at_min ? -1 : 1);
  return step > 0 ? end + (at_min ? -step : step) : std::nextafter(end, away);
}

// `v` as a scene writes e's key: with the field's unit ("0.01 deg"), an
// integer, or a bare fraction; `list`: in an array, `pair`: twice in one.
inline nlohmann::json SceneValue(const OptionSpec& e, double v, bool list, bool pair = false) {
  if (e.kind == OptionKind::kInteger || e.type == "integer") return int64_t(v);
  nlohmann::json value = v;
  if (!e.FieldUnit().empty()) {
    std::ostringstream s;
    s.precision(17);
    s << v << " " << e.FieldUnit();
    value = s.str();
  }
  if (pair) return nlohmann::json::array({value, value});
  return list ? nlohmann::json::array({value}) : value;
}

}  // namespace layerlab::testing
