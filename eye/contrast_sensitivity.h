// The eye's contrast sensitivity by spatial frequency, as a weight for
// retinal-space errors: the Mannos and Sakrison (1974) model
//   S(f) = 2.6 (0.0192 + 0.114 f) exp(-(0.114 f)^1.1),  f in cycles per degree,
// divided by its peak (S is largest at f_peak = 7.89 cpd) and held at 1
// below the peak, so that errors of the mean and of coarse detail count
// fully (the low-pass form image-quality metrics use) and finer detail
// counts as much as the eye sees it: 0.50 at 20.3 cpd, 0.10 at 35.7 cpd.
#pragma once

namespace layerlab {

// S at f (cycles per degree, >= 0), as above; 1 at and below the peak.
double ContrastSensitivityWeight(double cycles_per_degree);
// Where S peaks, in cycles per degree.
double ContrastSensitivityPeak();

}  // namespace layerlab
