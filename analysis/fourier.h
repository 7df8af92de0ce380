// Contrast of a retinal image at one angular frequency.
#pragma once

#include <vector>

namespace layerlab {

// The amplitude of the component of frequency `cycles_per_degree` in the
// samples `values` taken at `degrees` (uniformly spaced): 2/N |sum v e^{-2 pi i f a}|.
// Exact for a cosine when the samples span a whole number of cycles.
double FourierAmplitude(const std::vector<double>& values, const std::vector<double>& degrees,
                        double cycles_per_degree);

// The largest whole number of cycles of `cycles_per_degree` that fits in `count`
// samples of `resolution_deg`, as a sample count (at least 1).
int WholeCycleSamples(int count, double resolution_deg, double cycles_per_degree);

// The peak of a sampled curve: the grid argmax, and the vertex of the parabola
// through it and its neighbours (the grid value at an end of the range).
struct Peak {
  double at_grid = 0;      // the x of the largest sample
  double at_parabola = 0;  // refined
  double value = 0;        // the largest sample
};
Peak FindPeak(const std::vector<double>& x, const std::vector<double>& y);

// A peak with its sampling uncertainty, from the curve `y` and the same curve
// sampled differently (`y_other`, e.g. the retina moved by half a sample;
// may be empty): the uncertainty is how far the two parabola peaks lie apart.
// The curve is too flat to place a peak ("flat") when that exceeds
// `flat_limit`, or when either curve's maximum is at an end of the range or
// its top is not concave (no parabola vertex).
struct PeakEstimate {
  double at = 0;           // the parabola peak of y
  double uncertainty = 0;  // same units as x
  bool flat = false;
};
PeakEstimate EstimatePeak(const std::vector<double>& x, const std::vector<double>& y,
                          const std::vector<double>& y_other, double flat_limit);

}  // namespace layerlab
