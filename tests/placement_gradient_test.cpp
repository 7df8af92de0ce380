// The light-field error's derivative with respect to each layer's placement
// (design/placement_gradient.h) against central differences of the error,
// computed by a brute-force trace written here in double (checked against
// the display's own forward model, solvers/objective.h's Objective, at the
// start), on a multiplicative, an additive and a mirrored hybrid display.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "layerlab/design/placement_gradient.h"
#include "layerlab/solvers/objective.h"
#include "test_util.h"

namespace layerlab {
namespace {

using layerlab::testing::CompileJson;
using layerlab::testing::ErrorOf;
using layerlab::testing::RandomLightField;
using layerlab::testing::RandomPatterns;
using layerlab::testing::ShrunkExample;

struct Field {
  const char* name;
  std::function<double&(VirtualLayer&)> value;
  std::function<double(const LayerPlacementGradient&)> gradient;
  std::function<double(const VirtualLayer&, const LightFieldGeometry&)> step;  // moves a ray by about 2e-3 px
};

std::vector<Field> Fields() {
  const double shift = 2e-5;
  return {
      {"diopters", [](VirtualLayer& l) -> double& { return l.diopters; },
       [](const LayerPlacementGradient& g) { return g.diopters; },
       [=](const VirtualLayer& l, const LightFieldGeometry& lf) {
         return shift * l.tan_pitch_x / (lf.eyebox_width_m / 2);
       }},
      {"center_tan_x", [](VirtualLayer& l) -> double& { return l.eye_from_layer_tan_x; },
       [](const LayerPlacementGradient& g) { return g.center_tan_x; },
       [=](const VirtualLayer& l, const LightFieldGeometry&) { return shift * l.tan_pitch_x; }},
      {"center_tan_y", [](VirtualLayer& l) -> double& { return l.eye_from_layer_tan_y; },
       [](const LayerPlacementGradient& g) { return g.center_tan_y; },
       [=](const VirtualLayer& l, const LightFieldGeometry&) { return shift * l.tan_pitch_y; }},
      {"tan_pitch_x", [](VirtualLayer& l) -> double& { return l.tan_pitch_x; },
       [](const LayerPlacementGradient& g) { return g.tan_pitch_x; },
       [=](const VirtualLayer& l, const LightFieldGeometry&) { return shift * l.tan_pitch_x / (0.5 * l.cols); }},
      {"tan_pitch_y", [](VirtualLayer& l) -> double& { return l.tan_pitch_y; },
       [](const LayerPlacementGradient& g) { return g.tan_pitch_y; },
       [=](const VirtualLayer& l, const LightFieldGeometry&) { return shift * l.tan_pitch_y / (0.5 * l.rows); }},
  };
}

// E = sum (L - T)^2, each ray read by hand: u = D p + (x - p) / z, the cell coordinates, bilinear weights.
double BruteForceError(const DisplaySystem& system, const DisplayModel& model, const LightField& target,
                       const Patterns& t) {
  const LightFieldGeometry& lf = target.geometry;
  double sum = 0;
  for (int vr = 0; vr < lf.views_y; ++vr)
    for (int vc = 0; vc < lf.views_x; ++vc)
      for (int i = 0; i < lf.rows; ++i)
        for (int j = 0; j < lf.cols; ++j)
          for (int c = 0; c < 3; ++c) {
            const double px = lf.view_x(vc), py = lf.view_y(vr);
            std::vector<double> read(system.layers.size());
            for (size_t k = 0; k < system.layers.size(); ++k) {
              const VirtualLayer& l = system.layers[k];
              const double ux = l.diopters * px + (lf.pixel_x(j) - px) / lf.origin_z_m;
              const double uy = l.diopters * py + (lf.pixel_y(i) - py) / lf.origin_z_m;
              const double col = (ux - l.eye_from_layer_tan_x) / l.tan_pitch_x + l.cols / 2.0 - 0.5;
              const double row = -(uy - l.eye_from_layer_tan_y) / l.tan_pitch_y + l.rows / 2.0 - 0.5;
              auto at = [&](int a, int b) -> double {
                if (a < 0 || a >= l.cols || b < 0 || b >= l.rows) return 0;
                const int pa = l.flip_x ? l.cols - 1 - a : a, pb = l.flip_y ? l.rows - 1 - b : b;
                return t[k].rgb[(static_cast<size_t>(pb) * l.cols + pa) * 3 + c];
              };
              read[k] = 0;
              if (col >= -1 && col < l.cols && row >= -1 && row < l.rows) {
                const int a = static_cast<int>(std::floor(col)), b = static_cast<int>(std::floor(row));
                const double f = col - a, g = row - b;
                read[k] = (1 - g) * ((1 - f) * at(a, b) + f * at(a + 1, b)) +
                          g * ((1 - f) * at(a, b + 1) + f * at(a + 1, b + 1));
              }
            }
            double light = 0;
            for (size_t b = 0; b < system.branches.size(); ++b) {
              double product = model.weight(b)[c];
              for (int k : system.branches[b].layers) product *= read[static_cast<size_t>(k)];
              light += product;
            }
            const size_t ray = lf.view_index(vr, vc) * lf.pixels_per_view() + static_cast<size_t>(i) * lf.cols + j;
            sum += (light - target.rgb[ray * 3 + c]) * (light - target.rgb[ray * 3 + c]);
          }
  return sum;
}

class PlacementGradientTest : public ::testing::TestWithParam<const char*> {};

TEST_P(PlacementGradientTest, MatchesCentralDifferencesOfTheForwardModel) {
  const DisplaySystem system = CompileJson(ShrunkExample(GetParam(), 36, 20, 5));
  // The display's own light field puts rays on a layer's pixel centres, where a bilinear read bends:
  // there the gradient is the central one. Shifted by a fraction of a pixel, every ray meets each
  // layer inside a cell.
  for (const bool shifted : {false, true}) {
    LightFieldGeometry lf = DisplayLightFieldGeometry(system);
    if (shifted) {
      lf.window_left_m += 0.37 * lf.window_width_m / lf.cols;
      lf.window_top_m -= 0.29 * lf.window_height_m / lf.rows;
    }
    const DisplayModel model(system, lf, Sampling::kBilinear);
    const LightField target = RandomLightField(lf, 11);
    const Patterns t = RandomPatterns(model, 5, 0.1f, 0.9f);
    double error = 0;
    const std::vector<LayerPlacementGradient> g = PlacementGradient(model, target, t, &error);
    EXPECT_NEAR(error, Objective(model, target, t), 1e-5 * error);
    EXPECT_NEAR(BruteForceError(system, model, target, t), error, 1e-9 * error);
    ASSERT_EQ(g.size(), system.layers.size());
    for (const Field& f : Fields())
      for (size_t k = 0; k < system.layers.size(); ++k) {
        const double h = f.step(system.layers[k], lf);
        auto moved = [&](double by) {
          DisplaySystem s = system;
          f.value(s.layers[k]) += by;
          return BruteForceError(s, model, target, t);
        };
        const double fd = (moved(h) - moved(-h)) / (2 * h), exact = f.gradient(g[k]);
        EXPECT_NEAR(exact, fd, 1e-3 * std::max(std::abs(fd), std::abs(exact)) + 1e-9 * error / h)
            << GetParam() << (shifted ? " (shifted)" : "") << ": layer " << k << " " << f.name;
      }
  }
}

INSTANTIATE_TEST_SUITE_P(Displays, PlacementGradientTest,
                         ::testing::Values("multiplicative_2layer.json", "hybrid_pbs_hwp.json",
                                           "additive_2layer.json"));

TEST(PlacementGradient, RefusesNearestSampling) {
  const DisplaySystem system = CompileJson(ShrunkExample("multiplicative_2layer.json", 12, 8, 3));
  const LightFieldGeometry lf = DisplayLightFieldGeometry(system);
  const DisplayModel model(system, lf, Sampling::kNearest);
  const std::string e =
      ErrorOf([&] { PlacementGradient(model, RandomLightField(lf, 1), model.UniformPatterns(0.5f)); });
  EXPECT_NE(e.find("needs bilinear sampling"), std::string::npos) << e;
}

}  // namespace
}  // namespace layerlab
