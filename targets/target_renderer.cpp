#include "layerlab/targets/target_renderer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <vector>

#include <tbb/parallel_for.h>

#include "layerlab/targets/pixel_sampling.h"
#include "layerlab/targets/plane_wave_table.h"
#include "layerlab/targets/target_tracer.h"

namespace layerlab {
namespace {

// The rays a view traces as one stream, at most (a block of a row's pixels, their samples and centres).
constexpr size_t kRaysPerStream = 4096;
// A plane-wave table of a block is made when it takes at most this much and more than one view reads it.
constexpr size_t kTableBytes = size_t(32) << 20;

// A block of one pixel row, in every view. Its samples' points on the origin plane are the same in every
// view (pixel_sampling.h), so the phases of a plane-wave texture at those points are computed once for the
// block (plane_wave_table.h), and each view traces the block's rays as one coherent stream.
class RowRenderer {
 public:
  RowRenderer(const TargetScene& target, const TargetTracer& tracer, const PixelSampler& sampler, int row,
              int first_col, int cols)
      : g_(target.geometry), tracer_(tracer), n_(sampler.samples()), row_(row), first_col_(first_col), cols_(cols) {
    for (int j = first_col; j < first_col + cols; ++j)
      for (int k = 0; k < n_; ++k) points_.push_back(sampler.Sample(row, j, k));
    if (n_ > 1)
      for (int j = first_col; j < first_col + cols; ++j) points_.push_back({g_.pixel_x(j), g_.pixel_y(row)});
    const size_t samples = size_t(cols) * n_;
    tables_.resize(target.planes.size());
    for (size_t p = 0; p < target.planes.size(); ++p) {
      const TargetPlane& plane = target.planes[p];
      const PlaneWaves* waves = plane.texture->plane_waves();
      if (waves && g_.view_count() > 1 && samples * 2 * waves->kx.size() * sizeof(double) <= kTableBytes) {
        tables_[p].emplace(*waves, plane.depth_m, plane.center_m, g_.origin_z_m);
        tables_[p]->SetPoints(std::span(points_).first(samples));
      }
    }
    phases_.resize(target.planes.size());
    slopes_.resize(points_.size());
    hits_.resize(points_.size());
  }

  // Renders the row in `view` into `lf`; returns the rays traced.
  uint64_t RenderView(size_t view, LightField* lf) {
    const double vx = g_.view_x(static_cast<int>(view % g_.views_x));
    const double vy = g_.view_y(static_cast<int>(view / g_.views_x));
    const double z_lf = g_.origin_z_m;
    for (size_t i = 0; i < points_.size(); ++i) slopes_[i] = {(points_[i][0] - vx) / z_lf, (points_[i][1] - vy) / z_lf};
    tracer_.IntersectFrom(vx, vy, slopes_, hits_);
    for (size_t p = 0; p < tables_.size(); ++p)
      if (tables_[p]) tables_[p]->PhasesOfView(vx, vy, &phases_[p]);
    const size_t first = size_t(row_) * g_.cols + first_col_;
    float* rgb = lf->view(view) + first * 3;
    float* depth = lf->depth.data() + view * g_.pixels_per_view() + first;
    for (int j = 0; j < cols_; ++j) {
      double sum[3] = {0, 0, 0};
      for (int k = 0; k < n_; ++k) {
        const size_t s = size_t(j) * n_ + k;
        const Rgb color = Color(s, vx, vy);
        for (int ch = 0; ch < 3; ++ch) sum[ch] += color[ch];
      }
      const size_t centre = n_ > 1 ? size_t(cols_) * n_ + j : size_t(j);
      const double z = tracer_.Depth(hits_[centre], vx, vy, slopes_[centre][0], slopes_[centre][1]);
      if (std::isfinite(z)) depth[j] = static_cast<float>(z);
      for (int ch = 0; ch < 3; ++ch) rgb[size_t(j) * 3 + ch] = static_cast<float>(sum[ch] / n_);
    }
    return points_.size();
  }

 private:
  Rgb Color(size_t s, double vx, double vy) const {
    const int plane = tracer_.PlaneOf(hits_[s]);
    if (plane >= 0 && tables_[plane]) {
      const double value = tables_[plane]->Value(s, phases_[plane]);
      return {value, value, value};
    }
    return tracer_.Shade(hits_[s], vx, vy, slopes_[s][0], slopes_[s][1]).color;
  }

  const LightFieldGeometry& g_;
  const TargetTracer& tracer_;
  const int n_, row_, first_col_, cols_;
  std::vector<std::array<double, 2>> points_;          // the row's samples, pixel by pixel; then its centres when n > 1
  std::vector<std::optional<PlaneWaveTable>> tables_;  // per plane: the row's plane-wave phases
  std::vector<PlaneWaveTable::ViewPhases> phases_;     // per plane: the view's
  std::vector<std::array<double, 2>> slopes_;          // the view's ray directions (dx, dy, 1)
  std::vector<RayHit> hits_;
};

}  // namespace

LightField RenderTarget(const TargetScene& target, RenderStats* stats, const RenderProgress& progress) {
  auto start = std::chrono::steady_clock::now();
  const LightFieldGeometry& g = target.geometry;
  TargetTracer tracer(target);
  LightField lf(g);
  lf.scene = target.description;
  lf.depth.assign(g.ray_count(), kBackgroundDepth);
  const PixelSampler sampler(g, target.samples_per_pixel, target.seed);
  std::atomic<uint64_t> rays{0};
  std::atomic<size_t> rows_done{0};

  const int rays_per_pixel = sampler.samples() + (sampler.samples() > 1 ? 1 : 0);
  const int block = std::max(1, int(kRaysPerStream / size_t(rays_per_pixel)));
  tbb::parallel_for(0, g.rows, [&](int row) {
    uint64_t row_rays = 0;
    for (int first_col = 0; first_col < g.cols; first_col += block) {
      RowRenderer renderer(target, tracer, sampler, row, first_col, std::min(block, g.cols - first_col));
      for (size_t view = 0; view < g.view_count(); ++view) row_rays += renderer.RenderView(view, &lf);
    }
    rays += row_rays;
    size_t done = ++rows_done;
    if (progress) progress(done, size_t(g.rows));
  });

  if (stats) {
    stats->rays = rays;
    stats->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return lf;
}

}  // namespace layerlab
