// A rotationally symmetric refracting surface in its own frame: vertex at the
// origin, axis +z (the direction light travels), sag z(r) with r^2 = x^2 + y^2:
//   z(r) = c r^2 / (1 + sqrt(1 - (1 + k) c^2 r^2)) + A4 r^4 + A6 r^6 + ...
// c the curvature (1/R; 0 is a plane), k the conic constant (0 sphere, -1
// paraboloid), A4, A6, ... the even-asphere terms (units m^-3, m^-5, ...).
//
// Fresnel: with a groove pitch p > 0 the profile above is folded onto a flat
// substrate in annular zones r in [j p, (j + 1) p): the surface there is
// z(r) - z(j p), so every zone starts at z = 0 and keeps the slope, and so
// the normal, of the underlying profile. The groove walls (the steps at
// r = j p) are not modelled: the hit is sought zone by zone (the face of the
// zone where the ray crosses the substrate plane, then of the zone that hit
// lands in, ...); a ray whose search does not settle on a face inside its own
// zone would reach it through a wall and is reported (HitStatus::kGrooveWall),
// never bent. The search assumes faces whose depth changes monotonically.
//
// Intersections are exact in double: analytic for the conic, Newton's method
// from the conic (or vertex-plane) point for an asphere, converged to 1e-15
// of the lengths involved or reported as failed, never a wrong point. An
// asphere's hit is checked for an earlier crossing (a grazing ray can pass
// through a bump before the point Newton finds) at 32 points along the ray
// from its origin, and bisected to the first one found; a crossing pair
// narrower than 1/32 of the path is not seen.
#pragma once

#include <limits>
#include <vector>

#include <Eigen/Core>

namespace layerlab::lenses {

struct SurfaceShape {
  double curvature_per_m = 0.0;      // c = 1/R
  double conic = 0.0;                // k
  std::vector<double> even_asphere;  // A4, A6, A8, ...: the coefficients of r^4, r^6, r^8, ...
  double fresnel_pitch_m = 0.0;      // 0: a smooth surface
  double semi_diameter_m = std::numeric_limits<double>::infinity();  // the clear aperture's radius
};

enum class HitStatus {
  kHit,
  kMissed,         // the ray does not meet the surface ahead of it
  kNoConvergence,  // the asphere's Newton iteration did not converge
  kGrooveWall,     // a Fresnel ray that would meet a groove wall
};

struct SurfaceHit {
  HitStatus status = HitStatus::kMissed;
  double t = 0.0;                                     // path length along the (unit) direction to the hit
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    // on the surface, in its frame
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, +z component > 0
};

class Surface {
 public:
  Surface() = default;
  explicit Surface(SurfaceShape shape);

  const SurfaceShape& shape() const { return shape_; }
  bool is_fresnel() const { return shape_.fresnel_pitch_m > 0; }

  // The underlying (unfolded) sag and its derivative dz/dr; `r` inside the
  // conic's domain 1 - (1 + k) c^2 r^2 >= 0.
  double UnderlyingSag(double r) const;
  double UnderlyingSlope(double r) const;
  // The surface's sag, folded into zones for a Fresnel surface.
  double Sag(double r) const;
  // True where the sag formula is defined.
  bool InDomain(double r) const;
  // The unit normal at (x, y) from the underlying profile, +z component > 0.
  Eigen::Vector3d Normal(double x, double y) const;

  // Where the ray origin + t direction (unit) first meets the surface with
  // t >= -1e-12 m (a ray that starts on the surface may hit it at t = 0).
  // The clear aperture is not applied here (the trace reports vignetting).
  SurfaceHit Intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;

 private:
  // The first hit of the underlying profile shifted by `z_shift` along z.
  SurfaceHit IntersectShifted(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double z_shift) const;
  SurfaceHit IntersectConic(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double z_shift) const;
  SurfaceHit PolishAsphere(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double z_shift,
                           double t_start) const;
  double AsphereGap(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double z_shift, double t) const;
  double FirstCrossingBefore(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double z_shift,
                             double t) const;
  SurfaceHit HitAt(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t) const;
  SurfaceHit IntersectFresnel(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const;
  double ZoneStartSag(double r) const;

  SurfaceShape shape_;
};

}  // namespace layerlab::lenses
