// Retinal images against geometric optics.
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "layerlab/framework/units.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retina.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

using testing::Close;
using testing::CompileJson;
using testing::ElementNamed;

EyeModel Eye(int samples, double pupil = 4e-3) {
  EyeModel eye;
  eye.pupil_diameter_m = pupil;
  eye.pupil_samples_x = eye.pupil_samples_y = samples;
  return eye;
}

TEST(Pupil, GridIsCellCenteredOverTheSquare) {
  std::vector<PupilPoint> p = PupilSamples(Eye(9));
  ASSERT_EQ(p.size(), 81u);
  EXPECT_TRUE(Close(p.front().x_m, -2e-3 + 2e-3 / 9, 1e-12));
  EXPECT_TRUE(Close(p.front().y_m, 2e-3 - 2e-3 / 9, 1e-12));
  EXPECT_TRUE(Close(p.back().x_m, 2e-3 - 2e-3 / 9, 1e-12));
}

// A round pupil's grid is the square grid's cell centers that lie in the circle: all but the corner cells, by hand
// three at each corner of 9 x 9 (69 points), one at each corner of 6 x 6 (32) and of 7 x 4 (24).
TEST(Pupil, RoundGridIsTheSquareGridsCellCentersInsideTheCircle) {
  for (const auto& [nx, ny, count] : {std::tuple{9, 9, 69}, std::tuple{6, 6, 32}, std::tuple{7, 4, 24}}) {
    SCOPED_TRACE(std::to_string(nx) + " x " + std::to_string(ny));
    EyeModel eye = Eye(nx, 3e-3);
    eye.pupil_samples_y = ny;
    const std::vector<PupilPoint> square = PupilSamples(eye);
    eye.pupil_shape = PupilShape::kRound;
    const std::vector<PupilPoint> round = PupilSamples(eye);
    ASSERT_EQ(round.size(), size_t(count));
    size_t k = 0;
    for (const PupilPoint& q : square) {
      if (std::hypot(q.x_m, q.y_m) > 1.5e-3) continue;
      ASSERT_LT(k, round.size());
      EXPECT_EQ(round[k].x_m, q.x_m);
      EXPECT_EQ(round[k].y_m, q.y_m);
      ++k;
    }
    EXPECT_EQ(k, round.size());
  }
}

TEST(Pupil, RoundJitteredPoissonAndPinhole) {
  EyeModel eye = Eye(9);
  eye.pupil_shape = PupilShape::kRound;
  std::vector<PupilPoint> round = PupilSamples(eye);
  EXPECT_LT(round.size(), 81u);
  EXPECT_GT(round.size(), 50u);  // about pi/4 of them
  for (const PupilPoint& q : round) EXPECT_LE(std::hypot(q.x_m, q.y_m), 2e-3);
  eye.pupil_sampling = PupilSampling::kJittered;
  eye.pupil_shape = PupilShape::kSquare;
  std::vector<PupilPoint> jittered = PupilSamples(eye);
  ASSERT_EQ(jittered.size(), 81u);
  // The jitter is framework/random.h's from pupil_seed 1: its first two
  // uniforms (tests/solver_test.cpp RandomInitialPatternsComeFromTheProjectsGenerator).
  EXPECT_DOUBLE_EQ(jittered[0].x_m, -2e-3 + 0.5665615751722809 * 4e-3 / 9);
  EXPECT_DOUBLE_EQ(jittered[0].y_m, 2e-3 - 0.7457817572627011 * 4e-3 / 9);
  for (size_t k = 0; k < 81; ++k) {  // each point stays in its cell
    int j = int(k % 9), i = int(k / 9);
    EXPECT_GE(jittered[k].x_m, -2e-3 + j * 4e-3 / 9 - 1e-15);
    EXPECT_LE(jittered[k].x_m, -2e-3 + (j + 1) * 4e-3 / 9 + 1e-15);
    EXPECT_LE(jittered[k].y_m, 2e-3 - i * 4e-3 / 9 + 1e-15);
  }
  eye.pupil_sampling = PupilSampling::kPoisson;
  std::vector<PupilPoint> poisson = PupilSamples(eye);
  EXPECT_GT(poisson.size(), 40u);
  EXPECT_EQ(PupilSamples(Eye(9, 0.0)).size(), 1u);
}

