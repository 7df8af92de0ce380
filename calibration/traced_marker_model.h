// The marker model of marker_model.h for a layer seen through real lenses (a
// lens described by its surfaces), by the compile's exact trace
// (systems/layer_ray_map.h) instead of the ray transfer.
//
// The camera at pupil point c sees a marker at visual angles a. In the eye's
// frame its direction is e = R_cam (tan a_x, tan a_y, 1) (R_cam as in
// marker_model.h); the ray from c with slopes (e_x / e_z, e_y / e_z) is traced
// at the green channel's wavelength (a gray camera) through the layer's path
// with the fitted gaps, the ideal elements' fitted focal lengths and the
// fitted panel distance, to the point Y where it meets the panel's plane
// (in eye-space order: sign(b) X of the unfolded frame, as the panel point of
// a ray is given in display_system.h). The marker lies at x = o + R(theta) l.
// The residual is the angle error to first order,
//   r = -J0^-1 (Y(a) - x),   J0 = dY/da at the measurement, as designed,
// so that it weighs as marker_model.h's angle residuals (the model-error test
// compares both with the detection noise). A real lens keeps its surfaces: its
// focal length and distortion are not parameters of this model.
#pragma once

#include <array>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "layerlab/calibration/marker_model.h"
#include "layerlab/systems/layer_ray_map.h"

namespace layerlab {

struct TracedMarker {
  MarkerPlacement placement;
  double angle_x = 0, angle_y = 0;
  Eigen::Matrix2d inverse_jacobian = Eigen::Matrix2d::Identity();  // J0^-1, rad per m
};

class TracedLayerModel {
 public:
  // `layer` compiled with its path, behind real lenses (layer.ray_map set, its
  // panel untilted); `designed` the layer's parameters as the scene has them,
  // whose gaps and focal lengths are those of the layer's elements with power
  // (LayerOptics' order). A fitted gap moves its element and everything behind it.
  TracedLayerModel(const VirtualLayer& layer, const MarkerParameters<double>& designed);

  // The marker with its Jacobian at the designed parameters; nullopt when the
  // measured ray is lost there (vignetted, or missing the panel).
  std::optional<TracedMarker> Prepare(const MarkerPlacement& m, double angle_x, double angle_y) const;

  // Model minus measurement (rad, to first order) under `q`; false when the ray is lost.
  bool AngleError(const MarkerParameters<double>& q, const TracedMarker& m, double error[2]) const;

  // The panel's virtual depth under `q` (D), in the paraxial limit of the
  // trace: X = b (D p + u) for rays near the axis, so D = (dX/dp) / (dX/du).
  double Diopters(const MarkerParameters<double>& q) const;

 private:
  std::optional<std::array<double, 2>> Seen(const MarkerParameters<double>& q, double camera_x_m, double camera_y_m,
                                            double angle_x, double angle_y) const;

  const LayerRayMap* map_;
  double sign_b_;
  MarkerParameters<double> designed_;
  // Per element of the ray map: its index among the fit's elements (LayerOptics'), or -1 for an element the
  // fit has no parameters of (a lens of zero power described by its surfaces).
  std::vector<int> fit_element_;
};

}  // namespace layerlab
