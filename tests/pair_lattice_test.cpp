// The pixel-pair lattice (kernels/pair_lattice.h) against the rays one by
// one: its binned targets and update sums are every ray's terms added by
// pixel pair, the same bits on any thread count, and the hybrid that makes
// its sub-iterations from it follows the general path's solve.
#include <omp.h>

#include <cmath>
#include <cstring>

#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/pair_lattice.h"
#include "layerlab/kernels/solve_workspace.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/solvers/multiplicative_update.h"
#include "layerlab/solvers/solver.h"
#include "layerlab/tests/support/array_compare.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::ArraysNear;
using testing::ArraysSameBits;
using testing::CompileJson;
using testing::RandomLightField;
using testing::RandomPatterns;
using testing::ShrunkExample;

// The displays the lattice is tested on: the paper prototype (its front
// panels mounted reversed) and a strip of its rows off the centre (rays
// that miss a layer's rows at the strip's ends), each with enough views
// that pairs repeat.
struct Case {
  std::string name;
  DisplaySystem system;
  LightFieldGeometry geometry;
};

std::vector<Case> Cases() {
  std::vector<Case> cases;
  const DisplaySystem paper = CompileJson(ShrunkExample("paper_prototype.json", 31, 17, 9));
  cases.push_back({"paper prototype", paper, DisplayLightFieldGeometry(paper)});
  LightFieldGeometry strip = DisplayLightFieldGeometry(paper);
  const double row_height = strip.window_height_m / strip.rows;
  strip.rows = 4;
  strip.window_height_m = strip.rows * row_height;
  strip.window_top_m = strip.window_height_m / 2 + 0.37 * row_height + 5 * row_height;
  cases.push_back({"strip", paper, strip});
  LightFieldGeometry wide = DisplayLightFieldGeometry(paper);
  wide.window_left_m -= 0.3 * wide.window_width_m, wide.window_width_m *= 1.6;  // rays past the layers' sides
  cases.push_back({"wider than the layers", paper, wide});
  return cases;
}

// num[p] = sum r q, den[p] = sum q^2 over the rays that read pixel p of
// `layer` and a pixel of `other`, ray by ray through LayerProjection::Taps, in double.
void RayByRaySums(const DisplayModel& model, int layer, int other, const Patterns& t, const LightField& r,
                  std::vector<double>* num, std::vector<double>* den, double* rays, std::vector<double>* r_sum) {
  const LightFieldGeometry& g = model.geometry();
  num->assign(model.projection(layer).pixel_count() * 3, 0.0);
  den->assign(num->size(), 0.0);
  *rays = 0;
  r_sum->assign(3, 0.0);
  for (size_t view = 0; view < g.view_count(); ++view)
    for (int i = 0; i < g.rows; ++i)
      for (int j = 0; j < g.cols; ++j) {
        const RayTaps a = model.projection(layer).Taps(view, i, j), b = model.projection(other).Taps(view, i, j);
        if (a.count == 0 || b.count == 0) continue;
        EXPECT_EQ(a.count, 1);
        EXPECT_EQ(b.count, 1);
        *rays += 1;
        const float* rv = r.view(view) + (size_t(i) * g.cols + j) * 3;
        for (int c = 0; c < 3; ++c) {
          const double q = t[other].rgb[size_t(b.index[0]) * 3 + c];
          (*num)[size_t(a.index[0]) * 3 + c] += rv[c] * q;
          (*den)[size_t(a.index[0]) * 3 + c] += q * q;
          (*r_sum)[c] += rv[c];
        }
      }
}