// The extent of the retinal image of a bright point at depth z.
double BlurDiameter(double z, double accommodation, const RetinaGrid& retina, int samples,
                    PupilShape shape = PupilShape::kSquare) {
  // A disk a little larger than one retinal sample, so every pupil ray lights one.
  double radius = 0.75 * retina.resolution_rad * z;
  SceneRadiance point = [&](const PupilPoint& u, double dx, double dy) {
    double x = u.x_m + dx * z, y = u.y_m + dy * z;
    return x * x + y * y <= radius * radius ? Rgb{1, 1, 1} : Rgb{0, 0, 0};
  };
  EyeModel eye = Eye(samples);
  eye.pupil_shape = shape;
  Image image = RetinaOfScene(point, retina, PupilSamples(eye), {accommodation, accommodation, accommodation});
  double lo = INFINITY, hi = -INFINITY;
  for (int j = 0; j < retina.cols; ++j)
    for (int i = 0; i < retina.rows; ++i)
      if (image.at(i, j, 0) > 0) lo = std::min(lo, retina.angle_x(j)), hi = std::max(hi, retina.angle_x(j));
  return hi - lo;
}

// The pupil grid of any sides: the cell centers (grid) or a point in each cell
// (jittered), row by row from the top, covering the square pupil evenly.
TEST(Retina, PupilPointsOfUnequalSidesLieEachInItsOwnCell) {
  for (const auto& [nx, ny] : {std::pair{4, 2}, std::pair{2, 5}, std::pair{3, 3}})
    for (PupilSampling sampling : {PupilSampling::kGrid, PupilSampling::kJittered}) {
      SCOPED_TRACE(std::to_string(nx) + " x " + std::to_string(ny) +
                   (sampling == PupilSampling::kGrid ? " grid" : " jittered"));
      EyeModel eye;
      eye.pupil_diameter_m = 4e-3;
      eye.pupil_samples_x = nx, eye.pupil_samples_y = ny;
      eye.pupil_sampling = sampling;
      const double a = eye.pupil_diameter_m;
      const std::vector<PupilPoint> points = PupilSamples(eye);
      ASSERT_EQ(points.size(), size_t(nx * ny));
      double mean_x = 0, mean_y = 0;
      for (int i = 0; i < ny; ++i)
        for (int j = 0; j < nx; ++j) {
          const PupilPoint& p = points[size_t(i * nx + j)];
          const double left = -a / 2 + j * a / nx, top = a / 2 - i * a / ny;
          if (sampling == PupilSampling::kGrid) {
            EXPECT_NEAR(p.x_m, left + 0.5 * a / nx, 1e-15) << "row " << i << ", column " << j;
            EXPECT_NEAR(p.y_m, top - 0.5 * a / ny, 1e-15) << "row " << i << ", column " << j;
          } else {
            EXPECT_TRUE(p.x_m >= left && p.x_m <= left + a / nx) << "row " << i << ", column " << j << ": x " << p.x_m;
            EXPECT_TRUE(p.y_m <= top && p.y_m >= top - a / ny) << "row " << i << ", column " << j << ": y " << p.y_m;
          }
          mean_x += p.x_m / (nx * ny), mean_y += p.y_m / (nx * ny);
        }
      if (sampling == PupilSampling::kGrid) {
        EXPECT_NEAR(mean_x, 0, 1e-15);
        EXPECT_NEAR(mean_y, 0, 1e-15);
      }
    }
}

