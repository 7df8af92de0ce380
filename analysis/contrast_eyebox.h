// The accommodation response across the eyebox: each display's curves seen
// from a grid of pupil positions (ContrastOptions::eyebox_range_m), their
// peaks against where the pupil is.
//
//   eyebox_peaks.csv  one row per display, target, frequency and pupil position:
//                     display, target_D, frequency_cpd, pupil_x_mm, pupil_y_mm
//                     (the pupil's move from the display eye's), peak_D (the
//                     parabola's), placed (no: too flat to place a peak),
//                     peak_error_D (peak_D - target_D)
//   eyebox_peaks.svg  the peak error along x (pupil y = 0) and along y (x = 0),
//                     a panel per target and frequency, a line per display
#pragma once

#include <string>
#include <vector>

#include "layerlab/analysis/contrast.h"

namespace layerlab {

std::string ContrastEyeboxCsv(const std::vector<ContrastCurve>& curves);
std::string ContrastEyeboxSvg(const std::vector<ContrastCurve>& curves);

}  // namespace layerlab
