#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <string>

#include "layerlab/calibration/measurements.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/framework/params.h"

namespace layerlab {
namespace {

using nlohmann::json;

double Number(const json& v, const Location& at) {
  if (!v.is_number()) throw Error(at, "expected a number, got " + JsonKindName(v));
  double x = v.get<double>();
  if (!std::isfinite(x)) throw Error(at, "expected a finite number");
  return x;
}

double Number(Params& p, const std::string& key) { return Number(p.raw(key), p.where(key)); }

const json& PairOf(Params& p, const std::string& key, const std::string& what) {
  const json& v = p.raw(key);
  if (!v.is_array() || v.size() != 2)
    p.fail(key, "expected two values " + what + ", got " + JsonKindName(v) + " " + v.dump());
  return v;
}

std::array<double, 2> NumberPair(Params& p, const std::string& key, const std::string& what) {
  const json& v = PairOf(p, key, what);
  return {Number(v[0], p.where(key).child(0)), Number(v[1], p.where(key).child(1))};
}

MarkerObservation ReadMarker(Params p, const std::optional<CameraIntrinsics>& camera) {
  MarkerObservation m;
  m.where = p.where();
  auto pixel = NumberPair(p, "panel_pixel", "[col, row]");
  m.col = pixel[0];
  m.row = pixel[1];
  p.mark_read("camera_pixel");
  p.mark_read("angle");
  const bool by_pixel = p.has("camera_pixel"), by_angle = p.has("angle");
  if (by_pixel == by_angle)
    throw Error(m.where, by_pixel ? "give either \"camera_pixel\" or \"angle\", not both"
                                  : "missing the marker's image: give \"camera_pixel\": [u, v] or \"angle\": [x, y]");
  if (by_angle) {
    PairOf(p, "angle", "[x, y]");
    auto angle = p.quantity_pair("angle", Dimension::kAngle, {0, 0});
    for (int i = 0; i < 2; ++i)
      if (!(std::abs(angle[i]) < 1.5))
        throw Error(p.where("angle").child(i), "a visual angle must lie within (-1.5, 1.5) rad (86 deg)");
    m.angle_x = angle[0];
    m.angle_y = angle[1];
  } else {
    m.camera_pixel = NumberPair(p, "camera_pixel", "[u, v]");
    if (!camera)
      p.fail("camera_pixel",
             "a camera pixel needs the camera's intrinsics: add \"camera\": {\"fx\", \"fy\", "
             "\"cx\", \"cy\"} at the top level, or give \"angle\" instead");
    auto angle = AngleFromCameraPixel(*camera, (*m.camera_pixel)[0], (*m.camera_pixel)[1]);
    if (!angle)
      p.fail("camera_pixel", "the camera's distortion (k1, k2) folds back before this pixel: it cannot be undistorted");
    m.angle_x = (*angle)[0];
    m.angle_y = (*angle)[1];
  }
  p.check_all_read();
  return m;
}

// "detection_noise": {"<panel>": {"sigma": angle, "degrees_of_freedom": integer}}, by panel.
std::map<std::string, DetectionNoise> ReadDetectionNoise(Params& capture) {
  const json& object = capture.raw("detection_noise");
  const Location at = capture.where("detection_noise");
  if (!object.is_object())
    throw Error(at, "expected an object of detection noises by panel name, got " + JsonKindName(object));
  std::map<std::string, DetectionNoise> noise;
  for (auto it = object.begin(); it != object.end(); ++it) {
    Params p(*it, at.child(it.key()));
    DetectionNoise n;
    n.sigma_rad = p.quantity("sigma", Dimension::kAngle);
    if (!(n.sigma_rad > 0) || !std::isfinite(n.sigma_rad))
      p.fail("sigma", "a detection noise must be positive and finite");
    n.degrees_of_freedom = static_cast<int>(p.integer("degrees_of_freedom", 1, 1 << 30, 0));
    p.check_all_read();
    noise[it.key()] = n;
  }
  return noise;
}

Capture ReadCapture(Params p, const std::optional<CameraIntrinsics>& camera) {
  Capture c;
  c.where = p.where();
  p.mark_read("camera_position");
  if (p.has("camera_position")) {
    PairOf(p, "camera_position", "[x, y]");
    c.camera_position = p.quantity_pair("camera_position", Dimension::kLength, {0, 0});
  }
  p.string("description", "");
  std::map<std::string, DetectionNoise> noise;
  p.mark_read("detection_noise");
  if (p.has("detection_noise")) noise = ReadDetectionNoise(p);
  const json& markers = p.raw("markers");
  Location markers_at = p.where("markers");
  if (!markers.is_object())
    throw Error(markers_at, "expected an object of marker lists by panel name, got " + JsonKindName(markers));
  if (markers.empty()) throw Error(markers_at, "no panels: name at least one panel and its markers");
  for (auto it = markers.begin(); it != markers.end(); ++it) {
    PanelMarkers panel;
    panel.panel = it.key();
    panel.where = markers_at.child(it.key());
    if (!it->is_array()) throw Error(panel.where, "expected an array of markers, got " + JsonKindName(*it));
    if (it->empty()) throw Error(panel.where, "an empty list of markers; leave the panel out instead");
    for (size_t i = 0; i < it->size(); ++i)
      panel.markers.push_back(ReadMarker(Params((*it)[i], panel.where.child(i)), camera));
    if (auto found = noise.find(panel.panel); found != noise.end()) {
      panel.detection_noise = found->second;
      noise.erase(found);
    }
    c.panels.push_back(std::move(panel));
  }
  if (!noise.empty())
    throw Error(p.where("detection_noise").child(noise.begin()->first),
                "a detection noise for a panel without markers in this capture");
  p.check_all_read();
  return c;
}

PanelLuminance ReadLuminance(Params p, const std::string& panel) {
  PanelLuminance l;
  l.panel = panel;
  l.where = p.where();
  if (!p.has("levels")) p.raw("levels");  // reports the missing key
  l.levels =
      p.choice("levels", {"8-bit", "fraction"}, "8-bit") == "8-bit" ? InputLevels::k8Bit : InputLevels::kFraction;
  const json& samples = p.raw("samples");
  Location at = p.where("samples");
  if (!samples.is_array())
    throw Error(at, "expected an array of [level, luminance] pairs, got " + JsonKindName(samples));
  if (samples.empty()) throw Error(at, "no samples; leave the panel out instead");
  for (size_t i = 0; i < samples.size(); ++i) {
    const json& pair = samples[i];
    Location sample_at = at.child(i);
    if (!pair.is_array() || pair.size() != 2)
      throw Error(sample_at, "expected a pair [level, luminance], got " + JsonKindName(pair) + " " + pair.dump());
    LuminanceSample s;
    s.where = sample_at;
    double level = Number(pair[0], sample_at.child(0));
    if (l.levels == InputLevels::k8Bit) {
      if (level != std::floor(level) || level < 0 || level > 255)
        throw Error(sample_at.child(0), "an 8-bit level is an integer in [0, 255], got " + pair[0].dump());
      s.level = level / 255.0;
    } else {
      if (level < 0 || level > 1)
        throw Error(sample_at.child(0), "a fractional level lies in [0, 1], got " + pair[0].dump());
      s.level = level;
    }
    Params reader(json::object({{"1", pair[1]}}), sample_at);
    s.luminance = reader.quantity("1", Dimension::kLuminance);
    if (s.luminance < 0) throw Error(sample_at.child(1), "a luminance cannot be negative, got " + pair[1].dump());
    l.samples.push_back(s);
  }
  p.check_all_read();
  return l;
}

// The standard deviations `layerlab camera-intrinsics` writes: all of them or none.
std::optional<CameraIntrinsicsUncertainty> ReadCameraUncertainty(Params& p) {
  CameraIntrinsicsUncertainty u;
  const std::array<std::pair<const char*, double*>, 7> fields = {{{"fx_std_px", &u.fx_px},
                                                                  {"fy_std_px", &u.fy_px},
                                                                  {"cx_std_px", &u.cx_px},
                                                                  {"cy_std_px", &u.cy_px},
                                                                  {"k1_std", &u.k1},
                                                                  {"k2_std", &u.k2},
                                                                  {"rms_reprojection_px", &u.rms_reprojection_px}}};
  const char* given = nullptr;
  for (const auto& [key, value] : fields) {
    p.mark_read(key);  // known, so that a misspelling is suggested the right name
    if (p.has(key)) given = key;
  }
  if (!given) return std::nullopt;
  for (const auto& [key, value] : fields) {
    if (!p.has(key))
      throw Error(p.where(), std::string("\"") + given + "\" is given without \"" + key +
                                 "\": the uncertainty of an estimate comes whole (all of fx_std_px, fy_std_px, "
                                 "cx_std_px, cy_std_px, k1_std, k2_std, rms_reprojection_px) or not at all");
    *value = Number(p, key);
    if (!(*value >= 0)) p.fail(key, "a standard deviation or an RMS error cannot be negative");
  }
  return u;
}

}  // namespace

CameraIntrinsics ReadCameraIntrinsics(Params p) {
  CameraIntrinsics c;
  c.fx = Number(p, "fx");
  if (!(c.fx > 0)) p.fail("fx", "the focal length in pixels must be positive");
  c.fy = Number(p, "fy");
  if (!(c.fy > 0)) p.fail("fy", "the focal length in pixels must be positive");
  c.cx = Number(p, "cx");
  c.cy = Number(p, "cy");
  if (p.has("k1")) c.k1 = Number(p, "k1");
  if (p.has("k2")) c.k2 = Number(p, "k2");
  p.mark_read("k1");
  p.mark_read("k2");
  c.uncertainty = ReadCameraUncertainty(p);
  p.check_all_read();
  return c;
}

size_t Measurements::marker_count() const {
  size_t n = 0;
  for (const Capture& c : captures)
    for (const PanelMarkers& p : c.panels) n += p.markers.size();
  return n;
}

size_t Measurements::luminance_sample_count() const {
  size_t n = 0;
  for (const PanelLuminance& l : luminance) n += l.samples.size();
  return n;
}

Measurements ParseMeasurements(const json& document, const std::string& file) {
  Measurements m;
  m.file = file;
  Params top(document, {file, ""});
  std::string format = top.string("format");
  if (format != kMeasurementsFormat)
    top.fail("format",
             "unknown measurements format \"" + format + "\"; this layerlab reads \"" + kMeasurementsFormat + "\"");
  m.description = top.string("description", "");
  top.mark_read("camera");
  if (top.has("camera")) m.camera = ReadCameraIntrinsics(top.object("camera"));

  top.mark_read("captures");
  if (top.has("captures")) {
    const json& captures = top.raw("captures");
    if (!captures.is_array()) top.fail("captures", "expected an array of captures, got " + JsonKindName(captures));
    for (size_t i = 0; i < captures.size(); ++i)
      m.captures.push_back(ReadCapture(Params(captures[i], top.where("captures").child(i)), m.camera));
  }
  top.mark_read("luminance");
  if (top.has("luminance")) {
    const json& luminance = top.raw("luminance");
    if (!luminance.is_object())
      top.fail("luminance", "expected an object of luminance curves by panel name, got " + JsonKindName(luminance));
    for (auto it = luminance.begin(); it != luminance.end(); ++it)
      m.luminance.push_back(ReadLuminance(Params(*it, top.where("luminance").child(it.key())), it.key()));
  }
  top.check_all_read();
  if (m.marker_count() == 0 && m.luminance.empty())
    throw Error(Location{file, ""}, "nothing to fit: the file has neither \"captures\" with markers nor \"luminance\"");
  return m;
}

CameraIntrinsics ReadCameraIntrinsicsFile(const std::string& path) {
  const json document = ReadJsonFile(path);
  if (document.is_object() && document.contains("camera") && document.contains("format")) {
    Params top(document, {path, ""});
    return ReadCameraIntrinsics(top.object("camera"));
  }
  return ReadCameraIntrinsics(Params(document, {path, ""}));
}

Measurements ReadMeasurementsFile(const std::string& path) { return ParseMeasurements(ReadJsonFile(path), path); }

}  // namespace layerlab
