#include "layerlab/lenses/lens_system.h"

#include <cmath>
#include <utility>

#include <Eigen/Geometry>

namespace layerlab::lenses {
namespace {

const Material& MaterialAt(const std::string& name, const Location& where) {
  try {
    return FindMaterial(name);
  } catch (const Error& e) {
    throw Error(where, e.message());
  }
}

void CheckShape(const SurfaceShape& s, const Location& where) {
  auto require = [&](bool ok, const std::string& key, const std::string& what) {
    if (!ok) throw Error(where.child(key), what);
  };
  require(std::isfinite(s.curvature_per_m), "curvature_per_m", "expected a finite curvature (0 for a plane)");
  require(std::isfinite(s.conic), "conic", "expected a finite conic constant");
  for (size_t i = 0; i < s.even_asphere.size(); ++i) {
    if (!std::isfinite(s.even_asphere[i])) throw Error(where.child("even_asphere").child(i), "expected a finite term");
  }
  require(s.fresnel_pitch_m >= 0 && std::isfinite(s.fresnel_pitch_m), "fresnel_pitch_m",
          "expected a pitch >= 0 (0: no grooves)");
  require(s.semi_diameter_m > 0, "semi_diameter_m", "expected a semi-diameter > 0");
  require(s.semi_diameter_m == std::numeric_limits<double>::infinity() || Surface(s).InDomain(s.semi_diameter_m),
          "semi_diameter_m", "the clear aperture reaches beyond the conic's edge, where its sag is undefined");
}

void CheckCoating(const Coating& c, const Location& where) {
  switch (c.kind) {
    case Coating::Kind::kQuarterWave:
      if (!(c.index >= 1.0 && std::isfinite(c.index))) {
        throw Error(where.child("index"), "expected the film's refractive index, finite and >= 1 (MgF2: 1.38)");
      }
      if (!(c.design_wavelength_m > 0 && std::isfinite(c.design_wavelength_m))) {
        throw Error(where.child("design_wavelength_m"), "expected a design wavelength > 0 (meters)");
      }
      break;
    case Coating::Kind::kStatedReflectance:
      if (!(c.reflectance >= 0 && c.reflectance < 1)) {
        throw Error(where.child("reflectance"), "expected a reflectance in [0, 1) (0.005: 0.5 %)");
      }
      break;
    case Coating::Kind::kUncoated:
      break;
  }
}

// Rotation of a group: about x by tilt_x, then about y by tilt_y.
Eigen::Matrix3d GroupAxes(const GroupPlacement& g) {
  return (Eigen::AngleAxisd(g.tilt_y_rad, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(g.tilt_x_rad, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

void CheckPlacement(const GroupPlacement& g, int surfaces, std::vector<bool>& placed, const Location& where) {
  if (g.first_surface < 0 || g.last_surface < g.first_surface || g.last_surface >= surfaces) {
    throw Error(where, "expected surfaces first_surface <= last_surface within 0 to " + std::to_string(surfaces - 1));
  }
  for (double v : {g.tilt_x_rad, g.tilt_y_rad, g.decentre_x_m, g.decentre_y_m}) {
    if (!std::isfinite(v)) throw Error(where, "expected finite tilts and decentres");
  }
  for (int i = g.first_surface; i <= g.last_surface; ++i) {
    if (placed[i]) throw Error(where, "surface " + std::to_string(i) + " is already in another placed group");
    placed[i] = true;
  }
}

}  // namespace

LensSystem::LensSystem(Prescription prescription, const Location& where) : prescription_(std::move(prescription)) {
  const Prescription& p = prescription_;
  if (p.surfaces.empty()) throw Error(where.child("surfaces"), "expected at least one surface");
  material_before_ = &MaterialAt(p.material_before, where.child("material_before"));
  double z = 0.0;
  for (size_t i = 0; i < p.surfaces.size(); ++i) {
    const Location at = where.child("surfaces").child(i);
    const PrescriptionSurface& s = p.surfaces[i];
    CheckShape(s.shape, at);
    CheckCoating(s.coating, at.child("coating"));
    if (!std::isfinite(s.thickness_m)) throw Error(at.child("thickness_m"), "expected a finite thickness");
    materials_after_.push_back(&MaterialAt(s.material, at.child("material")));
    surfaces_.emplace_back(s.shape);
    vertex_z_m_.push_back(z);
    SurfaceFrame frame;
    frame.vertex = Eigen::Vector3d(0, 0, z);
    frames_.push_back(frame);
    z += s.thickness_m;
  }
  std::vector<bool> placed(p.surfaces.size(), false);
  for (size_t g = 0; g < p.placements.size(); ++g) {
    const GroupPlacement& group = p.placements[g];
    CheckPlacement(group, size(), placed, where.child("placements").child(g));
    const Eigen::Matrix3d axes = GroupAxes(group);
    const Eigen::Vector3d pivot(0, 0, vertex_z_m_[group.first_surface]);
    const Eigen::Vector3d shift(group.decentre_x_m, group.decentre_y_m, 0);
    for (int i = group.first_surface; i <= group.last_surface; ++i) {
      frames_[i].axes = axes;
      frames_[i].vertex = pivot + shift + axes * (Eigen::Vector3d(0, 0, vertex_z_m_[i]) - pivot);
    }
  }
  if (p.stop_surface < -1 || p.stop_surface >= size()) {
    throw Error(where.child("stop_surface"),
                "expected a surface index 0 to " + std::to_string(size() - 1) + " (or -1: none)");
  }
}

bool LensSystem::IsCentred() const {
  for (const GroupPlacement& g : prescription_.placements) {
    if (g.tilt_x_rad != 0 || g.tilt_y_rad != 0 || g.decentre_x_m != 0 || g.decentre_y_m != 0) return false;
  }
  return true;
}

}  // namespace layerlab::lenses
