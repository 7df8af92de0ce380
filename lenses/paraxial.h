// First-order (paraxial) properties of a centred LensSystem at one wavelength,
// two ways from the one prescription:
//  - the ray-transfer matrix product (reduced angles n u): refraction by
//    (1 0; -(n' - n) c 1), a gap t in index n by (1 t/n; 0 1), from the first
//    vertex plane to the last (aspheric terms and Fresnel folds do not change
//    the paraxial power: the underlying curvature does);
//  - the exact trace in the paraxial limit: rays at a height h = 1e-6 m and at
//    a slope 1e-5 (and at twice each), traced exactly, their vertex-plane
//    heights and slopes extrapolated to zero (Richardson, removing the
//    aberrations' h^2 term).
// The two agree to ~1e-12 relative for the shipped tests; the compile uses the
// same quantities as its thick-lens ray transfer.
//
// Conventions: z along the light; the front focal length is the distance from
// the front focal point to the first vertex (positive in front of it); the
// back focal length from the last vertex to the back focal point; principal
// planes as signed z offsets from the first (front) and last (back) vertex.
// The effective focal length is 1 / power (the focal length in air).
#pragma once

#include "layerlab/lenses/lens_system.h"

namespace layerlab::lenses {

// (y', n'u') = (a y + b nu, c y + d nu), first vertex plane to the last.
struct VertexTransfer {
  double a = 1, b = 0, c = 0, d = 1;
};

struct ParaxialProperties {
  double efl_m = 0;  // 1 / power
  double bfl_m = 0;
  double ffl_m = 0;
  double front_principal_plane_m = 0;  // from the first vertex
  double back_principal_plane_m = 0;   // from the last vertex
  double n_before = 1, n_after = 1;
};

// Both throw layerlab::Error for a tilted or decentred system (first-order
// optics needs a centred one) and for wavelengths outside a material's range.
VertexTransfer TransferFromMatrices(const LensSystem& system, double wavelength_m);
VertexTransfer TransferFromExactTrace(const LensSystem& system, double wavelength_m);

// Throws layerlab::Error for an afocal transfer (no power).
ParaxialProperties PropertiesOf(const VertexTransfer& m, double n_before, double n_after);

// The properties from the matrix product.
ParaxialProperties ParaxialAt(const LensSystem& system, double wavelength_m);

}  // namespace layerlab::lenses
