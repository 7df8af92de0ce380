// Pupil swim: how a still point of a layer's image seems to move as the
// pupil moves, beyond the parallax of a point at the layer's depth.
//
// From pupil point p (m, on the eye plane) the point U of a layer (tan-angle
// on its paraxial grid, systems/layer_ray_map.h) is seen along the direction
// u where the layer's ray map sends (p, u) to U. Through ideal optics the map
// is U = D p + u, so u(p) = U - D p: the point moves exactly as a real point
// at the layer's depth 1/D, and its swim
//   s(p) = u(p) - (u(0) - D p)
// is 0 (taken as angles: atan u(p) - atan(u(0) - D p)). Behind a real lens
// the map's aberrations make s(p) the apparent motion the wearer sees when
// the eye moves.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/systems/display_system.h"
#include "layerlab/systems/layer_ray_map.h"

namespace layerlab {

// The direction u with map.Trace(channel, p, u) = U, by Newton steps on the
// exact trace from u = U - D p (finite-difference Jacobian), to 1e-13 in
// tan; nullopt when a ray is lost on the way or the steps do not converge.
std::optional<std::array<double, 2>> ApparentDirection(const LayerRayMap& map, int channel,
                                                       const std::array<double, 2>& p, const std::array<double, 2>& U);

struct SwimSample {
  std::array<double, 2> field_tan{};  // U, the layer point
  std::array<double, 2> pupil_m{};    // p
  std::array<double, 2> swim{};       // s(p), rad; NaN where a ray is lost
};

struct LayerSwim {
  std::string layer;
  bool real_optics = false;  // behind a real lens or tilted (a ray map); otherwise every swim is 0
  std::vector<SwimSample> samples;
  double max_arcmin = 0;          // the largest |s| over the samples, arcmin
  double rate_arcmin_per_mm = 0;  // the largest |s(p)| / |p|, arcmin per mm of pupil motion
};

// Each layer's swim for the design channel (green) at the field points
// U = centre + f (half field) for f in {-0.9, -0.5, 0, 0.5, 0.9} along x and y,
// from pupil points on the x and y axes within pupil_half_range_m in `steps`
// steps each side.
std::vector<LayerSwim> MeasurePupilSwim(const DisplaySystem& system, double pupil_half_range_m, int steps);

}  // namespace layerlab
