// The metrics a display's retinal image is scored by against natural viewing
// of its target (docs/metrics.md): registered by name, each with the column
// it writes, its unit and which way is better. Every one is a function of
// one file in metrics/ (psnr.h, ssim.h, csf_jnd.h); the registry says how a
// retinal image (linear RGB, display-relative) is handed to it:
//   psnr     every pixel and channel, peak 1                  (psnr.h)
//   ssim     the sRGB-encoded luminance, data range 1         (ssim.h)
//   ms_ssim  the same, at least kMsSsimMinSide on each side   (ssim.h)
//   jnd      the luminance in cd/m2 (times the display's white), Barten's
//            CSF at the images' sampling, Minkowski exponent 4 (csf_jnd.h)
// A luminance below 0 by at most kRingingFloor (the wave-optics eye's
// transform can ring that far below a black edge) counts as 0; lower, or
// undefined, is refused naming its pixel.
#pragma once

#include <string>
#include <vector>

#include "layerlab/framework/exr_image.h"

namespace layerlab {

inline constexpr double kRingingFloor = 1e-3;

// What the metrics need beyond the two images.
struct MetricViewing {
  double pixel_deg = 0;    // the images' sampling, both axes
  double white_cd_m2 = 0;  // the luminance of display-relative 1
  // Every metric's mean over the image weighted by eccentricity from the gaze (foveal_weight.h), the gaze
  // measured from the image's centre (deg right, up).
  bool foveal = false;
  double gaze_x_deg = 0, gaze_y_deg = 0;
};

struct RetinalMetric {
  std::string name;    // as --metrics and Python take it
  std::string column;  // in retina.csv, compare.csv and the reports
  std::string unit;    // "dB", "JND", or "" for a score in [0, 1]
  bool higher_is_better = true;
  int min_side = 0;  // the least width and height it takes
  std::string meaning;
  double (*score)(const Image& display, const Image& reference, const MetricViewing& viewing) = nullptr;
};

// In the order columns are written: psnr, ssim, ms_ssim, jnd.
const std::vector<RetinalMetric>& RetinalMetrics();

// A comma-separated list of names ("ms_ssim,jnd"; "all": every one), in the
// registry's order, psnr always among them. Throws layerlab::Error naming
// `what` and the known names for an unknown or repeated one.
std::vector<const RetinalMetric*> ParseRetinalMetrics(const std::string& list, const std::string& what);

// Throws layerlab::Error naming `what` when a metric does not take images of width x height.
void CheckMetricSize(const std::vector<const RetinalMetric*>& metrics, int width, int height, const std::string& what);

}  // namespace layerlab
