// The Kronecker-factored normal matrix of additive displays against A^T A x
// computed ray by ray (gather through every branch, scatter back).
#include <random>

#include "layerlab/solvers/additive_gram.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::CompileJson;
using testing::ShrunkExample;

// A^T (A x) by passes over the rays, in double.
LayerVectors RayByRay(const DisplayModel& model, const LayerVectors& x) {
  const LightFieldGeometry& g = model.geometry();
  const size_t n = g.pixels_per_view() * 3;
  Patterns xf;
  for (size_t k = 0; k < model.layer_count(); ++k) {
    LayerPattern p(model.projection(k).cols(), model.projection(k).rows(), 0);
    for (size_t i = 0; i < p.rgb.size(); ++i) p.rgb[i] = static_cast<float>(x[k][i]);
    xf.push_back(std::move(p));
  }
  LayerVectors out(model.layer_count());
  for (size_t k = 0; k < out.size(); ++k) out[k].assign(x[k].size(), 0.0);
  std::vector<float> ax(n), one(n), weighted(n);
  for (size_t v = 0; v < g.view_count(); ++v) {
    std::fill(ax.begin(), ax.end(), 0.0f);
    for (size_t b = 0; b < model.branch_count(); ++b) {
      const int k = model.branch_layers(b)[0];
      model.projection(k).Gather(v, xf[k].rgb.data(), one.data());
      for (size_t i = 0; i < n; ++i) ax[i] += model.weight(b)[i % 3] * one[i];
    }
    for (size_t b = 0; b < model.branch_count(); ++b) {
      const int k = model.branch_layers(b)[0];
      for (size_t i = 0; i < n; ++i) weighted[i] = model.weight(b)[i % 3] * ax[i];
      model.projection(k).ScatterAdd(v, weighted.data(), out[k].data());
    }
  }
  return out;
}

// Every layer value uniform in [0, 1).
LayerVectors RandomLayers(const DisplayModel& model, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  LayerVectors x(model.layer_count());
  for (size_t k = 0; k < x.size(); ++k) {
    x[k].resize(model.projection(k).pixel_count() * 3);
    for (double& v : x[k]) v = u(rng);
  }
  return x;
}

class AdditiveGramTest : public ::testing::TestWithParam<Sampling> {};

TEST_P(AdditiveGramTest, MatchesTheRayByRayNormalProduct) {
  // Two branches, one mirrored, and a three-branch variant with unequal weights.
  for (const char* example : {"additive_2layer.json", "hybrid_pbs_hwp.json"}) {
    DisplaySystem system = CompileJson(ShrunkExample(example, 24, 12, 5));
    if (std::string(example) == "hybrid_pbs_hwp.json") {
      // Keep one layer per branch: the nearest layer of each.
      for (Branch& b : system.branches) b.layers.resize(1);
    }
    DisplayModel model(system, DisplayLightFieldGeometry(system), GetParam());
    ASSERT_TRUE(AdditiveGram::Applicable(model)) << example;
    const LayerVectors x = RandomLayers(model, 3);
    LayerVectors fast;
    AdditiveGram(model).Apply(x, &fast);
    LayerVectors slow = RayByRay(model, x);
    double worst = 0, largest = 0;
    for (size_t k = 0; k < x.size(); ++k)
      for (size_t i = 0; i < x[k].size(); ++i) {
        worst = std::max(worst, std::abs(fast[k][i] - slow[k][i]));
        largest = std::max(largest, std::abs(slow[k][i]));
      }
    EXPECT_GT(largest, 1.0) << example;
    EXPECT_LT(worst, 1e-5 * largest) << example;  // the ray path gathers in float
  }
}

INSTANTIATE_TEST_SUITE_P(Sampling, AdditiveGramTest, ::testing::Values(Sampling::kNearest, Sampling::kBilinear),
                         [](const auto& p) { return p.param == Sampling::kNearest ? "Nearest" : "Bilinear"; });

// A strip of light-field rows (as the contrast sweep solves) reaches a band
// of each layer's rows; the product skips the rest, which must come out 0.
TEST(AdditiveGram, OnAStripMatchesTheRayByRayProductAndLeavesUnreachedRowsZero) {
  DisplaySystem system = CompileJson(ShrunkExample("additive_2layer.json", 24, 12, 5));
  LightFieldGeometry g = DisplayLightFieldGeometry(system);
  const double row_height = g.window_height_m / g.rows;
  g.rows = 2, g.window_height_m = 2 * row_height, g.window_top_m = row_height;
  DisplayModel model(system, g);
  const LayerVectors x = RandomLayers(model, 5);
  LayerVectors fast;
  AdditiveGram(model).Apply(x, &fast);
  const LayerVectors slow = RayByRay(model, x);
  for (size_t k = 0; k < x.size(); ++k) {
    const size_t row_values = size_t(model.projection(k).cols()) * 3;
    int reached = 0;
    for (int r = 0; r < model.projection(k).rows(); ++r) {
      double largest = 0;
      for (size_t i = r * row_values; i < (r + 1) * row_values; ++i) {
        if (slow[k][i] == 0)
          EXPECT_EQ(fast[k][i], 0.0) << "layer " << k << " row " << r;
        else
          EXPECT_NEAR(fast[k][i], slow[k][i], 1e-5 * std::max(1.0, std::abs(slow[k][i]))) << "layer " << k;
        largest = std::max(largest, std::abs(slow[k][i]));
      }
      reached += largest > 0;
    }
    EXPECT_GT(reached, 0) << "layer " << k;
    EXPECT_LT(reached, model.projection(k).rows()) << "layer " << k << ": the strip should leave rows unreached";
  }
}

TEST(AdditiveGram, RotatedLayersAreNotApplicable) {
  DisplaySystem system = CompileJson(ShrunkExample("additive_2layer.json", 24, 12, 5));
  system.layers[0].rotation_rad = 0.01;
  DisplayModel model(system, DisplayLightFieldGeometry(system));
  EXPECT_FALSE(AdditiveGram::Applicable(model));
}

}  // namespace
}  // namespace layerlab
