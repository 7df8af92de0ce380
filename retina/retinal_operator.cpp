#include "layerlab/retina/retinal_operator.h"

#include <algorithm>
#include <cmath>

#include "layerlab/framework/error.h"
#include "layerlab/framework/heap_block.h"
#include "layerlab/retina/lightfield_taps.h"

namespace layerlab {

namespace {

// Consecutive retinal columns that read consecutive light-field columns, in the columns' order, so that the
// nearest-sampling loops below add the same terms in the same order as a loop over the columns would.
template <typename Run, typename Column>
std::vector<Run> RunsOf(const std::vector<Column>& columns) {
  std::vector<Run> runs;
  for (const Column& col : columns) {
    if (!runs.empty()) {
      Run& last = runs.back();
      if (col.ray == last.ray + last.length && col.c0 == last.c + last.length) {
        ++last.length;
        continue;
      }
    }
    runs.push_back({col.ray, col.c0, 1});
  }
  return runs;
}

}  // namespace

RetinalOperator::RetinalOperator(const LightFieldGeometry& g, Sampling pixels, const RetinaGrid& retina,
                                 const std::vector<PupilPoint>& pupil, const std::vector<std::array<double, 3>>& states)
    : state_count_(states.size()), nearest_(pixels == Sampling::kNearest), geometry_(g), retina_(retina) {
  using namespace lightfield_taps;
  if (pupil.empty()) throw Error("a retinal operator needs at least one pupil point");
  const double inverse_count = 1.0 / pupil.size();
  views_.resize(pupil.size());
  for (size_t p = 0; p < pupil.size(); ++p) {
    const ViewWeights v = ViewsAround(g, pupil[p]);
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b)
        if (v.weight[a][b] != 0) {
          PupilViews& pv = views_[p];
          pv.view[pv.count] = v.view[a][b];
          pv.weight[pv.count++] = static_cast<float>(v.weight[a][b] * inverse_count);
        }
  }
  const Tangents tangents = TangentsOf(retina);
  ForEachFocus(states, [&](size_t a, double focus, const int* channels, int channel_count) {
    Entry e;
    e.state = a;
    e.channel_count = channel_count;
    std::copy(channels, channels + channel_count, e.channels);
    e.tables.resize(pupil.size());
#pragma omp parallel for schedule(dynamic)
    for (size_t p = 0; p < pupil.size(); ++p) e.tables[p] = MakeTable(g, nearest_, retina, tangents, pupil[p], focus);
    entries_.push_back(std::move(e));
  });
}

RetinalOperator::Tangents RetinalOperator::TangentsOf(const RetinaGrid& retina) {
  Tangents t{std::vector<double>(retina.cols), std::vector<double>(retina.rows)};
  for (int j = 0; j < retina.cols; ++j) t.x[j] = std::tan(retina.angle_x(j));
  for (int i = 0; i < retina.rows; ++i) t.y[i] = std::tan(retina.angle_y(i));
  return t;
}

template <class Visit>
void RetinalOperator::ForEachFocus(const std::vector<std::array<double, 3>>& states, Visit visit) {
  for (size_t a = 0; a < states.size(); ++a)
    for (int c = 0; c < 3; ++c) {
      bool seen = false;  // an earlier channel of this state at the same focus
      for (int d = 0; d < c; ++d) seen = seen || states[a][d] == states[a][c];
      if (seen) continue;
      int channels[3], count = 0;
      for (int d = c; d < 3; ++d)
        if (states[a][d] == states[a][c]) channels[count++] = d;
      visit(a, states[a][c], channels, count);
    }
}

RetinalOperator::FocusTable RetinalOperator::MakeTable(const LightFieldGeometry& g, bool nearest,
                                                       const RetinaGrid& retina, const Tangents& tangents,
                                                       const PupilPoint& u, double focus) {
  using namespace lightfield_taps;
  FocusTable t;
  // The ray's direction and crossing exactly as RetinaOfSceneRayByRay and LightFieldRays compute them.
  for (int j = 0; j < retina.cols; ++j) {
    const double dx = tangents.x[j] - u.x_m * focus - u.deviation_x(focus);
    Bracket col;
    if (!ColumnAt(g, u.x_m + dx * g.origin_z_m, nearest, &col)) continue;
    t.columns.push_back({j, col.k0, col.k1, float(1 - col.w1), float(col.w1)});
  }
  if (nearest) t.runs = RunsOf<Run>(t.columns);
  t.rows.resize(retina.rows);
  t.sources.resize(g.rows);
  for (int i = 0; i < retina.rows; ++i) {
    const double dy = tangents.y[i] - u.y_m * focus - u.deviation_y(focus);
    Bracket row;
    if (!RowAt(g, u.y_m + dy * g.origin_z_m, nearest, &row)) continue;
    t.rows[i] = {row.k0, row.k1, float(1 - row.w1), float(row.w1)};
    t.sources[row.k0].push_back({i, float(1 - row.w1)});
    if (row.w1 != 0) t.sources[row.k1].push_back({i, float(row.w1)});
  }
  return t;
}

