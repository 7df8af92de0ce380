// The target renderer against geometry worked out here from the ray equation
// of docs/lightfield-format.md, p(z) = v + (x - v) z / z_lf, with view and
// pixel positions written out from that document (not taken from the code):
//   v_x = -W_e/2 + (c + 0.5) W_e / N_c,  v_y = H_e/2 - (r + 0.5) H_e / N_r,
//   x = x0 + (j + 0.5) W / cols,         y = y0 - (i + 0.5) H / rows.
#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

#include "layerlab/analysis/target_cache.h"
#include "layerlab/framework/json_file.h"
#include "layerlab/targets/pixel_sampling.h"
#include "layerlab/targets/plane_lightfield.h"
#include "layerlab/targets/target_renderer.h"
#include "layerlab/targets/target_scene.h"
#include "layerlab/targets/target_tracer.h"
#include "layerlab/tests/render_test_util.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using nlohmann::json;
using testing::Close;

constexpr double kPi = std::numbers::pi;

double ViewX(const LightFieldGeometry& g, int c) {
  return -g.eyebox_width_m / 2 + (c + 0.5) * g.eyebox_width_m / g.views_x;
}
double ViewY(const LightFieldGeometry& g, int r) {
  return g.eyebox_height_m / 2 - (r + 0.5) * g.eyebox_height_m / g.views_y;
}
double PixelX(const LightFieldGeometry& g, int j) { return g.window_left_m + (j + 0.5) * g.window_width_m / g.cols; }
double PixelY(const LightFieldGeometry& g, int i) { return g.window_top_m - (i + 0.5) * g.window_height_m / g.rows; }

float Red(const LightField& lf, int view_row, int view_col, int i, int j) {
  const LightFieldGeometry& g = lf.geometry;
  return lf.view(static_cast<size_t>(view_row) * g.views_x + view_col)[(static_cast<size_t>(i) * g.cols + j) * 3];
}
float DepthAt(const LightField& lf, int view_row, int view_col, int i, int j) {
  const LightFieldGeometry& g = lf.geometry;
  return lf.depth[(static_cast<size_t>(view_row) * g.views_x + view_col) * g.pixels_per_view() +
                  static_cast<size_t>(i) * g.cols + j];
}

json LightFieldJson(const std::string& origin, json fov, json resolution, json views) {
  return {{"origin_plane", origin},
          {"field_of_view", fov},
          {"resolution", resolution},
          {"views", views},
          {"eyebox", {"6 mm", "6 mm"}}};
}

// A vector, not a json: `json objects = {one}` is an array of one under GCC
// but a copy of `one` under Clang (which follows CWG 2137 for one-element lists).
json Target(json light_field, std::vector<json> objects, int spp = 1) {
  return {
      {"format", "layerlab-target/1"}, {"light_field", light_field}, {"samples_per_pixel", spp}, {"objects", objects}};
}

json GratingPlane(const std::string& depth, const std::string& orientation, const std::string& frequency = "2 cpd") {
  return {
      {"type", "plane"},
      {"depth", depth},
      {"texture", {{"type", "grating"}, {"frequency", frequency}, {"orientation", orientation}, {"phase", "30 deg"}}}};
}

// Least squares a cos(w u) + b sin(w u) + c; returns (phase, amplitude) of cos(w u + phase).
std::array<double, 2> FitSinusoid(const std::vector<double>& u, const std::vector<double>& value, double w) {
  double m[3][4] = {};
  for (size_t k = 0; k < u.size(); ++k) {
    double basis[3] = {std::cos(w * u[k]), std::sin(w * u[k]), 1.0};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) m[r][c] += basis[r] * basis[c];
      m[r][3] += basis[r] * value[k];
    }
  }
  for (int p = 0; p < 3; ++p)  // Gauss-Jordan; the system is well conditioned over many periods
    for (int r = 0; r < 3; ++r) {
      if (r == p) continue;
      double f = m[r][p] / m[p][p];
      for (int c = 0; c < 4; ++c) m[r][c] -= f * m[p][c];
    }
  double a = m[0][3] / m[0][0], b = m[1][3] / m[1][1];
  return {std::atan2(-b, a), std::hypot(a, b)};
}

double Wrap(double angle) { return std::remainder(angle, 2 * kPi); }

