#include "layerlab/lenses/surface.h"

#include <cmath>
#include <utility>

namespace layerlab::lenses {
namespace {

constexpr double kBehindTolerance_m = 1e-12;  // a ray starting on the surface meets it at t = 0
constexpr int kMaxNewtonSteps = 50;
constexpr int kMaxFresnelZones = 8;
constexpr int kCrossingSamples = 32;

SurfaceHit Missed() { return SurfaceHit{}; }

}  // namespace

Surface::Surface(SurfaceShape shape) : shape_(std::move(shape)) {}

bool Surface::InDomain(double r) const {
  const double c = shape_.curvature_per_m;
  return 1.0 - (1.0 + shape_.conic) * c * c * r * r >= 0.0;
}

double Surface::UnderlyingSag(double r) const {
  const double c = shape_.curvature_per_m;
  const double r2 = r * r;
  double z = c * r2 / (1.0 + std::sqrt(1.0 - (1.0 + shape_.conic) * c * c * r2));
  double power = r2 * r2;
  for (double a : shape_.even_asphere) {
    z += a * power;
    power *= r2;
  }
  return z;
}

double Surface::UnderlyingSlope(double r) const {
  const double c = shape_.curvature_per_m;
  double slope = c * r / std::sqrt(1.0 - (1.0 + shape_.conic) * c * c * r * r);
  double power = r * r * r;  // d/dr r^(2m) = 2m r^(2m - 1), m = 2, 3, ...
  double order = 4.0;
  for (double a : shape_.even_asphere) {
    slope += order * a * power;
    power *= r * r;
    order += 2.0;
  }
  return slope;
}

double Surface::ZoneStartSag(double r) const {
  return UnderlyingSag(std::floor(r / shape_.fresnel_pitch_m) * shape_.fresnel_pitch_m);
}

double Surface::Sag(double r) const { return UnderlyingSag(r) - (is_fresnel() ? ZoneStartSag(r) : 0.0); }

Eigen::Vector3d Surface::Normal(double x, double y) const {
  const double r = std::hypot(x, y);
  if (r == 0.0) return Eigen::Vector3d::UnitZ();
  const double slope = UnderlyingSlope(r);
  return Eigen::Vector3d(-slope * x / r, -slope * y / r, 1.0).normalized();
}

SurfaceHit Surface::Intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) const {
  if (!origin.allFinite() || !direction.allFinite()) return Missed();
  if (is_fresnel()) return IntersectFresnel(origin, direction);
  return IntersectShifted(origin, direction, 0.0);
}

SurfaceHit Surface::IntersectShifted(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                                     double z_shift) const {
  SurfaceHit hit = IntersectConic(origin, direction, z_shift);
  if (shape_.even_asphere.empty()) return hit;
  double t_start = hit.t;
  if (hit.status != HitStatus::kHit) {  // start from the vertex plane
    if (direction.z() == 0.0) return Missed();
    t_start = (z_shift - origin.z()) / direction.z();
  }
  return PolishAsphere(origin, direction, z_shift, t_start);
}

// The conic c (x^2 + y^2) + c (1 + k) z^2 - 2 z = 0 (z from the shifted vertex)
// along the ray: A t^2 + 2 Bh t + C = 0, both roots in the stable form; the hit
// is the nearest root ahead on the vertex sheet (1 + k) c z <= 1.
SurfaceHit Surface::IntersectConic(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double z_shift) const {
  const double c = shape_.curvature_per_m;
  const double e = 1.0 + shape_.conic;
  const Eigen::Vector3d q(origin.x(), origin.y(), origin.z() - z_shift);
  const double a = c * (d.x() * d.x() + d.y() * d.y() + e * d.z() * d.z());
  const double bh = c * (q.x() * d.x() + q.y() * d.y() + e * q.z() * d.z()) - d.z();
  const double cc = c * (q.x() * q.x() + q.y() * q.y() + e * q.z() * q.z()) - 2.0 * q.z();
  const double disc = bh * bh - a * cc;
  if (disc < 0.0) return Missed();
  const double root = -(bh + std::copysign(std::sqrt(disc), bh));
  double best = std::numeric_limits<double>::infinity();
  for (const double t : {a != 0.0 ? root / a : NAN, root != 0.0 ? cc / root : NAN}) {
    if (!(t >= -kBehindTolerance_m) || t >= best) continue;
    if (e * c * (q.z() + t * d.z()) > 1.0) continue;  // the conic's other sheet
    best = t;
  }
  if (!std::isfinite(best)) return Missed();
  return HitAt(origin, d, best);
}

