// Natural viewing of a light-field target (retina/lightfield_radiance.h)
// against the plane it was made from, and against hand-derived interpolation.
#include <cmath>
#include <numbers>

#include "layerlab/framework/units.h"
#include "layerlab/retina/lightfield_radiance.h"
#include "layerlab/retina/retina.h"
#include "layerlab/targets/plane_lightfield.h"
#include "layerlab/targets/texture.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

// 13 x 13 views.
LightFieldGeometry Geometry(int cols = 200, int rows = 120) { return testing::WindowGeometry(cols, rows, 13); }

std::unique_ptr<Texture> Grating(double cycles_per_meter) {
  GratingSpec spec;
  spec.cycles_per_meter = cycles_per_meter;
  spec.phase_rad = 0.3;
  return MakeGratingTexture(spec);
}

TEST(LightFieldRadiance, PlaneOnTheOriginPlaneReadsItsPixelFromAnyPupilPoint) {
  const LightFieldGeometry g = Geometry();
  auto texture = Grating(40);
  LightField lf = RenderPlaneLightField(g, g.origin_z_m, *texture);
  SceneRadiance radiance = LightFieldRadiance(lf);
  // Pupil points between views and off the view grid's centers; rays through pixel centers.
  for (PupilPoint u : {PupilPoint{0.0011, -0.0007}, PupilPoint{-0.0019, 0.0016}, PupilPoint{0, 0}})
    for (int j : {3, 77, 150})
      for (int i : {5, 60}) {
        double x = g.pixel_x(j), y = g.pixel_y(i);
        Rgb value = radiance(u, (x - u.x_m) / g.origin_z_m, (y - u.y_m) / g.origin_z_m);
        Rgb expected = texture->Evaluate(x, y);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(value[c], expected[c], 2e-6) << "pixel " << i << "," << j;
      }
}

TEST(LightFieldRadiance, BetweenTwoViewsItAveragesThem) {
  const LightFieldGeometry g = Geometry();
  auto texture = Grating(60);
  LightField lf = RenderPlaneLightField(g, 0.5, *texture);  // 2 D: parallax against the 1.3 D origin
  SceneRadiance radiance = LightFieldRadiance(lf);
  const int i = 40, j = 90, r = 6;
  const double x = g.pixel_x(j), y = g.pixel_y(i);
  // Halfway between view columns 4 and 5 of view row 6 (whose v_y is 0).
  PupilPoint u{0.5 * (g.view_x(4) + g.view_x(5)), g.view_y(r)};
  Rgb value = radiance(u, (x - u.x_m) / g.origin_z_m, (y - u.y_m) / g.origin_z_m);
  const size_t p = (static_cast<size_t>(i) * g.cols + j) * 3;
  double expected = 0.5 * (lf.view(g.view_index(r, 4))[p] + lf.view(g.view_index(r, 5))[p]);
  EXPECT_NEAR(value[0], expected, 1e-6);
  EXPECT_GT(std::abs(lf.view(g.view_index(r, 4))[p] - lf.view(g.view_index(r, 5))[p]), 0.01)  // the views differ
      << "the test needs parallax between the two views";
}

// Between two pixel centers of one view: nearest (the default, as the layers
// are read) holds the pixel containing the crossing, bilinear blends the two.
TEST(LightFieldRadiance, NearestHoldsThePixelBilinearBlends) {
  const LightFieldGeometry g = Geometry();
  LightField lf = RenderPlaneLightField(g, g.origin_z_m, *Grating(60));
  const int i = 30, j = 120, r = 6, c = 6;  // the central view: v = (0, 0)
  const PupilPoint u{g.view_x(c), g.view_y(r)};
  const size_t here = (static_cast<size_t>(i) * g.cols + j) * 3, right = here + 3;
  const float* view = lf.view(g.view_index(r, c));
  ASSERT_GT(std::abs(view[here] - view[right]), 0.01) << "the test needs neighbours that differ";
  const double pixel = g.window_width_m / g.cols, y = g.pixel_y(i);
  for (double fraction : {0.3, 0.7}) {
    const double x = g.pixel_x(j) + fraction * pixel;  // crossing the origin plane here
    const double dx = (x - u.x_m) / g.origin_z_m, dy = (y - u.y_m) / g.origin_z_m;
    // Pixel j spans [center - pitch/2, center + pitch/2): 0.3 is still in it, 0.7 in j + 1.
    EXPECT_NEAR(LightFieldRadiance(lf)(u, dx, dy)[0], fraction < 0.5 ? view[here] : view[right], 1e-7);
    EXPECT_NEAR(LightFieldRadiance(lf, Sampling::kBilinear)(u, dx, dy)[0],
                (1 - fraction) * view[here] + fraction * view[right], 1e-6);
  }
}

TEST(LightFieldRadiance, OutsideTheWindowIsDark) {
  const LightFieldGeometry g = Geometry(20, 10);
  LightField lf = RenderPlaneLightField(g, g.origin_z_m, *MakeConstantTexture({1, 1, 1}));
  SceneRadiance radiance = LightFieldRadiance(lf);
  Rgb outside = radiance({0, 0}, std::tan(5.5 * kRadiansPerDegree), 0);
  Rgb inside = radiance({0, 0}, std::tan(4.5 * kRadiansPerDegree), 0);
  EXPECT_EQ(outside[0], 0.0);
  EXPECT_NEAR(inside[0], 1.0, 1e-6);
}

