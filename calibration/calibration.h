// Calibration of a built display from measurements (docs/measurements-format.md):
// options in, a report out, in the manner of ceres::Solver.
//
// Geometry (marker_model.h), per panel with markers: its distance from the
// nearest lens or curved mirror in front of it (which sets its magnification
// and image depth), its lateral offset and its in-plane rotation; optionally
// the focal lengths and gaps of the lenses and curved mirrors on the paths,
// each shared by every panel behind it; the camera's pointing when the axis is
// referenced to the farthest panel. The
// flips are known from the scene (reversed panels, mirrored branches) and are
// not fitted, but a panel whose markers fit a mirror image far better is reported.
// Photometry (luminance_model.h), per panel with luminance data: the maximum
// luminance, the black level and gamma.
//
// The fit starts from the scene's values. Whatever the data cannot determine
// is held at its scene value and the report says so (a warning naming the
// parameter), never fitted silently; uncertainties come from ceres::Covariance.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/calibration/measurements.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

enum class RobustLoss { kNone, kHuber, kCauchy };
std::string ToString(RobustLoss loss);
RobustLoss RobustLossFromString(const std::string& name);  // throws layerlab::Error naming the known ones

// What defines the eye's axis and its horizontal.
enum class AxisReference {
  // The measuring camera's: its principal point is the axis, its rows the horizontal.
  kCamera,
  // The farthest panel's image center and rows, as the paper centers the
  // farthest panel on its camera: that panel's offset and rotation become 0,
  // the camera's pan, tilt and roll are fitted instead.
  kFarthestPanel,
};
std::string ToString(AxisReference reference);
AxisReference AxisReferenceFromString(const std::string& name);  // throws layerlab::Error

// Whether a parameter that only some captures determine is fitted.
enum class FitChoice {
  // Fitted when the captures determine it (markers from two or more camera
  // positions), else held at its scene value and the report says so, with the
  // value assumed; also held when fitting it leaves it undetermined.
  kAuto,
  kFit,   // fitted; a fit that cannot determine it says so and writes nothing without --force
  kHold,  // held at its scene value
};
std::string ToString(FitChoice choice);
FitChoice FitChoiceFromString(const std::string& name);  // throws layerlab::Error naming the known ones

struct CalibrationOptions {
  // The focal length of every lens and curved mirror on the paths (the
  // magnifier's, on the paper's layout). Only parallax tells it from the
  // panel distances: the markers must be seen from more than one camera position.
  FitChoice focal_length = FitChoice::kAuto;
  // The gap of every lens and curved mirror (from the element before it; the
  // magnifier placed by the eye's eye_relief: from the pupil). Again only
  // parallax sees it, and only with two panels at different depths behind it.
  FitChoice lens_gaps = FitChoice::kAuto;
  // The radial distortion k of every lens and curved mirror (marker_model.h:
  // a point at tan-angle t from the pupil's center seen at t (1 + k |t|^2)),
  // which a real magnifier has and the paraxial model lacks. Reported, not
  // carried into the calibrated scene. Held at 0 unless asked for (auto fits
  // it wherever there are markers).
  FitChoice distortion = FitChoice::kHold;
  // The model-error test (docs/calibration.md): when the markers carry the
  // noise detect measured in the photographs, a residual above it at this
  // significance level is a model error, and the result is not usable unless
  // accepted.
  double model_error_level = 1e-3;
  // Nor is a residual within this factor of the noise (RMS) a model error:
  // the noise measured on each board about a smooth map of it leaves out the
  // part of the corners' error that varies slowly over the board (the
  // sensor's sampling phase), some 10 % of it in the project's renderer.
  double model_error_min_ratio = 1.25;
  bool accept_model_error = false;
  // Discounts outliers (a misdetected marker, a reading of the wrong pattern).
  // Turn it on when the report counts markers far beyond the noise.
  RobustLoss loss = RobustLoss::kNone;
  // Where the loss starts to discount: a marker's angular error (rad), and a
  // luminance residual relative to the panel's brightest reading. About three
  // times the noise is a good choice.
  double marker_loss_scale_rad = 2.908882086657216e-4;  // 1 arcmin
  double luminance_loss_scale = 0.02;
  AxisReference reference = AxisReference::kCamera;
  // Levenberg-Marquardt; the problems are small, so the tolerances are tight.
  int max_iterations = 200;
  double function_tolerance = 1e-14;
  double parameter_tolerance = 1e-13;

  // False with "field: value: constraint" in *error when an option is out of range.
  bool IsValid(std::string* error) const;
};

// A fitted distance, focal length or gap whose standard deviation exceeds
// this fraction of its value is not determined by the data; neither is a
// parameter that ends at a bound of the model (a panel at the focal length).
// Both are reported "undetermined by the fit" (docs/measurements-format.md).
inline constexpr double kUndeterminedStdDevFraction = 0.1;

enum class ParameterStatus {
  kFitted,
  kUndetermined,  // the data cannot determine it: held at its scene value
  kReference,     // fixed by the axis reference
  kNotFitted,     // not asked for (FitChoice::kHold)
  kUnresolved,    // fitted, but at a bound of the model or with a standard deviation beyond kUndeterminedStdDevFraction
};
std::string ToString(ParameterStatus status);

