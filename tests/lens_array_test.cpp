// A lens array before a panel (elements/lens_array.cpp, systems/lenslet_map.h):
// integral imaging. Checked against computations written here: an elemental
// image's place by hand (the chief ray through a lenslet's centre is not
// deviated), random eye rays traced lenslet by lenslet (the lenslet found by
// searching every centre, a thin lens centred on it, free space to the
// panel) against the layer's sampler, and the span of pupil points free of
// crosstalk against rays sent through every lenslet from its edges.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "layerlab/framework/units.h"
#include "layerlab/retina/retina.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/layer_sampler.h"
#include "layerlab/systems/lenslet_map.h"
#include "test_util.h"

namespace layerlab {
namespace {

using layerlab::testing::CompileError;
using layerlab::testing::CompileJson;

constexpr double kEyeToArray = 30e-3, kPitch = 1e-3, kF = 3.3e-3, kPixel = 50e-6;
constexpr int kCols = 16, kRows = 12, kPanelCols = 320, kPanelRows = 240;

// The eye, a lens array kEyeToArray away, a panel `gap` behind it (or placed by `depth`).
nlohmann::json IntegralImaging(const std::string& gap, const nlohmann::json& array_extra = nlohmann::json::object(),
                               const std::string& eyebox = "4 mm") {
  nlohmann::json array = {{"type", "lens_array"},    {"name", "mla"},  {"focal_length", "3.3 mm"}, {"pitch", "1 mm"},
                          {"count", {kCols, kRows}}, {"gap", "30 mm"}, {"next", "panel"}};
  array.update(array_extra);
  nlohmann::json panel = {{"type", "lc_panel"},
                          {"name", "panel"},
                          {"pixel_pitch", "50 um"},
                          {"resolution", {kPanelCols, kPanelRows}},
                          {"next", "backlight"}};
  panel[gap.find('D') != std::string::npos ? "virtual_depth" : "gap"] = gap;
  return {{"format", "layerlab-scene/1"},
          {"elements",
           {{{"type", "eye"},
             {"name", "eye"},
             {"pupil_diameter", "4 mm"},
             {"eyebox", {eyebox, eyebox}},
             {"views", {3, 3}},
             {"next", "mla"}},
            array,
            panel,
            {{"type", "backlight"}, {"name", "backlight"}, {"luminance", "100 cd/m2"}}}}};
}

// Where a ray from pupil point p with direction u meets the panel, in the panel's pixel coordinates (centres at
// integers), traced here: the lenslet whose centre is nearest where it meets the array (searched over every
// centre), lost between clear apertures; u' = u - (h - c) / f; then free space. NaN when lost.
std::array<double, 2> Traced(double gap, double px, double py, double ux, double uy, bool hexagonal, double fill) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double hx = px + ux * kEyeToArray, hy = py + uy * kEyeToArray;
  double best = INFINITY, cx = nan, cy = nan;
  for (int r = 0; r < kRows; ++r)
    for (int i = 0; i < kCols; ++i) {
      double x, y;
      if (hexagonal) {
        x = (i - 0.5 * (kCols - 1)) * kPitch + (r % 2 ? 0.5 * kPitch : 0.0);
        y = (r - 0.5 * (kRows - 1)) * kPitch * std::sqrt(3.0) / 2;
      } else {
        x = (i + 0.5 - 0.5 * kCols) * kPitch, y = (r + 0.5 - 0.5 * kRows) * kPitch;
      }
      const double d = std::hypot(hx - x, hy - y);
      if (d < best) best = d, cx = x, cy = y;
    }
  const double dx = hx - cx, dy = hy - cy, reach = 0.5 * fill * kPitch;
  const bool inside = hexagonal ? std::abs(dx) <= reach && std::abs(0.5 * dx + 0.5 * std::sqrt(3.0) * dy) <= reach &&
                                      std::abs(0.5 * dx - 0.5 * std::sqrt(3.0) * dy) <= reach
                                : std::abs(dx) <= reach && std::abs(dy) <= reach;
  const bool on_array = hexagonal || (std::abs(hx) < 0.5 * kCols * kPitch && std::abs(hy) < 0.5 * kRows * kPitch);
  if (!inside || !on_array) return {nan, nan};
  const double X = hx + (ux - dx / kF) * gap, Y = hy + (uy - dy / kF) * gap;
  // Seen through a magnifier the panel is upright: column right with x, row down with -y.
  return {X / kPixel + 0.5 * kPanelCols - 0.5, -Y / kPixel + 0.5 * kPanelRows - 0.5};
}

// The layer's own answer for ray (p, u): its tan-angle on the grid U = u + D p, moved by the lenslet.
std::array<double, 2> Sampled(const VirtualLayer& l, double px, double py, double ux, double uy) {
  const std::array<double, 2> U = l.lenslets->Shift(px, py, ux + l.diopters * px, uy + l.diopters * py);
  return LayerSampler(l, Sampling::kNearest).PanelCoordinates(U[0], U[1]);
}

TEST(LensArray, AnElementalImageSitsWhereTheChiefRayMeetsThePanel) {
  const double g = 3.2e-3;
  const DisplaySystem s = CompileJson(IntegralImaging("3.2 mm"));
  ASSERT_EQ(s.layers.size(), 1u);
  const VirtualLayer& l = s.layers[0];
  ASSERT_NE(l.lenslets, nullptr);
  // The panel through a lenslet on the axis: 1/D = 30 mm + the image of a panel g inside f.
  EXPECT_NEAR(1 / l.diopters, kEyeToArray + g * kF / (kF - g), 1e-12);
  // From the pupil's centre toward lenslet i's centre (c_i, c_j): undeviated, on to the panel at c (1 + g / z).
  for (int i : {0, 3, 8, 15})
    for (int j : {0, 5, 11}) {
      const double cx = (i + 0.5 - 0.5 * kCols) * kPitch, cy = (j + 0.5 - 0.5 * kRows) * kPitch;
      const std::array<double, 2> at = Sampled(l, 0, 0, cx / kEyeToArray, cy / kEyeToArray);
      EXPECT_NEAR(at[0], cx * (1 + g / kEyeToArray) / kPixel + 0.5 * kPanelCols - 0.5, 1e-9) << i << "," << j;
      EXPECT_NEAR(at[1], -cy * (1 + g / kEyeToArray) / kPixel + 0.5 * kPanelRows - 0.5, 1e-9) << i << "," << j;
    }
  // The field is the array's, seen from the pupil: 2 atan(8 mm / 30 mm) by 2 atan(6 mm / 30 mm).
  EXPECT_NEAR(l.fov_x_rad, 2 * std::atan(8.0 / 30), 1e-12);
  EXPECT_NEAR(l.fov_y_rad, 2 * std::atan(6.0 / 30), 1e-12);
}

TEST(LensArray, EveryRayReadsThePixelItsLensletSendsItTo) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> pupil(-3e-3, 3e-3), angle(-0.3, 0.3);
  for (const bool hexagonal : {false, true})
    for (const double fill : {1.0, 0.7}) {
      nlohmann::json extra = {{"fill_factor", fill}, {"lattice", hexagonal ? "hexagonal" : "square"}};
      const DisplaySystem s = CompileJson(IntegralImaging("3.25 mm", extra));
      const VirtualLayer& l = s.layers[0];
      int lost = 0, seen = 0;
      for (int n = 0; n < 2000; ++n) {
        const double px = pupil(random), py = pupil(random), ux = angle(random), uy = angle(random);
        const std::array<double, 2> want = Traced(3.25e-3, px, py, ux, uy, hexagonal, fill);
        const std::array<double, 2> got = Sampled(l, px, py, ux, uy);
        if (std::isnan(want[0])) {
          EXPECT_TRUE(std::isnan(got[0]) || std::isnan(got[1])) << n;
          ++lost;
          continue;
        }
        ++seen;
        ASSERT_NEAR(got[0], want[0], 1e-8) << "hexagonal " << hexagonal << " fill " << fill << " ray " << n;
        ASSERT_NEAR(got[1], want[1], 1e-8) << "hexagonal " << hexagonal << " fill " << fill << " ray " << n;
      }
      EXPECT_GT(seen, 300);
      if (fill < 1) {
        EXPECT_GT(lost, 200);  // half the cell's area lies outside a 0.7 aperture
      }
    }
}

