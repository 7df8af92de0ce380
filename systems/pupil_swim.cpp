#include "layerlab/systems/pupil_swim.h"

#include <algorithm>
#include <cmath>

#include "layerlab/framework/units.h"

namespace layerlab {
namespace {
constexpr double kArcmin = 60 * kDegreesPerRadian;  // arcmin per radian
}  // namespace

std::optional<std::array<double, 2>> ApparentDirection(const LayerRayMap& map, int channel,
                                                       const std::array<double, 2>& p, const std::array<double, 2>& U) {
  std::array<double, 2> u = {U[0] - map.diopters() * p[0], U[1] - map.diopters() * p[1]};
  const double h = 1e-7;  // tan: a central difference's truncation (h^2 U''') far below the 1e-13 asked
  for (int step = 0; step < 30; ++step) {
    const auto at = map.Trace(channel, p[0], p[1], u[0], u[1]);
    if (!at) return std::nullopt;
    const std::array<double, 2> r = {(*at)[0] - U[0], (*at)[1] - U[1]};
    if (std::abs(r[0]) < 1e-13 && std::abs(r[1]) < 1e-13) return u;
    double J[2][2];
    for (int a = 0; a < 2; ++a) {
      std::array<double, 2> plus = u, minus = u;
      plus[a] += h, minus[a] -= h;
      const auto hi = map.Trace(channel, p[0], p[1], plus[0], plus[1]);
      const auto lo = map.Trace(channel, p[0], p[1], minus[0], minus[1]);
      if (!hi || !lo) return std::nullopt;
      J[0][a] = ((*hi)[0] - (*lo)[0]) / (2 * h), J[1][a] = ((*hi)[1] - (*lo)[1]) / (2 * h);
    }
    const double det = J[0][0] * J[1][1] - J[0][1] * J[1][0];
    if (!(std::abs(det) > 1e-12)) return std::nullopt;
    u[0] -= (J[1][1] * r[0] - J[0][1] * r[1]) / det;
    u[1] -= (-J[1][0] * r[0] + J[0][0] * r[1]) / det;
  }
  return std::nullopt;
}

std::vector<LayerSwim> MeasurePupilSwim(const DisplaySystem& system, double pupil_half_range_m, int steps) {
  const int channel = 1;
  std::vector<LayerSwim> out;
  for (const VirtualLayer& l : system.layers) {
    LayerSwim swim;
    swim.layer = l.name;
    swim.real_optics = l.ray_map != nullptr;
    const std::array<double, 2> centre = {l.eye_from_layer_tan_x, l.eye_from_layer_tan_y};
    const std::array<double, 2> half = {0.5 * l.cols * l.tan_pitch_x, 0.5 * l.rows * l.tan_pitch_y};
    std::vector<std::array<double, 2>> fields, pupils;
    for (double f : {-0.9, -0.5, 0.0, 0.5, 0.9}) {
      fields.push_back({centre[0] + f * half[0], centre[1]});
      if (f != 0) fields.push_back({centre[0], centre[1] + f * half[1]});
    }
    for (int k = -steps; k <= steps; ++k) {
      if (k == 0) continue;
      const double p = pupil_half_range_m * k / steps;
      pupils.push_back({p, 0}), pupils.push_back({0, p});
    }
    for (const std::array<double, 2>& U : fields) {
      std::optional<std::array<double, 2>> u0 = std::array<double, 2>{U[0], U[1]};
      if (swim.real_optics) u0 = ApparentDirection(l.ray_map->exact(), channel, {0, 0}, U);
      for (const std::array<double, 2>& p : pupils) {
        SwimSample s{U, p, {0, 0}};
        if (swim.real_optics) {
          const auto u = u0 ? ApparentDirection(l.ray_map->exact(), channel, p, U) : std::nullopt;
          for (int a = 0; a < 2; ++a)
            s.swim[a] = u ? std::atan((*u)[a]) - std::atan((*u0)[a] - l.diopters * p[a]) : NAN;
        }
        const double size = std::hypot(s.swim[0], s.swim[1]);
        if (std::isfinite(size)) {
          swim.max_arcmin = std::max(swim.max_arcmin, size * kArcmin);
          swim.rate_arcmin_per_mm = std::max(swim.rate_arcmin_per_mm, size * kArcmin / (std::hypot(p[0], p[1]) * 1e3));
        }
        swim.samples.push_back(s);
      }
    }
    out.push_back(std::move(swim));
  }
  return out;
}

}  // namespace layerlab
