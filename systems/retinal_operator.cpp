#include "systems/retinal_operator.h"

#include <algorithm>
#include <cmath>

#include "framework/error.h"
#include "systems/lightfield_taps.h"

namespace layerlab {

RetinalOperator::RetinalOperator(const LightFieldGeometry& g, Sampling pixels, const RetinaGrid& retina,
                                 const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation)
    : geometry_(g), retina_(retina) {
  using namespace lightfield_taps;
  if (pupil.empty()) throw Error("a retinal operator needs at least one pupil point");
  std::vector<double> foci;
  for (int c = 0; c < 3; ++c) {
    auto it = std::find(foci.begin(), foci.end(), accommodation[c]);
    focus_of_[c] = static_cast<int>(it - foci.begin());
    if (it == foci.end()) foci.push_back(accommodation[c]);
  }
  const bool nearest = pixels == Sampling::kNearest;
  std::vector<double> tan_x(retina.cols), tan_y(retina.rows);
  for (int j = 0; j < retina.cols; ++j) tan_x[j] = std::tan(retina.angle_x(j));
  for (int i = 0; i < retina.rows; ++i) tan_y[i] = std::tan(retina.angle_y(i));
  const double inverse_count = 1.0 / pupil.size();
  tables_.assign(foci.size(), std::vector<PupilTable>(pupil.size()));
  readers_.assign(g.view_count(), {});
  for (size_t f = 0; f < foci.size(); ++f)
    for (size_t p = 0; p < pupil.size(); ++p) {
      const PupilPoint& u = pupil[p];
      PupilTable& t = tables_[f][p];
      const ViewWeights v = ViewsAround(g, u);
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          if (v.weight[a][b] != 0) {
            t.view[t.views] = v.view[a][b];
            t.view_weight[t.views] = static_cast<float>(v.weight[a][b] * inverse_count);
            readers_[v.view[a][b]].push_back({int(f), int(p), t.views});
            ++t.views;
          }
      // The ray's direction and crossing exactly as RetinaOfSceneRayByRay and LightFieldRays compute them.
      for (int j = 0; j < retina.cols; ++j) {
        const double dx = tan_x[j] - u.x * foci[f] - u.slope_x;
        Bracket col;
        if (!ColumnAt(g, u.x + dx * g.origin_z, nearest, &col)) continue;
        t.columns.push_back({j, col.k0, col.k1, float(1 - col.w1), float(col.w1)});
      }
      t.rows.resize(retina.rows);
      for (int i = 0; i < retina.rows; ++i) {
        const double dy = tan_y[i] - u.y * foci[f] - u.slope_y;
        Bracket row;
        if (RowAt(g, u.y + dy * g.origin_z, nearest, &row))
          t.rows[i] = {row.k0, row.k1, float(1 - row.w1), float(row.w1)};
      }
    }
}

void RetinalOperator::Apply(const LightField& x, std::vector<float>* out) const {
  const LightFieldGeometry& g = geometry_;
  if (x.geometry.ray_count() != g.ray_count() || x.geometry.cols != g.cols)
    throw Error("the retinal operator was made for another light-field geometry");
  out->resize(retinal_values());
  const size_t row_stride = size_t(g.cols) * 3;
#pragma omp parallel
  {
    std::vector<double> sum(size_t(retina_.cols) * 3);
#pragma omp for schedule(dynamic)
    for (int i = 0; i < retina_.rows; ++i) {
      std::fill(sum.begin(), sum.end(), 0.0);
      for (size_t f = 0; f < tables_.size(); ++f) {
        int channels[3], n = 0;
        for (int c = 0; c < 3; ++c)
          if (focus_of_[c] == int(f)) channels[n++] = c;
        for (const PupilTable& t : tables_[f]) {
          const Row& r = t.rows[i];
          if (r.k0 < 0) continue;
          for (int s = 0; s < t.views; ++s)
            for (int a = 0; a < 2; ++a) {
              const double w = double(t.view_weight[s]) * (a ? r.w1 : r.w0);
              if (w == 0) continue;
              const float* src = x.view(t.view[s]) + size_t(a ? r.k1 : r.k0) * row_stride;
              for (const Column& col : t.columns) {
                const float* p0 = src + size_t(col.c0) * 3;
                const float* p1 = src + size_t(col.c1) * 3;
                double* o = &sum[size_t(col.ray) * 3];
                for (int q = 0; q < n; ++q) {
                  const int c = channels[q];
                  o[c] += w * (col.w0 * p0[c] + col.w1 * p1[c]);
                }
              }
            }
        }
      }
      float* dst = out->data() + size_t(i) * retina_.cols * 3;
      for (size_t k = 0; k < sum.size(); ++k) dst[k] = static_cast<float>(sum[k]);
    }
  }
}

void RetinalOperator::ApplyTranspose(const std::vector<float>& y, LightField* out, bool accumulate) const {
  const LightFieldGeometry& g = geometry_;
  if (y.size() != retinal_values()) throw Error("the retinal image does not match the retinal operator's grid");
  if (out->geometry.ray_count() != g.ray_count() || out->geometry.cols != g.cols)
    throw Error("the retinal operator was made for another light-field geometry");
  const size_t row_stride = size_t(g.cols) * 3;
  const size_t retina_stride = size_t(retina_.cols) * 3;
  // Each thread owns whole views: no two threads write one value.
#pragma omp parallel for schedule(dynamic)
  for (size_t v = 0; v < readers_.size(); ++v) {
    float* view = out->view(v);
    if (!accumulate) std::fill(view, view + g.pixels_per_view() * 3, 0.0f);
    for (const Reader& reader : readers_[v]) {
      const PupilTable& t = tables_[reader.focus][reader.point];
      int channels[3], n = 0;
      for (int c = 0; c < 3; ++c)
        if (focus_of_[c] == reader.focus) channels[n++] = c;
      const float view_weight = t.view_weight[reader.slot];
      for (int i = 0; i < retina_.rows; ++i) {
        const Row& r = t.rows[i];
        if (r.k0 < 0) continue;
        const float* src = y.data() + size_t(i) * retina_stride;
        for (int a = 0; a < 2; ++a) {
          const float w = view_weight * (a ? r.w1 : r.w0);
          if (w == 0) continue;
          float* dst = view + size_t(a ? r.k1 : r.k0) * row_stride;
          for (const Column& col : t.columns) {
            const float* value = src + size_t(col.ray) * 3;
            float* d0 = dst + size_t(col.c0) * 3;
            float* d1 = dst + size_t(col.c1) * 3;
            for (int q = 0; q < n; ++q) {
              const int c = channels[q];
              d0[c] += w * col.w0 * value[c];
              d1[c] += w * col.w1 * value[c];
            }
          }
        }
      }
    }
  }
}

std::vector<double> AccommodationStates(double from, double to, double step) {
  if (!(step > 0) || !(to >= from)) throw Error("accommodation states need from <= to and a positive step");
  std::vector<double> states;
  for (int k = 0;; ++k) {
    const double d = from + k * step;
    if (d > to + 1e-9 * std::max(1.0, std::abs(to))) break;
    states.push_back(d);
  }
  return states;
}

}  // namespace layerlab
