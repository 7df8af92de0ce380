#include "layerlab/calibration/calibrated_scene.h"

#include <cstdio>
#include <map>
#include <numbers>
#include <set>

#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

using nlohmann::ordered_json;

std::string WithUnit(double si_value, double scale, const char* unit) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.12g %s", si_value * scale, unit);
  return buf;
}

double Rounded(double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.12g", value);
  return std::strtod(buf, nullptr);
}

// Replaces keys in place; the placement (`placement_key`, if any) takes the
// place of "virtual_depth"; new keys go before the element's connection
// ("next"), or last.
void Update(ordered_json& element, const std::vector<std::pair<std::string, ordered_json>>& values,
            const std::string& placement_key = "") {
  std::map<std::string, ordered_json> pending(values.begin(), values.end());
  std::set<std::string> present;
  for (auto it = element.begin(); it != element.end(); ++it) present.insert(it.key());
  // The placement waits for the "virtual_depth" it replaces, wherever that stands ("next" may come first).
  const bool replaces = !placement_key.empty() && pending.count(placement_key) && element.contains("virtual_depth");
  if (replaces) present.insert(placement_key);
  ordered_json updated = ordered_json::object();
  auto emit_new = [&] {
    for (const auto& [key, value] : values)
      if (!present.count(key) && pending.count(key)) updated[key] = value, pending.erase(key);
  };
  for (auto it = element.begin(); it != element.end(); ++it) {
    const std::string& key = it.key();
    if (key == "next") emit_new();
    if (key == "virtual_depth" && replaces) {
      updated[placement_key] = pending[placement_key];
      pending.erase(placement_key);
    } else if (pending.count(key)) {
      updated[key] = pending[key];
      pending.erase(key);
    } else {
      updated[key] = *it;
    }
  }
  emit_new();
  element = std::move(updated);
}

ordered_json& ElementNamed(ordered_json& scene, const std::string& file, const std::string& name) {
  if (scene.contains("elements") && scene["elements"].is_array())
    for (ordered_json& e : scene["elements"])
      if (e.is_object() && e.contains("name") && e["name"] == name) return e;
  throw Error(Location{file, "/elements"}, "no element named \"" + name + "\" to write the calibration into");
}

}  // namespace

ordered_json CalibratedSceneDocument(const ordered_json& scene, const std::string& file,
                                     const CalibratedDisplay& display) {
  ordered_json out = scene;
  for (const CalibratedPanel& panel : display.panels) {
    std::vector<std::pair<std::string, ordered_json>> values;
    ordered_json& element = ElementNamed(out, file, panel.name);
    // Its place as the scene gives it: a "gap" stays a gap; "distance" and
    // "virtual_depth" become the distance from the optics in front (a gap without any).
    const std::string key = element.contains("gap") || !panel.behind_optics ? "gap" : "distance";
    if (panel.geometry_measured || panel.optics_fitted)
      values.push_back({key, WithUnit(key == "gap" ? panel.gap_m : panel.distance_m, 1e3, "mm")});
    if (panel.geometry_measured) {
      values.push_back(
          {"offset", {WithUnit(panel.eye_from_panel_x_m, 1e3, "mm"), WithUnit(panel.eye_from_panel_y_m, 1e3, "mm")}});
      values.push_back({"rotation", WithUnit(panel.rotation_rad, kDegreesPerRadian, "deg")});
    }
    if (panel.luminance_measured) {
      values.push_back({"gamma", Rounded(panel.gamma)});
      values.push_back({"black_level", Rounded(panel.black_level)});
    }
    if (!values.empty()) Update(element, values, key);
  }
  for (const CalibratedOptic& optic : display.optics) {
    std::vector<std::pair<std::string, ordered_json>> values;
    if (optic.gap_fitted) values.push_back({"gap", WithUnit(optic.gap_m, 1e3, "mm")});
    if (optic.focal_length_fitted) values.push_back({"focal_length", WithUnit(optic.focal_length_m, 1e3, "mm")});
    if (!values.empty()) Update(ElementNamed(out, file, optic.name), values);
  }
  return out;
}

}  // namespace layerlab