TEST(PairLattice, SumsAreEveryRaysTermsAddedByPixelPair) {
  for (const Case& c : Cases()) {
    const DisplayModel model(c.system, c.geometry);
    const Patterns t = RandomPatterns(model, 3, 0.05f, 1.0f);
    const LightField r = RandomLightField(c.geometry, 4);
    PaddedLayers padded;
    padded.PadAll(t);
    for (size_t b = 0; b < model.branch_count(); ++b) {
      ASSERT_TRUE(PairLattice::Suits(model, b)) << c.name;
      const PairLattice lattice(model, b);
      PairCells binned;
      lattice.Bin(r, &binned);
      ASSERT_EQ(binned.size(), lattice.cells());
      for (const int layer : {lattice.layer_a(), lattice.layer_b()}) {
        const std::string name = c.name + ", branch " + std::to_string(b) + ", layer " + std::to_string(layer);
        const int other = lattice.other_layer(layer);
        std::vector<double> num, den, r_sum;
        double rays = 0;
        RayByRaySums(model, layer, other, t, r, &num, &den, &rays, &r_sum);
        EXPECT_EQ(lattice.rays(), rays) << name;
        if (c.name == "wider than the layers") {
          EXPECT_LT(lattice.rays(), 0.8 * double(c.geometry.ray_count())) << name;
        }
        std::vector<double> lattice_num(num.size(), -1.0), lattice_den(den.size(), -1.0);
        lattice.UpdateSums(layer, padded.pixels(other), binned, lattice_num.data(), lattice_den.data());
        EXPECT_TRUE(ArraysNear(lattice_num, num, 1e-5, 1e-9)) << name;
        EXPECT_TRUE(ArraysNear(lattice_den, den, 1e-5, 1e-9)) << name;
        double binned_sum[3] = {0, 0, 0};
        for (const Rgb4& v : binned)
          for (int ch = 0; ch < 3; ++ch) binned_sum[ch] += v[ch];
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(binned_sum[ch], r_sum[ch], 1e-5 * r_sum[ch]) << name;
      }
    }
  }
}

// The lattice's update is the one-tap ray pass's (ComputeLayerUpdate), w_b
// and the layer's own value put back alike, to rounding.
TEST(PairLattice, UpdateIsTheRayPassUpdate) {
  for (const Case& c : Cases()) {
    const DisplayModel model(c.system, c.geometry);
    const Patterns t = RandomPatterns(model, 5, 0.05f, 1.0f);
    const LightField r = RandomLightField(c.geometry, 6);
    const BranchTarget whole = [&](size_t view, float*) { return r.view(view); };
    SolveWorkspace workspace(model, omp_get_max_threads(), kAllPasses);
    for (size_t b = 0; b < model.branch_count(); ++b) {
      ASSERT_TRUE(OneTapBranch(model, b));
      const PairLattice lattice(model, b);
      PairCells binned;
      lattice.Bin(r, &binned);
      for (const int layer : model.branch_layers(b)) {
        const std::string name = c.name + ", layer " + std::to_string(layer);
        std::vector<double> ray_num, ray_den, pair_num, pair_den;
        LayerUpdate by_rays{0, -1, &ray_num, &ray_den}, by_pairs{0, -1, &pair_num, &pair_den};
        ComputeLayerUpdate(model, {b, layer}, whole, t, &workspace, &by_rays);
        ComputeLayerUpdateFromPairs(model, {b, layer}, lattice, binned, t, &workspace, &by_pairs);
        EXPECT_EQ(by_pairs.layer, layer);
        EXPECT_TRUE(ArraysNear(pair_num, ray_num, 1e-5, 1e-9)) << name;
        EXPECT_TRUE(ArraysNear(pair_den, ray_den, 1e-5, 1e-9)) << name;
      }
    }
  }
}

