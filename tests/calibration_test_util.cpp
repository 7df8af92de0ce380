#include "tests/calibration_test_util.h"

#include <cmath>
#include <numbers>

#include <Eigen/Dense>

namespace layerlab::testing {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kArcmin = kDeg / 60.0;

}  // namespace

std::vector<PanelTruth> ExampleTruth() {
  return {
      {"rear_a", 0.35e-3, 0.30e-3, -0.20e-3, 0.25 * kDeg, 80.0, 0.004, 2.4},
      {"rear_b", -0.25e-3, -0.45e-3, 0.15e-3, -0.40 * kDeg, 78.0, 0.006, 2.2},
      {"front_a", 0.20e-3, 0.10e-3, 0.35e-3, 0.15 * kDeg, 82.0, 0.003, 2.5},
      {"front_b", -0.15e-3, -0.25e-3, -0.30e-3, -0.20 * kDeg, 76.0, 0.005, 2.3},
  };
}

DisplaySystem BuiltSystem(const DisplaySystem& designed, const std::vector<PanelTruth>& truth) {
  DisplaySystem built = designed;
  for (const PanelTruth& t : truth)
    for (VirtualLayer& layer : built.layers)
      if (layer.name == t.name) {
        layer.panel_distance += t.distance_change;
        layer.panel.offset = {t.offset_x, t.offset_y};
        layer.panel.rotation = t.rotation;
      }
  return built;
}

SyntheticSetup ExampleSetup() {
  SyntheticSetup setup;
  setup.grid = {7, 5, 0.1};
  setup.camera.intrinsics = CameraIntrinsics{3000, 3000, 2000, 1500, -0.02, 0};
  setup.camera.positions = {{0.0, 0.0}, {2e-3, 0.0}, {0.0, 2e-3}};
  setup.noise.marker_sigma = 0.3 * kArcmin;
  setup.noise.luminance_sigma = 0.003;
  setup.noise.seed = 20240601;
  for (int code = 0; code < 255; code += 16) setup.luminance_codes.push_back(code);
  setup.luminance_codes.push_back(255);
  return setup;
}

Measurements SyntheticMeasurements(const DisplaySystem& built, const std::vector<PanelTruth>& truth,
                                   const SyntheticSetup& setup) {
  Measurements m;
  m.file = "synthetic";
  m.camera = setup.camera.intrinsics;
  m.captures = SyntheticCaptures(built, setup.grid, setup.camera, setup.noise);
  if (!setup.luminance_codes.empty())
    for (size_t k = 0; k < truth.size(); ++k) {
      SyntheticNoise noise = setup.noise;
      noise.seed += 1000 + k;
      m.luminance.push_back(SyntheticLuminance(truth[k].name, setup.luminance_codes, truth[k].max_luminance,
                                               truth[k].black_level, truth[k].gamma, noise));
    }
  return m;
}

GeometrySigma ExpectedGeometrySigma(const DisplaySystem& built, const VirtualLayer& layer, const PanelMarkers& markers,
                                    int positions, double sigma) {
  const double s = layer.panel_distance, f = built.focal_length, e = built.eye.eye_relief;
  const double denominator = s * f + e * (f - s);
  const double T = f / denominator;             // tan-angle per meter in the panel plane
  const double dT = -f * (f - e) / (denominator * denominator);
  const PanelSpec& p = layer.panel;
  double spread = 0;  // sum of |l|^2 over the markers, l from the active region's center
  for (const MarkerObservation& o : markers.markers) {
    const double x = (o.col - p.active_left + 0.5 - 0.5 * p.active_cols) * p.pitch_x;
    const double y = (0.5 * p.active_rows - (o.row - p.active_top) - 0.5) * p.pitch_y;
    spread += x * x + y * y;
  }
  spread *= positions;
  const double n = static_cast<double>(markers.markers.size() * positions);
  return {sigma / (std::abs(dT) * std::sqrt(spread)), sigma / (T * std::sqrt(n)), sigma / (T * std::sqrt(spread))};
}

LuminanceSigma ExpectedLuminanceSigma(const std::vector<int>& codes, double max_luminance, double black_level,
                                      double gamma, double sigma) {
  Eigen::MatrixXd J(codes.size(), 3);
  for (size_t i = 0; i < codes.size(); ++i) {
    const double x = codes[i] / 255.0, shape = x > 0 ? std::pow(x, gamma) : 0.0;
    J(i, 0) = black_level + (1 - black_level) * shape;
    J(i, 1) = max_luminance * (1 - shape);
    J(i, 2) = x > 0 ? max_luminance * (1 - black_level) * shape * std::log(x) : 0.0;
  }
  const Eigen::Matrix3d covariance = (J.transpose() * J).inverse();
  const double scale = sigma * max_luminance;
  return {scale * std::sqrt(covariance(0, 0)), scale * std::sqrt(covariance(1, 1)), scale * std::sqrt(covariance(2, 2))};
}

}  // namespace layerlab::testing
