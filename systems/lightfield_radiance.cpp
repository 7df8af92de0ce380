#include "systems/lightfield_radiance.h"

#include <algorithm>
#include <cmath>

namespace layerlab {
namespace {

// Cell-centered samples at lo + (k + 0.5) step: the two around `at` and the
// weight of the second, clamped to the edge samples.
struct Bracket {
  int k0, k1;
  double w1;
};
Bracket Around(double at, double lo, double step, int count) {
  double f = (at - lo) / step - 0.5;
  if (!(f > 0)) return {0, 0, 0.0};
  if (f >= count - 1) return {count - 1, count - 1, 0.0};
  int k = static_cast<int>(f);
  return {k, k + 1, f - k};
}

// The cell of `count` cells of `step` from `lo` that contains `at`, as a bracket of one.
Bracket Containing(double at, double lo, double step, int count) {
  int k = std::clamp(static_cast<int>(std::floor((at - lo) / step)), 0, count - 1);
  return {k, k, 0.0};
}

}  // namespace

SceneRadiance LightFieldRadiance(const LightField& lf, Sampling pixels) {
  const bool nearest = pixels == Sampling::kNearest;
  return [&lf, nearest](const PupilPoint& u, double dx, double dy) -> Rgb {
    const LightFieldGeometry& g = lf.geometry;
    const double x = u.x + dx * g.origin_z, y = u.y + dy * g.origin_z;
    const double pixel_w = g.window_width / g.cols, pixel_h = g.window_height / g.rows;
    // Outside the window there is no light field: dark, not the edge pixel.
    if (x < g.window_left || x > g.window_left + g.window_width || y > g.window_top ||
        y < g.window_top - g.window_height)
      return {0, 0, 0};
    const Bracket col =
        nearest ? Containing(x, g.window_left, pixel_w, g.cols) : Around(x, g.window_left, pixel_w, g.cols);
    const Bracket row = nearest ? Containing(g.window_top - y, 0.0, pixel_h, g.rows)  // rows run down
                                : Around(g.window_top - y, 0.0, pixel_h, g.rows);
    const Bracket vcol = Around(u.x, -g.eyebox_width / 2, g.eyebox_width / g.views_x, g.views_x);
    const Bracket vrow = Around(g.eyebox_height / 2 - u.y, 0.0, g.eyebox_height / g.views_y, g.views_y);

    Rgb sum{0, 0, 0};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const double w_view = (a ? vrow.w1 : 1 - vrow.w1) * (b ? vcol.w1 : 1 - vcol.w1);
        if (w_view == 0) continue;
        const float* view = lf.view(g.view_index(a ? vrow.k1 : vrow.k0, b ? vcol.k1 : vcol.k0));
        for (int c = 0; c < 2; ++c)
          for (int d = 0; d < 2; ++d) {
            const double w = w_view * (c ? row.w1 : 1 - row.w1) * (d ? col.w1 : 1 - col.w1);
            if (w == 0) continue;
            const float* p = view + (static_cast<size_t>(c ? row.k1 : row.k0) * g.cols + (d ? col.k1 : col.k0)) * 3;
            for (int ch = 0; ch < 3; ++ch) sum[ch] += w * p[ch];
          }
      }
    return sum;
  };
}

}  // namespace layerlab
