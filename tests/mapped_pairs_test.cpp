// The pixel-pair list behind a real lens (kernels/mapped_pairs.h) against
// the rays one by one: its binned targets and update sums are every
// ray-channel's terms added by pixel pair, and its update is the general ray
// pass's.
#include <omp.h>

#include <algorithm>
#include <cstring>

#include "layerlab/kernels/branch_pairs.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/systems/mapped_pairs.h"
#include "layerlab/tests/support/array_compare.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::ArraysNear;
using testing::CompileJson;
using testing::RandomLightField;
using testing::RandomPatterns;
using testing::ShrunkExample;

// The LA1608 singlet's display at 31 x 17 pixels a panel and 9 x 9 views:
// every layer mapped, lateral colour moving the channels' pixels apart.
const DisplayModel& SingletModel() {
  static const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype_la1608.json", 31, 17, 9));
  static const DisplayModel model(system, DisplayLightFieldGeometry(system));
  return model;
}

// Branch b's list, made here whether or not it pays.
MappedPairs ListOf(const DisplayModel& model, size_t b) {
  const std::vector<int>& layers = model.branch_layers(b);
  const int a = std::min(layers[0], layers[1]), o = std::max(layers[0], layers[1]);
  return MappedPairs(a, model.projection(a), o, model.projection(o));
}

bool Suits(const DisplayModel& model, size_t b) {
  const std::vector<int>& layers = model.branch_layers(b);
  return layers.size() == 2 && MappedPairs::Suits(model.projection(layers[0]), model.projection(layers[1]));
}

// Each layer's pixel per ray and channel, read tap by tap (ForEachChannelTap).
std::vector<int32_t> PixelsOf(const LayerProjection& P, size_t view) {
  std::vector<int32_t> pixels(P.geometry().pixels_per_view() * 3, -1);
  P.ForEachChannelTap(view, [&](size_t ray, int c, int32_t pixel, float weight) {
    EXPECT_EQ(weight, 1.0f);
    pixels[ray * 3 + c] = pixel;
  });
  return pixels;
}

// num[p] = sum r q, den[p] = sum q^2 over the ray-channels that read pixel p
// of `layer` and a pixel of `other`, in double.
void RayByRaySums(const DisplayModel& model, int layer, int other, const Patterns& t, const LightField& r,
                  std::vector<double>* num, std::vector<double>* den, double* rays) {
  num->assign(model.projection(layer).pixel_count() * 3, 0.0);
  den->assign(num->size(), 0.0);
  *rays = 0;
  for (size_t v = 0; v < model.geometry().view_count(); ++v) {
    const std::vector<int32_t> a = PixelsOf(model.projection(layer), v), b = PixelsOf(model.projection(other), v);
    for (size_t k = 0; k < a.size(); ++k) {
      if (a[k] < 0 || b[k] < 0) continue;
      const int c = static_cast<int>(k % 3);
      const double q = t[other].rgb[size_t(b[k]) * 3 + c];
      (*num)[size_t(a[k]) * 3 + c] += r.view(v)[k] * q;
      (*den)[size_t(a[k]) * 3 + c] += q * q;
      *rays += 1;
    }
  }
}

TEST(MappedPairs, SumsAreEveryRayChannelsTermsAddedByPixelPair) {
  const DisplayModel& model = SingletModel();
  const Patterns t = RandomPatterns(model, 3, 0.05f, 1.0f);
  const LightField r = RandomLightField(model.geometry(), 4);
  for (size_t b = 0; b < model.branch_count(); ++b) {
    ASSERT_TRUE(Suits(model, b));
    const MappedPairs pairs = ListOf(model, b);
    std::vector<float> binned;
    std::vector<std::vector<float>> parts;
    pairs.Bin(r, &binned, &parts);
    ASSERT_EQ(binned.size(), pairs.pairs());
    for (const int layer : {pairs.layer_a(), pairs.layer_b()}) {
      const std::string name = "branch " + std::to_string(b) + ", layer " + std::to_string(layer);
      const int other = pairs.other_layer(layer);
      std::vector<double> num, den;
      double rays = 0;
      RayByRaySums(model, layer, other, t, r, &num, &den, &rays);
      EXPECT_EQ(pairs.rays(), rays) << name;
      EXPECT_GT(rays, 0.5 * 3 * double(model.geometry().ray_count())) << name;
      std::vector<double> pair_num(num.size(), -1.0), pair_den(den.size(), -1.0);
      pairs.UpdateSums(layer, t[other].rgb.data(), binned, pair_num.data(), pair_den.data());
      EXPECT_TRUE(ArraysNear(pair_num, num, 1e-5, 1e-9)) << name;
      EXPECT_TRUE(ArraysNear(pair_den, den, 1e-5, 1e-9)) << name;
    }
  }
}

