// Where a ray crossing the eyebox reads a light field (docs/lightfield-format.md):
// the views around its pupil point, blended bilinearly, and in each view the
// pixel columns and rows around its crossing of the origin plane, by the
// layers' sampling rule. Natural viewing (retina/lightfield_radiance.cpp)
// and the retinal operator's tables and their transpose read by these rules.
#pragma once

#include <algorithm>
#include <cmath>

#include "layerlab/framework/lightfield.h"
#include "layerlab/retina/scene_radiance.h"

namespace layerlab::lightfield_taps {

// Cell-centered samples at lo + (k + 0.5) step: the two around `at` and the
// weight of the second, clamped to the edge samples.
struct Bracket {
  int k0, k1;
  double w1;
};
inline Bracket Around(double at, double lo, double step, int count) {
  double f = (at - lo) / step - 0.5;
  if (!(f > 0)) return {0, 0, 0.0};
  if (f >= count - 1) return {count - 1, count - 1, 0.0};
  int k = static_cast<int>(f);
  return {k, k + 1, f - k};
}

// The cell of `count` cells of `step` from `lo` that contains `at`, as a bracket of one.
inline Bracket Containing(double at, double lo, double step, int count) {
  int k = std::clamp(static_cast<int>(std::floor((at - lo) / step)), 0, count - 1);
  return {k, k, 0.0};
}

// The pixel columns a ray crossing the origin plane at x reads; false outside the window.
inline bool ColumnAt(const LightFieldGeometry& g, double x, bool nearest, Bracket* col) {
  if (x < g.window_left_m || x > g.window_left_m + g.window_width_m) return false;
  const double pixel_w = g.window_width_m / g.cols;
  *col = nearest ? Containing(x, g.window_left_m, pixel_w, g.cols) : Around(x, g.window_left_m, pixel_w, g.cols);
  return true;
}
// The pixel rows at height y (rows run down from the window's top).
inline bool RowAt(const LightFieldGeometry& g, double y, bool nearest, Bracket* row) {
  if (y > g.window_top_m || y < g.window_top_m - g.window_height_m) return false;
  const double pixel_h = g.window_height_m / g.rows;
  *row =
      nearest ? Containing(g.window_top_m - y, 0.0, pixel_h, g.rows) : Around(g.window_top_m - y, 0.0, pixel_h, g.rows);
  return true;
}

// The views around pupil point u and their weights, (view row a, view column b) for a, b in {0, 1}.
struct ViewWeights {
  size_t view[2][2];
  double weight[2][2];
};
inline ViewWeights ViewsAround(const LightFieldGeometry& g, const PupilPoint& u) {
  const Bracket vcol = Around(u.x_m, -g.eyebox_width_m / 2, g.eyebox_width_m / g.views_x, g.views_x);
  const Bracket vrow = Around(g.eyebox_height_m / 2 - u.y_m, 0.0, g.eyebox_height_m / g.views_y, g.views_y);
  ViewWeights v;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      v.weight[a][b] = (a ? vrow.w1 : 1 - vrow.w1) * (b ? vcol.w1 : 1 - vcol.w1);
      v.view[a][b] = g.view_index(a ? vrow.k1 : vrow.k0, b ? vcol.k1 : vcol.k0);
    }
  return v;
}

}  // namespace layerlab::lightfield_taps