// Retinal images of natural viewing: through the light field of a plane, and
// of the plane itself (the ray meets it at u + d z), at focus and out of focus.
TEST(LightFieldRadiance, RetinaMatchesTheAnalyticPlaneAtEveryFocus) {
  const LightFieldGeometry g = Geometry(400, 60);
  const double z = 1 / 1.0;
  auto texture = Grating(1.0 / (z * kRadiansPerDegree));  // 1 cpd at the line of sight
  LightField lf = RenderPlaneLightField(g, z, *texture);
  SceneRadiance from_lf = LightFieldRadiance(lf, Sampling::kBilinear);
  SceneRadiance plane = [&](const PupilPoint& u, double dx, double dy) {
    return texture->Evaluate(u.x_m + dx * z, u.y_m + dy * z);
  };
  EyeModel eye;
  eye.pupil_samples_x = eye.pupil_samples_y = 9;
  const std::vector<PupilPoint> pupil = PupilSamples(eye);
  RetinaGrid grid = MakeRetinaGrid(6 * kRadiansPerDegree, 1 * kRadiansPerDegree, 0.02 * kRadiansPerDegree);
  for (double focus : {0.4, 1.0, 1.6}) {
    const std::array<double, 3> a{focus, focus, focus};
    Image seen = RetinaOfScene(from_lf, grid, pupil, a), expected = RetinaOfScene(plane, grid, pupil, a);
    double worst = 0;
    for (size_t k = 0; k < seen.pixels.size(); ++k)
      worst = std::max(worst, double(std::abs(seen.pixels[k] - expected.pixels[k])));
    // Bilinear interpolation of a 1 cpd grating sampled at ~0.025 deg: error (pi f h)^2 / 2 of the amplitude.
    EXPECT_LT(worst, 2e-3) << "focus " << focus << " D";
  }
}

// The image-wise path (RetinaOfLightField, what RetinaOfScene takes for a
// light field) against the radiance called per ray and summed in double:
// a texture varying along both axes, a plane off the origin plane
// (parallax), a retina wider than the window (rays that miss it), pupil
// points between views and off the grid (jittered), both sampling rules,
// foci on and off the plane, a chromatic focus per channel, and an eye with
// a wavefront aberration (coma and astigmatism: each pupil ray deviated by its slope).
TEST(LightFieldRadiance, ImageWiseRetinaIsTheRayByRayRetina) {
  const LightFieldGeometry g = Geometry(160, 90);
  auto texture = MakeNoiseTexture(20, 400, 24, 7, 0.6, 0.5);  // values in [0.2, 0.8]
  LightField lf = RenderPlaneLightField(g, 1 / 1.9, *texture);
  EyeModel eye;
  eye.pupil_samples_x = eye.pupil_samples_y = 9;
  for (int variant = 0; variant < 3; ++variant) {
    eye.pupil_sampling = variant == 1 ? PupilSampling::kJittered : PupilSampling::kGrid;
    if (variant == 2) eye.wavefront = {{0, 0, 0, 0.3e-6, 0, 0, 0, 0.4e-6, -0.5e-6}, 5e-3, ""};
    const std::vector<PupilPoint> pupil = PupilSamples(eye);
    RetinaGrid grid = MakeRetinaGrid(12 * kRadiansPerDegree, 7 * kRadiansPerDegree,
                                     0.07 * kRadiansPerDegree);  // the window is 10 x 6 deg
    grid.center_x_rad = 0.013 * kRadiansPerDegree;
    for (Sampling pixels : {Sampling::kNearest, Sampling::kBilinear})
      for (std::array<double, 3> focus :
           {std::array<double, 3>{1.3, 1.3, 1.3}, std::array<double, 3>{0.4, 0.4, 0.4},
            std::array<double, 3>{1.9, 1.9, 1.9}, std::array<double, 3>{1.1, 1.2, 1.35}}) {
        const SceneRadiance rays = LightFieldRadiance(lf, pixels);
        const Image fast = RetinaOfLightField(lf, pixels, grid, pupil, focus);
        const Image slow = RetinaOfSceneRayByRay(rays, grid, pupil, focus);
        const Image dispatched = RetinaOfScene(rays, grid, pupil, focus);
        ASSERT_EQ(fast.pixels.size(), slow.pixels.size());
        EXPECT_EQ(fast.pixels, dispatched.pixels);
        double worst = 0;
        size_t zeros = 0, partial = 0;
        for (size_t k = 0; k < fast.pixels.size(); ++k) {
          const double a = fast.pixels[k], b = slow.pixels[k];
          zeros += b == 0;
          partial += b > 0 && b < 0.15;  // rays of some pupil points miss the window
          if (b == 0)
            EXPECT_EQ(a, 0.0) << k;
          else
            worst = std::max(worst, std::abs(a - b) / b);
        }
        EXPECT_LT(worst, 1e-5) << "focus " << focus[0] << " D, "
                               << (pixels == Sampling::kNearest ? "nearest" : "bilinear");
        EXPECT_GT(zeros, 0u);
        EXPECT_GT(partial, 0u);
      }
  }
}

}  // namespace
}  // namespace layerlab
