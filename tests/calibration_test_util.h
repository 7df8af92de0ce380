// Synthetic calibration data of the paper prototype from known placements,
// and the uncertainties a least-squares fit of them should reach, derived
// here from the noise and the marker layout (not from the fit).
#pragma once

#include <string>
#include <vector>

#include "calibration/calibration.h"
#include "calibration/synthetic_measurements.h"

namespace layerlab::testing {

// How one panel is really built, against the scene as designed.
struct PanelTruth {
  std::string name;
  double distance_change = 0;           // m, added to the designed distance from the lens
  double offset_x = 0, offset_y = 0;    // m
  double rotation = 0;                  // rad
  double max_luminance = 0, black_level = 0, gamma = 0;
};

// The true values examples/paper_prototype_measurements.json was made from.
std::vector<PanelTruth> ExampleTruth();

// `designed` with the panels placed as `truth` says.
DisplaySystem BuiltSystem(const DisplaySystem& designed, const std::vector<PanelTruth>& truth);

struct SyntheticSetup {
  MarkerGrid grid;
  SyntheticCamera camera;
  SyntheticNoise noise;
  std::vector<int> luminance_codes;  // 8-bit levels; none: no luminance data
};

// The setup of the example file: a 4000 x 3000 camera, 7 x 5 markers per
// panel from three camera positions, 0.3 arcmin noise per axis, luminance at
// 17 levels with 0.3 % noise.
SyntheticSetup ExampleSetup();

Measurements SyntheticMeasurements(const DisplaySystem& built, const std::vector<PanelTruth>& truth,
                                   const SyntheticSetup& setup);

// One standard deviation of a least-squares fit of one panel's distance,
// offset (per axis) and rotation from `markers` (on `layer`), each seen at
// `positions` camera positions with angular noise `sigma` per axis:
// (J^T J)^-1 of the pupil-center model t = T(s) (o + R l), whose parameters
// decouple for a grid centered on the panel.
struct GeometrySigma {
  double distance = 0, offset = 0, rotation = 0;
};
GeometrySigma ExpectedGeometrySigma(const DisplaySystem& built, const VirtualLayer& layer, const PanelMarkers& markers,
                                    int positions, double sigma);

// The same for the luminance curve, from the Jacobian of
// L = max (b + (1 - b) x^gamma) at the true values, samples at `codes` with
// noise `sigma` relative to the maximum.
struct LuminanceSigma {
  double max_luminance = 0, black_level = 0, gamma = 0;
};
LuminanceSigma ExpectedLuminanceSigma(const std::vector<int>& codes, double max_luminance, double black_level,
                                      double gamma, double sigma);

}  // namespace layerlab::testing
