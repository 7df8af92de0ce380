#include "layerlab/retina/lightfield_radiance.h"

#include <algorithm>
#include <cmath>

#include "layerlab/framework/rgb4.h"
#include "layerlab/kernels/row_kernels.h"
#include "layerlab/retina/lightfield_taps.h"

namespace layerlab {
namespace {

using namespace lightfield_taps;  // the lookup rules, shared with the retinal operator

// What the rays of one pupil point read, for one focus.
struct PupilTables {
  struct View {
    const float* pixels;
    double weight;
  };
  std::vector<View> views;  // those of nonzero weight
  struct Column {
    int32_t ray, c0, c1;  // retinal column, light-field columns
    float w0, w1;
  };
  std::vector<Column> columns;  // the retinal columns whose rays cross the window
  int c_lo = 0, c_hi = -1;      // the light-field columns they read
  std::vector<Bracket> rows;    // per retinal row; k0 = -1: outside the window
};

PupilTables TablesOf(const LightField& lf, bool nearest, const PupilPoint& u, double focus,
                     const std::vector<double>& tan_x, const std::vector<double>& tan_y) {
  const LightFieldGeometry& g = lf.geometry;
  PupilTables t;
  const ViewWeights v = ViewsAround(g, u);
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      if (v.weight[a][b] != 0) t.views.push_back({lf.view(v.view[a][b]), v.weight[a][b]});
  // The ray's direction and crossing exactly as RetinaOfSceneRayByRay and LightFieldRays compute them.
  t.c_lo = g.cols;
  for (size_t j = 0; j < tan_x.size(); ++j) {
    const double dx = tan_x[j] - u.x_m * focus - u.deviation_x(focus);
    Bracket col;
    if (!ColumnAt(g, u.x_m + dx * g.origin_z_m, nearest, &col)) continue;
    t.columns.push_back({int32_t(j), col.k0, col.k1, float(1 - col.w1), float(col.w1)});
    t.c_lo = std::min(t.c_lo, col.k0), t.c_hi = std::max(t.c_hi, col.k1);
  }
  t.rows.resize(tan_y.size());
  for (size_t i = 0; i < tan_y.size(); ++i) {
    const double dy = tan_y[i] - u.y_m * focus - u.deviation_y(focus);
    if (!RowAt(g, u.y_m + dy * g.origin_z_m, nearest, &t.rows[i])) t.rows[i] = {-1, -1, 0.0};
  }
  return t;
}

// One focus for every channel.
void RetinaAtFocus(const LightField& lf, bool nearest, const RetinaGrid& retina, const std::vector<PupilPoint>& pupil,
                   double focus, RetinaWorkspace* workspace, Image* image) {
  const LightFieldGeometry& g = lf.geometry;
  std::vector<double> tan_x(retina.cols), tan_y(retina.rows);
  for (int j = 0; j < retina.cols; ++j) tan_x[j] = std::tan(retina.angle_x(j));
  for (int i = 0; i < retina.rows; ++i) tan_y[i] = std::tan(retina.angle_y(i));
  std::vector<PupilTables> tables(pupil.size());
#pragma omp parallel for schedule(dynamic)
  for (size_t p = 0; p < pupil.size(); ++p) tables[p] = TablesOf(lf, nearest, pupil[p], focus, tan_x, tan_y);

  const size_t stride = LightFieldRetinaSizes(g, retina, pupil).blended_row;
  const float inverse_count = static_cast<float>(1.0 / pupil.size());
#pragma omp parallel num_threads(workspace->threads())
  {
    // Per pupil point the blended row of the last retinal row, kept while the
    // next row reads the same light-field rows (about two retinal rows a pixel row).
    RetinaThreadWorkspace& mine = workspace->thread();
    std::vector<float>& blended = mine.blended;
    std::vector<Bracket>& blended_rows = mine.blended_rows;
    std::vector<Rgb4>& sum = mine.sum;
    blended.resize(pupil.size() * stride);
    blended_rows.assign(pupil.size(), Bracket{-1, -1, 0.0});
    sum.resize(retina.cols);
#pragma omp for schedule(static)
    for (int i = 0; i < retina.rows; ++i) {
      std::fill(sum.begin(), sum.end(), Rgb4{});
      for (size_t p = 0; p < pupil.size(); ++p) {
        const PupilTables& t = tables[p];
        const Bracket& r = t.rows[i];
        if (r.k0 < 0 || t.columns.empty()) continue;
        float* m = &blended[p * stride];
        const size_t offset = size_t(t.c_lo) * 3, n = size_t(t.c_hi - t.c_lo + 1) * 3;
        Bracket& kept = blended_rows[p];
        if (kept.k0 != r.k0 || kept.k1 != r.k1 || kept.w1 != r.w1) {
          kept = r;
          bool first = true;
          for (const PupilTables::View& v : t.views)
            for (int a = 0; a < 2; ++a) {
              const double row_weight = a ? r.w1 : 1 - r.w1;
              if (row_weight == 0) continue;
              const float w = static_cast<float>(v.weight * row_weight);
              const float* src = v.pixels + size_t(a ? r.k1 : r.k0) * g.cols * 3 + offset;
              if (first)
                for (size_t k = 0; k < n; ++k) m[k] = w * src[k];
              else
                for (size_t k = 0; k < n; ++k) m[k] += w * src[k];
              first = false;
            }
          m[n] = 0;
        }
        const int lo = t.c_lo;
        if (nearest)
          for (const PupilTables::Column& c : t.columns) sum[c.ray] += LoadRgbOver(m + size_t(c.c0 - lo) * 3);
        else
          for (const PupilTables::Column& c : t.columns)
            sum[c.ray] += c.w0 * LoadRgbOver(m + size_t(c.c0 - lo) * 3) + c.w1 * LoadRgbOver(m + size_t(c.c1 - lo) * 3);
      }
      for (Rgb4& value : sum) value *= inverse_count;
      PackRow(sum.data(), retina.cols, image->pixels.data() + size_t(i) * retina.cols * 3);
    }
  }
}

}  // namespace

Rgb LightFieldRays::operator()(const PupilPoint& u, double dx, double dy) const {
  const LightFieldGeometry& g = lf_->geometry;
  const bool nearest = pixels_ == Sampling::kNearest;
  Bracket col, row;
  if (!ColumnAt(g, u.x_m + dx * g.origin_z_m, nearest, &col) || !RowAt(g, u.y_m + dy * g.origin_z_m, nearest, &row))
    return {0, 0, 0};
  const ViewWeights v = ViewsAround(g, u);
  Rgb sum{0, 0, 0};
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      const double w_view = v.weight[a][b];
      if (w_view == 0) continue;
      const float* view = lf_->view(v.view[a][b]);
      for (int c = 0; c < 2; ++c)
        for (int d = 0; d < 2; ++d) {
          const double w = w_view * (c ? row.w1 : 1 - row.w1) * (d ? col.w1 : 1 - col.w1);
          if (w == 0) continue;
          const float* p = view + (static_cast<size_t>(c ? row.k1 : row.k0) * g.cols + (d ? col.k1 : col.k0)) * 3;
          for (int ch = 0; ch < 3; ++ch) sum[ch] += w * p[ch];
        }
    }
  return sum;
}

