// Calibration measurements, "layerlab-measurements/1" (docs/measurements-format.md):
// what a camera at the eye position records while markers are shown on each
// panel, and each panel's luminance against its input level.
//
// Reading is strict (every key accounted for, an unknown one refused with a
// suggestion, every error with the file and JSON pointer). Marker positions
// given in camera pixels are turned into visual angles on reading, so the fit
// sees angles only; the pixels are kept for writing the file back.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/calibration/camera_model.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/params.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

inline constexpr const char* kMeasurementsFormat = "layerlab-measurements/1";

struct MarkerObservation {
  // The marker's panel pixel in the panel's full grid (active-region offset
  // included), in the panel's own order; integers are pixel centers.
  double col = 0, row = 0;
  // The direction the camera sees it in: atan(x/z), atan(y/z), x right, y up (rad).
  double angle_x = 0, angle_y = 0;
  // As measured (u right, v down), when given in camera pixels.
  std::optional<std::array<double, 2>> camera_pixel;
  Location where;
};

// The scatter of one photograph's markers about a smooth map of its board,
// per axis (calibration/detection_noise.h): what the fit's residual is tested
// against, and what its uncertainties are scaled by.
struct DetectionNoise {
  double sigma_rad = 0;  // rad, one standard deviation per axis
  // Of the estimate; 0 when it is taken as exact (given without them).
  int degrees_of_freedom = 0;
};

struct PanelMarkers {
  std::string panel;
  std::vector<MarkerObservation> markers;
  std::optional<DetectionNoise> detection_noise;  // none when not measured
  Location where;
};

// Markers recorded from one camera position.
struct Capture {
  // Lateral position of the camera's entrance pupil in the eye's pupil plane,
  // m, x right, y up. Captures from several positions see parallax, which is
  // what separates the focal length from the panel distances.
  std::array<double, 2> camera_position = {0, 0};
  std::vector<PanelMarkers> panels;
  Location where;
};

enum class InputLevels { k8Bit, kFraction };

struct LuminanceSample {
  double level = 0;      // input, as a fraction of full scale
  double luminance = 0;  // in any unit consistent within the panel (cd/m^2 when given with a unit)
  Location where;
};

struct PanelLuminance {
  std::string panel;
  InputLevels levels = InputLevels::k8Bit;
  std::vector<LuminanceSample> samples;
  Location where;
};

struct Measurements {
  std::string file;
  std::string description;
  std::optional<CameraIntrinsics> camera;
  std::vector<Capture> captures;
  std::vector<PanelLuminance> luminance;

  size_t marker_count() const;
  size_t luminance_sample_count() const;
};

// The "camera" object (strict) and its file form.
CameraIntrinsics ReadCameraIntrinsics(Params p);
nlohmann::ordered_json CameraIntrinsicsToJson(const CameraIntrinsics& camera);
// A file holding that object alone, or a measurements file's or capture plan's "camera".
CameraIntrinsics ReadCameraIntrinsicsFile(const std::string& path);

Measurements ParseMeasurements(const nlohmann::json& document, const std::string& file);
Measurements ReadMeasurementsFile(const std::string& path);

// Checks the measurements against the display they were taken on: every panel
// name is a panel of the system (the closest one suggested), every marker
// pixel lies on its panel's grid, every panel with luminance data has a
// non-zero reading. Throws layerlab::Error with the file and pointer.
void CheckMeasurements(const Measurements& measurements, const DisplaySystem& system);

// The marker model (marker_model.h) is first order: a panel square to the
// axis, placed by its distance, offset and in-plane rotation. Throws
// layerlab::Error naming the scene, the panel and its "tilt" when a panel is
// tilted; `use` says what refuses it ("the calibration fit").
void RefuseTiltedPanels(const DisplaySystem& system, const std::string& use);

// The file form of `measurements`: camera pixels where a marker has them,
// angles (rad) otherwise; one marker or sample per line.
nlohmann::ordered_json MeasurementsToJson(const Measurements& measurements);
std::string FormatMeasurements(const Measurements& measurements);

}  // namespace layerlab
