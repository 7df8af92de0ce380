// Exact sequential ray tracing through a LensSystem: each surface in order,
// intersected exactly in its own frame and refracted by Snell's law in vector
// form, n1 (d x N) = n2 (d' x N):
//   d' = mu d + (sqrt(1 - mu^2 (1 - cos_i^2)) - mu cos_i) N,   mu = n1 / n2, cos_i = d . N,
// with total internal reflection where the root's argument is negative. A
// ray that misses a surface, lands outside its clear aperture (vignetted) or
// is reflected totally is lost, with the surface and the reason, never bent
// or NaN. Sequential only: no ghosts (reflected paths), no scattering.
//
// Transmittance: each exited ray carries the fraction of its power (unpolarized
// light) that leaves the last surface, the product over the surfaces of
// 1 - (Rs + Rp) / 2 (surface_transmission.h: Fresnel, or the surface's
// coating) and over the media between the first and the last surface of the
// internal transmittance exp(-alpha L) of its geometric path L in each
// (glass_absorption.h; a material without published data absorbs nothing).
// The media before the first and after the last surface belong to the
// caller's gaps and are not counted. A lost ray carries 0.
//
// `SequentialTrace` evaluates the indices of one wavelength once; its
// Trace() is const, allocation-free and safe to call from many threads. It
// keeps a reference to the LensSystem, which must outlive it.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "layerlab/lenses/lens_system.h"

namespace layerlab::lenses {

// A ray in the system's frame (the first surface's vertex at the origin,
// light along +z): a point and a unit direction, meters.
struct Ray {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
};

enum class RayFate {
  kExited,                   // through every surface
  kMissed,                   // does not meet a surface ahead of it
  kVignetted,                // meets it outside the clear aperture
  kTotalInternalReflection,  // no refracted ray
  kNoConvergence,            // the asphere intersection did not converge
  kGrooveWall,               // would cross a Fresnel groove wall (not modelled)
};
const char* ToString(RayFate fate);

struct TraceResult {
  RayFate fate = RayFate::kMissed;
  int surface = -1;             // where it was lost (-1 when it exited)
  Ray exit;                     // at the last surface, refracted (when it exited)
  double optical_path_m = 0.0;  // sum of n * length from the origin to the exit point
  double transmittance = 0.0;   // power fraction through the system (see above); 0 when lost

  bool exited() const { return fate == RayFate::kExited; }
};

class SequentialTrace {
 public:
  // Throws layerlab::Error when a material's formula does not cover the wavelength.
  SequentialTrace(const LensSystem& system, double wavelength_m);

  TraceResult Trace(const Ray& ray) const;

  double wavelength_m() const { return wavelength_m_; }
  // The index before surface i (i = 0 .. size-1) and after the last (i = size).
  double index(int i) const { return indices_[i]; }
  // The absorption coefficient (1/m) of the medium after surface i (0 .. size-1).
  double absorption_per_m(int i) const { return absorption_per_m_[i]; }

 private:
  const LensSystem& system_;
  double wavelength_m_;
  std::vector<double> indices_;
  std::vector<double> absorption_per_m_;
};

// One ray at one wavelength (evaluates the indices on the way; for many rays
// build a SequentialTrace once).
TraceResult TraceRay(const LensSystem& system, const Ray& ray, double wavelength_m);

// The transmittance of the ray along the system's axis (x = y = 0, along +z)
// at `wavelength_m`: what the compile uses as a branch's lens efficiency per
// channel. Throws layerlab::Error when that ray is lost (the surface and why).
double AxialTransmittance(const LensSystem& system, double wavelength_m);

// The refracted unit direction, or false for total internal reflection.
// `normal` is unit and on the side the ray travels toward (d . normal >= 0).
bool Refract(const Eigen::Vector3d& direction, const Eigen::Vector3d& normal, double n1, double n2,
             Eigen::Vector3d* refracted);

}  // namespace layerlab::lenses
