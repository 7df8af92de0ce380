// The synthetic camera both photograph renderers use (synthetic_photo.h for a
// display, synthetic_chessboard.h for a printed board): where each pixel's
// rays go and what the sensor makes of the light they bring.
//
// The camera is a thin lens with Brown radial distortion (camera_model.h), its
// entrance pupil at the origin, focused at `focus_diopters`: every ray of a
// pixel sample leaves a point p of the aperture toward the pixel's point in
// the focus plane, slope t - p * focus. Each pixel is the mean over
// supersampling^2 stratified samples, jittered anew in every photograph (on a
// fixed grid an edge's rendered place would lock to the grid's steps, 1/s
// pixel, a bias no blur afterwards removes). The image is blurred by the lens's
// own point spread (psf_sigma_px), then the sensor adds photon noise
// (full_well electrons at full scale) and read noise, clips at full scale,
// applies its response (value = signal^(1/gamma)) and optionally rounds to
// `bits`.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "layerlab/calibration/camera_model.h"
#include "layerlab/framework/exr_image.h"

namespace layerlab {

struct PhotoCamera {
  CameraIntrinsics intrinsics;
  int width = 0, height = 0;
  double aperture_m = 0;      // entrance pupil diameter, m; 0 is a pinhole
  double focus_diopters = 0;  // diopters the camera is focused at
  // Signal (fraction of full scale) of the brightest thing photographed, at exposure 1.
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

// Throws layerlab::Error when a setting is out of range (size, finiteness, signs).
void CheckPhotoCamera(const PhotoCamera& camera);

// The undistorted slope (tan of the visual angles, x right, y up) of every
// pixel corner, [row][col][x, y] over (height + 1) x (width + 1) corners; NaN
// where the distortion cannot be inverted. A sample's slope is interpolated
// between them (the distortion is smooth: the error is far below a
// thousandth of a pixel).
std::vector<double> PixelCornerSlopes(const PhotoCamera& camera);

// The light a ray brings: from `origin` (m, in the entrance pupil's plane, relative to its center, x right, y up)
// with `slope` (x right, y up).
using RayLight = std::function<double(const std::array<double, 2>& origin, const std::array<double, 2>& slope)>;

// Each pixel's signal before blur and noise, [row][col]: the mean of `light` over its samples.
// `seed_key` picks the jitter (MixSeed with the camera's seed).
std::vector<double> PixelSignals(const PhotoCamera& camera, const std::vector<double>& corner_slopes, uint64_t seed_key,
                                 const RayLight& light);

// What the sensor records of `signals` (fraction of full scale, [row][col]): blurred, noisy, clipped, through
// its response and rounding; one channel "Y". `seed_key` picks the noise.
Image RecordOnSensor(const PhotoCamera& camera, std::vector<double> signals, uint64_t seed_key);

}  // namespace layerlab
