// The light-field error's derivative with respect to where each layer is,
// at fixed patterns: what `layerlab optimize` needs for an exact gradient of
// a solve's PSNR with respect to a layer's depth (design/design_gradient.h).
//
//   E = sum over rays and channels (L - T)^2,   L = sum_b w_b prod_{k in b} s_k
//
// s_k is layer k read bilinearly where ray (x, p) meets it, at tan-angle
// u = D_k p + (x - p) / z_lf (systems/projection.h), at the cell coordinates
// of the sampler's rule (LayerSampler::PanelCoordinates), in eye order:
//   col = (u_x - c_x) / a_x + cols/2 - 1/2,   row = -(u_y - c_y) / a_y + rows/2 - 1/2
// (mirrored for flip_x / flip_y), with D_k the layer's diopters, c its grid
// centre (eye_from_layer_tan) and a its tan pitch. Each of these five enters
// E only through col and row, so with the bilinear read's slopes ds/dcol and
// ds/drow (constant within a cell) E's partial derivatives are sums over the
// rays, exact up to float rounding of the patterns and the sums in double
// (on a pixel centre, to 1e-6 of a pixel, where the read bends, the mean of the two cells'
// slopes: the derivative a central difference sees):
//   dcol/dD = p_x / a_x,  dcol/dc_x = -1 / a_x,  dcol/da_x = -(col - cols/2 + 1/2) / a_x
//   drow/dD = -p_y / a_y, drow/dc_y = 1 / a_y,   drow/da_y = -(row - rows/2 + 1/2) / a_y
// Nearest sampling's E is a step function of these (zero derivative almost
// everywhere), so the gradient is of the bilinear model only.
#pragma once

#include <vector>

#include "layerlab/framework/lightfield.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

struct LayerPlacementGradient {
  double diopters = 0;                        // dE/dD_k, per diopter
  double center_tan_x = 0, center_tan_y = 0;  // dE/dc_x, dE/dc_y
  double tan_pitch_x = 0, tan_pitch_y = 0;    // dE/da_x, dE/da_y
};

// dE for each layer of `model` (bound to `target`'s rays, bilinear sampling)
// at patterns `t`; *error (optional) is E itself. Throws layerlab::Error for
// nearest sampling, a rotated layer or one behind a real lens (its ray map is
// not affine in D), naming the layer.
std::vector<LayerPlacementGradient> PlacementGradient(const DisplayModel& model, const LightField& target,
                                                      const Patterns& t, double* error = nullptr);

}  // namespace layerlab
