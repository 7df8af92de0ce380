// Rays into a target scene (planes and meshes) with Embree: the one place
// that turns a hit into a color, shared by the light-field renderer and by
// natural viewing on the retina.
//
// Planes are unlit: the value is the texture at the exact hit point,
// computed in double precision, so a grating is exact. Meshes are
// Lambertian: texture * (ambient + (1 - ambient) max(0, n . to_light)), n the
// geometric normal turned toward the viewer; their depth is refined in double
// precision against the hit triangle's plane.
#pragma once

#include <array>
#include <span>
#include <vector>

#include "layerlab/targets/embree_scene.h"
#include "layerlab/targets/target_scene.h"

namespace layerlab {

struct TracedSample {
  Rgb color;
  double z;  // eye-space depth of the hit, or +inf
};

class TargetTracer {
 public:
  explicit TargetTracer(const TargetScene& target);  // builds the Embree scene

  // The ray from the pupil-plane point (vx, vy, 0) along (dx, dy, 1): it
  // passes (vx + dx z, vy + dy z, z) at depth z. Safe from many threads.
  TracedSample TraceDirection(double vx, double vy, double dx, double dy) const;
  // The ray from (vx, vy, 0) through (x, y) on the target's origin plane.
  TracedSample Trace(double vx, double vy, double x, double y) const {
    const double z_lf = target_.geometry.origin_z_m;
    return TraceDirection(vx, vy, (x - vx) / z_lf, (y - vy) / z_lf);
  }

  // The same in two steps, for many rays at once: the closest hits of the rays from (vx, vy, 0) along
  // (dx, dy, 1) for each (dx, dy) in `slopes`, traced as one coherent stream; then what a hit shows.
  void IntersectFrom(double vx, double vy, std::span<const std::array<double, 2>> slopes, std::span<RayHit> hits) const;
  TracedSample Shade(const RayHit& hit, double vx, double vy, double dx, double dy) const;
  // The eye-space depth of a hit (+inf for a miss), without its color.
  double Depth(const RayHit& hit, double vx, double vy, double dx, double dy) const;
  // The plane a hit lies on, as an index into the scene's planes; -1 for a mesh or a miss.
  int PlaneOf(const RayHit& hit) const {
    return hit.hit() && surfaces_[hit.geom_id].is_plane ? static_cast<int>(surfaces_[hit.geom_id].index) : -1;
  }

 private:
  // What an Embree geometry id stands for.
  struct Surface {
    bool is_plane = true;
    size_t index = 0;  // into target.planes or target.meshes
  };
  void Register(unsigned id, Surface surface);

  const TargetScene& target_;
  EmbreeScene scene_;
  std::vector<Surface> surfaces_;
};

}  // namespace layerlab
