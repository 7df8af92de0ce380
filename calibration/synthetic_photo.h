// Synthetic photographs of a built display, for the tests and for trying the
// calibration loop without a prototype (`layerlab photograph`): what a camera
// at the eye records while the panels show a capture plan's patterns.
//
// The camera is a thin lens with Brown radial distortion (camera_model.h),
// its entrance pupil at the capture's position in the eye's pupil plane,
// focused at `focus` diopters: every ray of a pixel sample leaves a point p of
// the camera's aperture toward the pixel's point in the focus plane, slope
// t - p * focus, so each panel is defocused by its own distance. Each ray
// meets every panel of every branch through that layer's compiled ray
// transfer (synthetic_measurements.h: PanelPointOfRay), or behind a real lens
// through its traced ray map (systems/layer_ray_map.h, the green channel's:
// the lens's distortion and field curvature, not its lateral colour), and the camera sees
// per branch the backlight times the branch's efficiency times the product of
// its panels' transmittances, max (black + (1 - black) x^gamma) at the shown
// level x (outside a panel's pixel grid: opaque), the branches added.
// The image is blurred by the lens's own point spread (psf_sigma), then the sensor adds photon noise (full_well electrons at full scale) and read
// noise, clips at full scale, applies its response (value = signal^(1/gamma))
// and optionally rounds to `bits`.
#pragma once

#include <cstdint>
#include <vector>

#include "layerlab/calibration/camera_model.h"
#include "layerlab/calibration/capture_plan.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/systems/display_system.h"

namespace layerlab {

struct PhotoCamera {
  CameraIntrinsics intrinsics;
  int width = 0, height = 0;
  double aperture_m = 0;      // entrance pupil diameter, m; 0 is a pinhole
  double focus_diopters = 0;  // diopters the camera is focused at
  // Signal (fraction of full scale) of the brightest branch at full white, at exposure 1.
  double white = 0.5;
  double full_well = 20000;   // electrons at full scale (photon noise); 0: none
  double read_noise = 0;      // rms, fraction of full scale
  double response_gamma = 1;  // stored value = signal^(1 / response_gamma)
  int bits = 0;               // 0: float; else rounded to 2^bits - 1 steps
  int supersampling = 3;      // samples per axis of a pixel, each through its own point of the aperture
  // The lens's and sensor's own blur (diffraction, aberrations, the color filter's demosaicing), a Gaussian
  // of this standard deviation in pixels; a perfectly sharp image would lock sub-pixel positions to the grid.
  double psf_sigma_px = 0.8;
  uint64_t seed = 1;
};

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
