#include "layerlab/framework/option_reader.h"

#include "layerlab/framework/json_file.h"

namespace layerlab {

using nlohmann::json;

Params ArrayItems(Params& p, const std::string& key) {
  const json& a = p.raw(key);
  if (!a.is_array() || a.empty()) p.fail(key, "expected a non-empty array, got " + JsonKindName(a));
  json items = json::object();
  for (size_t k = 0; k < a.size(); ++k) items[std::to_string(k)] = a[k];
  return Params(std::move(items), p.where(key));
}

std::vector<double> ReadQuantityList(Params& p, const OptionSpec& e) {
  Params items = ArrayItems(p, e.key);
  const double unit = e.FieldUnitInSI();
  std::vector<double> out;
  for (size_t k = 0; items.has(std::to_string(k)); ++k) {
    const std::string i = std::to_string(k);
    const double v = e.dimension == Dimension::kOpticalPower ? items.optional_depth(i)->diopters
                                                             : items.quantity(i, e.dimension) / unit;
    items.require_range(i, v, e.range.min, e.range.max, e.range.min_open, e.range.max_open);
    out.push_back(v);
  }
  return out;
}

}  // namespace layerlab
