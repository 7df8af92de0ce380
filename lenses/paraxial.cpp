#include "layerlab/lenses/paraxial.h"

#include <cmath>
#include <string>

#include "layerlab/lenses/sequential_trace.h"

namespace layerlab::lenses {
namespace {

constexpr double kLimitHeight_m = 1e-6;
constexpr double kLimitSlope = 1e-5;
constexpr double kStartBefore_m = 1e-3;  // the limit rays start this far in front of the first vertex

void RequireCentred(const LensSystem& system) {
  if (!system.IsCentred()) {
    throw Error("paraxial properties need a centred system: a placement tilts or decentres a group");
  }
}

// The exact ray through the system, its height and reduced slope on the last vertex plane.
Eigen::Vector2d AtLastVertex(const SequentialTrace& trace, const LensSystem& system, const Ray& ray) {
  const TraceResult r = trace.Trace(ray);
  if (!r.exited()) {
    throw Error(std::string("paraxial limit ray lost at surface ") + std::to_string(r.surface) + ": " +
                ToString(r.fate));
  }
  const Eigen::Vector3d& p = r.exit.origin;
  const Eigen::Vector3d& e = r.exit.direction;
  const double slope = e.y() / e.z();
  const double z_last = system.vertex_z_m(system.size() - 1);
  return Eigen::Vector2d(p.y() + (z_last - p.z()) * slope, trace.index(system.size()) * slope);
}

// Column (a, c) for a ray of height h and no slope at the first vertex, or
// column (b, d) for height 0 and slope u, exact at scale s.
Eigen::Vector2d Column(const SequentialTrace& trace, const LensSystem& system, bool height, double s) {
  Ray ray;
  const double u = height ? 0.0 : s;
  ray.origin = Eigen::Vector3d(0, (height ? s : 0.0) - u * kStartBefore_m, -kStartBefore_m);
  ray.direction = Eigen::Vector3d(0, u, 1).normalized();
  const double input = height ? s : trace.index(0) * u;
  return AtLastVertex(trace, system, ray) / input;
}

}  // namespace

VertexTransfer TransferFromMatrices(const LensSystem& system, double wavelength_m) {
  RequireCentred(system);
  double n = system.material_before().Index(wavelength_m);
  VertexTransfer m;
  for (int i = 0; i < system.size(); ++i) {
    const double n_after = system.material_after(i).Index(wavelength_m);
    const double power = (n_after - n) * system.surface(i).shape().curvature_per_m;
    m = {m.a, m.b, m.c - power * m.a, m.d - power * m.b};  // then refraction
    if (i + 1 < system.size()) {
      const double reduced_gap = system.prescription().surfaces[i].thickness_m / n_after;
      m = {m.a + reduced_gap * m.c, m.b + reduced_gap * m.d, m.c, m.d};  // then the gap
    }
    n = n_after;
  }
  return m;
}

VertexTransfer TransferFromExactTrace(const LensSystem& system, double wavelength_m) {
  RequireCentred(system);
  const SequentialTrace trace(system, wavelength_m);
  auto limit = [&](bool height, double s) -> Eigen::Vector2d {  // a plain vector, not an expression of temporaries
    const Eigen::Vector2d once = Column(trace, system, height, s);
    const Eigen::Vector2d twice = Column(trace, system, height, 2.0 * s);
    return (4.0 * once - twice) / 3.0;
  };
  const Eigen::Vector2d ac = limit(true, kLimitHeight_m);
  const Eigen::Vector2d bd = limit(false, kLimitSlope);
  return {ac.x(), bd.x(), ac.y(), bd.y()};
}

ParaxialProperties PropertiesOf(const VertexTransfer& m, double n_before, double n_after) {
  if (m.c == 0.0) throw Error("the system is afocal (no power): it has no focal length");
  const double power = -m.c;
  ParaxialProperties p;
  p.n_before = n_before;
  p.n_after = n_after;
  p.efl_m = 1.0 / power;
  p.bfl_m = m.a * n_after / power;
  p.ffl_m = m.d * n_before / power;
  p.front_principal_plane_m = n_before / power - p.ffl_m;
  p.back_principal_plane_m = p.bfl_m - n_after / power;
  return p;
}

ParaxialProperties ParaxialAt(const LensSystem& system, double wavelength_m) {
  return PropertiesOf(TransferFromMatrices(system, wavelength_m), system.material_before().Index(wavelength_m),
                      system.material_after(system.size() - 1).Index(wavelength_m));
}

}  // namespace layerlab::lenses