TEST(Retina, PointBlurMatchesGeometricOptics) {
  // Three rows through the center: the odd pupil grid has a row at u_y = 0,
  // so the central row shows the blur's full width, a round pupil's as a square one's.
  RetinaGrid retina = MakeRetinaGrid(1.2 * kRadiansPerDegree, 0.015 * kRadiansPerDegree, 0.005 * kRadiansPerDegree);
  const int n = 41;
  const double pupil = 4e-3;
  for (PupilShape shape : {PupilShape::kSquare, PupilShape::kRound})
    for (double z : {0.4545, 1.0, 2.5})
      for (double accommodation : {0.0, 0.4, 1.3, 2.2}) {
        double expected = pupil * std::abs(1 / z - accommodation);  // rad, small angles
        double measured = BlurDiameter(z, accommodation, retina, n, shape);
        // Pupil samples span (n - 1)/n of the pupil; the disk adds up to 1.5 samples.
        EXPECT_NEAR(measured, expected * (n - 1) / n, 2 * retina.resolution_rad)
            << "z " << z << " m, accommodation " << accommodation << " D"
            << (shape == PupilShape::kRound ? ", round pupil" : ", square pupil");
      }
}

// A one-panel display with a checkerboard of one-pixel squares.
testing::OneLayer OneLayerDisplay(const std::string& depth) {
  testing::OneLayer d = testing::OneLayerDisplay(depth);
  for (int i = 0; i < 48; ++i)
    for (int j = 0; j < 64; ++j)
      for (int c = 0; c < 3; ++c)
        d.t[0].rgb[(size_t(i) * 64 + j) * 3 + c] = ((i / 2 + j / 3) % 2) ? 0.9f : 0.1f + 0.2f * c;
  return d;
}

TEST(Retina, LayerAtTheFocusDepthIsSharp) {
  testing::OneLayer d = OneLayerDisplay("1.0 D");
  const VirtualLayer& layer = d.system.layers[0];
  RetinaGrid retina = MakeRetinaGrid(10 * kRadiansPerDegree, 8 * kRadiansPerDegree, 0.03 * kRadiansPerDegree);
  Image image = RetinaOfDisplay(*d.model, d.t, retina, PupilSamples(d.system.eye), {1.0, 1.0, 1.0});
  const double w = d.model->weight(0)[0];
  for (int i = 0; i < retina.rows; i += 7)
    for (int j = 0; j < retina.cols; j += 5) {
      // With the eye focused on the layer every pupil ray reads the same pixel.
      int col = int(std::floor(std::tan(retina.angle_x(j)) / layer.tan_pitch_x + 32));
      int row = int(std::floor(24 - std::tan(retina.angle_y(i)) / layer.tan_pitch_y));
      if (col < 0 || col >= 64 || row < 0 || row >= 48) continue;
      int panel_col = layer.flip_x ? 63 - col : col;
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(image.at(i, j, c), w * d.t[0].rgb[(size_t(row) * 64 + panel_col) * 3 + c], 1e-6) << i << "," << j;
    }
}

TEST(Retina, OneLayerDisplayMatchesNaturalViewingOfThatPlane) {
  testing::OneLayer d = OneLayerDisplay("1.0 D");
  const VirtualLayer& layer = d.system.layers[0];
  const double w = d.model->weight(0)[0];
  // Natural viewing of the same pixels painted on a plane at 1 m, traced in meters.
  SceneRadiance plane = [&](const PupilPoint& u, double dx, double dy) {
    double x = u.x_m + dx * layer.depth_m, y = u.y_m + dy * layer.depth_m;
    int col = int(std::floor(x / layer.pitch_x_m + 32)), row = int(std::floor(24 - y / layer.pitch_y_m));
    if (col < 0 || col >= 64 || row < 0 || row >= 48) return Rgb{0, 0, 0};
    int panel_col = layer.flip_x ? 63 - col : col;
    const float* p = &d.t[0].rgb[(size_t(row) * 64 + panel_col) * 3];
    return Rgb{w * p[0], w * p[1], w * p[2]};
  };
  RetinaGrid retina = MakeRetinaGrid(6 * kRadiansPerDegree, 4 * kRadiansPerDegree, 0.05 * kRadiansPerDegree);
  std::vector<PupilPoint> pupil = PupilSamples(d.system.eye);
  for (double accommodation : {0.0, 0.6, 1.0, 1.9}) {
    std::array<double, 3> focus{accommodation, accommodation, accommodation};
    Image display = RetinaOfDisplay(*d.model, d.t, retina, pupil, focus);
    Image natural = RetinaOfScene(plane, retina, pupil, focus);
    for (size_t k = 0; k < display.pixels.size(); ++k)
      ASSERT_NEAR(display.pixels[k], natural.pixels[k], 1e-5) << "accommodation " << accommodation << ", sample " << k;
  }
}