// Lateral colour: a channel's pairs are its own, not the green channel's.
TEST(MappedPairs, TheChannelsReadTheirOwnPairs) {
  const DisplayModel& model = SingletModel();
  const LayerProjection& P = model.projection(model.branch_layers(0)[0]);
  size_t differ = 0;
  for (size_t v = 0; v < model.geometry().view_count(); ++v) {
    const std::vector<int32_t> pixels = PixelsOf(P, v);
    for (size_t k = 0; k < pixels.size(); k += 3) differ += pixels[k] != pixels[k + 2];
  }
  EXPECT_GT(differ, 0u) << "the test display shows no lateral colour: the channels' pairs are not tested apart";
}

// The list's update is the general ray pass's (ComputeLayerUpdate), w_b and
// the layer's own value put back alike, to rounding.
TEST(MappedPairs, UpdateIsTheRayPassUpdate) {
  const DisplayModel& model = SingletModel();
  const Patterns t = RandomPatterns(model, 5, 0.05f, 1.0f);
  const LightField r = RandomLightField(model.geometry(), 6);
  const BranchTarget whole = [&](size_t view, float*) { return r.view(view); };
  SolveWorkspace workspace(model, omp_get_max_threads(), kAllPasses);
  for (size_t b = 0; b < model.branch_count(); ++b) {
    const std::optional<BranchPairs> pairs = BranchPairs::IfItPays(model, b);
    ASSERT_TRUE(pairs) << "branch " << b;
    pairs->Bin(r, &workspace);
    for (const int layer : model.branch_layers(b)) {
      const std::string name = "branch " + std::to_string(b) + ", layer " + std::to_string(layer);
      std::vector<double> ray_num, ray_den, pair_num, pair_den;
      LayerUpdate by_rays{0, -1, &ray_num, &ray_den}, by_pairs{0, -1, &pair_num, &pair_den};
      ComputeLayerUpdate(model, {b, layer}, whole, t, &workspace, &by_rays);
      pairs->ComputeUpdate(model, b, layer, t, &workspace, &by_pairs);
      EXPECT_EQ(by_pairs.layer, layer);
      EXPECT_TRUE(ArraysNear(pair_num, ray_num, 1e-5, 1e-9)) << name;
      EXPECT_TRUE(ArraysNear(pair_den, ray_den, 1e-5, 1e-9)) << name;
    }
  }
}

TEST(MappedPairs, TheSameBitsRunToRun) {
  const DisplayModel& model = SingletModel();
  const LightField r = RandomLightField(model.geometry(), 8);
  const MappedPairs pairs = ListOf(model, 1);
  std::vector<float> first, second;
  std::vector<std::vector<float>> parts;
  pairs.Bin(r, &first, &parts);
  pairs.Bin(r, &second, &parts);
  ASSERT_EQ(first.size(), second.size());
  EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(float)), 0);
}

// Ideal optics keep the lattice; one view has about one ray-channel per pair, so binning does not pay.
TEST(MappedPairs, OnlyBehindARealLensAndWhereRaysRepeatPairs) {
  const DisplaySystem ideal = CompileJson(ShrunkExample("paper_prototype.json", 31, 17, 9));
  const DisplayModel ideal_model(ideal, DisplayLightFieldGeometry(ideal));
  EXPECT_FALSE(Suits(ideal_model, 0));
  EXPECT_EQ(ideal_model.pair_list(0), nullptr);
  const DisplaySystem one_view = CompileJson(ShrunkExample("paper_prototype_la1608.json", 31, 17, 1));
  const DisplayModel model(one_view, DisplayLightFieldGeometry(one_view));
  ASSERT_TRUE(Suits(model, 0));
  const MappedPairs pairs = ListOf(model, 0);
  EXPECT_LT(pairs.rays(), 2.0 * double(pairs.pairs()));
  EXPECT_FALSE(pairs.Pays());
  EXPECT_EQ(model.pair_list(0), nullptr);
  EXPECT_NE(SingletModel().pair_list(0), nullptr);
}

}  // namespace
}  // namespace layerlab