// The SI unit of a ParameterEstimate's quantity: "m", "D", "rad", or "" (a ratio, gamma, or max_luminance in
// the measurements' own unit).
const char* ParameterSiUnit(const std::string& quantity);

struct ParameterEstimate {
  std::string element;     // a panel, a lens or curved mirror, or "camera"
  std::string quantity;    // distance, virtual_depth, offset_x, offset_y, rotation, focal_length, gap, distortion,
                           // pan, tilt, roll, max_luminance, black_level, gamma
  double scene_value = 0;  // SI (m, rad, D); max_luminance in the measurements' unit
  double value = 0;        // after the fit
  std::optional<double> std_dev;  // one standard deviation; empty when not fitted or not estimable
  ParameterStatus status = ParameterStatus::kFitted;
  bool derived = false;  // computed from fitted ones (virtual_depth)
};

struct PanelResiduals {
  std::string panel;
  int markers = 0;
  double marker_rms_before_rad = 0, marker_rms_after_rad = 0;  // rad, the angular error per marker
  int luminance_samples = 0;
  double luminance_rms_before = 0, luminance_rms_after = 0;  // relative to the panel's brightest reading
};

struct CalibrationReport {
  std::string scene, measurements;  // files, for the report
  CalibrationOptions options;
  bool usable = false;
  std::string message = "not run";

  int markers = 0, captures = 0, camera_positions = 0, luminance_samples = 0;
  double marker_rms_before_rad = 0, marker_rms_after_rad = 0;  // rad, over all markers
  // rad per axis: measured in the photographs when the markers carry their
  // detection noise, else estimated from the residuals (NaN when not estimable).
  double marker_noise_rad = 0;
  bool noise_from_detection = false;
  // The model-error test, with the detection noise: the residuals' mean square
  // over their degrees of freedom against the detection noise's, and the ratio
  // at which it becomes significant at options.model_error_level.
  double variance_ratio = 0, critical_variance_ratio = 0;
  int residual_degrees_of_freedom = 0, noise_degrees_of_freedom = 0;  // 0 noise degrees: taken as exact
  std::string model_error;                                            // what the test found, or empty
  double luminance_rms_before = 0, luminance_rms_after = 0;
  std::string geometry_solver, luminance_solver;  // Ceres' brief reports
  std::vector<PanelResiduals> panels;
  std::vector<ParameterEstimate> parameters;
  std::vector<std::string> warnings;
  // What the fit held as the options allow (FitChoice::kAuto: a focal length
  // or gap the captures cannot determine), with the value it assumed.
  std::vector<std::string> notes;
  // Parameters with ParameterStatus::kUnresolved, and why: `fit` writes no calibrated scene then unless --force.
  std::vector<std::string> unresolved;

  bool IsSolutionUsable() const { return usable; }
  const ParameterEstimate* find(const std::string& element, const std::string& quantity) const;
  std::string BriefReport() const;
  std::string FullReport() const;
  nlohmann::json ToJson() const;
};

// The display as calibrated: what the calibrated scene file is written from.
struct CalibratedPanel {
  std::string name;
  bool geometry_measured = false, luminance_measured = false;
  // Some element with power in front of it had its focal length or gap fitted:
  // its physical place is what stays, so it is written even without markers.
  bool optics_fitted = false;
  bool behind_optics = false;                             // some lens or curved mirror lies in front of it
  double distance_m = 0;                                  // m, from the nearest of them (from the pupil without one)
  double gap_m = 0;                                       // m, from the element before it on its path
  double eye_from_panel_x_m = 0, eye_from_panel_y_m = 0;  // PanelSpec::eye_from_panel_m (the scene's "offset")
  double rotation_rad = 0;                                // rad, counterclockwise as the eye sees it
  double gamma = 0, black_level = 0;
  double max_luminance = 0;  // in the measurements' unit; 0 when not measured
};

// A lens or curved mirror on the paths.
struct CalibratedOptic {
  std::string name;
  double focal_length_m = 0;  // m
  double gap_m = 0;           // m, from the element before it (the pupil for the magnifier placed by eye_relief)
  bool focal_length_fitted = false, gap_fitted = false;
};

struct CalibratedDisplay {
  std::vector<CalibratedOptic> optics;  // every lens and curved mirror on a measured path, nearest the eye first
  std::vector<CalibratedPanel> panels;  // in the system's layer order (farthest first)

  const CalibratedPanel* find(const std::string& panel) const;
  const CalibratedOptic* find_optic(const std::string& name) const;
};

// Fits `system` (compiled from the scene as designed) to `measurements`.
// Does not throw: bad options, measurements that do not belong to the
// system, and a failed solve land in the report's message; *display is
// usable only when report.IsSolutionUsable().
CalibrationReport Calibrate(const DisplaySystem& system, const Measurements& measurements,
                            const CalibrationOptions& options, CalibratedDisplay* display);

}  // namespace layerlab
