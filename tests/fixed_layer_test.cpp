// A layer with a fixed pattern (lc_panel's "fixed_pattern": a printed mask):
// read from an OpenEXR file beside the scene and checked (size, range); the
// multiplicative solver leaves it as it is, bit for bit, and the free layer
// in front of it reaches the least-squares optimum that, with the mask fixed,
// has a closed form per pixel (computed here ray by ray); the solvers that
// would change it refuse the display, naming the layer.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <random>

#include "layerlab/framework/exr_image.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/systems/system_report.h"
#include "test_util.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;
using layerlab::testing::CompileJson;
using layerlab::testing::ErrorOf;
using layerlab::testing::RandomLightField;
using layerlab::testing::ShrunkExample;

constexpr int kCols = 24, kRows = 12, kViews = 3;

std::string Folder() {
  const fs::path dir = fs::temp_directory_path() / ("layerlab_fixed_layer_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir.string();
}

// The reduced 2-layer display with a fixed pattern in `file` (written beside the scene) on its rear panel
// (element 3), or on its front one (element 2).
nlohmann::json SceneWithMask(const std::string& file, int element = 3) {
  nlohmann::json s = ShrunkExample("multiplicative_2layer.json", kCols, kRows, kViews);
  s["elements"][element]["fixed_pattern"] = file;
  return s;
}

Image RandomMask(int cols, int rows, unsigned seed) {
  Image mask;
  mask.width = cols, mask.height = rows, mask.channels = {"R", "G", "B"};
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.2f, 1.0f);
  for (int i = 0; i < cols * rows * 3; ++i) mask.pixels.push_back(u(rng));
  return mask;
}

TEST(FixedLayer, IsReadFromItsFileAndChecked) {
  const std::string folder = Folder();
  WriteExr(folder + "/mask.exr", RandomMask(kCols, kRows, 1));
  const DisplaySystem system = CompileJson(SceneWithMask("mask.exr"), folder + "/scene.json");
  const VirtualLayer& rear = system.layers[0];
  ASSERT_EQ(rear.name, "rear");
  ASSERT_TRUE(rear.panel.fixed_pattern);
  EXPECT_EQ(rear.panel.fixed_pattern->size(), static_cast<size_t>(kCols * kRows * 3));
  EXPECT_FALSE(system.layers[1].panel.fixed_pattern);
  EXPECT_NE(FormatSystemTable(system).find("rear shows a fixed pattern, mask.exr: the solve leaves it as it is"),
            std::string::npos);

  WriteExr(folder + "/small.exr", RandomMask(kCols - 1, kRows, 1));
  std::string e = ErrorOf([&] { CompileJson(SceneWithMask("small.exr"), folder + "/scene.json"); });
  EXPECT_NE(e.find("/elements/3/fixed_pattern: " + folder +
                   "/small.exr is 23 x 12 pixels; the panel's active region "
                   "is 24 x 12"),
            std::string::npos)
      << e;
  Image bright = RandomMask(kCols, kRows, 1);
  bright.pixels[5] = 1.5f;
  WriteExr(folder + "/bright.exr", bright);
  e = ErrorOf([&] { CompileJson(SceneWithMask("bright.exr"), folder + "/scene.json"); });
  EXPECT_NE(e.find("pixel (row 0, col 1) holds 1.5"), std::string::npos) << e;
  e = ErrorOf([&] { CompileJson(SceneWithMask("missing.exr"), folder + "/scene.json"); });
  EXPECT_NE(e.find("/elements/3/fixed_pattern"), std::string::npos) << e;
}

