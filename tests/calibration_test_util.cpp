#include "layerlab/tests/calibration_test_util.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <Eigen/Dense>

#include "layerlab/framework/json_file.h"
#include "layerlab/framework/units.h"
#include "layerlab/tests/test_util.h"

namespace layerlab::testing {
namespace {}  // namespace

std::vector<PanelTruth> ExampleTruth() {
  return {
      {"rear_a", 0.35e-3, 0.30e-3, -0.20e-3, 0.25 * kRadiansPerDegree, 80.0, 0.004, 2.4},
      {"rear_b", -0.25e-3, -0.45e-3, 0.15e-3, -0.40 * kRadiansPerDegree, 78.0, 0.006, 2.2},
      {"front_a", 0.20e-3, 0.10e-3, 0.35e-3, 0.15 * kRadiansPerDegree, 82.0, 0.003, 2.5},
      {"front_b", -0.15e-3, -0.25e-3, -0.30e-3, -0.20 * kRadiansPerDegree, 76.0, 0.005, 2.3},
  };
}

std::string Exact(double value, const std::string& unit) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g ", value);
  return buf + unit;
}

nlohmann::json BuiltScene(const DisplaySystem& designed, const std::vector<PanelTruth>& truth,
                          const std::vector<OpticTruth>& optics) {
  nlohmann::json scene = ReadJsonFile(designed.file);
  for (const VirtualLayer& layer : designed.layers) {
    nlohmann::json& panel = ElementNamed(scene, layer.name);
    double change = 0;
    for (const PanelTruth& t : truth)
      if (t.name == layer.name) {
        change = t.distance_change;
        panel["offset"] = {Exact(t.eye_from_panel_x_m, "m"), Exact(t.eye_from_panel_y_m, "m")};
        panel["rotation"] = Exact(t.rotation, "rad");
      }
    const bool behind_optics =
        std::any_of(layer.path.begin(), layer.path.end(), [](const PathStep& s) { return s.power_diopters != 0; });
    if (panel.contains("virtual_depth")) {
      panel.erase("virtual_depth");
      panel[behind_optics ? "distance" : "gap"] = 0;  // set below
    }
    if (panel.contains("distance"))
      panel["distance"] = Exact(layer.panel_distance_m + change, "m");
    else
      panel["gap"] = Exact(
          layer.position_m - (layer.path.empty() ? 0.0 : layer.path.back().position_m.value_or(0.0)) + change, "m");
  }
  for (const OpticTruth& t : optics) {
    nlohmann::json& optic = ElementNamed(scene, t.name);
    if (t.gap_change != 0)
      for (const VirtualLayer& layer : designed.layers)
        for (size_t j = 0; j < layer.path.size(); ++j)
          if (layer.path[j].element == t.name) {
            const double before = j == 0 ? 0.0 : layer.path[j - 1].position_m.value_or(0.0);
            optic["gap"] = Exact(*layer.path[j].position_m - before + t.gap_change, "m");
          }
    if (t.focal_length) optic["focal_length"] = Exact(*t.focal_length, "m");
  }
  return scene;
}

DisplaySystem BuiltSystem(const DisplaySystem& designed, const std::vector<PanelTruth>& truth,
                          const std::vector<OpticTruth>& optics) {
  return CompileJson(BuiltScene(designed, truth, optics), designed.file);
}

void ExpectPlacementsOf(const DisplaySystem& built, const CalibratedDisplay& display, double tolerance) {
  for (const VirtualLayer& layer : built.layers) {
    const CalibratedPanel* p = display.find(layer.name);
    ASSERT_NE(p, nullptr) << layer.name;
    EXPECT_NEAR(p->distance_m, layer.panel_distance_m, tolerance) << layer.name;
    EXPECT_NEAR(p->eye_from_panel_x_m, layer.panel.eye_from_panel_m[0], tolerance) << layer.name;
    EXPECT_NEAR(p->eye_from_panel_y_m, layer.panel.eye_from_panel_m[1], tolerance) << layer.name;
    EXPECT_NEAR(p->rotation_rad, layer.panel.rotation_rad, tolerance) << layer.name;
  }
}

SyntheticSetup ExampleSetup() {
  SyntheticSetup setup;
  setup.grid = {7, 5, 0.1};
  setup.camera.intrinsics = CameraIntrinsics{3000, 3000, 2000, 1500, -0.02, 0, std::nullopt};
  setup.camera.positions_m = {{0.0, 0.0}, {2e-3, 0.0}, {0.0, 2e-3}};
  setup.noise.marker_sigma_rad = 0.3 * kArcmin;
  setup.noise.luminance_sigma = 0.003;
  setup.noise.seed = 20240601;
  for (int code = 0; code < 255; code += 16) setup.luminance_codes.push_back(code);
  setup.luminance_codes.push_back(255);
  return setup;
}

