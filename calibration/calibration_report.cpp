#include <cmath>
#include <cstdio>
#include <numbers>

#include "layerlab/calibration/fit_steps.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

struct Shown {
  const char* unit;
  double scale;  // display units per SI unit
  int decimals;
};

Shown ShownAs(const std::string& quantity) {
  if (quantity == "distance" || quantity == "focal_length" || quantity == "gap" || quantity == "offset_x" ||
      quantity == "offset_y")
    return {"mm", 1e3, 4};
  if (quantity == "virtual_depth") return {"D", 1, 4};
  if (quantity == "rotation") return {"deg", kDegreesPerRadian, 4};
  if (quantity == "pan" || quantity == "tilt" || quantity == "roll") return {"arcmin", kDegreesPerRadian * 60, 3};
  if (quantity == "black_level") return {"", 1, 5};
  if (quantity == "gamma") return {"", 1, 4};
  if (quantity == "distortion") return {"", 1, 5};
  return {"", 1, -1};  // max_luminance: in the measurements' own unit, significant digits
}

std::string Show(const std::string& quantity, double value, bool with_unit) {
  const Shown s = ShownAs(quantity);
  char buf[64];
  if (s.decimals < 0)
    std::snprintf(buf, sizeof buf, "%.5g", value);
  else
    std::snprintf(buf, sizeof buf, "%.*f", s.decimals, value * s.scale);
  std::string text = buf;
  if (text.find_first_not_of("-0.") == std::string::npos) text = FormatFixed(0.0, s.decimals < 0 ? 0 : s.decimals);
  return with_unit && *s.unit ? text + " " + s.unit : text;
}

std::string Percent(double relative) { return FormatFixed(100 * relative, 3) + " %"; }

nlohmann::json Finite(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); }

std::string Pad(std::string text, size_t width) {
  if (text.size() < width) text.append(width - text.size(), ' ');
  return text + " ";
}

}  // namespace

double ArcminFromRadians(double radians) { return radians * 180.0 / std::numbers::pi * 60.0; }

std::string Arcmin(double radians) { return FormatFixed(ArcminFromRadians(radians), 3) + " arcmin"; }

std::string JoinedBySemicolons(const std::vector<std::string>& parts) {
  std::string out;
  for (const std::string& part : parts) out += (out.empty() ? "" : "; ") + part;
  return out;
}

std::string ShowValue(const std::string& quantity, double si_value) { return Show(quantity, si_value, true); }

std::string ShowUnit(const std::string& quantity) { return ShownAs(quantity).unit; }

const char* ParameterSiUnit(const std::string& quantity) {
  const std::string shown = ShownAs(quantity).unit;
  if (shown == "mm") return "m";
  if (shown == "deg" || shown == "arcmin") return "rad";
  return shown == "D" ? "D" : "";
}

const ParameterEstimate* CalibrationReport::find(const std::string& element, const std::string& quantity) const {
  for (const ParameterEstimate& p : parameters)
    if (p.element == element && p.quantity == quantity) return &p;
  return nullptr;
}

std::string CalibrationReport::BriefReport() const {
  std::string out = std::string("calibration: ") + (usable ? "usable" : "NOT usable") + " (" + message + ")";
  if (markers) out += "; markers: RMS " + Arcmin(marker_rms_before_rad) + " -> " + Arcmin(marker_rms_after_rad);
  if (luminance_samples)
    out += "; luminance: RMS " + Percent(luminance_rms_before) + " -> " + Percent(luminance_rms_after);
  if (!warnings.empty()) out += "; " + std::to_string(warnings.size()) + " warning" + (warnings.size() > 1 ? "s" : "");
  return out;
}

