// A sequential lens prescription, validated and placed in space.
//
// The surfaces are met in order along +z. Surface i has its vertex on the
// axis at z_i = sum of the thicknesses before it (z_0 = 0), the material
// after it (up to the next surface), and its clear aperture. A placement
// moves a group of consecutive surfaces as a rigid body (a lens tilted or
// decentred in its mount): tilted about the x axis, then about the y axis,
// through the group's first vertex, then decentred in x and y; the surfaces
// after the group stay where the thicknesses put them (a coordinate break
// and its return). Everything in meters and radians, in double.
//
// Build a `Prescription` (plain data, as a scene reader or a .zmx importer
// fills it), then a `LensSystem` from it: that checks the names against the
// glass catalogue and every number, and throws layerlab::Error at the
// offending field ("lens.json: /surfaces/2/material: unknown material ...").
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "layerlab/framework/error.h"
#include "layerlab/lenses/glass_catalog.h"
#include "layerlab/lenses/surface.h"
#include "layerlab/lenses/surface_transmission.h"

namespace layerlab::lenses {

struct PrescriptionSurface {
  SurfaceShape shape;
  std::string material = "air";  // after the surface (catalogue name)
  double thickness_m = 0.0;      // axial gap from this vertex to the next (unused after the last)
  Coating coating;               // uncoated by default (Fresnel reflection)
};

struct GroupPlacement {
  int first_surface = 0;  // the group, inclusive
  int last_surface = 0;
  double tilt_x_rad = 0.0;  // about the x axis (turns the axis toward -y), then
  double tilt_y_rad = 0.0;  // about the y axis (turns it toward +x)
  double decentre_x_m = 0.0;
  double decentre_y_m = 0.0;
};

struct Prescription {
  std::string material_before = "air";  // the medium the rays start in
  std::vector<PrescriptionSurface> surfaces;
  std::vector<GroupPlacement> placements;  // groups do not overlap
  int stop_surface = -1;                   // the aperture stop's surface; -1: none named
};

// Where a surface sits: point_global = vertex + axes * point_local.
struct SurfaceFrame {
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d vertex = Eigen::Vector3d::Zero();
};

class LensSystem {
 public:
  // Throws layerlab::Error at `where` (the prescription's location) + the field.
  explicit LensSystem(Prescription prescription, const Location& where = {});

  const Prescription& prescription() const { return prescription_; }
  int size() const { return static_cast<int>(surfaces_.size()); }
  const Surface& surface(int i) const { return surfaces_[i]; }
  const SurfaceFrame& frame(int i) const { return frames_[i]; }
  const Material& material_before() const { return *material_before_; }
  const Material& material_after(int i) const { return *materials_after_[i]; }
  // The nominal (unplaced) vertex of surface i on the axis.
  double vertex_z_m(int i) const { return vertex_z_m_[i]; }
  // True when no placement tilts or decentres anything.
  bool IsCentred() const;

 private:
  Prescription prescription_;
  std::vector<Surface> surfaces_;
  std::vector<SurfaceFrame> frames_;
  std::vector<const Material*> materials_after_;
  const Material* material_before_ = nullptr;
  std::vector<double> vertex_z_m_;
};

}  // namespace layerlab::lenses
