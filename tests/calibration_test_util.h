// Synthetic calibration data of a display built with known placements (the
// paper prototype's example, any scene's misplaced lenses and panels), and the
// uncertainties a least-squares fit of them should reach, derived here from
// the noise and the marker layout (not from the fit).
#pragma once

#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/calibration/calibration.h"
#include "layerlab/calibration/synthetic_measurements.h"

namespace layerlab::testing {

inline constexpr double kArcmin = std::numbers::pi / 180.0 / 60.0;
// A recovered value may lie this many (independently derived) standard deviations from the truth.
inline constexpr double kSigmas = 4.0;

// How one panel is really built, against the scene as designed.
struct PanelTruth {
  std::string name;
  double distance_change = 0;                             // m, added to the designed distance from the lens
  double eye_from_panel_x_m = 0, eye_from_panel_y_m = 0;  // m
  double rotation = 0;                                    // rad
  double max_luminance = 0, black_level = 0, gamma = 0;
};

// How a lens or curved mirror is really built.
struct OpticTruth {
  std::string name;
  double gap_change = 0;               // m, added to its designed gap
  std::optional<double> focal_length;  // m; as designed when empty
};

// The true values examples/paper_prototype_measurements.json was made from.
std::vector<PanelTruth> ExampleTruth();

// The scene `designed` was compiled from (its file), as built: every panel
// placed by its physical distance from the optics in front ("distance" in the
// place of "virtual_depth", so that it stays put when the optics change; "gap"
// without optics in front), moved,
// offset and turned as `truth` says; every optic's gap and focal length as
// `optics` says.
nlohmann::json BuiltScene(const DisplaySystem& designed, const std::vector<PanelTruth>& truth,
                          const std::vector<OpticTruth>& optics = {});
// That scene compiled.
DisplaySystem BuiltSystem(const DisplaySystem& designed, const std::vector<PanelTruth>& truth,
                          const std::vector<OpticTruth>& optics = {});

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

// Every panel's distance, offset and rotation in `display` are those of `built` to within `tolerance` (SI).
void ExpectPlacementsOf(const DisplaySystem& built, const CalibratedDisplay& display, double tolerance);

// examples/per_branch_magnifiers_measurements.json: each branch's lens off its
// designed gap, every panel moved, offset and turned; the example's camera
// from five positions (the center and 3 mm to each side), no luminance data.
std::vector<PanelTruth> PerBranchTruth();
std::vector<OpticTruth> PerBranchOptics();
SyntheticSetup PerBranchSetup();

Measurements SyntheticMeasurements(const DisplaySystem& built, const std::vector<PanelTruth>& truth,
                                   const SyntheticSetup& setup);

// One standard deviation of a least-squares fit of one panel's distance,
// offset (per axis) and rotation from `markers` (on `layer`), each seen at
// `positions` camera positions with angular noise `sigma` per axis:
// (J^T J)^-1 of the pupil-center model t = T(s) (o + R l), T = 1 / |B| of the
// layer's transfer, whose parameters decouple for a grid centered on the panel.
struct GeometrySigma {
  double distance = 0, offset = 0, rotation = 0;
};
GeometrySigma ExpectedGeometrySigma(const VirtualLayer& layer, const PanelMarkers& markers, int positions,
                                    double sigma);

// The same for the luminance curve, from the Jacobian of
// L = max (b + (1 - b) x^gamma) at the true values, samples at `codes` with
// noise `sigma` relative to the maximum.
struct LuminanceSigma {
  double max_luminance = 0, black_level = 0, gamma = 0;
};
LuminanceSigma ExpectedLuminanceSigma(const std::vector<int>& codes, double max_luminance, double black_level,
                                      double gamma, double sigma);

// The same by brute force for any set of parameters: each a change of the
// built scene's document by a small step (`apply(scene, step)`), the markers
// of `setup` (noise off) imaged on the recompiled scene, the Jacobian by
// central differences, and sigma^2 (J^T J)^-1. One standard deviation each.
struct SceneParameter {
  std::string name;
  double step = 0;  // SI
  std::function<void(nlohmann::json& scene, double change)> apply;
};
std::vector<double> BruteForceSigmas(const nlohmann::json& built_scene, const std::vector<SceneParameter>& parameters,
                                     const SyntheticSetup& setup, double sigma);

// A value as the scene reads it, to the last bit: Exact(0.0155, "m") is "0.015500000000000000 m".
std::string Exact(double value, const std::string& unit);

}  // namespace layerlab::testing