TEST(FixedLayer, MultiplicativeKeepsItAndFindsTheFreeLayersClosedForm) {
  const std::string folder = Folder();
  WriteExr(folder + "/mask.exr", RandomMask(kCols, kRows, 2));
  // The rear fixed (the layer the solver's first update reads), then the front.
  for (const int element : {3, 2}) {
    const DisplaySystem system = CompileJson(SceneWithMask("mask.exr", element), folder + "/scene.json");
    const size_t fixed = element == 3 ? 0 : 1, free = 1 - fixed;  // layers farthest first
    const DisplayModel model(system, DisplayLightFieldGeometry(system), Sampling::kNearest);
    const LightField target = RandomLightField(model.geometry(), 3);
    SolverOptions options;
    options.iterations = 20;
    options.threads = 1;
    Patterns t;
    const SolverReport report = SolverRegistry::Builtins().create("multiplicative")->Solve(model, target, options, &t);
    ASSERT_TRUE(report.IsSolutionUsable()) << report.message;
    ASSERT_EQ(t[fixed].rgb, *system.layers[fixed].panel.fixed_pattern) << "the mask changed";

    // With the other layer fixed at m, the free pixel p minimizes sum over its rays (w p m - T)^2:
    // p = sum w m T / sum (w m)^2, clamped to [floor, 1].
    const LightFieldGeometry& lf = model.geometry();
    std::vector<double> num(t[free].rgb.size(), 0.0), den(t[free].rgb.size(), 0.0);
    for (size_t v = 0; v < lf.view_count(); ++v)
      for (int i = 0; i < lf.rows; ++i)
        for (int j = 0; j < lf.cols; ++j) {
          const RayTaps p = model.projection(free).Taps(v, i, j), m = model.projection(fixed).Taps(v, i, j);
          if (p.count == 0 || m.count == 0) continue;
          for (int c = 0; c < 3; ++c) {
            const double w = model.weight(0)[c];
            const double mask = t[fixed].rgb[static_cast<size_t>(m.index[0]) * 3 + c];
            const double value = target.rgb[(v * lf.pixels_per_view() + static_cast<size_t>(i) * lf.cols + j) * 3 + c];
            num[static_cast<size_t>(p.index[0]) * 3 + c] += w * mask * value;
            den[static_cast<size_t>(p.index[0]) * 3 + c] += w * mask * w * mask;
          }
        }
    size_t checked = 0;
    for (size_t k = 0; k < num.size(); ++k) {
      if (den[k] <= 0) continue;
      const double expected = std::clamp(num[k] / den[k], options.floor, 1.0);
      EXPECT_NEAR(t[free].rgb[k], expected, 1e-5) << "element " << element << ", free value " << k;
      ++checked;
    }
    EXPECT_GT(checked, t[free].rgb.size() / 2);

    // A warm start from patterns of another display's making: the mask is written over them.
    const Patterns other = model.UniformPatterns(0.7f);
    options.initial_patterns = &other;
    options.iterations = 1;
    Patterns warm;
    ASSERT_TRUE(
        SolverRegistry::Builtins().create("multiplicative")->Solve(model, target, options, &warm).IsSolutionUsable());
    EXPECT_EQ(warm[fixed].rgb, *system.layers[fixed].panel.fixed_pattern) << "a warm start replaced the mask";
  }
}

TEST(FixedLayer, SolversThatWouldChangeItRefuse) {
  const std::string folder = Folder();
  WriteExr(folder + "/mask.exr", RandomMask(kCols, kRows, 4));
  const DisplaySystem system = CompileJson(SceneWithMask("mask.exr"), folder + "/scene.json");
  const DisplayModel model(system, DisplayLightFieldGeometry(system), Sampling::kNearest);
  const LightField target = RandomLightField(model.geometry(), 5);
  for (const char* solver : {"quasi-newton", "joint"}) {
    Patterns t;
    const SolverReport report = SolverRegistry::Builtins().create(solver)->Solve(model, target, SolverOptions(), &t);
    EXPECT_FALSE(report.IsSolutionUsable()) << solver;
    EXPECT_NE(report.message.find("layer rear shows a fixed pattern (mask.exr), which the " + std::string(solver) +
                                  " solver would change: solve this display with the multiplicative solver"),
              std::string::npos)
        << report.message;
  }
  // A display of two stacks: the multiplicative solver, which would keep the mask, solves one stack only.
  nlohmann::json hybrid = ShrunkExample("hybrid_pbs_hwp.json", kCols, kRows, kViews);
  hybrid["elements"][5]["fixed_pattern"] = "mask.exr";
  const DisplaySystem two_stacks = CompileJson(hybrid, folder + "/scene.json");
  const DisplayModel hybrid_model(two_stacks, DisplayLightFieldGeometry(two_stacks), Sampling::kNearest);
  Patterns t;
  const SolverReport report = SolverRegistry::Builtins().create("hybrid")->Solve(
      hybrid_model, RandomLightField(hybrid_model.geometry(), 6), SolverOptions(), &t);
  EXPECT_NE(report.message.find("layer rear_a shows a fixed pattern (mask.exr), which the hybrid solver would change: "
                                "no solver here keeps a fixed layer of a display like this one"),
            std::string::npos)
      << report.message;
}

}  // namespace
}  // namespace layerlab
