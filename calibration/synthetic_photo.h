// Synthetic photographs of a built display, for the tests and for trying the
// calibration loop without a prototype (`layerlab photograph`): what a camera
// at the eye records while the panels show a capture plan's patterns.
//
// The camera (photo_camera.h) has its entrance pupil at the capture's
// position in the eye's pupil plane, so each panel is defocused by its own
// distance. Each ray meets every panel of every branch through that layer's
// compiled ray transfer (synthetic_measurements.h: PanelPointOfRay), or behind
// a real lens through its traced ray map (systems/layer_ray_map.h, the green
// channel's: the lens's distortion and field curvature, not its lateral
// colour), and the camera sees per branch the backlight times the branch's
// efficiency times the product of its panels' transmittances,
// max (black + (1 - black) x^gamma) at the shown level x (outside a panel's
// pixel grid: opaque), the branches added; `white` is the signal of the
// brightest branch at full white.
#pragma once

#include <cstdint>
#include <vector>

#include "layerlab/calibration/capture_plan.h"
#include "layerlab/calibration/photo_camera.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

class PhotoRenderer {
 public:
  // Precomputes the undistorted slope of every pixel corner.
  explicit PhotoRenderer(const PhotoCamera& camera);
  const PhotoCamera& camera() const { return camera_; }

  // The photograph of `capture` (its patterns from PatternImage) on the
  // display `truth` as built: one channel "Y", linear or per the response.
  // `seed_key` picks the noise (MixSeed with the camera's seed).
  Image Render(const DisplaySystem& truth, const CapturePlan& plan, const PlannedCapture& capture,
               uint64_t seed_key) const;

 private:
  PhotoCamera camera_;
  std::vector<double> slopes_;  // [row][col][x, y] at pixel corners; NaN where the distortion cannot be inverted
};

}  // namespace layerlab
