// An independent ray tracer for the lens tests, written apart from lenses/:
// the sag from its formula, the normal from a finite-difference slope, the
// intersection by scanning and bisection on z(t) - sag(r(t)), and Snell's law
// in its angle form (sin t = n1/n2 sin i, in the plane of incidence). Centred
// systems only; slow and simple on purpose.
#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Core>

namespace layerlab::lens_testing {

struct BruteSurface {
  double vertex_z = 0;    // on the axis
  double c = 0, k = 0;    // curvature, conic
  std::vector<double> a;  // A4, A6, ...
  double pitch = 0;       // Fresnel zones (0: smooth)
  double n_after = 1;
};

inline double BruteUnderlyingSag(const BruteSurface& s, double r) {
  double z = s.c * r * r / (1 + std::sqrt(1 - (1 + s.k) * s.c * s.c * r * r));
  for (size_t i = 0; i < s.a.size(); ++i) z += s.a[i] * std::pow(r, 4 + 2 * static_cast<int>(i));
  return z;
}

inline double BruteSag(const BruteSurface& s, double r) {
  if (s.pitch == 0) return BruteUnderlyingSag(s, r);
  return BruteUnderlyingSag(s, r) - BruteUnderlyingSag(s, std::floor(r / s.pitch) * s.pitch);
}

// dz/dr by the five-point central difference.
inline double BruteSlope(const BruteSurface& s, double r) {
  const double h = 1e-6;
  auto f = [&](double x) { return BruteUnderlyingSag(s, std::abs(x)); };
  return (8 * (f(r + h) - f(r - h)) - (f(r + 2 * h) - f(r - 2 * h))) / (12 * h);
}

inline Eigen::Vector3d BruteNormal(const BruteSurface& s, const Eigen::Vector3d& p) {
  const double r = std::hypot(p.x(), p.y());
  if (r == 0) return Eigen::Vector3d::UnitZ();
  const double m = BruteSlope(s, r);
  return Eigen::Vector3d(-m * p.x() / r, -m * p.y() / r, 1).normalized();
}

// The first t >= 0 where the ray passes the surface (scan by 1e-4 m, then bisect); -1 if none within 1 m.
inline double BruteCrossing(const BruteSurface& s, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  auto g = [&](double t) {
    const Eigen::Vector3d p = o + t * d;
    return p.z() - s.vertex_z - BruteSag(s, std::hypot(p.x(), p.y()));
  };
  double lo = 0, hi = 0;
  for (double t = 1e-4; t < 1.0; t += 1e-4) {
    if (g(t) > 0) {
      hi = t;
      break;
    }
    lo = t;
  }
  if (hi == 0) return -1;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid == lo || mid == hi) break;
    (g(mid) > 0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

// Snell's law as angles: sin(t) = n1/n2 sin(i), the refracted ray in the plane
// of the incident ray and the normal. False for total internal reflection.
inline bool BruteRefract(const Eigen::Vector3d& d, Eigen::Vector3d n, double n1, double n2, Eigen::Vector3d* out) {
  if (d.dot(n) < 0) n = -n;
  const Eigen::Vector3d tangential = d - d.dot(n) * n;
  const double sin_i = tangential.norm();
  const double sin_t = n1 / n2 * sin_i;
  if (sin_t > 1) return false;
  const double cos_t = std::sqrt(1 - sin_t * sin_t);
  *out = sin_i == 0 ? n : Eigen::Vector3d(cos_t * n + sin_t * tangential / sin_i);
  return true;
}

struct BruteResult {
  bool ok = false;
  Eigen::Vector3d point, direction;
  double optical_path = 0;
};

inline BruteResult BruteTrace(const std::vector<BruteSurface>& surfaces, double n_before, Eigen::Vector3d o,
                              Eigen::Vector3d d) {
  BruteResult result;
  double n1 = n_before;
  d.normalize();
  for (const BruteSurface& s : surfaces) {
    const double t = BruteCrossing(s, o, d);
    if (t < 0) return result;
    o += t * d;
    result.optical_path += n1 * t;
    Eigen::Vector3d refracted;
    if (!BruteRefract(d, BruteNormal(s, o), n1, s.n_after, &refracted)) return result;
    d = refracted;
    n1 = s.n_after;
  }
  result.ok = true;
  result.point = o;
  result.direction = d;
  return result;
}

// Where the ray (point, direction) crosses the plane z = plane_z.
inline Eigen::Vector3d AtPlane(const Eigen::Vector3d& p, const Eigen::Vector3d& d, double plane_z) {
  return p + (plane_z - p.z()) / d.z() * d;
}

}  // namespace layerlab::lens_testing
