// P_k against an explicit sparse matrix built ray by ray from the ray
// equation in meters, p(z) = v + (x - v) z / z_lf, and the adjoint identity.
#include <cmath>
#include <limits>
#include <random>

#include <Eigen/Sparse>

#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/projection.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::Close;

LightFieldGeometry SmallGeometry() {
  LightFieldGeometry g;
  g.origin_z_m = 0.77;
  g.window_left_m = -0.2113;
  g.window_top_m = 0.1071;
  g.window_width_m = 0.4137;
  g.window_height_m = 0.2219;
  g.cols = 23;
  g.rows = 17;
  g.views_x = 3;
  g.views_y = 2;
  g.eyebox_width_m = 0.006;
  g.eyebox_height_m = 0.005;
  return g;
}

struct LayerCase {
  std::string name;
  double diopters;
  double rotation = 0;
  bool flip_x = false, flip_y = false;
  double offset_x_m = 0, offset_y_m = 0;  // at the layer's depth
};

void PrintTo(const LayerCase& c, std::ostream* os) { *os << c.name; }

VirtualLayer MakeLayer(const LayerCase& c) {
  VirtualLayer l;
  l.name = c.name;
  l.diopters = c.diopters;
  l.depth_m = 1 / c.diopters;
  l.cols = 19;
  l.rows = 13;
  l.pitch_x_m = 0.0245 * l.depth_m;  // about 0.021 rad per pixel wide
  l.pitch_y_m = 0.0231 * l.depth_m;
  l.tan_pitch_x = l.pitch_x_m / l.depth_m;
  l.tan_pitch_y = l.pitch_y_m / l.depth_m;
  l.eye_from_layer_tan_x = c.offset_x_m / l.depth_m;
  l.eye_from_layer_tan_y = c.offset_y_m / l.depth_m;
  l.rotation_rad = c.rotation;
  l.flip_x = c.flip_x;
  l.flip_y = c.flip_y;
  return l;
}

// One axis of a layer grid: the taps (cell, weight) of a coordinate measured
// in pixels from the grid's left (or top) edge.
std::vector<std::pair<int, double>> AxisTaps(double from_edge, int size, bool flip, Sampling s) {
  std::vector<std::pair<int, double>> taps;
  auto add = [&](double cell, double w) {
    if (cell >= 0 && cell < size && w > 0) taps.push_back({flip ? size - 1 - int(cell) : int(cell), w});
  };
  if (s == Sampling::kNearest) {
    add(std::floor(from_edge), 1.0);
  } else {
    double center = from_edge - 0.5, low = std::floor(center);
    add(low, 1 - (center - low));
    add(low + 1, center - low);
  }
  return taps;
}

// The explicit L x N matrix of one layer, built from the ray equation in meters.
Eigen::SparseMatrix<double, Eigen::RowMajor> ExplicitMatrix(const VirtualLayer& l, const LightFieldGeometry& g,
                                                            Sampling s) {
  std::vector<Eigen::Triplet<double>> entries;
  const double z = l.depth_m;
  for (int vr = 0; vr < g.views_y; ++vr)
    for (int vc = 0; vc < g.views_x; ++vc)
      for (int i = 0; i < g.rows; ++i)
        for (int j = 0; j < g.cols; ++j) {
          double vx = g.view_x(vc), vy = g.view_y(vr), xx = g.pixel_x(j), xy = g.pixel_y(i);
          double px = vx + (xx - vx) * z / g.origin_z_m - l.eye_from_layer_tan_x * z;
          double py = vy + (xy - vy) * z / g.origin_z_m - l.eye_from_layer_tan_y * z;
          double a = std::cos(l.rotation_rad) * px + std::sin(l.rotation_rad) * py;
          double b = -std::sin(l.rotation_rad) * px + std::cos(l.rotation_rad) * py;
          auto cols = AxisTaps(a / l.pitch_x_m + l.cols / 2.0, l.cols, l.flip_x, s);
          auto rows = AxisTaps(l.rows / 2.0 - b / l.pitch_y_m, l.rows, l.flip_y, s);
          size_t ray = g.view_index(vr, vc) * g.pixels_per_view() + size_t(i) * g.cols + j;
          for (auto [row, wr] : rows)
            for (auto [col, wc] : cols) entries.emplace_back(int(ray), row * l.cols + col, wr * wc);
        }
  Eigen::SparseMatrix<double, Eigen::RowMajor> P(int(g.ray_count()), l.cols * l.rows);
  P.setFromTriplets(entries.begin(), entries.end());
  return P;
}