// Natural viewing of the light field a one-layer display on the origin plane
// emits equals the display itself, for a random pattern, at every focus:
// under the default sampling and under bilinear, where each side reads as
// the other. Natural viewing read bilinearly against nearest layers does not.
TEST(Retina, OneLayerDisplayEqualsNaturalViewingOfItsLightFieldOnARandomPattern) {
  testing::OneLayer d = OneLayerDisplay("1.0 D");
  for (size_t i = 0; i < d.t[0].rgb.size(); ++i) d.t[0].rgb[i] = float((i * 2654435761u) % 1000) / 1000;
  RetinaGrid retina = MakeRetinaGrid(6 * kRadiansPerDegree, 4 * kRadiansPerDegree, 0.05 * kRadiansPerDegree);
  // Off the symmetric grid, so that no ray crosses the plane exactly on a pixel edge.
  retina.center_x_rad = 0.3183 * retina.resolution_rad, retina.center_y_rad = 0.2718 * retina.resolution_rad;
  RetinaGrid inner = MakeRetinaGrid(4 * kRadiansPerDegree, 3 * kRadiansPerDegree, 0.05 * kRadiansPerDegree);
  inner.center_x_rad = retina.center_x_rad, inner.center_y_rad = retina.center_y_rad;
  std::vector<PupilPoint> pupil = PupilSamples(d.system.eye);
  const LightFieldGeometry g = d.model->geometry();
  ASSERT_TRUE(Close(g.origin_z_m, d.system.layers[0].depth_m, 1e-12));
  DisplayModel bilinear(d.system, g, Sampling::kBilinear);
  const LightField nearest_lf = Synthesize(*d.model, d.t), bilinear_lf = Synthesize(bilinear, d.t);
  auto rms = [](const Image& a, const Image& b) {
    double s = 0;
    for (size_t k = 0; k < a.pixels.size(); ++k) s += double(a.pixels[k] - b.pixels[k]) * (a.pixels[k] - b.pixels[k]);
    return std::sqrt(s / a.pixels.size());
  };
  for (double accommodation : {0.0, 0.6, 1.0, 1.9}) {
    std::array<double, 3> focus{accommodation, accommodation, accommodation};
    Image display = RetinaOfDisplay(*d.model, d.t, retina, pupil, focus);
    Image natural = RetinaOfScene(LightFieldRadiance(nearest_lf), retina, pupil, focus);
    for (size_t k = 0; k < display.pixels.size(); ++k)
      ASSERT_NEAR(display.pixels[k], natural.pixels[k], 1e-5) << "accommodation " << accommodation << ", sample " << k;
    // Within half a pixel of the layer's edge bilinear layers blend toward 0
    // and the light field holds its edge pixel: compare where no ray gets there.
    Image display_bilinear = RetinaOfDisplay(bilinear, d.t, inner, pupil, focus);
    Image natural_bilinear = RetinaOfScene(LightFieldRadiance(bilinear_lf, Sampling::kBilinear), inner, pupil, focus);
    EXPECT_LT(rms(display_bilinear, natural_bilinear), 1e-5) << "bilinear, accommodation " << accommodation;
    if (accommodation == 1.0) {  // in focus, a pixel-held pattern against its bilinear blend
      EXPECT_GT(rms(display, RetinaOfScene(LightFieldRadiance(nearest_lf, Sampling::kBilinear), retina, pupil, focus)),
                0.05);
    }
  }
}

