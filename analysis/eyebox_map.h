// The display seen from across the eyebox and over the gaze: at each pupil
// position of a grid (the gaze straight ahead) and each gaze of a grid (the
// eye's centre of rotation on the axis), the retinal image of the display
// against that of the target from the same pupil.
//
//   eyebox.csv   one row per pose: pupil_x_mm, pupil_y_mm, gaze_x_deg, gaze_y_deg,
//                psnr_db (peak 1, display-relative), display_mean_cd_m2,
//                natural_mean_cd_m2, brightness_ratio (display mean over the
//                centre pose's), vignetting (1 - a full-white display's mean
//                over the centre pose's)
//   eyebox.svg   PSNR and brightness over the pupil grid and over the gaze grid
//   swim.csv     behind real optics: each layer's pupil swim (systems/pupil_swim.h),
//   swim.svg     one row per field point and pupil position, in arcmin
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "layerlab/retina/retina.h"
#include "layerlab/systems/display_model.h"
#include "layerlab/systems/pupil_swim.h"

namespace layerlab {

struct EyeboxMapOptions {
  double accommodation_diopters = 0;
  std::array<double, 2> pupil_half_range_m = {0.002, 0.002};  // m: the grid spans -half .. +half
  double pupil_step_m = 0.001;                                // m; 0 with a zero range
  std::array<double, 2> gaze_half_range_rad = {0, 0};         // rad; {0, 0}: no gaze grid
  double gaze_step_rad = 0;                                   // rad
  double resolution_deg = 0.1;                                // per retinal sample
  std::array<double, 2> field_deg = {0, 0};                   // of the pupil grid's images; 0: the display's field
  std::array<double, 2> gaze_field_deg = {10, 10};            // of the gaze grid's, centred on each gaze
  double quality_db = 1.0;  // the eyebox: where the PSNR stays within this of the centre's
};

struct EyeboxPoseResult {
  EyePose pose;
  double psnr_db = 0;
  double display_mean_cd_m2 = 0, natural_mean_cd_m2 = 0;
  double brightness_ratio = 1, vignetting = 0;  // against the centre pose of its grid
};

// One grid of poses, row-major from the top row (+y) and the left column (-x).
struct EyeboxGrid {
  int cols = 0, rows = 0;
  double step = 0;  // m for the pupil grid, rad for the gaze grid
  std::vector<EyeboxPoseResult> poses;
  size_t centre_index() const { return size_t(rows / 2) * cols + cols / 2; }
  const EyeboxPoseResult& centre() const { return poses[centre_index()]; }
  // Through the centre along x and y: the extent of the run of poses whose
  // PSNR is within `quality_db` of the centre's (m or rad), and whether the
  // run reaches the grid's edge (so the eyebox is at least that).
  std::array<double, 2> within(double quality_db) const;
  std::array<bool, 2> within_reaches_edge(double quality_db) const;
};

struct EyeboxMap {
  EyeboxGrid pupil, gaze;  // gaze: empty without a gaze range
  double quality_db = 0;
};

// Throws Error, naming the option ("--eyebox-range", "--gaze-range"), for a grid
// whose gaze leaves the display's field, or whose pupil leaves the eyebox
// when `natural` is a light field's (LightFieldRadiance: it holds rays only
// across its eyebox; a traced target scene is seen from anywhere), before
// computing anything. `natural` is required.
EyeboxMap MapEyebox(const DisplayModel& model, const Patterns& t, const SceneRadiance& natural,
                    const EyeboxMapOptions& options,
                    const std::function<void(size_t done, size_t total)>& progress = {});

// eyebox.csv and eyebox.svg into `folder` (which must exist).
void WriteEyeboxMap(const EyeboxMap& map, const std::string& folder);

// swim.csv and swim.svg into `folder`: the swim along x of the field points
// on each layer's horizontal midline as the pupil moves along x.
void WritePupilSwim(const std::vector<LayerSwim>& swim, const std::string& folder);

}  // namespace layerlab
