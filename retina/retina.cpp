#include "layerlab/retina/retina.h"

#include "layerlab/kernels/one_tap_view.h"
#include "layerlab/retina/lightfield_radiance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>

#include "layerlab/eye/chromatic_eye.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/random.h"
#include "layerlab/framework/units.h"
#include "layerlab/systems/eye_pose_limits.h"
#include "layerlab/systems/layer_ray_map.h"

namespace layerlab {

void CheckRetinaSampling(double field_x_deg, double field_y_deg, double resolution_deg, const std::string& field_name,
                         const std::string& resolution_name) {
  if (!(resolution_deg > 0) || !(resolution_deg < 10))
    throw Error(resolution_name + ": " + FormatGeneral(resolution_deg) +
                " deg is not a retinal sample size in (0, 10) deg");
  for (double side : {field_x_deg, field_y_deg})
    if (!(side > 0) || !(side <= 170))
      throw Error(field_name + ": " + FormatGeneral(side) + " deg is not a retinal field side in (0, 170] deg");
  const double cols = std::max(1.0, std::round(field_x_deg / resolution_deg));
  const double rows = std::max(1.0, std::round(field_y_deg / resolution_deg));
  if (cols * rows > 1e8)
    throw Error(resolution_name + ": " + FormatGeneral(resolution_deg) + " deg over a field of " +
                FormatGeneral(field_x_deg) + " x " + FormatGeneral(field_y_deg) + " deg is " + FormatGeneral(cols) +
                " x " + FormatGeneral(rows) +
                " retinal samples, beyond the 1e8 a retina may have; give a larger sample size or a smaller field");
}

RetinaGrid MakeRetinaGrid(double field_x, double field_y, double resolution) {
  CheckRetinaSampling(field_x / kRadiansPerDegree, field_y / kRadiansPerDegree, resolution / kRadiansPerDegree,
                      "the retinal field", "the retinal sample size");
  RetinaGrid g;
  g.resolution_rad = resolution;
  g.cols = std::max(1, static_cast<int>(std::lround(field_x / resolution)));
  g.rows = std::max(1, static_cast<int>(std::lround(field_y / resolution)));
  return g;
}

RetinaGrid CenteredOnGaze(RetinaGrid grid, const EyePose& pose) {
  const std::array<double, 2> gaze = GazeAngles(pose);
  grid.center_x_rad = gaze[0], grid.center_y_rad = gaze[1];
  return grid;
}

namespace {

std::vector<PupilPoint> PupilPositions(const EyeModel& eye) {
  const double a = eye.pupil_diameter_m;
  if (a == 0) return {PupilPoint{}};
  const int nx = eye.pupil_samples_x, ny = eye.pupil_samples_y;
  const bool round = eye.pupil_shape == PupilShape::kRound;
  auto inside = [&](double x, double y) { return !round || x * x + y * y <= 0.25 * a * a; };
  SplitMix64 rng(eye.pupil_seed);  // the same points with every standard library
  auto unit = [&](SplitMix64& r) { return r.uniform(); };
  std::vector<PupilPoint> points;
  if (eye.pupil_sampling == PupilSampling::kPoisson) {
    // Dart throwing with a minimum distance that packs about nx * ny points.
    const size_t wanted = static_cast<size_t>(nx) * ny;
    double area = round ? 0.785398 * a * a : a * a;
    double min_distance = 0.75 * std::sqrt(area / wanted);
    for (int attempt = 0; attempt < 200000 && points.size() < wanted; ++attempt) {
      PupilPoint p{(unit(rng) - 0.5) * a, (unit(rng) - 0.5) * a};
      if (!inside(p.x_m, p.y_m)) continue;
      bool far = std::all_of(points.begin(), points.end(), [&](const PupilPoint& q) {
        return (p.x_m - q.x_m) * (p.x_m - q.x_m) + (p.y_m - q.y_m) * (p.y_m - q.y_m) >= min_distance * min_distance;
      });
      if (far) points.push_back(p);
    }
    return points;
  }
  const bool jitter = eye.pupil_sampling == PupilSampling::kJittered;
  for (int i = 0; i < ny; ++i)
    for (int j = 0; j < nx; ++j) {
      double fx = jitter ? unit(rng) : 0.5, fy = jitter ? unit(rng) : 0.5;
      PupilPoint p{-0.5 * a + (j + fx) * a / nx, 0.5 * a - (i + fy) * a / ny};
      if (inside(p.x_m, p.y_m)) points.push_back(p);
    }
  if (points.empty()) points.push_back(PupilPoint{});
  return points;
}

}  // namespace

std::vector<PupilPoint> PupilSamplesInOwnPlane(const EyeModel& eye) {
  std::vector<PupilPoint> points = PupilPositions(eye);
  if (!eye.wavefront.empty())
    for (PupilPoint& u : points) {
      const WavefrontSlope g = WavefrontSlopeAt(eye.wavefront, u.x_m, u.y_m);
      u.slope_x = g.x, u.slope_y = g.y;
    }
  return points;
}

std::vector<PupilPoint> PupilSamples(const EyeModel& eye) {
  std::vector<PupilPoint> points = PupilSamplesInOwnPlane(eye);
  // Placed by the eye's pose: from the pupil's own plane to the eye plane.
  const std::array<double, 2> center = OnEyePlane(eye.pose, 0, 0);
  for (PupilPoint& u : points) {
    const std::array<double, 2> at = OnEyePlane(eye.pose, u.x_m, u.y_m);
    u.x_m = at[0], u.y_m = at[1], u.center_x_m = center[0], u.center_y_m = center[1];
  }
  return points;
}

std::array<double, 3> ChannelAccommodation(const EyeModel& eye, double diopters) {
  std::array<double, 3> focus = {diopters + eye.chromatic_defocus_diopters[0],
                                 diopters + eye.chromatic_defocus_diopters[1],
                                 diopters + eye.chromatic_defocus_diopters[2]};
  if (eye.chromatic_aberration == ChromaticAberration::kThibos)
    for (int c = 0; c < 3; ++c) focus[c] += ThibosDefocus(eye.channel_wavelengths_m[c], eye.reference_wavelength_m);
  return focus;
}

// The common case: one focus for all channels, every branch on the one-tap
// path (one_tap_view.h), the pupil points in the role of views. For one
// pupil point a layer's column tap depends on the retinal column alone and
// its row tap on the retinal row alone, and on a pupil grid the points of a
// pupil column share their column taps (those of a pupil row their row
// taps). So each layer row is resampled to the retinal columns once per
// distinct column table, kept while the next retinal rows read it, and every
// retinal row sums contiguous rows of products (AddBranchLightRow) in the
// order of the per-ray sums: pupil point, then branch.
struct OneTapTables {
  struct Table {
    int layer = 0;
    std::vector<AxisTap> taps;
  };
  std::vector<Table> cols, rows;    // distinct tables
  std::vector<int> col_of, row_of;  // [pupil point * layers + layer] -> table
  int ring = 1;                     // a power of two >= the layer rows one column table's rays read in a retinal row
};

namespace {

// Where the rays of one pupil point read one layer, for one channel's focus:
// the ray through retinal sample (i, j) meets the layer at tan-angle
// (tan x_j + u_x blur, tan y_i + u_y blur), blur = D_k - D_a; for a layer
// without rotation its column depends only on j and its row only on i.
struct LayerTables {
  std::vector<AxisTap> cols, rows;  // separable layers; empty otherwise
  double blur = 0;
  double deviation_x = 0, deviation_y = 0;  // PupilPoint::deviation at this focus
};

// The value a ray reads from one channel of a pattern.
inline double Read(const RayTaps& taps, const LayerPattern& t, int c) {
  double value = 0;
  for (int q = 0; q < taps.count; ++q) value += taps.weight[q] * t.rgb[size_t(taps.index[q]) * 3 + c];
  return value;
}
inline double Read(const AxisTap& row, const AxisTap& col, const LayerPattern& t, int c) {
  double value = 0;
  const int32_t ri[2] = {row.i0, row.i1}, ci[2] = {col.i0, col.i1};
  const float rw[2] = {row.w0, row.w1}, cw[2] = {col.w0, col.w1};
  for (int a = 0; a < 2; ++a) {
    if (ri[a] < 0) continue;
    for (int b = 0; b < 2; ++b)
      if (ci[b] >= 0) value += double(rw[a]) * cw[b] * t.rgb[(size_t(ri[a]) * t.cols + ci[b]) * 3 + c];
  }
  return value;
}

// A table per distinct offset of the layer's taps: (u blur, wavefront slope).
OneTapTables MakeOneTapTables(const DisplayModel& model, const RetinaGrid& retina, const std::vector<PupilPoint>& pupil,
                              const std::vector<double>& tan_x, const std::vector<double>& tan_y,
                              double accommodation) {
  const size_t layers = model.layer_count();
  OneTapTables tables;
  tables.col_of.resize(pupil.size() * layers), tables.row_of.resize(pupil.size() * layers);
  struct Key {
    int layer;
    double offset, slope;
  };
  std::vector<Key> col_keys, row_keys;
  auto find = [](std::vector<Key>& keys, Key key) {
    for (size_t n = 0; n < keys.size(); ++n)
      if (keys[n].layer == key.layer && keys[n].offset == key.offset && keys[n].slope == key.slope) return int(n);
    keys.push_back(key);
    return int(keys.size() - 1);
  };
  for (size_t p = 0; p < pupil.size(); ++p)
    for (size_t k = 0; k < layers; ++k) {
      const double blur = model.projection(k).sampler().diopters() - accommodation;
      const int c = find(col_keys, {int(k), pupil[p].x_m * blur, pupil[p].deviation_x(accommodation)});
      const int r = find(row_keys, {int(k), pupil[p].y_m * blur, pupil[p].deviation_y(accommodation)});
      tables.col_of[p * layers + k] = c, tables.row_of[p * layers + k] = r;
    }
  tables.cols.resize(col_keys.size()), tables.rows.resize(row_keys.size());
#pragma omp parallel for schedule(dynamic)
  for (size_t n = 0; n < col_keys.size() + row_keys.size(); ++n) {
    const bool col = n < col_keys.size();
    const Key& key = col ? col_keys[n] : row_keys[n - col_keys.size()];
    OneTapTables::Table& table = col ? tables.cols[n] : tables.rows[n - col_keys.size()];
    const LayerSampler& s = model.projection(key.layer).sampler();
    table.layer = key.layer;
    // The same expressions as the general path's tables, so the same taps.
    if (col) {
      table.taps.resize(retina.cols);
      for (int j = 0; j < retina.cols; ++j) table.taps[j] = s.Column(tan_x[j] + key.offset - key.slope);
    } else {
      table.taps.resize(retina.rows);
      for (int i = 0; i < retina.rows; ++i) table.taps[i] = s.Row(tan_y[i] + key.offset - key.slope);
    }
  }
  // The ring: how many layer rows the rays of one column table read in one retinal row.
  std::vector<int> lo(tables.cols.size()), hi(tables.cols.size());
  int span = 1;
  for (int i = 0; i < retina.rows; ++i) {
    std::fill(lo.begin(), lo.end(), std::numeric_limits<int>::max()), std::fill(hi.begin(), hi.end(), -1);
    for (size_t n = 0; n < tables.col_of.size(); ++n) {
      const int r = tables.rows[tables.row_of[n]].taps[i].i0, c = tables.col_of[n];
      if (r >= 0) lo[c] = std::min(lo[c], r), hi[c] = std::max(hi[c], r);
    }
    for (size_t c = 0; c < lo.size(); ++c) span = std::max(span, hi[c] - lo[c] + 1);
  }
  while (tables.ring < span) tables.ring *= 2;
  return tables;
}

// A thread's layer rows resampled to the retinal columns, per column table a
// ring of the last rows read (slot r mod ring), 0 where a ray misses the layer;
// in the thread's part of the workspace, sized for it.
class ResampledRows {
 public:
  ResampledRows(const OneTapTables& tables, int cols, RetinaThreadWorkspace& w)
      : cols_(cols), ring_(tables.ring), tags_(w.resampled_tags), rows_(w.resampled) {
    tags_.assign(tables.cols.size() * ring_, -1);
    rows_.resize(tags_.size() * cols);
  }
  const Rgb4* Row(const OneTapTables& tables, const PaddedLayers& padded, const DisplayModel& model, int table, int r) {
    const size_t slot = size_t(table) * ring_ + (r & (ring_ - 1));
    Rgb4* out = &rows_[slot * cols_];
    if (tags_[slot] != r) {
      const OneTapTables::Table& t = tables.cols[table];
      const Rgb4* pixels = padded.pixels(t.layer) + size_t(r) * model.projection(t.layer).cols();
      for (int j = 0; j < cols_; ++j) out[j] = t.taps[j].i0 < 0 ? Rgb4{} : pixels[t.taps[j].i0];
      tags_[slot] = r;
    }
    return out;
  }