size_t RetinalOperator::HeapBytes(const FocusTable& t) {
  size_t bytes = HeapBlockBytes(t.columns.capacity() * sizeof(Column)) +
                 HeapBlockBytes(t.runs.capacity() * sizeof(Run)) + HeapBlockBytes(t.rows.capacity() * sizeof(Row)) +
                 HeapBlockBytes(t.sources.capacity() * sizeof(std::vector<Source>));
  for (const std::vector<Source>& s : t.sources) bytes += HeapBlockBytes(s.capacity() * sizeof(Source));
  return bytes;
}

size_t RetinalOperator::TableBytes(const LightFieldGeometry& g, Sampling pixels, const RetinaGrid& retina,
                                   const std::vector<PupilPoint>& pupil,
                                   const std::vector<std::array<double, 3>>& states) {
  const Tangents tangents = TangentsOf(retina);
  const bool nearest = pixels == Sampling::kNearest;
  size_t bytes = HeapBlockBytes(pupil.size() * sizeof(PupilViews)), entries = 0;
  ForEachFocus(states, [&](size_t, double focus, const int*, int) {
    ++entries;
    bytes += HeapBlockBytes(pupil.size() * sizeof(FocusTable));
#pragma omp parallel for schedule(dynamic) reduction(+ : bytes)
    for (size_t p = 0; p < pupil.size(); ++p)
      bytes += HeapBytes(MakeTable(g, nearest, retina, tangents, pupil[p], focus));
  });
  size_t capacity = 1;  // push_back's: doubling from 1
  while (capacity < entries) capacity *= 2;
  return bytes + HeapBlockBytes(capacity * sizeof(Entry));
}

size_t RetinalOperator::TableBytes() const {
  size_t bytes =
      HeapBlockBytes(views_.capacity() * sizeof(PupilViews)) + HeapBlockBytes(entries_.capacity() * sizeof(Entry));
  for (const Entry& e : entries_) {
    bytes += HeapBlockBytes(e.tables.capacity() * sizeof(FocusTable));
    for (const FocusTable& t : e.tables) bytes += HeapBytes(t);
  }
  return bytes;
}

namespace {

void RequireGeometry(const LightFieldGeometry& a, const LightFieldGeometry& b) {
  if (a.ray_count() != b.ray_count() || a.cols != b.cols || a.views_x != b.views_x)
    throw Error("the retinal operator was made for another light-field geometry");
}

}  // namespace

void RetinalOperator::Apply(const LightField& x, std::vector<std::vector<float>>* out) const {
  const LightFieldGeometry& g = geometry_;
  RequireGeometry(x.geometry, g);
  out->resize(state_count_);
  for (std::vector<float>& image : *out) image.assign(retinal_values(), 0.0f);
  const size_t row_stride = size_t(g.cols) * 3, retina_stride = size_t(retina_.cols) * 3;
  const size_t view_values = g.pixels_per_view() * 3;
  // The blends of a group of pupil points (at most a few hundred terms of at most 1 each per sample, float
  // holds them), so that each retinal row gathers the whole group while it is in cache: every state's image is
  // read and written once per group, not once per pupil point. Each sample still adds its pupil points in order.
  const size_t group = std::min(kPupilGroup, views_.size());
  std::vector<float>& blends = work_;
  blends.resize(group * view_values);
#pragma omp parallel
  for (size_t first = 0; first < views_.size(); first += group) {
    const size_t count = std::min(group, views_.size() - first);
#pragma omp for schedule(static)
    for (int k = 0; k < g.rows; ++k)
      for (size_t m = 0; m < count; ++m) {
        const PupilViews& pv = views_[first + m];
        float* dst = blends.data() + m * view_values + size_t(k) * row_stride;
        for (int s = 0; s < pv.count; ++s) {
          const float* src = x.view(pv.view[s]) + size_t(k) * row_stride;
          const float w = pv.weight[s];
          if (s == 0)
            for (size_t q = 0; q < row_stride; ++q) dst[q] = w * src[q];
          else
            for (size_t q = 0; q < row_stride; ++q) dst[q] += w * src[q];
        }
      }
    for (const Entry& e : entries_) {
      float* image = (*out)[e.state].data();
      // Static rows: the same thread writes a retinal row at every entry, so entries need no barrier.
#pragma omp for schedule(static) nowait
      for (int i = 0; i < retina_.rows; ++i) {
        float* dst = image + size_t(i) * retina_stride;
        for (size_t m = 0; m < count; ++m) {
          const FocusTable& t = e.tables[first + m];
          const Row& r = t.rows[i];
          if (r.k0 < 0) continue;
          const float* blend = blends.data() + m * view_values;
          const float* row0 = blend + size_t(r.k0) * row_stride;
          const float* row1 = blend + size_t(r.k1) * row_stride;
          if (nearest_ && e.channel_count == 3) {
            for (const Run& run : t.runs) {
              const float* v = row0 + size_t(run.c) * 3;
              float* o = dst + size_t(run.ray) * 3;
              for (size_t q = 0, n = size_t(run.length) * 3; q < n; ++q) o[q] += v[q];
            }
            continue;
          }
          for (const Column& col : t.columns) {
            float* o = dst + size_t(col.ray) * 3;
            for (int q = 0; q < e.channel_count; ++q) {
              const int c = e.channels[q];
              const size_t c0 = size_t(col.c0) * 3 + c, c1 = size_t(col.c1) * 3 + c;
              o[c] += r.w0 * (col.w0 * row0[c0] + col.w1 * row0[c1]) + r.w1 * (col.w0 * row1[c0] + col.w1 * row1[c1]);
            }
          }
        }
      }
    }
#pragma omp barrier
  }
}

