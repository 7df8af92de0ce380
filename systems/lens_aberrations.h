// What a real lens does to each layer, measured on its exact ray map at the
// edge of the layer's horizontal field (the eye's chief ray, from the pupil
// centre, toward the layer's right edge on the design grid):
//  - distortion: where that ray lands on the panel against the paraxial
//    model, (U - u) / u; negative when it lands nearer the axis (the panel's
//    edge appears magnified beyond the ideal model: pincushion, as in every
//    magnifier);
//  - lateral color: the red and the blue ray from the same direction land
//    apart on the panel, in panel pixels and as an angle on the layer's grid;
//  - field curvature: the depth the rays from one panel point seem to come
//    from, as rays through the pupil edge (the pupil's radius off centre,
//    tangential and sagittal) see it, at the edge minus at the centre.
#pragma once

#include "layerlab/systems/display_system.h"

namespace layerlab {

struct LayerAberrations {
  double field_edge_deg = 0;            // deg, the chief ray's angle
  double distortion_percent = 0;        // %, green
  double lateral_color_px = 0;          // panel pixels, red minus blue
  double lateral_color_arcmin = 0;      // arcmin, red minus blue
  double tangential_diopters = 0;       // D, at the edge
  double sagittal_diopters = 0;         // D, at the edge
  double field_curvature_diopters = 0;  // D: the mean of the two at the edge minus at the centre
  double map_bound_px = 0;              // px: the sampled map against the exact trace
};

// For a layer with a ray map; `pupil_diameter_m` the eye's. Throws
// layerlab::Error when the chief ray or a pupil-edge ray to the field edge is
// lost (the lens vignettes its own field).
LayerAberrations MeasureAberrations(const VirtualLayer& layer, double pupil_diameter_m);

}  // namespace layerlab
