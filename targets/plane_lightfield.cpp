#include "layerlab/targets/plane_lightfield.h"

#include <algorithm>
#include <vector>

#include "layerlab/targets/pixel_sampling.h"

namespace layerlab {

LightField RenderPlaneLightField(const LightFieldGeometry& g, double z, const Texture& texture,
                                 const PlaneSampling& sampling, std::array<double, 2> center) {
  LightField lf(g);
  lf.depth.assign(g.ray_count(), static_cast<float>(z));
  lf.scene = "plane at " + FormatFixed(1.0 / z, 2) + " D (" + texture.Describe() + ")";
  const PixelSampler sampler(g, sampling.samples_per_pixel, sampling.seed);
  const double s = z / g.origin_z_m;
  // Pixel (i, j) of the view at (vx, vy) into out.
  auto pixel = [&](double vx, double vy, int i, int j, float* out) {
    double sum[3] = {0, 0, 0};
    for (int k = 0; k < sampler.samples(); ++k) {
      auto [x, y] = sampler.Sample(i, j, k);
      Rgb c = texture.Evaluate(vx + (x - vx) * s - center[0], vy + (y - vy) * s - center[1]);
      for (int ch = 0; ch < 3; ++ch) sum[ch] += c[ch];
    }
    for (int ch = 0; ch < 3; ++ch) out[ch] = static_cast<float>(sum[ch] / sampler.samples());
  };
  if (sampler.samples() == 1 && texture.ConstantAlongT()) {
    // A pixel's center depends on its column alone, and t does not matter:
    // one row per view column, copied to every row of its views (the
    // contrast sweep renders a grating for every curve; cos and atan per
    // ray were a tenth of its time).
#pragma omp parallel for schedule(static)
    for (int vc = 0; vc < g.views_x; ++vc) {
      std::vector<float> row(static_cast<size_t>(g.cols) * 3);
      const double vx = g.view_x(vc), vy = g.view_y(0);
      for (int j = 0; j < g.cols; ++j) pixel(vx, vy, 0, j, &row[static_cast<size_t>(j) * 3]);
      for (int vr = 0; vr < g.views_y; ++vr)
        for (int i = 0; i < g.rows; ++i)
          std::copy(row.begin(), row.end(), lf.view(g.view_index(vr, vc)) + static_cast<size_t>(i) * g.cols * 3);
    }
    return lf;
  }
#pragma omp parallel for schedule(dynamic)
  for (size_t view = 0; view < g.view_count(); ++view) {
    const double vx = g.view_x(static_cast<int>(view % g.views_x));
    const double vy = g.view_y(static_cast<int>(view / g.views_x));
    float* out = lf.view(view);
    for (int i = 0; i < g.rows; ++i)
      for (int j = 0; j < g.cols; ++j) pixel(vx, vy, i, j, out + (static_cast<size_t>(i) * g.cols + j) * 3);
  }
  return lf;
}

}  // namespace layerlab