TEST(PairLattice, SameBitsOnAnyThreadCount) {
  const Case c = Cases()[0];
  const DisplayModel model(c.system, c.geometry);
  const Patterns t = RandomPatterns(model, 7, 0.05f, 1.0f);
  const LightField r = RandomLightField(c.geometry, 8);
  PaddedLayers padded;
  padded.PadAll(t);
  const PairLattice lattice(model, 0);
  const int saved = omp_get_max_threads();
  std::vector<PairCells> binned;
  std::vector<std::vector<double>> nums, dens;
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    binned.emplace_back();
    lattice.Bin(r, &binned.back());
    nums.emplace_back(model.projection(lattice.layer_b()).pixel_count() * 3);
    dens.emplace_back(nums.back().size());
    lattice.UpdateSums(lattice.layer_b(), padded.pixels(lattice.layer_a()), binned.back(), nums.back().data(),
                       dens.back().data());
  }
  omp_set_num_threads(saved);
  for (size_t k = 1; k < nums.size(); ++k) {
    ASSERT_EQ(binned[k].size(), binned[0].size());
    EXPECT_EQ(std::memcmp(binned[k].data(), binned[0].data(), binned[0].size() * sizeof(Rgb4)), 0) << k + 1;
    EXPECT_TRUE(ArraysSameBits(nums[k], nums[0])) << k + 1 << " threads";
    EXPECT_TRUE(ArraysSameBits(dens[k], dens[0])) << k + 1 << " threads";
  }
}

// Binning costs about a pass over the rays: only where the rays are at
// least twice the cells. One view has a ray per pair; many views repeat pairs.
TEST(PairLattice, PaysWhereRaysRepeatPairs) {
  for (const int views : {1, 9}) {
    const DisplaySystem system = CompileJson(ShrunkExample("paper_prototype.json", 31, 17, views));
    const DisplayModel model(system, DisplayLightFieldGeometry(system));
    for (size_t b = 0; b < model.branch_count(); ++b) {
      const PairLattice lattice(model, b);
      const bool pays = PairLattice::IfItPays(model, b).has_value();
      EXPECT_EQ(pays, lattice.rays() >= 2.0 * double(lattice.cells()));
      EXPECT_EQ(pays, views == 9) << views << " views, branch " << b << ": " << lattice.rays() / double(lattice.cells())
                                  << " rays per cell";
    }
  }
  const DisplaySystem four = CompileJson(ShrunkExample("paper_prototype.json", 8, 4, 2));
  DisplaySystem one_stack = four;
  one_stack.branches.resize(1);
  one_stack.branches[0].layers = {0, 1, 2};
  EXPECT_FALSE(PairLattice::Suits(DisplayModel(one_stack, DisplayLightFieldGeometry(one_stack)), 0));
}

// The hybrid makes a set's updates after the first from the lattice where it
// pays: its solve is the general path's (rotated by 1e-12, ray by ray) to rounding.
TEST(PairLattice, HybridFromPairsFollowsTheGeneralPath) {
  const Case c = Cases()[0];
  DisplaySystem rotated = c.system;
  for (VirtualLayer& layer : rotated.layers) layer.rotation_rad = 1e-12;
  const DisplayModel fast(c.system, c.geometry), general(rotated, c.geometry);
  for (size_t b = 0; b < fast.branch_count(); ++b) ASSERT_TRUE(PairLattice::IfItPays(fast, b));
  const LightField target = Synthesize(fast, RandomPatterns(fast, 9, 0.05f, 1.0f));
  SolverOptions o;
  o.iterations = 3;
  o.initial_value = -1;
  Patterns pa, pb;
  const SolverReport ra = SolverRegistry::Builtins().create("hybrid")->Solve(fast, target, o, &pa);
  const SolverReport rb = SolverRegistry::Builtins().create("hybrid")->Solve(general, target, o, &pb);
  ASSERT_EQ(ra.trace.size(), rb.trace.size());
  for (size_t k = 0; k < ra.trace.size(); ++k)
    EXPECT_NEAR(ra.trace[k].objective, rb.trace[k].objective, 1e-5 * rb.trace[k].objective) << "iteration " << k;
  for (size_t k = 0; k < pa.size(); ++k) EXPECT_TRUE(ArraysNear(pa[k].rgb, pb[k].rgb, 0, 1e-4)) << "layer " << k;
}

}  // namespace
}  // namespace layerlab
