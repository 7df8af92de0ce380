#include "layerlab/lenses/sequential_trace.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "layerlab/framework/error.h"
#include "layerlab/lenses/glass_absorption.h"
#include "layerlab/lenses/surface_transmission.h"

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

struct Medium {
  double index = 1.0;
  double absorption_per_m = 0.0;
};

// The trace, with the medium after surface i from `medium_after(i)`.
template <class MediumAfter>
TraceResult TraceThrough(const LensSystem& system, const Ray& ray, double n_before, double wavelength_m,
                         MediumAfter medium_after) {
  Eigen::Vector3d point = ray.origin;
  Eigen::Vector3d direction = ray.direction.normalized();
  double n1 = n_before;
  double alpha1 = 0.0;  // the medium before the first surface is the caller's
  double path = 0.0;
  double transmittance = 1.0;
  for (int i = 0; i < system.size(); ++i) {
    const SurfaceFrame& frame = system.frame(i);
    const Eigen::Vector3d local_origin = frame.axes.transpose() * (point - frame.vertex);
    const Eigen::Vector3d local_direction = frame.axes.transpose() * direction;
    const Surface& surface = system.surface(i);
    const SurfaceHit hit = surface.Intersect(local_origin, local_direction);
    if (hit.status != HitStatus::kHit) return Lost(FateOf(hit.status), i, path);
    path += n1 * hit.t;
    transmittance *= std::exp(-alpha1 * hit.t);
    if (std::hypot(hit.point.x(), hit.point.y()) > surface.shape().semi_diameter_m) {
      return Lost(RayFate::kVignetted, i, path);
    }
    const Medium after = medium_after(i);
    Eigen::Vector3d normal = hit.normal;
    if (local_direction.dot(normal) < 0) normal = -normal;
    Eigen::Vector3d refracted;
    if (!Refract(local_direction, normal, n1, after.index, &refracted)) {
      return Lost(RayFate::kTotalInternalReflection, i, path);
    }
    transmittance *= SurfaceTransmittance(system.prescription().surfaces[i].coating, n1, after.index,
                                          local_direction.dot(normal), wavelength_m);
    point = frame.vertex + frame.axes * hit.point;
    direction = frame.axes * refracted;
    n1 = after.index;
    alpha1 = after.absorption_per_m;
  }
  TraceResult result;
  result.fate = RayFate::kExited;
  result.exit.origin = point;
  result.exit.direction = direction;
  result.optical_path_m = path;
  result.transmittance = transmittance;
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
  for (int i = 0; i < system.size(); ++i) {
    indices_.push_back(system.material_after(i).Index(wavelength_m));
    // The medium after the last surface is the caller's (not counted).
    const bool inside = i + 1 < system.size();
    absorption_per_m_.push_back(inside ? AbsorptionPerMeter(system.material_after(i), wavelength_m) : 0.0);
  }
}

TraceResult SequentialTrace::Trace(const Ray& ray) const {
  return TraceThrough(system_, ray, indices_[0], wavelength_m_, [this](int i) {
    return Medium{indices_[i + 1], absorption_per_m_[i]};
  });
}

TraceResult TraceRay(const LensSystem& system, const Ray& ray, double wavelength_m) {
  return TraceThrough(system, ray, system.material_before().Index(wavelength_m), wavelength_m, [&](int i) {
    const Material& m = system.material_after(i);
    return Medium{m.Index(wavelength_m), i + 1 < system.size() ? AbsorptionPerMeter(m, wavelength_m) : 0.0};
  });
}

double AxialTransmittance(const LensSystem& system, double wavelength_m) {
  const SequentialTrace trace(system, wavelength_m);
  // From 1 m before the first vertex: the medium there is not counted, so
  // only the start's being ahead of every surface matters.
  const TraceResult r = trace.Trace({Eigen::Vector3d(0, 0, -1.0), Eigen::Vector3d::UnitZ()});
  if (!r.exited()) {
    char text[64];
    std::snprintf(text, sizeof text, "the axial ray at %g nm is lost at surface %d (", wavelength_m * 1e9, r.surface);
    throw Error(text + std::string(ToString(r.fate)) + ")");
  }
  return r.transmittance;
}

}  // namespace layerlab::lenses