 private:
  int cols_, ring_;
  std::vector<int>& tags_;
  std::vector<Rgb4>& rows_;
};

void NearestRetina(const DisplayModel& model, const Patterns& t, const RetinaGrid& retina,
                   const std::vector<PupilPoint>& pupil, const OneTapTables& tables, RetinaWorkspace* workspace,
                   Image* image) {
  const size_t layers = model.layer_count(), branches = model.branch_count();
  PaddedLayers& padded = workspace->padded;
  padded.PadAll(t);
  std::vector<Rgb4> weight(branches);
  for (size_t b = 0; b < branches; ++b) {
    const std::array<float, 3>& w = model.weight(b);
    weight[b] = Rgb4{w[0], w[1], w[2], 0.0f};
  }
  const int longest = kMaxOneTapLayers;  // rows kept per term (pupil point, branch)
  const float inverse_count = static_cast<float>(1.0 / pupil.size());
#pragma omp parallel num_threads(workspace->threads())
  {
    RetinaThreadWorkspace& mine = workspace->thread();
    std::vector<Rgb4>& sum = mine.sum;
    ResampledRows resampled(tables, retina.cols, mine);
    std::vector<const Rgb4*>& rows = mine.term_rows;  // [term][layer of its branch]
    std::vector<Rgb4>& term_weight = mine.term_weight;
    std::vector<int>& term_layers = mine.term_layers;
    sum.resize(retina.cols);
    // Runs of retinal rows per thread: the rows a run reads are resampled once.
#pragma omp for schedule(dynamic, 16)
    for (int i = 0; i < retina.rows; ++i) {
      // The terms in the order of the per-ray sums (pupil point, then branch); none for a branch that misses the row.
      rows.clear(), term_weight.clear(), term_layers.clear();
      for (size_t p = 0; p < pupil.size(); ++p)
        for (size_t b = 0; b < branches; ++b) {
          const std::vector<int>& of_branch = model.branch_layers(b);
          bool reached = true;
          for (int k : of_branch) reached = reached && tables.rows[tables.row_of[p * layers + k]].taps[i].i0 >= 0;
          if (!reached) continue;
          for (int k : of_branch) {
            const size_t n = p * layers + k;
            rows.push_back(
                resampled.Row(tables, padded, model, tables.col_of[n], tables.rows[tables.row_of[n]].taps[i].i0));
          }
          for (int q = static_cast<int>(of_branch.size()); q < longest; ++q) rows.push_back(nullptr);
          term_weight.push_back(weight[b]);
          term_layers.push_back(static_cast<int>(of_branch.size()));
        }
      // At most a few hundred terms of at most 1 each per pixel: float holds them.
      std::fill(sum.begin(), sum.end(), Rgb4{});
      // Columns a few at a time, every term's rows for them staying in cache
      // (256 against 128 and the whole row: 15.1 against 16.5 and 14-17 ms),
      // the terms in runs of as many layers, in order.
      constexpr int kChunk = 256;
      const size_t terms = term_weight.size();
      for (int j0 = 0; j0 < retina.cols; j0 += kChunk) {
        const int end = std::min(retina.cols, j0 + kChunk);
        for (size_t q0 = 0, q1 = 0; q0 < terms; q0 = q1) {
          for (q1 = q0 + 1; q1 < terms && term_layers[q1] == term_layers[q0];) ++q1;
          const BranchRows group{rows.data() + q0 * longest, longest, term_layers[q0], term_weight.data() + q0,
                                 static_cast<int>(q1 - q0)};
          AddBranchLightTermsRow(group, j0, end, sum.data());
        }
      }
      for (Rgb4& value : sum) value *= inverse_count;
      PackRow(sum.data(), retina.cols, image->pixels.data() + size_t(i) * retina.cols * 3);
    }
  }
}

// The general path's tables, [pupil point][layer][focus]: each layer's blur
// and, when its sampler is separable, the columns and rows each retinal
// sample reads through that pupil point.
std::vector<LayerTables> GeneralTables(const DisplayModel& model, const RetinaGrid& retina,
                                       const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation,
                                       const std::vector<double>& tan_x, const std::vector<double>& tan_y, int foci) {
  const size_t layers = model.layer_count();
  std::vector<LayerTables> tables(pupil.size() * layers * foci);
#pragma omp parallel for schedule(dynamic)
  for (size_t p = 0; p < pupil.size(); ++p)
    for (size_t k = 0; k < layers; ++k)
      for (int f = 0; f < foci; ++f) {
        const LayerSampler& s = model.projection(k).sampler();
        LayerTables& table = tables[(p * layers + k) * foci + f];
        table.blur = s.diopters() - accommodation[f];
        table.deviation_x = pupil[p].deviation_x(accommodation[f]);
        table.deviation_y = pupil[p].deviation_y(accommodation[f]);
        if (!s.separable() || model.projection(k).mapped()) continue;
        table.cols.resize(retina.cols), table.rows.resize(retina.rows);
        for (int j = 0; j < retina.cols; ++j)
          table.cols[j] = s.Column(tan_x[j] + pupil[p].x_m * table.blur - table.deviation_x, pupil[p].x_m);
        for (int i = 0; i < retina.rows; ++i)
          table.rows[i] = s.Row(tan_y[i] + pupil[p].y_m * table.blur - table.deviation_y, pupil[p].y_m);
      }
  return tables;
}

// Behind a real lens: the pupil point's ray toward retinal direction tan,
// focused at the accommodation (D - blur), traced to the panel in channel c.
double ReadThroughLens(const SampledRayMap& map, const RayMapView& view, const LayerSampler& s, double blur,
                       const PupilPoint& p, double tan_x, double tan_y, const LayerPattern& t, int c) {
  const double accommodation = s.diopters() - blur;
  const auto U = view.Lookup(c, map.TanCell(0, tan_x - accommodation * p.x_m - p.deviation_x(accommodation)),
                             map.TanCell(1, tan_y - accommodation * p.y_m - p.deviation_y(accommodation)));
  return U ? Read(s.At((*U)[0], (*U)[1]), t, c) : 0.0;
}

// The general path: every layer read through every pupil point, each
// branch's product of its layers summed, averaged over the pupil.
void GeneralRetina(const DisplayModel& model, const Patterns& t, const RetinaGrid& retina,
                   const std::vector<PupilPoint>& pupil, const std::vector<LayerTables>& tables,
                   const std::vector<double>& tan_x, const std::vector<double>& tan_y, bool same_focus, Image* image) {
  const int foci = same_focus ? 1 : 3;
  const size_t layers = model.layer_count();
  const double inverse_count = 1.0 / pupil.size();
  std::vector<std::unique_ptr<RayMapView>> lens_views(pupil.size() * layers);  // [pupil point][layer], mapped layers
  for (size_t p = 0; p < pupil.size(); ++p)
    for (size_t k = 0; k < layers; ++k)
      if (const SampledRayMap* map = model.projection(k).ray_map())
        lens_views[p * layers + k] = std::make_unique<RayMapView>(*map, pupil[p].x_m, pupil[p].y_m);
#pragma omp parallel
  {
    std::vector<double> sum(size_t(retina.cols) * 3);
    std::vector<double> value(layers * 3);  // per layer and channel, for the current ray
#pragma omp for schedule(dynamic)
    for (int i = 0; i < retina.rows; ++i) {
      std::fill(sum.begin(), sum.end(), 0.0);
      for (size_t p = 0; p < pupil.size(); ++p)
        for (int j = 0; j < retina.cols; ++j) {
          for (size_t k = 0; k < layers; ++k) {
            const LayerSampler& s = model.projection(k).sampler();
            if (const SampledRayMap* map = model.projection(k).ray_map()) {
              for (int c = 0; c < 3; ++c) {
                const LayerTables& table = tables[(p * layers + k) * foci + (same_focus ? 0 : c)];
                value[k * 3 + c] = ReadThroughLens(*map, *lens_views[p * layers + k], s, table.blur, pupil[p], tan_x[j],
                                                   tan_y[i], t[k], c);
              }
              continue;
            }
            for (int c = 0; c < 3; ++c) {
              const LayerTables& table = tables[(p * layers + k) * foci + (same_focus ? 0 : c)];
              if (c > 0 && same_focus && s.separable()) {
                value[k * 3 + c] = Read(table.rows[i], table.cols[j], t[k], c);
                continue;
              }
              value[k * 3 + c] =
                  s.separable()
                      ? Read(table.rows[i], table.cols[j], t[k], c)
                      : Read(s.At(tan_x[j] + pupil[p].x_m * table.blur - table.deviation_x,
                                  tan_y[i] + pupil[p].y_m * table.blur - table.deviation_y, pupil[p].x_m, pupil[p].y_m),
                             t[k], c);
            }
          }
          for (size_t b = 0; b < model.branch_count(); ++b) {
            const auto& w = model.weight(b);
            for (int c = 0; c < 3; ++c) {
              double product = w[c];
              for (int k : model.branch_layers(b)) product *= value[k * 3 + c];
              sum[size_t(j) * 3 + c] += product;
            }
          }
        }
      for (size_t k = 0; k < sum.size(); ++k)
        image->pixels[size_t(i) * retina.cols * 3 + k] = static_cast<float>(sum[k] * inverse_count);
    }
  }
}

}  // namespace

DisplayRetinaTables::DisplayRetinaTables(const DisplayModel& model, const RetinaGrid& retina,
                                         const std::vector<PupilPoint>& pupil,
                                         const std::array<double, 3>& accommodation)
    : retina_(retina),
      pupil_(&pupil),
      accommodation_(accommodation),
      layers_(model.layer_count()),
      branches_(model.branch_count()),
      tan_x_(retina.cols),
      tan_y_(retina.rows) {
  for (int j = 0; j < retina.cols; ++j) tan_x_[j] = std::tan(retina.angle_x(j));
  for (int i = 0; i < retina.rows; ++i) tan_y_[i] = std::tan(retina.angle_y(i));
  same_focus_ = accommodation[0] == accommodation[1] && accommodation[1] == accommodation[2];
  one_tap_ = true;
  for (size_t b = 0; b < model.branch_count(); ++b) one_tap_ = one_tap_ && OneTapBranch(model, b);
  // A focus per channel (chromatic aberration): each channel from the fast
  // path at its own focus, three float passes instead of the general path.
  if (!one_tap_) return;
  for (int c = 0; c < (same_focus_ ? 1 : 3); ++c)
    foci_.push_back(MakeOneTapTables(model, retina, pupil, tan_x_, tan_y_, accommodation[c]));
  sizes_.retina_cols = retina.cols;
  for (size_t k = 0; k < layers_; ++k) sizes_.layer_pixels.push_back(model.projection(k).pixel_count());
  for (const OneTapTables& focus : foci_) {
    sizes_.column_tables = std::max(sizes_.column_tables, focus.cols.size());
    sizes_.ring = std::max(sizes_.ring, size_t(focus.ring));
  }
  sizes_.terms = pupil.size() * branches_;
}

DisplayRetinaTables::~DisplayRetinaTables() = default;
DisplayRetinaTables::DisplayRetinaTables(DisplayRetinaTables&&) noexcept = default;

Image RetinaOfDisplay(const DisplayModel& model, const Patterns& t, const RetinaGrid& retina,
                      const std::vector<PupilPoint>& pupil, const std::array<double, 3>& accommodation) {
  return RetinaOfDisplay(model, t, DisplayRetinaTables(model, retina, pupil, accommodation));
}

Image RetinaOfDisplay(const DisplayModel& model, const Patterns& t, const DisplayRetinaTables& made) {
  return RetinaOfDisplay(model, t, made, &made.workspace_);
}

Image RetinaOfDisplay(const DisplayModel& model, const std::vector<ShownInstant>& shown,
                      const DisplayRetinaTables& made, RetinaWorkspace* workspace) {
  if (shown.empty()) throw Error("internal error: no instant of the panels to see");
  auto image = [&](const Patterns& t) {
    return workspace ? RetinaOfDisplay(model, t, made, workspace) : RetinaOfDisplay(model, t, made);
  };
  if (shown.size() == 1) return image(shown[0].patterns);
  Image mean;
  for (const ShownInstant& instant : shown) {
    const Image at = image(instant.patterns);
    if (mean.pixels.empty()) mean = at, std::fill(mean.pixels.begin(), mean.pixels.end(), 0.0f);
    for (size_t k = 0; k < at.pixels.size(); ++k) mean.pixels[k] += static_cast<float>(instant.weight * at.pixels[k]);
  }
  return mean;
}

Image RetinaOfDisplay(const DisplayModel& model, const Patterns& t, const DisplayRetinaTables& made,
                      RetinaWorkspace* workspace) {
  if (model.layer_count() != made.layers_ || model.branch_count() != made.branches_)
    throw Error("internal error: retinal tables of another display");
  const RetinaGrid& retina = made.retina_;
  const std::vector<PupilPoint>& pupil = *made.pupil_;
  const std::array<double, 3>& accommodation = made.accommodation_;
  const std::vector<double>&tan_x = made.tan_x_, &tan_y = made.tan_y_;
  const bool same_focus = made.same_focus_;
  Image image{
      retina.cols, retina.rows, {"R", "G", "B"}, std::vector<float>(size_t(retina.cols) * retina.rows * 3, 0.0f)};
  if (made.one_tap_) workspace->Fit(made.sizes_, RetinaWorkspace::TeamSize());
  if (made.one_tap_ && !same_focus) {
    Image at_focus = image;
    for (int c = 0; c < 3; ++c) {
      NearestRetina(model, t, retina, pupil, made.foci_[c], workspace, &at_focus);
      for (size_t k = c; k < image.pixels.size(); k += 3) image.pixels[k] = at_focus.pixels[k];
    }
    return image;
  }
  if (made.one_tap_) {  // and so one focus
    NearestRetina(model, t, retina, pupil, made.foci_[0], workspace, &image);
    return image;
  }
  const int foci = same_focus ? 1 : 3;
  const std::vector<LayerTables> tables = GeneralTables(model, retina, pupil, accommodation, tan_x, tan_y, foci);
  GeneralRetina(model, t, retina, pupil, tables, tan_x, tan_y, same_focus, &image);
  return image;
}

Image RetinaOfScene(const SceneRadiance& scene, const RetinaGrid& retina, const std::vector<PupilPoint>& pupil,
                    const std::array<double, 3>& accommodation) {
  if (const LightFieldRays* rays = scene.target<LightFieldRays>())
    return RetinaOfLightField(rays->light_field(), rays->sampling(), retina, pupil, accommodation);
  return RetinaOfSceneRayByRay(scene, retina, pupil, accommodation);
}

Image RetinaOfSceneRayByRay(const SceneRadiance& scene, const RetinaGrid& retina, const std::vector<PupilPoint>& pupil,
                            const std::array<double, 3>& accommodation) {
  Image image{
      retina.cols, retina.rows, {"R", "G", "B"}, std::vector<float>(size_t(retina.cols) * retina.rows * 3, 0.0f)};
  const bool same_focus = accommodation[0] == accommodation[1] && accommodation[1] == accommodation[2];
  const double inverse_count = 1.0 / pupil.size();
#pragma omp parallel for schedule(dynamic)
  for (int i = 0; i < retina.rows; ++i)
    for (int j = 0; j < retina.cols; ++j) {
      double tx = std::tan(retina.angle_x(j)), ty = std::tan(retina.angle_y(i));
      double sum[3] = {0, 0, 0};
      for (const PupilPoint& u : pupil)
        for (int c = 0; c < (same_focus ? 1 : 3); ++c) {
          // Direction through the in-focus point: tan(a) - u D_a per unit depth, less the wavefront slope.
          Rgb radiance = scene(u, tx - u.x_m * accommodation[c] - u.deviation_x(accommodation[c]),
                               ty - u.y_m * accommodation[c] - u.deviation_y(accommodation[c]));
          if (same_focus)
            for (int k = 0; k < 3; ++k) sum[k] += radiance[k];
          else
            sum[c] += radiance[c];
        }
      for (int c = 0; c < 3; ++c) image.pixels[(size_t(i) * retina.cols + j) * 3 + c] = float(sum[c] * inverse_count);
    }
  return image;
}

}  // namespace layerlab
