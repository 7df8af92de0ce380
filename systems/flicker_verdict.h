// Whether a time-multiplexed display flickers visibly: the worst region of
// its field and the temporal harmonic of its luminance there that is most
// visible (analysis/flicker_check.h computes it; eye/temporal_csf.h is the
// eye's sensitivity). A display of one subframe shows a steady image.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace layerlab {

struct FlickerVerdict {
  // max over the regions and harmonics of m S(f; L, area, eccentricity): above 1 the flicker is visible.
  double visibility = 0;
  double frequency_hz = 0;      // the worst harmonic's frequency (n x the frame rate)
  double modulation = 0;        // its amplitude over the region's mean luminance
  double luminance_cd_m2 = 0;   // the worst region's mean luminance
  double x_deg = 0, y_deg = 0;  // the worst region's centre in the visual field (gaze straight ahead; +y up)
  double region_w_deg = 0, region_h_deg = 0;  // the worst region's extent
  double cff_hz = 0;                          // the critical flicker frequency of that region at that modulation
  std::string what;                           // the content checked ("the solved patterns", "the worst case: ...")

  bool visible() const { return visibility > 1; }
  // One line: "flicker visible: ..." or "no visible flicker: ...".
  std::string Describe() const;
  nlohmann::json ToJson() const;
};

}  // namespace layerlab
