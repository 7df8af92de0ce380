// A plane's plane-wave texture (texture.h PlaneWaves) at the hits of many
// views' rays through the same origin-plane points. The ray from pupil point
// v through origin-plane point x (depth z_lf) meets the plane at depth z,
// centred on c, at
//   s = v (1 - z / z_lf) + x z / z_lf - c,
// so each wave's phase is a part of the view, P = k.(v (1 - z / z_lf) - c) +
// phase, plus a part of the point, Q = (z / z_lf) k.x, and
//   cos(P + Q) = cos P cos Q - sin P sin Q.
// A point's cos Q and sin Q, computed once, serve every view: two products a
// wave where a direct evaluation takes a cosine.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "layerlab/targets/texture.h"

namespace layerlab {

class PlaneWaveTable {
 public:
  // `waves` must outlive the table.
  PlaneWaveTable(const PlaneWaves& waves, double plane_depth_m, std::array<double, 2> plane_center_m,
                 double origin_depth_m);

  // The origin-plane points (m) whose rays will be shaded.
  void SetPoints(std::span<const std::array<double, 2>> points_m);

  // A view's phases: cos P of every wave, then sin P.
  using ViewPhases = std::vector<double>;
  void PhasesOfView(double vx_m, double vy_m, ViewPhases* phases) const;

  // The texture's value where the ray from the view through point i meets the plane.
  double Value(size_t i, const ViewPhases& phases) const;

 private:
  const PlaneWaves& waves_;
  double scale_;                    // z / z_lf
  std::array<double, 2> center_m_;  // the plane's centre, m
  std::vector<double> point_;       // per point: cos Q of every wave, then sin Q
};

}  // namespace layerlab