// The table-driven path (nearest, one focus, no rotation) and the general
// one (a rotation of 1e-12 rad; bilinear sampling; per-channel focus) agree
// where they should, on the four-layer hybrid with its mirrored layers, for
// the eye on the axis and for an eye moved and turned (elements/eye_pose.h).
TEST(Retina, FastAndGeneralPathsAgree) {
  DisplaySystem system = CompileJson(testing::ShrunkExample("paper_prototype.json", 40, 24, 3));
  DisplayModel fast(system, DisplayLightFieldGeometry(system));
  DisplaySystem turned = system;
  for (VirtualLayer& layer : turned.layers) layer.rotation_rad = 1e-12;
  DisplayModel general(turned, DisplayLightFieldGeometry(turned));
  Patterns t = fast.UniformPatterns(0);
  for (size_t k = 0; k < t.size(); ++k)
    for (size_t i = 0; i < t[k].rgb.size(); ++i) t[k].rgb[i] = 0.1f + 0.8f * float((i * 2654435761u + k) % 1000) / 1000;
  RetinaGrid retina = MakeRetinaGrid(system.fov_x_rad * 0.9, system.fov_y_rad * 0.9, system.fov_x_rad / 120);
  // Off the symmetric grid, so that no ray lands exactly on a pixel edge, where
  // a rotation of 1e-12 rad may pick the neighbour.
  retina.center_x_rad = 0.3183 * retina.resolution_rad, retina.center_y_rad = 0.2718 * retina.resolution_rad;
  EyeModel moved = system.eye;
  moved.pose.pupil_offset_m = {0.4e-3, -0.3e-3};
  moved.pose.gaze_rad = {0.3 * kRadiansPerDegree, -0.2 * kRadiansPerDegree};
  for (const EyeModel& eye : {system.eye, moved}) {
    std::vector<PupilPoint> pupil = PupilSamples(eye);
    // One focus, and a focus per channel (the fast path once per channel, the general path at once).
    for (std::array<double, 3> a : {std::array<double, 3>{0.3, 0.3, 0.3}, std::array<double, 3>{1.3, 1.3, 1.3},
                                    std::array<double, 3>{2.4, 2.4, 2.4}, std::array<double, 3>{1.0, 1.3, 1.9}}) {
      Image one = RetinaOfDisplay(fast, t, retina, pupil, a);
      Image two = RetinaOfDisplay(general, t, retina, pupil, a);
      double worst = 0;
      for (size_t k = 0; k < one.pixels.size(); ++k)
        worst = std::max(worst, double(std::abs(one.pixels[k] - two.pixels[k])));
      EXPECT_LT(worst, 1e-5) << "accommodation " << a[0] << " / " << a[1] << " / " << a[2]
                             << (&eye == &moved ? ", moved eye" : "");
    }
  }
}

TEST(Retina, MeanLuminanceDoesNotChangeWithAccommodation) {
  nlohmann::json scene = testing::ShrunkExample("paper_prototype.json", 120, 60, 3);
  DisplaySystem system = CompileJson(scene);
  DisplayModel model(system, DisplayLightFieldGeometry(system));
  Patterns t = model.UniformPatterns(0);
  for (size_t k = 0; k < t.size(); ++k)
    for (size_t p = 0; p < t[k].rgb.size(); ++p)
      t[k].rgb[p] = 0.3f + 0.6f * float(((p / 3) * (k + 3) * 2654435761u) % 1000) / 1000;
  // The central 8 x 4 degrees, well inside every layer's field at every focus.
  RetinaGrid retina = MakeRetinaGrid(8 * kRadiansPerDegree, 4 * kRadiansPerDegree, 0.05 * kRadiansPerDegree);
  std::vector<PupilPoint> pupil = PupilSamples(system.eye);
  auto mean = [&](double accommodation) {
    Image image = RetinaOfDisplay(model, t, retina, pupil, {accommodation, accommodation, accommodation});
    double s = 0;
    for (float v : image.pixels) s += v;
    return s / image.pixels.size();
  };
  double reference = mean(1.3);
  for (double accommodation : {0.0, 0.4, 1.0, 2.2, 2.6}) EXPECT_TRUE(Close(mean(accommodation), reference, 0.01));
}

