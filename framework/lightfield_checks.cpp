#include "layerlab/framework/lightfield_checks.h"

#include <cmath>

#include "layerlab/framework/checked_count.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/exr_image.h"
#include "layerlab/framework/units.h"

namespace layerlab {

void CheckLightFieldGeometry(const LightFieldGeometry& g, const GeometryFailure& fail) {
  auto fail_now = [&](const std::string& field, const std::string& why) {
    fail(field, why);
    throw Error("internal error: a light-field geometry check did not throw for " + field);
  };
  auto length = [&](const std::string& field, double x, bool zero_allowed, double max) {
    if (!std::isfinite(x) || (zero_allowed ? x < 0 : x <= 0) || x > max)
      fail_now(field, "must be in " + std::string(zero_allowed ? "[" : "(") + "0, " + FormatGeneral(max) + "] m, got " +
                          FormatGeneral(x));
  };
  auto count = [&](const std::string& field, int n, int max) {
    if (n < 1 || n > max) fail_now(field, "must be in [1, " + std::to_string(max) + "], got " + std::to_string(n));
  };
  length("origin_z", g.origin_z_m, false, 1e6);
  if (!std::isfinite(g.window_left_m)) fail_now("window_left", "must be finite, got " + FormatGeneral(g.window_left_m));
  if (!std::isfinite(g.window_top_m)) fail_now("window_top", "must be finite, got " + FormatGeneral(g.window_top_m));
  length("window_width", g.window_width_m, false, 1e6);
  length("window_height", g.window_height_m, false, 1e6);
  count("cols", g.cols, kMaxPixelsPerAxis);
  count("rows", g.rows, kMaxPixelsPerAxis);
  count("views_x", g.views_x, kMaxViewsPerAxis);
  count("views_y", g.views_y, kMaxViewsPerAxis);
  length("eyebox_width", g.eyebox_width_m, true, 1.0);
  length("eyebox_height", g.eyebox_height_m, true, 1.0);
  const size_t rays = CheckedProduct({size_t(g.views_x), size_t(g.views_y), size_t(g.cols), size_t(g.rows)},
                                     "light-field rays (views x pixels)");
  if (rays > kMaxRays)
    fail_now("rays", std::to_string(g.views_y) + " x " + std::to_string(g.views_x) + " views of " +
                         std::to_string(g.cols) + " x " + std::to_string(g.rows) + " pixels: " + std::to_string(rays) +
                         " rays (views x pixels) is beyond the 2^31 this layerlab handles");
}

void CheckLightFieldValues(const LightField& lf, const std::string& what) {
  const LightFieldGeometry& g = lf.geometry;
  const size_t values = g.pixels_per_view() * 3;
  for (size_t v = 0; v < g.view_count(); ++v) {
    const std::string why = FindValueThatIsNotLight(lf.view(v), values, g.cols, {"R", "G", "B"});
    if (why.empty()) continue;
    throw Error(what + ": view " + std::to_string(v) + " (row " + std::to_string(v / g.views_x) + ", col " +
                std::to_string(v % g.views_x) + "): " + why);
  }
}

}  // namespace layerlab
