// Retinal images over accommodation, written to a folder: what the eye sees
// of the display at each state, and of the target itself (natural viewing)
// when a scene radiance is given.
//
//   display/<state>.exr, .png   linear display-relative RGB; sRGB PNG with 1 =
//                               the brightest branch's full white (values
//                               above are clipped and counted in retina.csv)
//   natural/<state>.exr, .png   the same for natural viewing
//   see_through/<state>.exr, .png  a see-through display's image with the
//                               world's light added (systems/world_view.h)
//   retina.csv                  one row per state: mean luminance (cd/m2), clipping, seconds; with a world,
//                               the world's luminance at the eye and the display's contrast against it
// <state> is the accommodation with two decimals: "0.40D".
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "layerlab/framework/exr_image.h"
#include "layerlab/metrics/retinal_metrics.h"
#include "layerlab/retina/retina.h"
#include "layerlab/systems/display_model.h"

namespace layerlab {

struct RetinaSweepOptions {
  std::vector<double> states_diopters;      // in the order written
  double resolution_deg = 0.05;             // per sample
  double field_x_deg = 0, field_y_deg = 0;  // 0: the display's field of view
  bool keep_images = false;                 // also return each state's images (RetinaStateResult::display, natural)
  // With natural viewing, each state's display image is scored against it by these (metrics/retinal_metrics.h;
  // empty: PSNR alone), one retina.csv column each.
  std::vector<const RetinalMetric*> metrics;
  // Foveal weighting (a gaze, deg right and up from the retina's centre, where the eye looks: {0, 0}) and the
  // JND's Minkowski exponent (metrics/retinal_metrics.h).
  MetricSettings metric_settings;
  // The EXRs of the images: half floats by default (pictures to look at; the scores and retina.csv come from
  // the float images in memory), float on request.
  ExrPixels exr_pixels = ExrPixels::kHalf;
  // A see-through display's worlds along each ray, cd/m^2 at the eye (analysis/world_scene.h,
  // WorldSceneRadiance); empty: its worlds are uniform (systems/world_view.h, WorldAtEye).
  SceneRadiance world;
};

// Accommodation states as `layerlab retina` takes them (ParseOptionValue:
// finite, >= 0 D): at least one, each a finite number of diopters >= 0.
// Throws Error naming `name` and the state's index ("accommodation[1]: nan
// ..."). The field and sample size have their own check, CheckRetinaSampling
// (retina/retina.h); WriteRetinaSweep and the Python module make both.
void CheckAccommodationStates(const std::vector<double>& states, const std::string& name);

struct RetinaStateResult {
  double diopters = 0;
  std::string name;  // "0.40D": the file stem in display/ and natural/
  double display_mean_cd_m2 = 0;
  double natural_mean_cd_m2 = 0;  // NaN without natural viewing
  // The display's image against natural viewing, by each metric: (column, value), PSNR first; NaN without
  // natural viewing.
  std::vector<std::pair<std::string, double>> scores;
  size_t display_clipped_in_png = 0;
  // The PNGs' size: the retina's, reduced by png_factor to kRetinaWidthPx where it is wider (framework/shown_image.h).
  int png_width = 0, png_height = 0, png_factor = 1;
  double seconds = 0;      // spent on its images and files (the files of a few states are written at once)
  Image display, natural;  // with RetinaSweepOptions::keep_images (natural: with natural viewing), else empty
  // See-through: the world's luminance at the eye (cd/m2), and (display_mean + world) / world; 0 and NaN without.
  double world_cd_m2 = 0, contrast_against_world = NAN;
};

std::string RetinaStateName(double diopters);

// Each metric's mean over the states (the focal stack's score), the metric found by its retina.csv column;
// empty without natural viewing (the scores are NaN) or without states.
struct MeanScore {
  const RetinalMetric* metric;
  double mean;
};
std::vector<MeanScore> MeanScoresOverStates(const std::vector<RetinaStateResult>& states);

// The mean luminance of a linear RGB image (kLuminanceWeights), in its units.
double MeanLuminance(const Image& image);

// Writes the folder (creating it); `progress` gets each state as it is done.
// `natural` may be empty. Throws layerlab::Error for bad options.
std::vector<RetinaStateResult> WriteRetinaSweep(
    const DisplayModel& model, const Patterns& t, const SceneRadiance& natural, const RetinaSweepOptions& options,
    const std::string& folder,
    const std::function<void(size_t done, size_t total, const RetinaStateResult&)>& progress = {});

}  // namespace layerlab