TEST(Retina, ChromaticDefocusShiftsEachChannelsFocus) {
  testing::OneLayer d = OneLayerDisplay("1.0 D");
  d.system.eye.chromatic_defocus_diopters = {0.5, 0.0, -0.5};
  RetinaGrid retina = MakeRetinaGrid(6 * kRadiansPerDegree, 4 * kRadiansPerDegree, 0.05 * kRadiansPerDegree);
  std::vector<PupilPoint> pupil = PupilSamples(d.system.eye);
  std::array<double, 3> focus = ChannelAccommodation(d.system.eye, 1.0);
  Image mixed = RetinaOfDisplay(*d.model, d.t, retina, pupil, focus);
  // Channel R focused at 1.5 D equals an image focused there for all channels; G at 1 D, B at 0.5 D likewise.
  Image red = RetinaOfDisplay(*d.model, d.t, retina, pupil, {1.5, 1.5, 1.5});
  Image green = RetinaOfDisplay(*d.model, d.t, retina, pupil, {1.0, 1.0, 1.0});
  Image blue = RetinaOfDisplay(*d.model, d.t, retina, pupil, {0.5, 0.5, 0.5});
  // The per-channel path sums the 81 pupil points in double, the one-focus
  // fast path in float: they agree to float rounding of such a sum (81 x 2^-24).
  for (size_t p = 0; p < mixed.pixels.size() / 3; ++p) {
    ASSERT_NEAR(mixed.pixels[p * 3], red.pixels[p * 3], 5e-6);
    ASSERT_NEAR(mixed.pixels[p * 3 + 1], green.pixels[p * 3 + 1], 5e-6);
    ASSERT_NEAR(mixed.pixels[p * 3 + 2], blue.pixels[p * 3 + 2], 5e-6);
  }
}

// The display's paths read each layer where the aberrated ray meets it: pure
// defocus c4 on the pupil rays is the ideal eye at D_a + 16 sqrt(3) c4 / p^2,
// on the fast path (one focus) and on the per-channel path.
TEST(Retina, WavefrontDefocusOnADisplayIsTheIdealEyeAtTheConvertedPower) {
  testing::OneLayer d = OneLayerDisplay("1.0 D");
  EyeModel aberrated = d.system.eye;
  aberrated.wavefront = {{0, 0, 0, 0, 0.25e-6}, 4e-3, ""};
  const double power = 16 * std::sqrt(3.0) * 0.25 / 16;  // 0.43301 D
  RetinaGrid retina = MakeRetinaGrid(6 * kRadiansPerDegree, 4 * kRadiansPerDegree, 0.05 * kRadiansPerDegree);
  const std::vector<PupilPoint> ideal = PupilSamples(d.system.eye), pupil = PupilSamples(aberrated);
  for (std::array<double, 3> focus : {std::array<double, 3>{0.6, 0.6, 0.6}, std::array<double, 3>{0.6, 0.8, 1.0}}) {
    Image seen = RetinaOfDisplay(*d.model, d.t, retina, pupil, focus);
    Image expected =
        RetinaOfDisplay(*d.model, d.t, retina, ideal, {focus[0] + power, focus[1] + power, focus[2] + power});
    size_t differ = 0;
    for (size_t k = 0; k < seen.pixels.size(); ++k) differ += std::abs(seen.pixels[k] - expected.pixels[k]) > 1e-5;
    // A ray a rounding error from a pixel edge may read its neighbour.
    EXPECT_LE(differ, seen.pixels.size() / 1000) << focus[0] << " D";
  }
  Image blurred = RetinaOfDisplay(*d.model, d.t, retina, pupil, {1.0, 1.0, 1.0});
  Image sharp = RetinaOfDisplay(*d.model, d.t, retina, ideal, {1.0, 1.0, 1.0});
  EXPECT_NE(blurred.pixels, sharp.pixels);
}

}  // namespace
}  // namespace layerlab