// How far past its elemental image's edge the worst ray from pupil points +-p lands (m; <= 0: none leaves),
// traced here: through a thin lens of focal length `lens_f` (0: none) `lens_at` from the eye, to the array at
// kEyeToArray, through the lenslet at offset d from its centre c (every lenslet, d at its centre and at the edges
// of its clear aperture, a `fill` of the pitch), free space g to the panel. Elemental image i is centred where the ray from the pupil's centre through
// lenslet i's centre meets the panel; it reaches half-way to its neighbours' centres.
double WorstCrosstalk(double p, double g, double lens_f, double lens_at, double fill) {
  const double P = lens_f ? 1 / lens_f : 0, d1 = lens_at, d2 = kEyeToArray - lens_at;
  auto panel_x = [&](double pupil, double h, double c) {
    const double u = (h - pupil * (1 - d2 * P)) / (d1 + d2 - d1 * d2 * P);  // the direction that reaches h
    const double at_lens = pupil + u * d1, u_array = u - P * at_lens;
    return h + (u_array - (h - c) / kF) * g;
  };
  double beyond = -INFINITY;
  for (int i = 0; i < kCols; ++i) {
    const double c = (i + 0.5 - 0.5 * kCols) * kPitch, centre = panel_x(0, c, c);
    const double half = 0.5 * (panel_x(0, c + kPitch, c + kPitch) - centre);
    for (double d : {-0.5 * fill * kPitch, 0.0, 0.5 * fill * kPitch})
      for (double pupil : {-p, p}) beyond = std::max(beyond, std::abs(panel_x(pupil, c + d, c) - centre) - half);
  }
  return beyond;
}

