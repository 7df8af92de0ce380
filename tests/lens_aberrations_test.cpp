// What `info` reports of a real lens (systems/lens_aberrations.h), against the
// same quantities computed here from the independent tracer (lens_brute_force.h)
// by their definitions: the chief ray's landing, its red-blue split, and the
// focus of rays through the pupil's edge found by bisection.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "layerlab/lenses/glass_catalog.h"
#include "layerlab/systems/compile.h"
#include "layerlab/systems/lens_aberrations.h"
#include "layerlab/systems/scene.h"
#include "lens_brute_force.h"

namespace layerlab {
namespace {

using lens_testing::BruteSurface;
using lens_testing::BruteTrace;

constexpr double kRadius = 38.6e-3, kThickness = 4.1e-3, kEyeRelief = 10e-3;

const DisplaySystem& Singlet() {
  static const DisplaySystem system =
      Compile(LoadScene(std::string(LAYERLAB_SOURCE_DIR) + "/examples/paper_prototype_la1608.json"));
  return system;
}

// Where the ray from pupil point (p_x, p_y) toward tan (u_x, u_y) meets the panel plane of `l`, in channel c.
Eigen::Vector3d Landing(const VirtualLayer& l, int c, double p_x, double p_y, double u_x, double u_y) {
  const double n = lenses::FindMaterial("N-BK7").Index(Singlet().eye.channel_wavelengths_m[c]);
  std::vector<BruteSurface> lens(2);
  lens[0].vertex_z = kEyeRelief, lens[0].c = 1 / kRadius, lens[0].n_after = n;
  lens[1].vertex_z = kEyeRelief + kThickness, lens[1].n_after = 1;
  const auto r = BruteTrace(lens, 1.0, Eigen::Vector3d(p_x, p_y, 0), Eigen::Vector3d(u_x, u_y, 1).normalized());
  EXPECT_TRUE(r.ok);
  return r.point + r.direction * ((l.position_m - r.point.z()) / r.direction.z());
}

// The direction u_x from pupil point (p, 0) whose green ray lands at x = target (bisection).
double AimX(const VirtualLayer& l, double p, double target) {
  double lo = -0.6, hi = 0.6;
  const bool rising = Landing(l, 1, p, 0, hi, 0).x() > Landing(l, 1, p, 0, lo, 0).x();
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    ((Landing(l, 1, p, 0, mid, 0).x() < target) == rising ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(LensAberrations, DistortionAndLateralColourAreTheChiefRaysLanding) {
  for (const VirtualLayer& l : Singlet().layers) {
    const LayerAberrations a = MeasureAberrations(l, Singlet().eye.pupil_diameter_m);
    const double u = l.eye_from_layer_tan_x + 0.5 * l.cols * l.tan_pitch_x;
    EXPECT_NEAR(a.field_edge_deg, std::atan(u) * 180 / std::numbers::pi, 1e-12);
    const double red = Landing(l, 0, 0, 0, u, 0).x() / l.transfer.b,
                 green = Landing(l, 1, 0, 0, u, 0).x() / l.transfer.b,
                 blue = Landing(l, 2, 0, 0, u, 0).x() / l.transfer.b;
    EXPECT_NEAR(a.distortion_percent, 100 * (green - u) / u, 1e-6) << l.name;
    EXPECT_NEAR(a.lateral_color_px, (red - blue) / l.tan_pitch_x, 1e-6) << l.name;
    EXPECT_LT(a.distortion_percent, -2.5) << l.name << ": a magnifier's pincushion";
    EXPECT_GT(a.lateral_color_px, 0.3) << l.name;
  }
}

TEST(LensAberrations, TheTangentialFocusIsWhereTheEdgeRaysSeemToCome) {
  const double r = 0.5 * Singlet().eye.pupil_diameter_m;
  for (const VirtualLayer& l : Singlet().layers) {
    const LayerAberrations a = MeasureAberrations(l, Singlet().eye.pupil_diameter_m);
    const double u = l.eye_from_layer_tan_x + 0.5 * l.cols * l.tan_pitch_x;
    const double target = Landing(l, 1, 0, 0, u, 0).x();
    // A point at depth 1/D is seen from pupil point p along u0 - D p.
    const double focus = -(AimX(l, r, target) - AimX(l, -r, target)) / (2 * r);
    EXPECT_NEAR(a.tangential_diopters, focus, 1e-6) << l.name;
    const double centre =
        -(AimX(l, r, Landing(l, 1, 0, 0, 0, 0).x()) - AimX(l, -r, Landing(l, 1, 0, 0, 0, 0).x())) / (2 * r);
    EXPECT_NEAR(centre, l.diopters, 0.1) << l.name << ": on axis the focus is the layer's, up to spherical aberration";
  }
}

}  // namespace
}  // namespace layerlab
