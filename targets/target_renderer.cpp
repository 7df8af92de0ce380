#include "layerlab/targets/target_renderer.h"

#include <atomic>
#include <chrono>
#include <cmath>

#include <tbb/parallel_for.h>

#include "layerlab/targets/pixel_sampling.h"
#include "layerlab/targets/target_tracer.h"

namespace layerlab {

LightField RenderTarget(const TargetScene& target, RenderStats* stats, const RenderProgress& progress) {
  auto start = std::chrono::steady_clock::now();
  const LightFieldGeometry& g = target.geometry;
  TargetTracer tracer(target);
  LightField lf(g);
  lf.scene = target.description;
  lf.depth.assign(g.ray_count(), kBackgroundDepth);
  const PixelSampler sampler(g, target.samples_per_pixel, target.seed);
  const int n = sampler.samples();
  std::atomic<uint64_t> rays{0};
  std::atomic<size_t> views_done{0};

  tbb::parallel_for(size_t{0}, g.view_count(), [&](size_t view) {
    const double vx = g.view_x(static_cast<int>(view % g.views_x));
    const double vy = g.view_y(static_cast<int>(view / g.views_x));
    float* rgb = lf.view(view);
    float* depth = lf.depth.data() + view * g.pixels_per_view();
    uint64_t view_rays = 0;
    for (int i = 0; i < g.rows; ++i)
      for (int j = 0; j < g.cols; ++j) {
        double sum[3] = {0, 0, 0};
        for (int k = 0; k < n; ++k) {
          auto [x, y] = sampler.Sample(i, j, k);
          TracedSample s = tracer.Trace(vx, vy, x, y);
          for (int ch = 0; ch < 3; ++ch) sum[ch] += s.color[ch];
          if (n == 1 && std::isfinite(s.z)) depth[static_cast<size_t>(i) * g.cols + j] = static_cast<float>(s.z);
        }
        view_rays += n;
        if (n > 1) {
          TracedSample center = tracer.Trace(vx, vy, g.pixel_x(j), g.pixel_y(i));
          if (std::isfinite(center.z)) depth[static_cast<size_t>(i) * g.cols + j] = static_cast<float>(center.z);
          ++view_rays;
        }
        size_t p = (static_cast<size_t>(i) * g.cols + j) * 3;
        for (int ch = 0; ch < 3; ++ch) rgb[p + ch] = static_cast<float>(sum[ch] / n);
      }
    rays += view_rays;
    size_t done = ++views_done;
    if (progress) progress(done, g.view_count());
  });

  if (stats) {
    stats->rays = rays;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return lf;
}

}  // namespace layerlab
