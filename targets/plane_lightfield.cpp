#include "targets/plane_lightfield.h"

#include "targets/pixel_sampling.h"

namespace layerlab {

LightField RenderPlaneLightField(const LightFieldGeometry& g, double z, const Texture& texture,
                                 const PlaneSampling& sampling, std::array<double, 2> center) {
  LightField lf(g);
  lf.depth.assign(g.ray_count(), static_cast<float>(z));
  lf.scene = "plane at " + FormatFixed(1.0 / z, 2) + " D (" + texture.Describe() + ")";
  const PixelSampler sampler(g, sampling.samples_per_pixel, sampling.seed);
  const double s = z / g.origin_z;
#pragma omp parallel for schedule(dynamic)
  for (size_t view = 0; view < g.view_count(); ++view) {
    const double vx = g.view_x(static_cast<int>(view % g.views_x));
    const double vy = g.view_y(static_cast<int>(view / g.views_x));
    float* out = lf.view(view);
    for (int i = 0; i < g.rows; ++i)
      for (int j = 0; j < g.cols; ++j) {
        double sum[3] = {0, 0, 0};
        for (int k = 0; k < sampler.samples(); ++k) {
          auto [x, y] = sampler.Sample(i, j, k);
          Rgb c = texture.Evaluate(vx + (x - vx) * s - center[0], vy + (y - vy) * s - center[1]);
          for (int ch = 0; ch < 3; ++ch) sum[ch] += c[ch];
        }
        for (int ch = 0; ch < 3; ++ch)
          out[(static_cast<size_t>(i) * g.cols + j) * 3 + ch] = static_cast<float>(sum[ch] / sampler.samples());
      }
  }
  return lf;
}

}  // namespace layerlab