std::vector<float> RandomValues(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<float> v(n);
  for (float& x : v) x = u(rng);
  return v;
}

const LayerCase kLayers[] = {
    {"BehindTheOriginPlane", 0.4},          {"InFrontOfTheOriginPlane", 2.2},
    {"OnTheOriginPlane", 1 / 0.77},         {"FlippedX", 1.6, 0, true, false},
    {"FlippedY", 1.0, 0, false, true},      {"Offset", 1.0, 0, false, false, 0.0213, -0.0117},
    {"Rotated", 1.6, 0.0731, false, false}, {"RotatedFlippedOffset", 0.7, -0.0412, true, true, -0.013, 0.007},
};

class ProjectionTest : public ::testing::TestWithParam<std::tuple<LayerCase, Sampling>> {};

TEST_P(ProjectionTest, MatchesTheExplicitMatrixAndItsTranspose) {
  const auto& [layer_case, sampling] = GetParam();
  LightFieldGeometry g = SmallGeometry();
  VirtualLayer layer = MakeLayer(layer_case);
  LayerProjection P(layer, g, sampling);
  auto M = ExplicitMatrix(layer, g, sampling);
  ASSERT_GT(M.nonZeros(), 0);

  std::vector<float> t = RandomValues(P.pixel_count() * 3, 1);
  std::vector<float> l = RandomValues(g.ray_count() * 3, 2);
  std::vector<double> scattered(P.pixel_count() * 3, 0.0);
  double lhs = 0;  // <P t, l>
  for (size_t v = 0; v < g.view_count(); ++v) {
    std::vector<float> view(g.pixels_per_view() * 3);
    P.Gather(v, t.data(), view.data());
    P.ScatterAdd(v, l.data() + v * g.pixels_per_view() * 3, scattered.data());
    for (size_t k = 0; k < view.size(); ++k) lhs += double(view[k]) * l[v * view.size() + k];
    for (int c = 0; c < 3; ++c) {
      Eigen::VectorXd tc(P.pixel_count());
      for (size_t p = 0; p < P.pixel_count(); ++p) tc[p] = t[p * 3 + c];
      Eigen::VectorXd expected = M.middleRows(int(v * g.pixels_per_view()), int(g.pixels_per_view())) * tc;
      for (size_t r = 0; r < g.pixels_per_view(); ++r)
        ASSERT_NEAR(view[r * 3 + c], expected[r], 1e-5) << "view " << v << " ray " << r << " channel " << c;
    }
  }
  double rhs = 0;  // <t, P^T l>
  for (size_t k = 0; k < t.size(); ++k) rhs += double(t[k]) * scattered[k];
  EXPECT_TRUE(Close(lhs, rhs, 1e-6));
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd lc(g.ray_count());
    for (size_t r = 0; r < g.ray_count(); ++r) lc[r] = l[r * 3 + c];
    Eigen::VectorXd expected = M.transpose() * lc;
    for (size_t p = 0; p < P.pixel_count(); ++p) ASSERT_NEAR(scattered[p * 3 + c], expected[p], 1e-4);
  }
}

INSTANTIATE_TEST_SUITE_P(Layers, ProjectionTest,
                         ::testing::Combine(::testing::ValuesIn(kLayers),
                                            ::testing::Values(Sampling::kNearest, Sampling::kBilinear)),
                         [](const auto& test_info) {
                           return std::get<0>(test_info.param).name + "_" + ToString(std::get<1>(test_info.param));
                         });