struct ParallaxCase {
  std::string name;
  bool vertical;
  std::string plane_depth;
};

void PrintTo(const ParallaxCase& c, std::ostream* os) { *os << c.name; }

class ParallaxTest : public ::testing::TestWithParam<ParallaxCase> {};

// A grating at depth z seen from view v: the pixel at x reads the plane at
// v + (x - v) s, s = z / z_lf, so the pattern on the origin plane is
// cos(w x + phase_v) with w = 2 pi f s and phase_v = 2 pi f v (1 - s) + phase_0:
// a feature moves by dv (1 - z_lf / z) between views.
TEST_P(ParallaxTest, GratingMovesAsTheRayEquationPredicts) {
  const ParallaxCase& c = GetParam();
  json lf = c.vertical ? LightFieldJson("1.3 D", {"0.5 deg", "4 deg"}, {2, 240}, {1, 5})
                       : LightFieldJson("1.3 D", {"4 deg", "0.5 deg"}, {240, 2}, {5, 1});
  TargetScene target =
      ParseTarget(Target(lf, {GratingPlane(c.plane_depth, c.vertical ? "90 deg" : "0 deg")}), "target.json");
  LightField rendered = RenderTarget(target);
  const LightFieldGeometry& g = target.geometry;
  const double z = target.planes[0].depth_m, s = z / g.origin_z_m;
  const double f = 2 / (z * kPi / 180);  // cycles per meter on the plane
  const double w = 2 * kPi * f * s;      // radians per meter on the origin plane
  const int n = c.vertical ? g.rows : g.cols;
  const double pixel = c.vertical ? g.window_height_m / g.rows : g.window_width_m / g.cols;

  std::vector<double> u(n);
  for (int k = 0; k < n; ++k) u[k] = c.vertical ? PixelY(g, k) : PixelX(g, k);
  std::vector<double> phases;
  for (int view = 0; view < 5; ++view) {
    std::vector<double> values(n);
    for (int k = 0; k < n; ++k) values[k] = c.vertical ? Red(rendered, view, 0, k, 0) : Red(rendered, 0, view, 0, k);
    auto [phase, amplitude] = FitSinusoid(u, values, w);
    EXPECT_TRUE(Close(amplitude, 0.5, 1e-5)) << "view " << view;
    phases.push_back(phase);
  }
  for (int view = 1; view < 5; ++view) {
    double dv = c.vertical ? ViewY(g, view) - ViewY(g, 0) : ViewX(g, view) - ViewX(g, 0);
    double expected_shift = dv * (1 - g.origin_z_m / z);  // m on the origin plane
    double measured_shift = expected_shift - Wrap(phases[view] - phases[0] + w * expected_shift) / w;
    EXPECT_NEAR(measured_shift / pixel, expected_shift / pixel, 1e-3)
        << "view " << view << ": shift in pixels (" << pixel * 1e6 << " um each)";
  }
  // The phase of view 0 itself: 2 pi f v (1 - s) + 30 deg.
  double v0 = c.vertical ? ViewY(g, 0) : ViewX(g, 0);
  EXPECT_NEAR(Wrap(phases[0] - (2 * kPi * f * v0 * (1 - s) + kPi / 6)), 0, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(Planes, ParallaxTest,
                         ::testing::Values(ParallaxCase{"BehindOriginHorizontal", false, "0.7 D"},
                                           ParallaxCase{"InFrontOfOriginHorizontal", false, "2 D"},
                                           ParallaxCase{"BehindOriginVertical", true, "0.7 D"},
                                           ParallaxCase{"InFrontOfOriginVertical", true, "2 D"}),
                         [](const auto& test) { return test.param.name; });

TEST(TargetRendererTest, PlaneOnTheOriginPlaneHasNoParallax) {
  json noise = {{"type", "plane"},
                {"depth", "1.3 D"},
                {"texture", {{"type", "noise"}, {"band", {"1 cpd", "6 cpd"}}, {"seed", 3}}}};
  json lf = LightFieldJson("1.3 D", {"6 deg", "3 deg"}, {48, 24}, {3, 3});
  for (int spp : {1, 4}) {
    TargetScene target = ParseTarget(Target(lf, {noise}, spp), "target.json");
    LightField rendered = RenderTarget(target);
    const LightFieldGeometry& g = target.geometry;
    double worst = 0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        for (int i = 0; i < g.rows; ++i)
          for (int j = 0; j < g.cols; ++j) {
            worst = std::max(worst, std::abs(double(Red(rendered, r, c, i, j)) - Red(rendered, 1, 1, i, j)));
            if (spp == 1) {
              EXPECT_NEAR(Red(rendered, r, c, i, j), target.planes[0].texture->Evaluate(PixelX(g, j), PixelY(g, i))[0],
                          1e-6);
            }
          }
    EXPECT_LT(worst, 1e-6) << spp << " samples per pixel";
    EXPECT_GT(rendered.rgb[0], 0.0f);
  }
}

// Zero crossings of the grating along the central row of the central view,
// against the visual angle atan(x / z_lf) seen from the pupil center.
double MeasuredCyclesPerDegree(const LightField& lf, double mean) {
  const LightFieldGeometry& g = lf.geometry;
  std::vector<double> crossings;
  int i = g.rows / 2;
  for (int j = 0; j + 1 < g.cols; ++j) {
    double a = Red(lf, 0, 0, i, j) - mean, b = Red(lf, 0, 0, i, j + 1) - mean;
    double ta = std::atan(PixelX(g, j) / g.origin_z_m) * 180 / kPi,
           tb = std::atan(PixelX(g, j + 1) / g.origin_z_m) * 180 / kPi;
    if (std::abs(ta) > 3 || std::abs(tb) > 3 || (a > 0) == (b > 0)) continue;
    crossings.push_back(ta + (tb - ta) * a / (a - b));
  }
  if (crossings.size() < 4) return 0;
  return (crossings.size() - 1) / 2.0 / (crossings.back() - crossings.front());
}

TEST(TargetRendererTest, GratingHasTheRequestedCyclesPerDegreeAtTheViewCenter) {
  json example = ReadJsonFile(testing::ExamplePath("targets/grating_1.3D.json"));
  for (const char* depth : {"1.3 D", "0.5 D", "2.5 D"}) {
    for (const char* frequency : {"2 cpd", "4 cpd"}) {
      json target = example;
      target["objects"][0]["depth"] = depth;
      target["objects"][0]["texture"]["frequency"] = frequency;
      TargetScene scene = ParseTarget(target, testing::ExamplePath("targets/grating_1.3D.json"));
      scene.geometry.views_x = scene.geometry.views_y = 1;  // the pupil center, v = 0
      double measured = MeasuredCyclesPerDegree(RenderTarget(scene), 0.5);
      // Over +-3 deg a grating linear on the plane reads at most 0.3% above its on-axis frequency.
      EXPECT_TRUE(Close(measured, std::atof(frequency), 3e-3)) << depth << ", " << frequency;
    }
  }
}

TEST(TargetRendererTest, PixelSamplesCoverThePixelFootprint) {
  // Four pixels per period: averaging over the footprint attenuates the
  // grating by sinc(1/4) = sin(pi/4) / (pi/4) = 0.9003; center sampling keeps 1.
  json lf = LightFieldJson("1 D", {"16 deg", "1 deg"}, {256, 2}, {1, 1});
  for (auto [spp, attenuation] : {std::pair{1, 1.0}, std::pair{64, std::sin(kPi / 4) / (kPi / 4)}}) {
    TargetScene target = ParseTarget(Target(lf, {GratingPlane("1 D", "0 deg", "1 cpd")}, spp), "target.json");
    const LightFieldGeometry& g = target.geometry;
    double pixel = g.window_width_m / g.cols;
    // Set the frequency so that one period is exactly four pixels on the origin plane.
    GratingSpec spec;
    spec.cycles_per_meter = 1 / (4 * pixel);
    spec.phase_rad = 0.3;
    target.planes[0].texture = MakeGratingTexture(spec);
    LightField rendered = RenderTarget(target);
    std::vector<double> u, values;
    for (int j = 0; j < g.cols; ++j) u.push_back(PixelX(g, j)), values.push_back(Red(rendered, 0, 0, 0, j));
    auto [phase, amplitude] = FitSinusoid(u, values, 2 * kPi * spec.cycles_per_meter);
    EXPECT_TRUE(Close(amplitude, 0.5 * attenuation, 5e-3)) << spp << " samples per pixel";
    EXPECT_NEAR(Wrap(phase - 0.3), 0, 5e-3);
  }
}

// A quad tilted about y: z = 1 m + 0.3 x. The ray from (v, 0) with direction
// (d, 1), d = (x - v) / z_lf, meets it at z = (1 + 0.3 v_x) / (1 - 0.3 d_x).
TEST(TargetRendererTest, TiltedQuadDepthMatchesRayPlaneIntersection) {
  std::string dir = testing::ScratchDir();
  testing::WriteTextFile(dir + "/tilted.obj", "v -1 -1 -0.3\nv 1 -1 0.3\nv 1 1 0.3\nv -1 1 -0.3\nf 1 2 3 4\n");
  json mesh = {{"type", "mesh"}, {"file", "tilted.obj"}, {"position", {0, 0, "1 m"}}};
  json lf = LightFieldJson("1 D", {"20 deg", "10 deg"}, {40, 20}, {3, 3});
  TargetScene target = ParseTarget(Target(lf, {mesh}, 4), dir + "/target.json");
  RenderStats stats;
  LightField rendered = RenderTarget(target, &stats);
  const LightFieldGeometry& g = target.geometry;
  ASSERT_EQ(rendered.depth.size(), g.ray_count());
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < g.rows; ++i)
        for (int j = 0; j < g.cols; ++j) {
          double vx = ViewX(g, c), dx = (PixelX(g, j) - vx) / g.origin_z_m;
          double z = (1 + 0.3 * vx) / (1 - 0.3 * dx);
          ASSERT_NEAR(DepthAt(rendered, r, c, i, j), z, 1e-6 * z)
              << "view " << r << "," << c << " pixel " << i << "," << j;
        }
  // Four jittered samples and one center ray for depth per pixel.
  EXPECT_EQ(stats.rays, g.ray_count() * 5);
}

// Slab intersection of a ray with the unit cube [-1, 1]^3 after undoing the
// die's placement (scale 5 cm, 30 deg about y, centered at (1 cm, 0, 1 m)).
double CubeDepth(double vx, double vy, double dx, double dy, bool& near_edge) {
  const double c = std::cos(kPi / 6), s = std::sin(kPi / 6), scale = 0.05;
  double o[3] = {vx - 0.01, vy, -1.0}, d[3] = {dx, dy, 1.0};
  // Local = Ry(30)^T (p - center) / scale, Ry = [[c, 0, s], [0, 1, 0], [-s, 0, c]].
  double lo[3] = {(c * o[0] - s * o[2]) / scale, o[1] / scale, (s * o[0] + c * o[2]) / scale};
  double ld[3] = {(c * d[0] - s * d[2]) / scale, d[1] / scale, (s * d[0] + c * d[2]) / scale};
  double t0 = -INFINITY, t1 = INFINITY;
  for (int k = 0; k < 3; ++k) {
    double a = (-1 - lo[k]) / ld[k], b = (1 - lo[k]) / ld[k];
    t0 = std::max(t0, std::min(a, b));
    t1 = std::min(t1, std::max(a, b));
  }
  near_edge = std::abs(t1 - t0) < 1e-3;
  return t0 <= t1 ? t0 : INFINITY;  // t is the eye-space z since d_z = 1
}

TEST(TargetRendererTest, RotatedCubeDepthMatchesSlabIntersection) {
  json die = {{"type", "mesh"},
              {"file", "die.obj"},
              {"scale", "5 cm"},
              {"position", {"1 cm", 0, "1 D"}},
              {"rotation", {0, "30 deg", 0}},
              {"color", 0.5}};
  json lf = LightFieldJson("1.3 D", {"8 deg", "6 deg"}, {64, 48}, {3, 3});
  TargetScene target = ParseTarget(Target(lf, {die}, 1), testing::ExamplePath("targets/target.json"));
  RenderStats stats;
  LightField rendered = RenderTarget(target, &stats);
  const LightFieldGeometry& g = target.geometry;
  int hits = 0, misses = 0;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int i = 0; i < g.rows; ++i)
        for (int j = 0; j < g.cols; ++j) {
          double vx = ViewX(g, c), vy = ViewY(g, r);
          bool near_edge = false;
          double z =
              CubeDepth(vx, vy, (PixelX(g, j) - vx) / g.origin_z_m, (PixelY(g, i) - vy) / g.origin_z_m, near_edge);
          if (near_edge) continue;
          float depth = DepthAt(rendered, r, c, i, j);
          if (std::isinf(z)) {
            ++misses;
            ASSERT_EQ(depth, kBackgroundDepth) << "pixel " << i << "," << j;
            ASSERT_EQ(Red(rendered, r, c, i, j), 0.0f);
          } else {
            ++hits;
            ASSERT_NEAR(depth, z, 1e-6 * z) << "pixel " << i << "," << j;
          }
        }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 1000);
  EXPECT_EQ(stats.rays, g.ray_count());  // one sample per pixel doubles as the depth ray
}