TEST(LensArray, TheCrosstalkFreeSpanIsWhereEveryLensletShowsItsOwnElementalImage) {
  // The panel at the focal plane: E = w z / f.
  const DisplaySystem s = CompileJson(IntegralImaging("3.3 mm"));
  const double E = s.layers[0].lenslets->crosstalk_free_m();
  EXPECT_NEAR(E, kPitch * kEyeToArray / kF, 1e-12);
  EXPECT_LE(WorstCrosstalk(0.5 * E * (1 - 1e-6), 3.3e-3, 0, 0, 1), 0);
  EXPECT_GT(WorstCrosstalk(0.5 * E * (1 + 1e-6), 3.3e-3, 0, 0, 1), 0);
  // A diverging lens (-100 mm) 10 mm from the eye before the array, lenslets of 80 % fill, the panel 3.2 mm
  // behind them: the span by the trace.
  nlohmann::json relay = IntegralImaging("3.2 mm", {{"fill_factor", 0.8}});
  relay["elements"][0]["next"] = "field_lens";
  relay["elements"][1]["gap"] = "20 mm";
  relay["elements"].push_back(
      {{"type", "thin_lens"}, {"name", "field_lens"}, {"focal_length", "-100 mm"}, {"gap", "10 mm"}, {"next", "mla"}});
  const double R = CompileJson(relay).layers[0].lenslets->crosstalk_free_m();
  EXPECT_LE(WorstCrosstalk(0.5 * R * (1 - 1e-6), 3.2e-3, -0.1, 0.01, 0.8), 0) << R;
  EXPECT_GT(WorstCrosstalk(0.5 * R * (1 + 1e-6), 3.2e-3, -0.1, 0.01, 0.8), 0) << R;
  // Its eyebox of 4 mm and pupil of 4 mm reach 8 mm across, within the 9.09 mm: no warning; 6 mm reach 10 mm.
  for (const std::string& w : s.warnings) EXPECT_EQ(w.find("crosstalk"), std::string::npos) << w;
  const DisplaySystem wide = CompileJson(IntegralImaging("3.3 mm", nlohmann::json::object(), "6 mm"));
  std::string warnings;
  for (const std::string& w : wide.warnings) warnings += w + "\n";
  EXPECT_NE(warnings.find("beyond the 9.09 mm within which each lenslet shows"), std::string::npos) << warnings;
}