// The one-tap resampling writes only the layer rows a run of views reads
// (RowsRead); every ray of the run must find there the pixel the explicit
// matrix gives it. On a strip of 3 ray rows that is a few of the layer's 13.
TEST(Projection, ResampledRowsHoldEveryPixelARunReads) {
  LightFieldGeometry g = SmallGeometry();
  g.rows = 3;
  g.window_height_m = g.window_height_m * 3 / 17;
  g.window_top_m = g.window_height_m / 2;
  g.views_y = 3;
  VirtualLayer layer = MakeLayer({"near", 2.1, 0, false, false, 0.0013, -0.0007});
  LayerProjection P(layer, g, Sampling::kNearest);
  ASSERT_TRUE(P.one_tap());
  auto M = ExplicitMatrix(layer, g, Sampling::kNearest);
  std::vector<float> t = RandomValues(P.pixel_count() * 3, 3);
  std::vector<Rgb4> padded;
  PadRgb(t, &padded);
  const float poison = std::numeric_limits<float>::quiet_NaN();
  int widest = 0, checked = 0;
  for (int vr_begin = 0; vr_begin < g.views_y; ++vr_begin)
    for (int vr_end = vr_begin + 1; vr_end <= g.views_y; ++vr_end)
      for (int vc = 0; vc < g.views_x; ++vc) {
        const RowSpan span = RowsRead(P, g, vr_begin, vr_end);
        ASSERT_LE(0, span.begin);
        ASSERT_LE(span.end, P.rows());
        widest = std::max(widest, span.end - span.begin);
        std::vector<Rgb4> out(P.pixel_count() * g.cols, Rgb4{poison, poison, poison, poison});
        ResampleToRayColumns(P, padded.data(), vc, g.cols, span, &out);
        for (int vr = vr_begin; vr < vr_end; ++vr)
          for (int i = 0; i < g.rows; ++i)
            for (int j = 0; j < g.cols; ++j) {
              const int ray = static_cast<int>(g.view_index(vr, vc) * g.pixels_per_view()) + i * g.cols + j;
              for (decltype(M)::InnerIterator it(M, ray); it; ++it) {
                const int pixel = static_cast<int>(it.col()), row = pixel / P.cols();
                ASSERT_TRUE(row >= span.begin && row < span.end) << "ray " << ray << " reads row " << row;
                const Rgb4 v = out[static_cast<size_t>(row) * g.cols + j];
                for (int c = 0; c < 3; ++c) ASSERT_EQ(v[c], t[static_cast<size_t>(pixel) * 3 + c]) << "ray " << ray;
                ++checked;
              }
            }
      }
  EXPECT_GT(checked, 0);
  EXPECT_LT(widest, P.rows());
}

TEST(Projection, OriginPlaneLayerHasNoParallax) {
  LightFieldGeometry g = SmallGeometry();
  VirtualLayer layer = MakeLayer({"origin", 1 / g.origin_z_m});
  LayerProjection P(layer, g, Sampling::kNearest);
  for (int i = 0; i < g.rows; ++i)
    for (int j = 0; j < g.cols; ++j) {
      RayTaps first = P.Taps(0, i, j);
      for (size_t v = 1; v < g.view_count(); ++v) {
        RayTaps other = P.Taps(v, i, j);
        ASSERT_EQ(other.count, first.count);
        if (first.count) {
          EXPECT_EQ(other.index[0], first.index[0]);
        }
      }
    }
}

TEST(Projection, BilinearTapsSumToOneInside) {
  LightFieldGeometry g = SmallGeometry();
  LayerProjection P(MakeLayer({"rot", 1.3, 0.05}), g, Sampling::kBilinear);
  RayTaps taps = P.Taps(2, g.rows / 2, g.cols / 2);
  ASSERT_EQ(taps.count, 4);
  EXPECT_TRUE(Close(taps.weight[0] + taps.weight[1] + taps.weight[2] + taps.weight[3], 1.0, 1e-6));
}

TEST(Projection, LayerAtInfinityIsFinite) {
  LightFieldGeometry g = SmallGeometry();
  VirtualLayer layer = MakeLayer({"far", 0.5});
  layer.diopters = 0;
  layer.depth_m = INFINITY;
  LayerProjection P(layer, g, Sampling::kNearest);
  // At infinity a ray's tan-angle is its direction (x - v) / z_lf alone.
  int i = 5, j = 11;
  size_t view = g.view_index(1, 2);
  double ux = (g.pixel_x(j) - g.view_x(2)) / g.origin_z_m, uy = (g.pixel_y(i) - g.view_y(1)) / g.origin_z_m;
  int col = int(std::floor(ux / layer.tan_pitch_x + layer.cols / 2.0));
  int row = int(std::floor(layer.rows / 2.0 - uy / layer.tan_pitch_y));
  RayTaps taps = P.Taps(view, i, j);
  ASSERT_EQ(taps.count, 1);
  EXPECT_EQ(taps.index[0], row * layer.cols + col);
}