std::vector<PanelTruth> PerBranchTruth() {
  return {
      {"front_a", 0.30e-3, 0.20e-3, -0.10e-3, 0.20 * kRadiansPerDegree, 0, 0, 0},
      {"rear_a", -0.40e-3, -0.30e-3, 0.25e-3, -0.30 * kRadiansPerDegree, 0, 0, 0},
      {"front_b", 0.25e-3, 0.15e-3, 0.30e-3, 0.10 * kRadiansPerDegree, 0, 0, 0},
      {"rear_b", -0.30e-3, -0.20e-3, -0.15e-3, -0.25 * kRadiansPerDegree, 0, 0,
       0},  // nearer: its image at 0 D moves forward
  };
}

std::vector<OpticTruth> PerBranchOptics() { return {{"lens_a", 0.50e-3, {}}, {"lens_b", -0.40e-3, {}}}; }

SyntheticSetup PerBranchSetup() {
  SyntheticSetup setup = ExampleSetup();
  setup.camera.positions_m = {{0.0, 0.0}, {-3e-3, 0.0}, {3e-3, 0.0}, {0.0, -3e-3}, {0.0, 3e-3}};
  setup.noise.seed = 20261201;
  setup.luminance_codes.clear();
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

GeometrySigma ExpectedGeometrySigma(const VirtualLayer& layer, const PanelMarkers& markers, int positions,
                                    double sigma) {
  // B = b + s d of the transfer up to the last element with power (free space keeps d): T = 1 / |B|, dT/ds = -d / B |B|.
  const double B = layer.transfer.b;
  const double T = 1.0 / std::abs(B);
  const double dT = -layer.transfer.d / (B * std::abs(B));
  const PanelSpec& p = layer.panel;
  double spread = 0;  // sum of |l|^2 over the markers, l from the active region's center
  for (const MarkerObservation& o : markers.markers) {
    const double x = (o.col - p.active_left + 0.5 - 0.5 * p.active_cols) * p.pitch_x_m;
    const double y = (0.5 * p.active_rows - (o.row - p.active_top) - 0.5) * p.pitch_y_m;
    spread += x * x + y * y;
  }
  spread *= positions;
  const double n = static_cast<double>(markers.markers.size() * positions);
  return {sigma / (std::abs(dT) * std::sqrt(spread)), sigma / (T * std::sqrt(n)), sigma / (T * std::sqrt(spread))};
}

std::vector<double> BruteForceSigmas(const nlohmann::json& built_scene, const std::vector<SceneParameter>& parameters,
                                     const SyntheticSetup& setup, double sigma) {
  SyntheticNoise quiet = setup.noise;
  quiet.marker_sigma_rad = quiet.outlier_fraction = 0;
  auto angles = [&](const SceneParameter* p, double change) {
    nlohmann::json scene = built_scene;
    if (p) p->apply(scene, change);
    const DisplaySystem system = CompileJson(scene, "built.json");
    std::vector<double> out;
    for (const Capture& c : SyntheticCaptures(system, setup.grid, setup.camera, quiet))
      for (const PanelMarkers& panel : c.panels)
        for (const MarkerObservation& m : panel.markers) out.push_back(m.angle_x), out.push_back(m.angle_y);
    return out;
  };
  const size_t rows = angles(nullptr, 0).size();
  Eigen::MatrixXd J(rows, parameters.size());
  for (size_t i = 0; i < parameters.size(); ++i) {
    const std::vector<double> plus = angles(&parameters[i], parameters[i].step);
    const std::vector<double> minus = angles(&parameters[i], -parameters[i].step);
    for (size_t r = 0; r < rows; ++r) J(r, i) = (plus[r] - minus[r]) / (2 * parameters[i].step);
  }
  const Eigen::MatrixXd covariance = (J.transpose() * J).inverse();
  std::vector<double> out;
  for (size_t i = 0; i < parameters.size(); ++i) out.push_back(sigma * std::sqrt(covariance(i, i)));
  return out;
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
  return {scale * std::sqrt(covariance(0, 0)), scale * std::sqrt(covariance(1, 1)),
          scale * std::sqrt(covariance(2, 2))};
}

}  // namespace layerlab::testing
