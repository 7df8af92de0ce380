#include "layerlab/lenses/sequential_trace.h"

#include <cmath>

namespace layerlab::lenses {
namespace {

RayFate FateOf(HitStatus status) {
  switch (status) {
    case HitStatus::kNoConvergence:
      return RayFate::kNoConvergence;
    case HitStatus::kGrooveWall:
      return RayFate::kGrooveWall;
    default:
      return RayFate::kMissed;
  }
}

TraceResult Lost(RayFate fate, int surface, double optical_path_m) {
  TraceResult result;
  result.fate = fate;
  result.surface = surface;
  result.optical_path_m = optical_path_m;
  return result;
}

// The trace, with the index after surface i from `index_after(i)`.
template <class IndexAfter>
TraceResult TraceThrough(const LensSystem& system, const Ray& ray, double n_before, IndexAfter index_after) {
  Eigen::Vector3d point = ray.origin;
  Eigen::Vector3d direction = ray.direction.normalized();
  double n1 = n_before;
  double path = 0.0;
  for (int i = 0; i < system.size(); ++i) {
    const SurfaceFrame& frame = system.frame(i);
    const Eigen::Vector3d local_origin = frame.axes.transpose() * (point - frame.vertex);
    const Eigen::Vector3d local_direction = frame.axes.transpose() * direction;
    const Surface& surface = system.surface(i);
    const SurfaceHit hit = surface.Intersect(local_origin, local_direction);
    if (hit.status != HitStatus::kHit) return Lost(FateOf(hit.status), i, path);
    path += n1 * hit.t;
    if (std::hypot(hit.point.x(), hit.point.y()) > surface.shape().semi_diameter_m) {
      return Lost(RayFate::kVignetted, i, path);
    }
    const double n2 = index_after(i);
    Eigen::Vector3d normal = hit.normal;
    if (local_direction.dot(normal) < 0) normal = -normal;
    Eigen::Vector3d refracted;
    if (!Refract(local_direction, normal, n1, n2, &refracted)) return Lost(RayFate::kTotalInternalReflection, i, path);
    point = frame.vertex + frame.axes * hit.point;
    direction = frame.axes * refracted;
    n1 = n2;
  }
  TraceResult result;
  result.fate = RayFate::kExited;
  result.exit.origin = point;
  result.exit.direction = direction;
  result.optical_path_m = path;
  return result;
}

}  // namespace

const char* ToString(RayFate fate) {
  switch (fate) {
    case RayFate::kExited:
      return "exited";
    case RayFate::kMissed:
      return "missed the surface";
    case RayFate::kVignetted:
      return "outside the clear aperture";
    case RayFate::kTotalInternalReflection:
      return "total internal reflection";
    case RayFate::kNoConvergence:
      return "asphere intersection did not converge";
    case RayFate::kGrooveWall:
      return "met a Fresnel groove wall";
  }
  return "unknown";
}

bool Refract(const Eigen::Vector3d& d, const Eigen::Vector3d& normal, double n1, double n2, Eigen::Vector3d* out) {
  const double mu = n1 / n2;
  const double cos_i = d.dot(normal);
  const double cos_t_squared = 1.0 - mu * mu * (1.0 - cos_i * cos_i);
  if (cos_t_squared < 0.0) return false;
  *out = (mu * d + (std::sqrt(cos_t_squared) - mu * cos_i) * normal).normalized();
  return true;
}

SequentialTrace::SequentialTrace(const LensSystem& system, double wavelength_m)
    : system_(system), wavelength_m_(wavelength_m) {
  indices_.push_back(system.material_before().Index(wavelength_m));
  for (int i = 0; i < system.size(); ++i) indices_.push_back(system.material_after(i).Index(wavelength_m));
}

TraceResult SequentialTrace::Trace(const Ray& ray) const {
  return TraceThrough(system_, ray, indices_[0], [this](int i) { return indices_[i + 1]; });
}

TraceResult TraceRay(const LensSystem& system, const Ray& ray, double wavelength_m) {
  return TraceThrough(system, ray, system.material_before().Index(wavelength_m),
                      [&](int i) { return system.material_after(i).Index(wavelength_m); });
}

}  // namespace layerlab::lenses
