// The two independent parts of Calibrate() (calibration.h), and how the
// report shows a value. Internal to calibration/.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/calibration/calibration.h"

namespace layerlab {

// The display as the scene has it, and a residual row per panel: where both fits start.
void StartFromScene(const DisplaySystem& system, CalibratedDisplay* display, CalibrationReport* report);

// Each fills its part of *display and *report; false (with report->message)
// when no usable result came out.
bool FitGeometry(const DisplaySystem& system, const Measurements& measurements, const CalibrationOptions& options,
                 CalibratedDisplay* display, CalibrationReport* report);
bool FitLuminance(const DisplaySystem& system, const Measurements& measurements, const CalibrationOptions& options,
                  CalibratedDisplay* display, CalibrationReport* report);

// The markers of one photograph: one panel's board seen from one capture.
struct MarkerBlock {
  std::string panel;
  std::array<double, 2> camera_position = {0, 0};  // m
  Location where;                                  // the photograph (or the measurements' list)
  std::optional<DetectionNoise> noise;
  double squared_error_rad2 = 0;  // rad^2, the fitted residuals' sum over its markers, both axes
  int markers = 0;
};

// The model-error test (calibration.h): the residuals against the detection
// noise, into *report; where the excess concentrates, named by photograph.
// False (with report->message) when a model error makes the result unusable
// (not accepted by the options). `remedies`: what the message may offer to
// fit, and whether lenses described by their surfaces (traced, not fitted)
// are on the measured paths.
struct ModelErrorRemedies {
  bool focal_lengths = true;  // an ideal lens or curved mirror has one to fit
  bool distortions = true;    // one of them has a panel behind it seen by the first-order model
  bool surfaces = false;      // a lens described by its surfaces may be other than they say
};
bool CheckModelError(const std::vector<MarkerBlock>& blocks, int free_parameters, const CalibrationOptions& options,
                     CalibrationReport* report, const ModelErrorRemedies& remedies = {});

// "a; b; c".
std::string JoinedBySemicolons(const std::vector<std::string>& parts);

// A parameter's value in the unit the report shows it in: "72.8123 mm", "0.1500 deg", "2.4000".
std::string ShowValue(const std::string& quantity, double si_value);
// The unit the report shows a quantity in ("mm", "deg", "D", "arcmin", "").
std::string ShowUnit(const std::string& quantity);
double ArcminFromRadians(double radians);
// "0.321 arcmin".
std::string Arcmin(double radians);

struct ScalarParameter;
// Why the fit does not determine the fitted value `p` of `parameter`
// (completing "it ..."), or "": it ends at a bound of the model, or, for a
// length that must be positive (a distance, focal length or gap), its standard
// deviation exceeds kUndeterminedStdDevFraction of its value.
std::string Unresolved(const ScalarParameter& parameter, const ParameterEstimate& p);

class ScalarFit;
struct ScalarFitOptions;
struct UndeterminedParameter;
// How both fits solve: the options' iteration limit, tolerances and robust noise.
ScalarFitOptions ScalarFitOptionsOf(const CalibrationOptions& options);
// The report's warning for a parameter of `fit` that the data do not determine
// (it trades off against its partners without changing any residual, so it
// keeps its scene value, shown as a `quantity`).
std::string UndeterminedWarning(const ScalarFit& fit, const UndeterminedParameter& u, const std::string& quantity);

}  // namespace layerlab

namespace ceres {
class LossFunction;
}

namespace layerlab {

// The robust loss of the options at `scale` (null for none); the caller owns it.
ceres::LossFunction* MakeLoss(RobustLoss loss, double scale);
// The index of the layer showing panel `name` (which must exist).
int LayerIndex(const DisplaySystem& system, const std::string& name);

}  // namespace layerlab