std::string CalibrationReport::FullReport() const {
  std::string out = "calibration of " + scene + " from " + measurements + "\n";
  out += "result      " + std::string(usable ? "usable: " : "NOT usable: ") + message + "\n";
  out += "options     loss " + ToString(options.loss);
  if (options.loss != RobustLoss::kNone)
    out += " (scales " + Arcmin(options.marker_loss_scale_rad) + ", " + Percent(options.luminance_loss_scale) + ")";
  out += "; axis reference " + ToString(options.reference) + "; focal length " + ToString(options.focal_length) +
         "; lens gaps " + ToString(options.lens_gaps) + "; distortion " + ToString(options.distortion) + "\n";
  if (markers) {
    out += "geometry    " + std::to_string(markers) + " markers in " + std::to_string(captures) + " capture" +
           (captures > 1 ? "s" : "") + " from " + std::to_string(camera_positions) + " camera position" +
           (camera_positions > 1 ? "s" : "") + "\n";
    out += "            residual RMS " + Arcmin(marker_rms_before_rad) + " (scene) -> " + Arcmin(marker_rms_after_rad) +
           " (fitted), per marker";
    if (std::isfinite(marker_noise_rad))
      out += "; noise " + Arcmin(marker_noise_rad) + " per axis" +
             (noise_from_detection ? " (measured in the photographs)" : " (estimated from the residuals)");
    if (noise_from_detection && residual_degrees_of_freedom > 0)
      out += "\n            model check: residual/noise variance " + FormatFixed(variance_ratio, 3) + " (" +
             (model_error.empty() ? "within" : "ABOVE") + " " + FormatFixed(critical_variance_ratio, 3) + " at " +
             FormatFixed(100 * options.model_error_level, 2) + " %)";
    out += "\n            " + geometry_solver + "\n";
  } else {
    out += "geometry    no markers: not fitted\n";
  }
  if (luminance_samples) {
    out += "luminance   " + std::to_string(luminance_samples) + " samples; residual RMS " +
           Percent(luminance_rms_before) + " (scene) -> " + Percent(luminance_rms_after) +
           " (fitted), of each panel's brightest reading\n";
    size_t start = 0;
    while (start < luminance_solver.size()) {
      size_t end = luminance_solver.find('\n', start);
      if (end == std::string::npos) end = luminance_solver.size();
      out += "            " + luminance_solver.substr(start, end - start) + "\n";
      start = end + 1;
    }
  } else {
    out += "luminance   no samples: not fitted\n";
  }

  out += "\n" + Pad("panel", 12) + Pad("markers", 8) + Pad("RMS scene", 16) + Pad("RMS fitted", 16) +
         Pad("samples", 8) + Pad("RMS scene", 10) + "RMS fitted\n";
  for (const PanelResiduals& p : panels) {
    out += Pad(p.panel, 12) + Pad(std::to_string(p.markers), 8);
    out += p.markers ? Pad(Arcmin(p.marker_rms_before_rad), 16) + Pad(Arcmin(p.marker_rms_after_rad), 16)
                     : Pad("-", 16) + Pad("-", 16);
    out += Pad(std::to_string(p.luminance_samples), 8);
    out += p.luminance_samples ? Pad(Percent(p.luminance_rms_before), 10) + Percent(p.luminance_rms_after)
                               : Pad("-", 10) + "-";
    out += "\n";
  }

  out += "\n" + Pad("parameter", 28) + Pad("scene", 14) + Pad("fitted", 14) + Pad("std dev", 14) + "unit    status\n";
  for (const ParameterEstimate& p : parameters) {
    std::string name = p.element + " " + p.quantity;
    out += Pad(name, 28) + Pad(Show(p.quantity, p.scene_value, false), 14) + Pad(Show(p.quantity, p.value, false), 14) +
           Pad(p.std_dev ? Show(p.quantity, *p.std_dev, false) : "-", 14) +
           Pad(ShowUnit(p.quantity).empty() ? "-" : ShowUnit(p.quantity), 7) + ToString(p.status) +
           (p.derived ? " (derived)" : "") + "\n";
  }
  if (!warnings.empty() || !notes.empty()) out += "\n";
  for (const std::string& n : notes) out += "note: " + n + "\n";
  for (const std::string& w : warnings) out += "warning: " + w + "\n";
  return out;
}

nlohmann::json CalibrationReport::ToJson() const {
  using nlohmann::json;
  json j;
  j["format"] = "layerlab-calibration-report/1";
  j["scene"] = scene;
  j["measurements"] = measurements;
  j["usable"] = usable;
  j["message"] = message;
  j["options"] = {{"loss", ToString(options.loss)},
                  {"marker_loss_scale_arcmin", ArcminFromRadians(options.marker_loss_scale_rad)},
                  {"luminance_loss_scale", options.luminance_loss_scale},
                  {"axis_reference", ToString(options.reference)},
                  {"focal_length", ToString(options.focal_length)},
                  {"lens_gaps", ToString(options.lens_gaps)},
                  {"distortion", ToString(options.distortion)},
                  {"model_error_level", options.model_error_level},
                  {"accept_model_error", options.accept_model_error}};
  j["geometry"] = {{"markers", markers},
                   {"captures", captures},
                   {"camera_positions", camera_positions},
                   {"rms_before_arcmin", ArcminFromRadians(marker_rms_before_rad)},
                   {"rms_after_arcmin", ArcminFromRadians(marker_rms_after_rad)},
                   {"noise_arcmin", Finite(ArcminFromRadians(marker_noise_rad))},
                   {"noise_from_detection", noise_from_detection},
                   {"solver", geometry_solver}};
  j["model_check"] = {{"variance_ratio", variance_ratio},
                      {"critical_variance_ratio", critical_variance_ratio},
                      {"residual_degrees_of_freedom", residual_degrees_of_freedom},
                      {"noise_degrees_of_freedom", noise_degrees_of_freedom},
                      {"model_error", model_error}};
  j["luminance"] = {{"samples", luminance_samples},
                    {"rms_before_relative", luminance_rms_before},
                    {"rms_after_relative", luminance_rms_after},
                    {"solver", luminance_solver}};
  json panel_list = json::array();
  for (const PanelResiduals& p : panels)
    panel_list.push_back({{"panel", p.panel},
                          {"markers", p.markers},
                          {"rms_before_arcmin", ArcminFromRadians(p.marker_rms_before_rad)},
                          {"rms_after_arcmin", ArcminFromRadians(p.marker_rms_after_rad)},
                          {"luminance_samples", p.luminance_samples},
                          {"luminance_rms_before_relative", p.luminance_rms_before},
                          {"luminance_rms_after_relative", p.luminance_rms_after}});
  j["panels"] = panel_list;
  json parameter_list = json::array();
  for (const ParameterEstimate& p : parameters) {
    const char* si = p.quantity == "virtual_depth"   ? "D"
                     : p.quantity == "max_luminance" ? "as measured"
                     : p.quantity == "gamma" || p.quantity == "black_level" || p.quantity == "distortion" ? ""
                     : p.quantity == "rotation" || p.quantity == "pan" || p.quantity == "tilt" || p.quantity == "roll"
                         ? "rad"
                         : "m";
    parameter_list.push_back({{"element", p.element},
                              {"quantity", p.quantity},
                              {"unit", si},
                              {"scene_value", p.scene_value},
                              {"value", p.value},
                              {"std_dev", p.std_dev ? json(*p.std_dev) : json(nullptr)},
                              {"status", ToString(p.status)},
                              {"derived", p.derived}});
  }
  j["parameters"] = parameter_list;
  j["warnings"] = warnings;
  j["notes"] = notes;
  return j;
}

}  // namespace layerlab
