#include "layerlab/systems/lens_aberrations.h"

#include <cmath>
#include <numbers>

#include "layerlab/framework/error.h"
#include "layerlab/framework/units.h"
#include "layerlab/systems/layer_ray_map.h"

namespace layerlab {
namespace {

constexpr double kArcminPerRadian = 60 * 180 / std::numbers::pi;

std::array<double, 2> Traced(const LayerRayMap& map, int c, double p_x, double p_y, double u_x, double u_y,
                             const std::string& layer) {
  const auto U = map.Trace(c, p_x, p_y, u_x, u_y);
  if (!U)
    throw Error("layer \"" + layer + "\": the ray from pupil point (" + FormatFixed(p_x * 1e3, 2) + ", " +
                FormatFixed(p_y * 1e3, 2) + ") mm toward tan (" + FormatFixed(u_x, 4) + ", " + FormatFixed(u_y, 4) +
                ") is lost in the lens (vignetted or totally reflected): its field edge cannot be measured");
  return *U;
}

// The direction from pupil point p whose green ray lands at `target` on axis `a`
// (the other direction component held at `other`), by Newton's method.
double AimAt(const LayerRayMap& map, double p_x, double p_y, int a, double target, double start, double other,
             const std::string& layer) {
  double u = start;
  for (int i = 0; i < 50; ++i) {
    auto at = [&](double v) {
      return a == 0 ? Traced(map, 1, p_x, p_y, v, other, layer)[0] : Traced(map, 1, p_x, p_y, other, v, layer)[1];
    };
    const double h = 1e-7, f = at(u) - target, slope = (at(u + h) - at(u - h)) / (2 * h);
    const double step = f / slope;
    u -= step;
    if (std::abs(step) < 1e-15) break;
  }
  return u;
}

// The depth (D) the rays from the panel point that the chief ray (0, u) reaches
// seem to come from, through pupil points +-r along x (tangential) and y (sagittal).
std::array<double, 2> FocusAt(const LayerRayMap& map, double u, double r, const std::string& layer) {
  const std::array<double, 2> point = Traced(map, 1, 0, 0, u, 0, layer);
  const double t_plus = AimAt(map, r, 0, 0, point[0], u, 0, layer);
  const double t_minus = AimAt(map, -r, 0, 0, point[0], u, 0, layer);
  const double s_plus = AimAt(map, 0, r, 1, point[1], 0, u, layer);
  const double s_minus = AimAt(map, 0, -r, 1, point[1], 0, u, layer);
  // A point at depth 1/D is seen from pupil point p along u0 - D p.
  return {-(t_plus - t_minus) / (2 * r), -(s_plus - s_minus) / (2 * r)};
}

}  // namespace

LayerAberrations MeasureAberrations(const VirtualLayer& l, double pupil_diameter_m) {
  if (!l.ray_map) throw Error("layer \"" + l.name + "\" has no ray map (no real lens on its path, no tilt)");
  const LayerRayMap& map = l.ray_map->exact();
  LayerAberrations out;
  const double u = l.eye_from_layer_tan_x + 0.5 * l.cols * l.tan_pitch_x;
  out.field_edge_deg = std::atan(u) * kDegreesPerRadian;
  const std::array<double, 2> red = Traced(map, 0, 0, 0, u, 0, l.name), green = Traced(map, 1, 0, 0, u, 0, l.name),
                              blue = Traced(map, 2, 0, 0, u, 0, l.name);
  out.distortion_percent = 100 * (green[0] - u) / u;
  out.lateral_color_px = (red[0] - blue[0]) / l.tan_pitch_x;
  out.lateral_color_arcmin = (std::atan(red[0]) - std::atan(blue[0])) * kArcminPerRadian;
  const double r = std::max(0.5 * pupil_diameter_m, 1e-4);  // a pinhole eye: the paraxial focus
  const std::array<double, 2> edge = FocusAt(map, u, r, l.name), centre = FocusAt(map, 0, r, l.name);
  out.tangential_diopters = edge[0], out.sagittal_diopters = edge[1];
  out.field_curvature_diopters = 0.5 * (edge[0] + edge[1]) - 0.5 * (centre[0] + centre[1]);
  out.map_bound_px = l.ray_map->bound_pixels();
  return out;
}

}  // namespace layerlab
