// Where a pixel's samples land on the origin plane. One sample is the pixel
// center; n samples are stratified over the pixel footprint (an nx x ny grid
// of cells, nx * ny = n, as square as n allows) and jittered inside their
// cells by a hash of (seed, row, col), so any thread order gives the same
// image. Every view uses the same jitter: the origin plane is where all views
// share their samples, so a point there has exactly zero disparity.
#pragma once

#include <array>
#include <cstdint>

#include "layerlab/framework/lightfield.h"
#include "layerlab/framework/random.h"

namespace layerlab {

class PixelSampler {
 public:
  PixelSampler(const LightFieldGeometry& g, int samples_per_pixel, uint64_t seed)
      : g_(g), n_(samples_per_pixel), seed_(seed) {
    ny_ = 1;
    for (int d = 1; d * d <= n_; ++d)
      if (n_ % d == 0) ny_ = d;
    nx_ = n_ / ny_;
  }

  int samples() const { return n_; }

  // Origin-plane position (x, y) of sample k of pixel (row i, col j), in every
  // view; in a tile, the same as the whole light field's pixel there.
  std::array<double, 2> Sample(int i, int j, int k) const {
    if (n_ == 1) return {g_.pixel_x(j), g_.pixel_y(i)};
    const int row = g_.first_pixel_row + i;
    uint64_t key = static_cast<uint64_t>(row) * g_.cols + j;
    SplitMix64 random(MixSeed(seed_, key * 4096 + k));
    double cell_x = (k % nx_ + random.uniform()) / nx_;  // in [0, 1) across the pixel, left to right
    double cell_y = (k / nx_ + random.uniform()) / ny_;  // top to bottom
    return {g_.window_left_m + (j + cell_x) * g_.window_width_m / g_.cols, g_.window_y(row + cell_y)};
  }

 private:
  LightFieldGeometry g_;
  int n_, nx_ = 1, ny_ = 1;
  uint64_t seed_;
};

}  // namespace layerlab
