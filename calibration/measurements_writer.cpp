#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "layerlab/calibration/measurements.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

using nlohmann::ordered_json;

// Rounded to `digits` significant digits, so the file shows what is measured, not float noise.
std::string FormatSignificant(double value, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, value);
  return buf;
}

double Significant(double value, int digits) { return std::strtod(FormatSignificant(value, digits).c_str(), nullptr); }

// Whole numbers are written without a fraction ("440", not "440.0").
ordered_json Value(double value) {
  if (value == std::round(value) && std::abs(value) < 1e15) return static_cast<int64_t>(value);
  return value;
}

double Decimals(double value, int decimals) {
  double scale = std::pow(10.0, decimals);
  return std::round(value * scale) / scale;
}

// One line for anything short enough, nested lines otherwise.
void Print(const ordered_json& j, int indent, std::string& out) {
  std::string inline_form;
  if (j.is_object()) {
    inline_form = "{";
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (it != j.begin()) inline_form += ", ";
      std::string child;
      Print(*it, 1 << 20, child);
      inline_form += ordered_json(it.key()).dump() + ": " + child;
    }
    inline_form += "}";
  } else if (j.is_array()) {
    inline_form = "[";
    for (size_t i = 0; i < j.size(); ++i) {
      std::string child;
      Print(j[i], 1 << 20, child);
      inline_form += (i ? ", " : "") + child;
    }
    inline_form += "]";
  } else {
    out += j.dump();
    return;
  }
  const bool nested = inline_form.find('\n') != std::string::npos;
  if (indent >= (1 << 20) || (!nested && indent + inline_form.size() <= 100) || j.empty()) {
    out += inline_form;
    return;
  }
  const std::string pad(indent + 2, ' ');
  out += j.is_object() ? "{\n" : "[\n";
  size_t i = 0;
  for (auto it = j.begin(); it != j.end(); ++it, ++i) {
    out += pad;
    if (j.is_object()) out += ordered_json(it.key()).dump() + ": ";
    Print(*it, indent + 2, out);
    out += (i + 1 < j.size() ? ",\n" : "\n");
  }
  out += std::string(indent, ' ') + (j.is_object() ? "}" : "]");
}

ordered_json MarkersJson(const PanelMarkers& panel) {
  ordered_json list = ordered_json::array();
  for (const MarkerObservation& o : panel.markers) {
    ordered_json marker;
    marker["panel_pixel"] = {Value(Significant(o.col, 12)), Value(Significant(o.row, 12))};
    if (o.camera_pixel)
      marker["camera_pixel"] = {Decimals((*o.camera_pixel)[0], 4), Decimals((*o.camera_pixel)[1], 4)};
    else
      marker["angle"] = {Significant(o.angle_x, 12), Significant(o.angle_y, 12)};
    list.push_back(marker);
  }
  return list;
}

ordered_json DetectionNoiseJson(const DetectionNoise& detection_noise) {
  ordered_json noise = {
      {"sigma", FormatSignificant(detection_noise.sigma_rad * kDegreesPerRadian * 60, 4) + " arcmin"}};
  if (detection_noise.degrees_of_freedom > 0) noise["degrees_of_freedom"] = detection_noise.degrees_of_freedom;
  return noise;
}

// The file's captures for `capture`: "markers" (and "detection_noise") are keyed by panel, so a panel that the
// capture holds twice (two photographs from one position) goes, with its second list, into a second capture at
// the same position, and so on; none is dropped.
std::vector<ordered_json> CaptureJson(const Capture& capture) {
  std::vector<std::pair<ordered_json, ordered_json>> slots;  // markers, detection noise
  for (const PanelMarkers& panel : capture.panels) {
    auto free = std::find_if(slots.begin(), slots.end(), [&](const auto& s) { return !s.first.contains(panel.panel); });
    if (free == slots.end()) {
      slots.emplace_back(ordered_json::object(), ordered_json::object());
      free = slots.end() - 1;
    }
    free->first[panel.panel] = MarkersJson(panel);
    if (panel.detection_noise) free->second[panel.panel] = DetectionNoiseJson(*panel.detection_noise);
  }
  std::vector<ordered_json> out;
  for (auto& [markers, detection_noise] : slots) {
    ordered_json c;
    c["camera_position"] = {Value(Significant(capture.camera_position[0], 12)),
                            Value(Significant(capture.camera_position[1], 12))};
    if (!detection_noise.empty()) c["detection_noise"] = std::move(detection_noise);
    c["markers"] = std::move(markers);
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace

ordered_json CameraIntrinsicsToJson(const CameraIntrinsics& c) {
  ordered_json j = {{"fx", Value(c.fx)}, {"fy", Value(c.fy)}, {"cx", Value(c.cx)}, {"cy", Value(c.cy)}};
  if (c.k1 != 0) j["k1"] = c.k1;
  if (c.k2 != 0) j["k2"] = c.k2;
  if (const auto& u = c.uncertainty) {
    j["fx_std_px"] = Significant(u->fx_px, 3);
    j["fy_std_px"] = Significant(u->fy_px, 3);
    j["cx_std_px"] = Significant(u->cx_px, 3);
    j["cy_std_px"] = Significant(u->cy_px, 3);
    j["k1_std"] = Significant(u->k1, 3);
    j["k2_std"] = Significant(u->k2, 3);
    j["rms_reprojection_px"] = Significant(u->rms_reprojection_px, 3);
  }
  return j;
}

ordered_json MeasurementsToJson(const Measurements& m) {
  ordered_json doc;
  doc["format"] = kMeasurementsFormat;
  if (!m.description.empty()) doc["description"] = m.description;
  if (m.camera) {
    doc["camera"] = CameraIntrinsicsToJson(*m.camera);
  }
  if (!m.captures.empty()) {
    ordered_json captures = ordered_json::array();
    for (const Capture& capture : m.captures)
      for (ordered_json& c : CaptureJson(capture)) captures.push_back(std::move(c));
    doc["captures"] = captures;
  }
  if (!m.luminance.empty()) {
    ordered_json curves = ordered_json::object();
    for (const PanelLuminance& curve : m.luminance) {
      const bool bits = curve.levels == InputLevels::k8Bit;
      ordered_json samples = ordered_json::array();
      for (const LuminanceSample& s : curve.samples)
        samples.push_back(
            {Value(bits ? std::round(s.level * 255) : Significant(s.level, 12)), Value(Significant(s.luminance, 6))});
      curves[curve.panel] = {{"levels", bits ? "8-bit" : "fraction"}, {"samples", samples}};
    }
    doc["luminance"] = curves;
  }
  return doc;
}

std::string FormatMeasurements(const Measurements& m) {
  std::string out;
  Print(MeasurementsToJson(m), 0, out);
  return out + "\n";
}

}  // namespace layerlab