TEST(TargetRendererTest, MeshShadingIsLambertianPlusAmbient) {
  std::string dir = testing::ScratchDir();
  testing::WriteTextFile(dir + "/card.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
  json card = {{"type", "mesh"}, {"file", "card.obj"}, {"position", {0, 0, "1 m"}}, {"color", {0.5, 0.25, 1}}};
  json lf = LightFieldJson("1 D", {"4 deg", "4 deg"}, {4, 4}, {1, 1});
  const double s45 = std::sqrt(0.5);
  // (direction to the light, expected shade): the card faces the viewer, normal (0, 0, -1).
  for (auto [to_light, shade] : {std::pair{json{0, 0, -1}, 1.0}, std::pair{json{0, 1, -1}, 0.2 + 0.8 * s45},
                                 std::pair{json{1, 0, 0}, 0.2}, std::pair{json{0, 0, 1}, 0.2}}) {
    json t = Target(lf, {card});
    t["light"] = {{"direction_to_light", to_light}, {"ambient", 0.2}};
    LightField rendered = RenderTarget(ParseTarget(t, dir + "/target.json"));
    const double color[3] = {0.5, 0.25, 1.0};
    for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(rendered.rgb[ch], color[ch] * shade, 1e-6) << to_light.dump();
  }
}

TEST(TargetRendererTest, FinitePlaneShowsBackgroundAroundIt) {
  json plane = {{"type", "plane"},
                {"depth", "1 D"},
                {"size", {"1 deg", "1 deg"}},
                {"texture", {{"type", "constant"}, {"color", 0.7}}}};
  json t = Target(LightFieldJson("1 D", {"10 deg", "10 deg"}, {21, 21}, {1, 1}), {plane});
  t["background"] = {0.1, 0.2, 0.3};
  LightField rendered = RenderTarget(ParseTarget(t, "target.json"));
  const float* center = rendered.view(0) + (10 * 21 + 10) * 3;
  EXPECT_FLOAT_EQ(center[0], 0.7f);
  EXPECT_FLOAT_EQ(rendered.depth[10 * 21 + 10], 1.0f);
  EXPECT_FLOAT_EQ(rendered.rgb[0], 0.1f);
  EXPECT_FLOAT_EQ(rendered.rgb[2], 0.3f);
  EXPECT_EQ(rendered.depth[0], kBackgroundDepth);
}

TEST(TargetRendererTest, EmbreeAndDirectPlaneLightFieldsAgree) {
  json noise = {{"type", "plane"},
                {"depth", "0.7 D"},
                {"center", {"1 cm", "-2 cm"}},
                {"texture", {{"type", "noise"}, {"band", {"0.5 cpd", "5 cpd"}}, {"seed", 9}, {"contrast", 0.5}}}};
  json t = Target(LightFieldJson("1.3 D", {"12 deg", "6 deg"}, {60, 30}, {3, 2}), {noise}, 4);
  t["seed"] = 3;
  TargetScene target = ParseTarget(t, "target.json");
  LightField traced = RenderTarget(target);
  const TargetPlane& plane = target.planes[0];
  LightField direct = RenderPlaneLightField(target.geometry, plane.depth_m, *plane.texture, {4, 3}, plane.center_m);
  ASSERT_EQ(traced.rgb.size(), direct.rgb.size());
  double worst = 0;
  for (size_t k = 0; k < traced.rgb.size(); ++k)
    worst = std::max(worst, std::abs(double(traced.rgb[k]) - direct.rgb[k]));
  EXPECT_LT(worst, 1e-5);
  EXPECT_EQ(traced.depth, direct.depth);
  // A different seed moves the samples.
  LightField other = RenderPlaneLightField(target.geometry, plane.depth_m, *plane.texture, {4, 4}, plane.center_m);
  EXPECT_NE(other.rgb, direct.rgb);
}

// The same texture, without the claim that lets a renderer copy rows.
class RowByRow final : public Texture {
 public:
  explicit RowByRow(const Texture& t) : t_(t) {}
  Rgb Evaluate(double s, double t) const override { return t_.Evaluate(s, t); }
  std::string Describe() const override { return t_.Describe(); }

 private:
  const Texture& t_;
};

TEST(TargetRendererTest, VerticalGratingRowsCopiedAreEveryPixelEvaluated) {
  LightFieldGeometry g = testing::WindowGeometry(37, 9, 3);
  g.views_y = 4;
  g.eyebox_height_m = 0.004;
  for (double phase : {0.0, 1.0, std::numbers::pi / 2})
    for (double angle_depth : {0.0, 0.6}) {
      GratingSpec spec;
      spec.cycles_per_meter = 900, spec.phase_rad = phase, spec.angle_depth_m = angle_depth;
      const std::unique_ptr<Texture> grating = MakeGratingTexture(spec);
      ASSERT_TRUE(grating->ConstantAlongT());
      for (double depth : {g.origin_z_m, 0.5}) {
        const std::array<double, 2> center{0.003, -0.02};
        const LightField fast = RenderPlaneLightField(g, depth, *grating, {}, center);
        const LightField general = RenderPlaneLightField(g, depth, RowByRow(*grating), {}, center);
        EXPECT_EQ(0, std::memcmp(fast.rgb.data(), general.rgb.data(), fast.rgb.size() * sizeof(float)))
            << "phase " << phase << ", angle depth " << angle_depth << ", depth " << depth;
        EXPECT_EQ(fast.depth, general.depth);
        // Each pixel from the plane equation, by hand.
        const double s = depth / g.origin_z_m;
        for (int vr = 0; vr < g.views_y; ++vr)
          for (int vc = 0; vc < g.views_x; ++vc)
            for (int i = 0; i < g.rows; i += 4)
              for (int j = 0; j < g.cols; j += 5) {
                const double vx = g.view_x(vc);
                const double w = vx + (g.pixel_x(j) - vx) * s - center[0];
                double phase_at = w;
                if (angle_depth > 0) phase_at = angle_depth * std::atan(w / angle_depth);
                const double value = 0.5 * (1 + std::cos(2 * std::numbers::pi * 900 * phase_at + phase));
                ASSERT_NEAR(fast.view(g.view_index(vr, vc))[(i * g.cols + j) * 3 + 1], value, 1e-6);
              }
      }
    }
  GratingSpec tilted;
  tilted.cycles_per_meter = 900, tilted.orientation_rad = std::numbers::pi / 2;
  EXPECT_FALSE(MakeGratingTexture(tilted)->ConstantAlongT());
}

TEST(TargetRendererTest, RenderingIsDeterministic) {
  TargetScene target = LoadTarget(testing::ExamplePath("targets/dice.json"));
  target.geometry.views_x = target.geometry.views_y = 2;
  target.geometry.cols = 80;
  target.geometry.rows = 40;
  LightField a = RenderTarget(target), b = RenderTarget(target);
  EXPECT_EQ(a.rgb, b.rgb);
  EXPECT_EQ(a.depth, b.depth);
  target.seed = 2;
  EXPECT_NE(RenderTarget(target).rgb, a.rgb);
}

// Natural viewing traces from any pupil point in any direction: a ray from
// (vx, vy, 0) along (dx, dy, 1) meets the plane at depth z at (vx + dx z, vy + dy z).
// The renderer traces each pixel row of a view as one stream and shades a noise plane through the row's
// shared phases; here every pixel is traced again ray by ray (TraceDirection, Embree's single-ray query and
// the texture evaluated at the hit) and averaged as the pixel's samples. A die in front of the noise gives
// mesh hits and edges. A ray that grazes an edge may meet the other triangle in the stream: a few pixels.
// Long rows are cut into streams of at most 4,096 rays.
TEST(TargetRendererTest, RowStreamsAndSharedPhasesAreTheRaysOneByOne) {
  const json die = {{"type", "mesh"},
                    {"file", "die.obj"},
                    {"scale", "2.5 cm"},
                    {"position", {"1 cm", "0.5 cm", "1.2 D"}},
                    {"rotation", {"20 deg", "30 deg", 0}},
                    {"texture", {{"type", "checkerboard"}, {"period", "2 cm"}}}};
  const json noise = {{"type", "plane"},
                      {"depth", "0.4 D"},
                      {"texture", {{"type", "noise"}, {"band", {"0.5 cpd", "3 cpd"}}, {"components", 24}}}};
  for (int spp : {1, 4, 144}) {  // 144 samples: each row of 36 pixels traced as two streams (28 + 8 pixels)
    const TargetScene target =
        ParseTarget(Target(LightFieldJson("1 D", {"12 deg", "8 deg"}, {36, 24}, {3, 2}), {noise, die}, spp),
                    testing::ExamplePath("targets/target.json"));
    const LightField rendered = RenderTarget(target);
    const LightFieldGeometry& g = target.geometry;
    const TargetTracer tracer(target);
    const PixelSampler sampler(g, spp, target.seed);
    int differ = 0, die_pixels = 0, noise_pixels = 0;
    for (size_t view = 0; view < g.view_count(); ++view) {
      const double vx = ViewX(g, int(view % g.views_x)), vy = ViewY(g, int(view / g.views_x));
      for (int i = 0; i < g.rows; ++i)
        for (int j = 0; j < g.cols; ++j) {
          double red = 0;
          for (int k = 0; k < spp; ++k) {
            auto [x, y] = sampler.Sample(i, j, k);
            red += tracer.Trace(vx, vy, x, y).color[0];
          }
          const double z = tracer.Trace(vx, vy, PixelX(g, j), PixelY(g, i)).z;
          (z < 2 ? die_pixels : noise_pixels) += 1;
          const size_t p = i * size_t(g.cols) + j;
          const bool same = std::abs(rendered.view(view)[p * 3] - red / spp) < 1e-6 &&
                            std::abs(rendered.depth[view * g.pixels_per_view() + p] - float(z)) <= 1e-6 * z;
          differ += !same;
        }
    }
    EXPECT_GT(die_pixels, 200) << spp;
    EXPECT_GT(noise_pixels, 2000) << spp;
    EXPECT_LE(differ, 4) << spp << " samples per pixel";
  }
}

// An MPI rank renders only its tile (LightFieldGeometry::ViewRows, PixelRows):
// its rays are the whole render's, jitter included, to the bit.
TEST(TargetRendererTest, ATileIsTheWholeRendersRaysBitForBit) {
  const json die = {{"type", "mesh"},
                    {"file", "die.obj"},
                    {"scale", "2.5 cm"},
                    {"position", {"1 cm", "0.5 cm", "1.2 D"}},
                    {"texture", {{"type", "checkerboard"}, {"period", "2 cm"}}}};
  const json noise = {{"type", "plane"},
                      {"depth", "0.4 D"},
                      {"texture", {{"type", "noise"}, {"band", {"0.5 cpd", "3 cpd"}}, {"components", 12}}}};
  TargetScene target =
      ParseTarget(Target(LightFieldJson("1 D", {"12 deg", "8 deg"}, {24, 10}, {3, 3}), {noise, die}, 4),
                  testing::ExamplePath("targets/target.json"));
  const LightField whole = RenderTarget(target);
  const LightFieldGeometry g = target.geometry;
  target.geometry = g.ViewRows(1, 2).PixelRows(3, 5);
  const LightField tile = RenderTarget(target);
  ASSERT_EQ(tile.geometry, target.geometry);
  for (size_t v = 0; v < tile.geometry.view_count(); ++v)
    for (int i = 0; i < 5; ++i) {
      const size_t at = (v + 3) * g.pixels_per_view() + size_t(i + 3) * g.cols,
                   mine = v * 5 * g.cols + size_t(i) * g.cols;
      EXPECT_EQ(std::memcmp(&tile.rgb[mine * 3], &whole.rgb[at * 3], g.cols * 3 * sizeof(float)), 0)
          << "view " << v << ", row " << i;
      EXPECT_EQ(std::memcmp(&tile.depth[mine], &whole.depth[at], g.cols * sizeof(float)), 0) << "depth, view " << v;
    }
}

TEST(TargetTracerTest, RayInAnyDirectionReadsThePlaneWhereItMeetsIt) {
  TargetScene target = ParseTarget(
      Target(LightFieldJson("1.3 D", {"10 deg", "6 deg"}, {20, 12}, {3, 3}), {GratingPlane("0.8 D", "20 deg")}),
      "target.json");
  TargetTracer tracer(target);
  const TargetPlane& plane = target.planes[0];
  for (double vx : {-0.0017, 0.0, 0.0021})
    for (double dx : {-0.05, 0.013, 0.07}) {
      const double vy = 0.6 * vx, dy = -0.4 * dx, z = plane.depth_m;
      TracedSample s = tracer.TraceDirection(vx, vy, dx, dy);
      Rgb expected = plane.texture->Evaluate(vx + dx * z - plane.center_m[0], vy + dy * z - plane.center_m[1]);
      EXPECT_NEAR(s.z, z, 1e-12);
      EXPECT_NEAR(s.color[0], expected[0], 1e-12) << "from " << vx << " along " << dx;
    }
}

// A scene moved across by v (a binocular eye's own display) is the scene
// seen from -v: every ray from (vx, vy) reads what the unmoved scene shows
// the ray from (vx - v_x, vy - v_y), planes and meshes alike; a move in depth
// moves every plane and vertex by it. Its render's key changes, and moved
// back it is the same key again.
TEST(TargetTracerTest, AMovedSceneIsTheSceneSeenFromTheOtherWay) {
  const json die = {{"type", "mesh"},
                    {"file", "die.obj"},
                    {"scale", "5 cm"},
                    {"position", {"1 cm", 0, "1 D"}},
                    {"rotation", {0, "30 deg", 0}},
                    {"color", 0.5}};
  const json t =
      Target(LightFieldJson("1.3 D", {"10 deg", "6 deg"}, {20, 12}, {3, 3}), {GratingPlane("0.8 D", "20 deg"), die});
  TargetScene still = ParseTarget(t, testing::ExamplePath("targets/target.json"));
  still.file_bytes = FileBytes{123, 456};  // the key's bytes of the file it was read from (not on disk)
  TargetScene moved = still;
  const std::array<double, 3> v = {0.0315, -0.004, 0};
  MoveTargetScene(&moved, v);
  EXPECT_EQ(moved.moved_m, v);
  const TargetTracer a(still), b(moved);
  int mesh_hits = 0, plane_hits = 0;
  for (double vx : {-0.0017, 0.0021})
    for (double dx : {-0.03, -0.01, 0.013, 0.03}) {
      const double vy = 0.6 * vx, dy = -0.4 * dx;
      const TracedSample s = a.TraceDirection(vx - v[0], vy - v[1], dx, dy);
      const TracedSample m = b.TraceDirection(vx, vy, dx, dy);
      ASSERT_TRUE(std::isfinite(s.z)) << vx << ", " << dx;
      EXPECT_NEAR(m.z, s.z, 1e-5 * s.z) << vx << ", " << dx;
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(m.color[c], s.color[c], 1e-5) << vx << ", " << dx;
      (s.z < 1.2 ? mesh_hits : plane_hits) += 1;
    }
  EXPECT_GT(mesh_hits, 0) << "no ray met the die";
  EXPECT_GT(plane_hits, 0) << "no ray met the plane";
  EXPECT_NE(TargetSceneDigest(moved), TargetSceneDigest(still));

  MoveTargetScene(&moved, {0.0315, -0.004, 0.02});
  EXPECT_NEAR(moved.planes[0].depth_m, still.planes[0].depth_m + 0.02, 1e-15);
  EXPECT_NEAR(moved.planes[0].center_m[0], still.planes[0].center_m[0] + 0.0315, 1e-15);
  EXPECT_NEAR(moved.meshes[0].mesh.positions[3][2], still.meshes[0].mesh.positions[3][2] + 0.02, 1e-15);
  EXPECT_NEAR(moved.meshes[0].mesh.positions[3][1], still.meshes[0].mesh.positions[3][1] - 0.004, 1e-15);
  MoveTargetScene(&moved, {0, 0, 0});
  EXPECT_EQ(TargetSceneDigest(moved), TargetSceneDigest(still));
}

}  // namespace
}  // namespace layerlab