// Newton's method on f(t) = z(t) - z_shift - sag(r(t)). Converged when the step
// falls below 1e-15 of the lengths involved, or stalls at the rounding of a
// step already below 1e-12 of them.
SurfaceHit Surface::PolishAsphere(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double z_shift,
                                  double t) const {
  const double scale = origin.norm() + std::abs(z_shift);
  double previous_step = std::numeric_limits<double>::infinity();
  for (int step = 0; step < kMaxNewtonSteps; ++step) {
    const Eigen::Vector3d p = origin + t * d;
    const double r = std::hypot(p.x(), p.y());
    if (!InDomain(r)) break;
    const double f = p.z() - z_shift - UnderlyingSag(r);
    const double radial = r > 0.0 ? (p.x() * d.x() + p.y() * d.y()) / r : 0.0;
    const double df = d.z() - UnderlyingSlope(r) * radial;
    if (df == 0.0 || !std::isfinite(df)) break;
    const double dt = f / df;
    t -= dt;
    const double tolerance = 1e-15 * (std::abs(t) + scale);
    const bool stalled = std::abs(dt) <= 1e3 * tolerance && std::abs(dt) >= previous_step;
    if (std::abs(dt) <= tolerance || stalled || dt == 0.0) {
      if (!(t >= -kBehindTolerance_m)) return Missed();
      if (!InDomain(std::hypot((origin + t * d).x(), (origin + t * d).y()))) break;
      return HitAt(origin, d, FirstCrossingBefore(origin, d, z_shift, t));
    }
    previous_step = std::abs(dt);
  }
  SurfaceHit failed;
  failed.status = HitStatus::kNoConvergence;
  return failed;
}

double Surface::AsphereGap(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double z_shift, double t) const {
  const Eigen::Vector3d p = origin + t * d;
  return p.z() - z_shift - UnderlyingSag(std::hypot(p.x(), p.y()));
}

// Newton may converge to a later crossing of a grazing ray: from a start in
// front of the surface, look for the gap z - sag turning >= 0 before `t` at
// kCrossingSamples points, and bisect the first bracket found.
double Surface::FirstCrossingBefore(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double z_shift,
                                    double t) const {
  if (t <= 0.0 || !(AsphereGap(origin, d, z_shift, 0.0) < 0.0)) return t;
  double lo = 0.0;
  for (int k = 1; k < kCrossingSamples; ++k) {
    const double tk = t * k / kCrossingSamples;
    const Eigen::Vector3d p = origin + tk * d;
    if (!InDomain(std::hypot(p.x(), p.y()))) return t;
    if (AsphereGap(origin, d, z_shift, tk) < 0.0) {
      lo = tk;
      continue;
    }
    double hi = tk;
    while (hi - lo > 1e-15 * hi) {
      const double mid = 0.5 * (lo + hi);
      if (mid <= lo || mid >= hi) break;
      (AsphereGap(origin, d, z_shift, mid) < 0.0 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  }
  return t;
}

SurfaceHit Surface::HitAt(const Eigen::Vector3d& origin, const Eigen::Vector3d& d, double t) const {
  SurfaceHit hit;
  hit.status = HitStatus::kHit;
  hit.t = t;
  hit.point = origin + t * d;
  hit.normal = Normal(hit.point.x(), hit.point.y());
  return hit;
}

// Zone by zone: the face of zone j is the underlying profile lowered by its
// sag at r = j p. Start in the zone where the ray crosses the substrate plane;
// move to the zone the hit lands in until it lands in the zone whose face was
// hit. A ray that misses its zone's face, or is sent back to a zone it left,
// crosses a groove wall (on a flat substrate a ray always meets a face or a wall).
SurfaceHit Surface::IntersectFresnel(const Eigen::Vector3d& origin, const Eigen::Vector3d& d) const {
  if (d.z() == 0.0) return Missed();
  const double pitch = shape_.fresnel_pitch_m;
  const Eigen::Vector3d on_plane = origin + (-origin.z() / d.z()) * d;
  long zone = static_cast<long>(std::floor(std::hypot(on_plane.x(), on_plane.y()) / pitch));
  long previous_zone = -1;
  for (int i = 0; i < kMaxFresnelZones; ++i) {
    const double zone_sag = UnderlyingSag(static_cast<double>(zone) * pitch);
    SurfaceHit hit = IntersectShifted(origin, d, -zone_sag);
    if (hit.status == HitStatus::kMissed) break;  // it leaves the zone sideways, through a wall
    if (hit.status != HitStatus::kHit) return hit;
    const long hit_zone = static_cast<long>(std::floor(std::hypot(hit.point.x(), hit.point.y()) / pitch));
    if (hit_zone == zone) return hit;
    if (hit_zone == previous_zone) break;
    previous_zone = zone;
    zone = hit_zone;
  }
  SurfaceHit wall;
  wall.status = HitStatus::kGrooveWall;
  return wall;
}

}  // namespace layerlab::lenses
