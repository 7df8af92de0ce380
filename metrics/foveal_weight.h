// A foveal weighting of an image's pixels by their eccentricity from a gaze
// point: the cortical area each covers, the square of the linear cortical
// magnification M(e) = 17.3 / (e + 0.75) mm/deg (Horton and Hoyt, "The
// representation of the visual field in human striate cortex", Arch.
// Ophthalmol. 109, 1991), relative to the fovea's:
//   w(e) = (e2 / (e + e2))^2,   e2 = 0.75 deg,
// so a pixel 0.75 deg out counts a quarter, 7 deg out a hundredth. The
// metrics (ssim.h, csf_jnd.h, psnr.h) take it as a weight per pixel:
// their means over the image become means weighted by it.
#pragma once

#include "layerlab/metrics/ssim.h"

namespace layerlab {

inline constexpr double kFovealE2Deg = 0.75;

// w(e) at eccentricity e (deg).
double FovealWeightAt(double eccentricity_deg);

// The weight of every pixel of a width x height image sampled `pixel_deg`
// apart on both axes, the gaze (gaze_x_deg right, gaze_y_deg up) measured
// from the image's centre. Throws layerlab::Error for an empty image, a
// pitch not above 0, or a gaze that is not finite.
Plane FovealWeight(int width, int height, double pixel_deg, double gaze_x_deg = 0, double gaze_y_deg = 0);

}  // namespace layerlab