// What the eye sees: the panel lit in the middle half of each elemental image (centred at c (1 + g / z), a pitch
// of w (1 + g / z) apart) and dark elsewhere. From pupil points within 1 mm of the centre every ray through a
// lenslet meets its own elemental image within 0.17 mm of the centre (d (1 + g / z - g / f) - g p / z): the eye
// sees white across the array's field. Read through the axial lenslet instead, the rays would cross dark bands.
TEST(LensArray, TheEyeSeesEachElementalImageThroughItsLenslet) {
  const double g = 3.29e-3, alpha = 1 + g / kEyeToArray;
  nlohmann::json scene = IntegralImaging("3.29 mm");
  scene["elements"][0]["pupil_diameter"] = "2 mm";
  scene["elements"][0]["pupil_samples"] = {3, 3};
  const DisplaySystem s = CompileJson(scene);
  const DisplayModel model(s, DisplayLightFieldGeometry(s), Sampling::kNearest);
  Patterns t = model.UniformPatterns(0.0f);
  const VirtualLayer& l = s.layers[0];
  for (int row = 0; row < kPanelRows; ++row)
    for (int col = 0; col < kPanelCols; ++col) {
      const double x = (col + 0.5 - 0.5 * kPanelCols) * kPixel, y = (0.5 * kPanelRows - row - 0.5) * kPixel;
      auto middle = [&](double v) {  // within the middle half of the elemental image v lies in
        const double cell = kPitch * alpha, from_centre = v / cell - std::floor(v / cell) - 0.5;
        return std::abs(from_centre) < 0.25;
      };
      if (middle(x) && middle(y))
        for (int c = 0; c < 3; ++c) t[0].rgb[(size_t(row) * kPanelCols + col) * 3 + c] = 1.0f;
    }
  const RetinaGrid retina = MakeRetinaGrid(20 * kRadiansPerDegree, 14 * kRadiansPerDegree, 0.25 * kRadiansPerDegree);
  const Image image = RetinaOfDisplay(model, t, retina, PupilSamples(s.eye), {l.diopters, l.diopters, l.diopters});
  double lowest = INFINITY;
  for (float v : image.pixels) lowest = std::min(lowest, double(v));
  EXPECT_GT(lowest, 0.999 * model.weight(0)[1]);
  // The light field's rays, from views up to 1.5 mm off the axis, read it the same way where they meet the array
  // inside its edge lenslets.
  const LightFieldGeometry& lf = model.geometry();
  std::vector<float> view(lf.pixels_per_view() * 3);
  int read = 0;
  for (size_t v = 0; v < lf.view_count(); ++v) {
    const double px = lf.view_x(int(v % lf.views_x)), py = lf.view_y(int(v / lf.views_x));
    if (std::abs(px) > 1.5e-3 || std::abs(py) > 1.5e-3) continue;
    model.projection(0).Gather(v, t[0].rgb.data(), view.data());
    for (int i = 0; i < lf.rows; ++i)
      for (int j = 0; j < lf.cols; ++j) {
        const double hx = px + (lf.pixel_x(j) - px) / lf.origin_z_m * kEyeToArray,
                     hy = py + (lf.pixel_y(i) - py) / lf.origin_z_m * kEyeToArray;
        if (std::abs(hx) > 7e-3 || std::abs(hy) > 5e-3) continue;
        ASSERT_EQ(view[(size_t(i) * lf.cols + j) * 3 + 1], 1.0f) << "view " << v << " ray " << i << "," << j;
        ++read;
      }
  }
  EXPECT_GT(read, 10000);
}

TEST(LensArray, RefusalsNameTheReason) {
  nlohmann::json none = IntegralImaging("3.2 mm", {{"fill_factor", 0}});
  EXPECT_NE(CompileError(none).find("/elements/1/fill_factor"), std::string::npos) << CompileError(none);
  nlohmann::json two = IntegralImaging("3.2 mm");
  nlohmann::json second = two["elements"][1];
  second["name"] = "mla2", second["gap"] = "1 mm";
  two["elements"][1]["next"] = "mla2";
  two["elements"].push_back(second);
  EXPECT_NE(CompileError(two).find("seen through two lens arrays"), std::string::npos) << CompileError(two);
}

}  // namespace
}  // namespace layerlab