void RetinalOperator::ApplyTranspose(const std::vector<std::vector<float>>& y, LightField* out, bool accumulate) const {
  const LightFieldGeometry& g = geometry_;
  RequireGeometry(out->geometry, g);
  if (y.size() != state_count_) throw Error("the retinal operator has another number of states");
  for (const std::vector<float>& image : y)
    if (image.size() != retinal_values()) throw Error("a retinal image does not match the retinal operator's grid");
  if (!accumulate) std::fill(out->rgb.begin(), out->rgb.end(), 0.0f);
  const size_t row_stride = size_t(g.cols) * 3, retina_stride = size_t(retina_.cols) * 3;
  // Each light-field row by one thread, every pupil point in order: the retinal rows that read the row through
  // that point scattered into one row, then added to the views the point blends. The retinal rows a light-field
  // row reads through neighbouring pupil points are neighbours, so they are read from cache.
#pragma omp parallel
  {
    std::vector<float> gathered(row_stride);
#pragma omp for schedule(static)
    for (int k = 0; k < g.rows; ++k)
      for (size_t p = 0; p < views_.size(); ++p) {
        float* dst = gathered.data();
        std::fill(dst, dst + row_stride, 0.0f);
        for (const Entry& e : entries_) {
          const FocusTable& t = e.tables[p];
          const float* image = y[e.state].data();
          for (const Source& source : t.sources[k]) {
            const float* src = image + size_t(source.ray_row) * retina_stride;
            const float w = source.weight;
            if (nearest_ && e.channel_count == 3) {
              for (const Run& run : t.runs) {
                const float* v = src + size_t(run.ray) * 3;
                float* o = dst + size_t(run.c) * 3;
                for (size_t q = 0, n = size_t(run.length) * 3; q < n; ++q) o[q] += w * v[q];
              }
              continue;
            }
            for (const Column& col : t.columns)
              for (int q = 0; q < e.channel_count; ++q) {
                const int c = e.channels[q];
                const float v = w * src[size_t(col.ray) * 3 + c];
                dst[size_t(col.c0) * 3 + c] += col.w0 * v;
                dst[size_t(col.c1) * 3 + c] += col.w1 * v;
              }
          }
        }
        const PupilViews& pv = views_[p];
        for (int s = 0; s < pv.count; ++s) {
          float* view = out->view(pv.view[s]) + size_t(k) * row_stride;
          const float w = pv.weight[s];
          for (size_t q = 0; q < row_stride; ++q) view[q] += w * dst[q];
        }
      }
  }
}

void RetinalOperator::Apply(const LightField& x, std::vector<float>* out) const {
  if (state_count_ != 1) throw Error("this retinal operator has " + std::to_string(state_count_) + " states");
  std::vector<std::vector<float>> images;
  Apply(x, &images);
  *out = std::move(images.front());
}

void RetinalOperator::ApplyTranspose(const std::vector<float>& y, LightField* out, bool accumulate) const {
  if (state_count_ != 1) throw Error("this retinal operator has " + std::to_string(state_count_) + " states");
  ApplyTranspose(std::vector<std::vector<float>>{y}, out, accumulate);
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