// Synthesis of a two-branch, two-layer-per-branch display against the explicit matrices.
TEST(Synthesis, SumOfProductsMatchesExplicitMatrices) {
  DisplaySystem system;
  for (const LayerCase& c :
       {LayerCase{"a0", 1.6, 0, true}, LayerCase{"a1", 0.4}, LayerCase{"b0", 2.2}, LayerCase{"b1", 1.0, 0, true}})
    system.layers.push_back(MakeLayer(c));
  system.branches.resize(2);
  system.branches[0].layers = {0, 1};
  system.branches[1].layers = {2, 3};
  system.branches[0].efficiency = {0.045, 0.04, 0.03};
  system.branches[1].efficiency = {0.02, 0.045, 0.045};
  for (Branch& b : system.branches) b.backlight_luminance_cd_m2 = 100;
  LightFieldGeometry g = SmallGeometry();
  DisplayModel model(system, g, Sampling::kNearest);
  // The brightest branch and channel (4.5 cd/m2) is 1; the rest relative to it.
  EXPECT_FLOAT_EQ(model.weight(0)[0], 1.0f);
  EXPECT_FLOAT_EQ(model.weight(0)[2], 3.0f / 4.5f);
  EXPECT_FLOAT_EQ(model.weight(1)[0], 2.0f / 4.5f);

  Patterns t = model.UniformPatterns(0);
  for (size_t k = 0; k < t.size(); ++k) t[k].rgb = RandomValues(t[k].rgb.size(), 10 + unsigned(k));
  LightField synthesized = Synthesize(model, t);

  std::vector<Eigen::SparseMatrix<double, Eigen::RowMajor>> M;
  for (const VirtualLayer& l : system.layers) M.push_back(ExplicitMatrix(l, g, Sampling::kNearest));
  for (int c = 0; c < 3; ++c) {
    Eigen::VectorXd total = Eigen::VectorXd::Zero(g.ray_count());
    for (size_t b = 0; b < 2; ++b) {
      Eigen::VectorXd product = Eigen::VectorXd::Ones(g.ray_count());
      for (int k : system.branches[b].layers) {
        Eigen::VectorXd tk(t[k].pixel_count());
        for (size_t p = 0; p < t[k].pixel_count(); ++p) tk[p] = t[k].rgb[p * 3 + c];
        product = product.cwiseProduct(M[k] * tk);
      }
      total += system.branches[b].backlight_luminance_cd_m2 * system.branches[b].efficiency[c] / 4.5 * product;
    }
    for (size_t r = 0; r < g.ray_count(); ++r) ASSERT_NEAR(synthesized.rgb[r * 3 + c], total[r], 1e-6) << r;
  }
}

TEST(Synthesis, PaperGeometryMatchesTheDiceManifest) {
  DisplaySystem system = testing::CompileJson(testing::ReadExample("paper_prototype.json"));
  LightFieldGeometry g = DisplayLightFieldGeometry(system);
  // lightfield-format.md: origin plane 1.3 D, window 0.49248 x 0.24624 m, 400 x 200, 13 x 13 views.
  EXPECT_TRUE(Close(g.origin_z_m, 1 / 1.3, 1e-12));
  EXPECT_TRUE(Close(g.window_width_m, 0.49248, 1e-4));
  EXPECT_TRUE(Close(g.window_height_m, 0.24624, 1e-4));
  EXPECT_EQ(g.cols, 400);
  EXPECT_EQ(g.rows, 200);
  EXPECT_EQ(g.views_x, 13);
  EXPECT_TRUE(Close(g.eyebox_width_m, 0.006, 1e-12));
}

}  // namespace
}  // namespace layerlab