SceneRadiance LightFieldRadiance(const LightField& lf, Sampling pixels) { return LightFieldRays(lf, pixels); }

Image RetinaOfLightField(const LightField& lf, Sampling pixels, const RetinaGrid& retina,
                         const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation) {
  RetinaWorkspace workspace(LightFieldRetinaSizes(lf.geometry, retina, pupil), RetinaWorkspace::TeamSize());
  return RetinaOfLightField(lf, pixels, retina, pupil, accommodation, &workspace);
}

Image RetinaOfLightField(const LightField& lf, Sampling pixels, const RetinaGrid& retina,
                         const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation,
                         RetinaWorkspace* workspace) {
  workspace->Fit(LightFieldRetinaSizes(lf.geometry, retina, pupil), RetinaWorkspace::TeamSize());
  const size_t samples = size_t(retina.cols) * retina.rows;
  Image image{retina.cols, retina.rows, {"R", "G", "B"}, std::vector<float>(samples * 3, 0.0f)};
  const bool nearest = pixels == Sampling::kNearest;
  if (accommodation[0] == accommodation[1] && accommodation[1] == accommodation[2]) {
    RetinaAtFocus(lf, nearest, retina, pupil, accommodation[0], workspace, &image);
    return image;
  }
  // Chromatic defocus: each channel from the image at its own focus.
  Image at_focus = image;
  for (int c = 0; c < 3; ++c) {
    RetinaAtFocus(lf, nearest, retina, pupil, accommodation[c], workspace, &at_focus);
    for (size_t k = 0; k < samples; ++k) image.pixels[k * 3 + c] = at_focus.pixels[k * 3 + c];
  }
  return image;
}

}  // namespace layerlab
