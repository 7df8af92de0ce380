// The metrics a display's retinal image is scored by against natural viewing
// of its target (docs/metrics.md): registered by name, each with the column
// it writes, its unit and which way is better. Every one is a function of
// one file in metrics/ (psnr.h, ssim.h, csf_jnd.h); the registry says how a
// retinal image (linear RGB, display-relative) is handed to it:
//   psnr     every pixel and channel, peak 1                  (psnr.h)
//   ssim     the sRGB-encoded luminance, data range 1         (ssim.h)
//   ms_ssim  the same, at least kMsSsimMinSide on each side   (ssim.h)
//   jnd      the luminance in cd/m2 (times the display's white), Barten's
//            CSF at the images' sampling, Minkowski exponent 4 unless the
//            user sets it (MetricSettings; csf_jnd.h)
// A luminance below 0 by at most kRingingFloor (the wave-optics eye's
// transform can ring that far below a black edge) counts as 0; lower, or
// undefined, is refused naming its pixel.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/framework/exr_image.h"

namespace layerlab {

inline constexpr double kRingingFloor = 1e-3;

inline constexpr double kDefaultJndExponent = 4;

// What a user sets of the metrics (retina, compare, run, sweep and Python take them alike).
struct MetricSettings {
  // Weight every metric's mean by eccentricity from this gaze (deg right, up from the image's centre;
  // foveal_weight.h); empty: uniform.
  std::optional<std::array<double, 2>> fovea_deg;
  double jnd_minkowski_exponent = kDefaultJndExponent;  // the JND metric's pooling, >= 1
  bool operator==(const MetricSettings&) const = default;
};
// Throws layerlab::Error naming `exponent_field` for an exponent below 1 or not finite, `fovea_field` for a
// gaze not finite.
void CheckMetricSettings(const MetricSettings& s, const std::string& exponent_field, const std::string& fovea_field);

// What the metrics need beyond the two images.
struct MetricViewing {
  double pixel_deg = 0;    // the images' sampling, both axes
  double white_cd_m2 = 0;  // the luminance of display-relative 1
  // Every metric's mean over the image weighted by eccentricity from the gaze (foveal_weight.h), the gaze
  // measured from the image's centre (deg right, up).
  bool foveal = false;
  double gaze_x_deg = 0, gaze_y_deg = 0;
  double jnd_minkowski_exponent = kDefaultJndExponent;

  static MetricViewing Of(double pixel_deg, double white_cd_m2, const MetricSettings& s) {
    return {pixel_deg,
            white_cd_m2,
            s.fovea_deg.has_value(),
            s.fovea_deg ? (*s.fovea_deg)[0] : 0.0,
            s.fovea_deg ? (*s.fovea_deg)[1] : 0.0,
            s.jnd_minkowski_exponent};
  }
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
