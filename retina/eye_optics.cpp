#include "layerlab/retina/eye_optics.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "layerlab/eye/spectral_filter.h"
#include "layerlab/framework/error.h"
#include "layerlab/retina/diffraction.h"
#include "layerlab/retina/retina.h"

namespace layerlab {
namespace {

// Cells across the pupil's bounding square for its OTF's parts, and for choosing the groups.
constexpr int kPartCells = 128, kGroupingCells = 32;

// The smallest even n' >= n whose prime factors are 2, 3 and 5.
int FastEvenFftSize(int n) {
  int m = FastFftSize(std::max(n, 2));
  while (m % 2 != 0) m = FastFftSize(m + 1);
  return m;
}

// The pupil sample nearest a point: the samples binned in square buckets, searched ring by ring.
class NearestSample {
 public:
  NearestSample(const std::vector<PupilPoint>& own, double diameter) : own_(own) {
    side_ = std::max(1, static_cast<int>(std::sqrt(double(own.size()))));
    bucket_ = diameter / side_, origin_ = -0.5 * diameter;
    buckets_.resize(size_t(side_) * side_);
    for (size_t s = 0; s < own.size(); ++s) buckets_[Index(Cell(own[s].x_m), Cell(own[s].y_m))].push_back(int(s));
  }
  int operator()(double x, double y) const {
    const int cx = Cell(x), cy = Cell(y);
    int best = 0;
    double nearest = INFINITY;
    for (int ring = 0; ring <= side_; ++ring) {
      // Every sample beyond this ring lies farther than ring bucket widths.
      if (nearest < INFINITY && std::sqrt(nearest) <= (ring - 1) * bucket_) break;
      for (int by = cy - ring; by <= cy + ring; ++by)
        for (int bx = cx - ring; bx <= cx + ring; ++bx) {
          if (std::max(std::abs(bx - cx), std::abs(by - cy)) != ring || bx < 0 || by < 0 || bx >= side_ || by >= side_)
            continue;
          for (int s : buckets_[Index(bx, by)]) {
            const double d = (own_[s].x_m - x) * (own_[s].x_m - x) + (own_[s].y_m - y) * (own_[s].y_m - y);
            if (d < nearest || (d == nearest && s < best)) nearest = d, best = s;
          }
        }
    }
    return best;
  }

 private:
  int Cell(double v) const { return std::clamp(static_cast<int>(std::floor((v - origin_) / bucket_)), 0, side_ - 1); }
  size_t Index(int bx, int by) const { return size_t(by) * side_ + bx; }
  const std::vector<PupilPoint>& own_;
  int side_;
  double bucket_, origin_;
  std::vector<std::vector<int>> buckets_;
};

// Each autocorrelation midpoint's shares among the pupil samples (PupilOtfLattice's half-cell grid of n
// cells): of 4 x 4 points over the midpoint's cell, the part nearest each sample (its tilt the sample's slope).
std::vector<std::vector<MidpointShare>> MidpointShares(const std::vector<PupilPoint>& own, double diameter, int n) {
  const int q = 2 * n - 1, sub = 4;
  const double h = diameter / n;
  const NearestSample nearest(own, diameter);
  std::vector<std::vector<MidpointShare>> shares(size_t(q) * q);
#pragma omp parallel for schedule(dynamic)
  for (int qy = 0; qy < q; ++qy)
    for (int qx = 0; qx < q; ++qx) {
      std::vector<MidpointShare>& of = shares[size_t(qy) * q + qx];
      for (int a = 0; a < sub; ++a)
        for (int b = 0; b < sub; ++b) {
          const double x = -0.5 * diameter + (qx + 1) * 0.5 * h + ((b + 0.5) / sub - 0.5) * h;
          const double y = 0.5 * diameter - (qy + 1) * 0.5 * h + ((a + 0.5) / sub - 0.5) * h;
          const int best = nearest(x, y);
          auto it = std::find_if(of.begin(), of.end(), [&](const MidpointShare& m) { return m.part == best; });
          if (it != of.end())
            it->weight += 1.0 / (sub * sub);
          else
            of.push_back({best, 1.0 / (sub * sub), best});
        }
    }
  return shares;
}

// The samples' wavefront slopes, the tilts of their shares.
std::vector<PupilTilt> Tilts(const std::vector<PupilPoint>& own) {
  std::vector<PupilTilt> tilts;
  for (const PupilPoint& u : own) tilts.push_back({u.slope_x, u.slope_y});
  return tilts;
}

// The lattice's reach that covers a grid's frequencies up to its Nyquist 1 / (2 resolution) on both axes.
int ReachFor(double resolution_rad, double wavelength_m, double diameter_m, int cells) {
  const double step = diameter_m / cells / wavelength_m;
  return std::min(cells - 1, static_cast<int>(std::ceil(1 / (2 * resolution_rad) / step)) + 1);
}

// Samples in groups whose parts of the OTF, each relative to its value at f = 0, agree within
// `tolerance` (leader clustering in the samples' order); group_of[s].
std::vector<int> GroupSamples(const PupilOptics& optics, const std::vector<PupilPoint>& own, double resolution_rad,
                              double tolerance) {
  const size_t samples = own.size();
  std::vector<std::vector<MidpointShare>> shares = MidpointShares(own, optics.diameter_m, kGroupingCells);
  const std::vector<PupilTilt> tilts = Tilts(own);
  if (optics.wavefront.empty())
    for (std::vector<MidpointShare>& of : shares)
      for (MidpointShare& share : of) share.tilt = -1;
  const int reach = ReachFor(resolution_rad, optics.wavelength_m, optics.diameter_m, kGroupingCells);
  const OtfLattice of_sample = PupilOtfLattice(optics, kGroupingCells, reach, static_cast<int>(samples), shares, tilts);
  const size_t points = size_t(2 * reach + 1) * (2 * reach + 1), zero = points / 2;
  // Each sample's part relative to its share at f = 0 (the cells' areas on the coarse grid are approximate).
  std::vector<std::complex<double>> shape(of_sample.values);
  for (size_t s = 0; s < samples; ++s) {
    const std::complex<double> share = of_sample.values[s * points + zero];
    for (size_t m = 0; m < points; ++m) shape[s * points + m] = share == 0.0 ? 0.0 : shape[s * points + m] / share;
  }
  std::vector<int> group_of(samples, -1), leaders;
  for (size_t s = 0; s < samples; ++s) {
    for (size_t g = 0; g < leaders.size() && group_of[s] < 0; ++g) {
      double distance = 0;
      for (size_t m = 0; m < points; ++m)
        distance = std::max(distance, std::abs(shape[s * points + m] - shape[leaders[g] * points + m]));
      if (distance <= tolerance) group_of[s] = static_cast<int>(g);
    }
    if (group_of[s] < 0) group_of[s] = static_cast<int>(leaders.size()), leaders.push_back(static_cast<int>(s));
  }
  return group_of;
}

}  // namespace

EyeOptics::EyeOptics(const EyeModel& eye, const std::vector<PupilPoint>& pupil, const RetinaGrid& grid, RowEdges rows,
                     double shape_tolerance)
    : mode_(eye.diffraction),
      shape_(eye.pupil_shape),
      diameter_m_(eye.pupil_diameter_m),
      wavelengths_m_(eye.channel_wavelengths_m),
      grid_(grid),
      traced_(grid) {
  if (mode_ == EyeDiffraction::kNone) {
    groups_ = {pupil};
    return;
  }
  if (!(diameter_m_ > 0)) throw Error("diffraction needs a pupil larger than a pinhole");
  const double longest = *std::max_element(wavelengths_m_.begin(), wavelengths_m_.end());
  const double support = longest / (std::numbers::pi * std::numbers::pi * diameter_m_ * kEdgeTailMass);
  const int pad = std::max(4, static_cast<int>(std::ceil(support / grid.resolution_rad)));
  field_cols_ = FastEvenFftSize(grid.cols + 2 * pad);
  left_ = (field_cols_ - grid.cols) / 2;
  traced_.cols = field_cols_;
  traced_.center_x_rad = grid.center_x_rad + (0.5 * field_cols_ - left_ - 0.5 * grid.cols) * grid.resolution_rad;
  if (rows == RowEdges::kTrace) {
    field_rows_ = FastEvenFftSize(grid.rows + 2 * pad);
    top_ = (field_rows_ - grid.rows) / 2;
    traced_.rows = field_rows_;
    traced_.center_y_rad = grid.center_y_rad + (0.5 * grid.rows - 0.5 * field_rows_ + top_) * grid.resolution_rad;
  } else {
    field_rows_ = grid.rows;  // uniform along y: the rows wrap, exactly
  }
  if (double(traced_.cols) * traced_.rows > 1e8)
    throw Error("diffraction: the retina widened by the PSF's support (" + std::to_string(pad) +
                " samples each side) would hold more than 1e8 samples; use a coarser resolution or a smaller field");
  const int half = field_cols_ / 2 + 1;
  const size_t bins = size_t(half) * field_rows_;
  if (mode_ == EyeDiffraction::kPupilMtf) {  // one group: the rays' image, its gain the MTF (real and even)
    groups_ = {pupil};
    flat_.assign(1, {false, false, false});
    for (int c = 0; c < 3; ++c) weights_[c] = {MtfOnHalfSpectrum(c)};
    return;
  }
  const std::vector<PupilPoint> own = PupilSamplesInOwnPlane(eye);
  if (own.size() != pupil.size()) throw Error("wave optics: the pupil samples are not the eye's");
  const std::vector<int> group_of =
      GroupSamples(PupilOpticsOf(eye, wavelengths_m_[1]), own, grid.resolution_rad, shape_tolerance);
  const int groups = *std::max_element(group_of.begin(), group_of.end()) + 1;
  groups_.assign(groups, {});
  for (size_t s = 0; s < pupil.size(); ++s) groups_[group_of[s]].push_back(pupil[s]);
  std::vector<std::vector<MidpointShare>> shares = MidpointShares(own, diameter_m_, kPartCells);
  const std::vector<PupilTilt> tilts = Tilts(own);
  const bool tilted = !eye.wavefront.empty();
  for (std::vector<MidpointShare>& of : shares)
    for (MidpointShare& share : of) share.tilt = tilted ? share.part : -1, share.part = group_of[share.part];
  flat_.assign(groups, {});
  for (int c = 0; c < 3; ++c) {
    const PupilOptics optics = PupilOpticsOf(eye, wavelengths_m_[c]);
    // Channels of one wavelength share their parts.
    const int same = c == 0                                             ? -1
                     : wavelengths_m_[c] == wavelengths_m_[c - 1]       ? c - 1
                     : c == 2 && wavelengths_m_[2] == wavelengths_m_[0] ? 0
                                                                        : -1;
    parts_[c] = same >= 0 ? parts_[same]
                          : PupilOtfLattice(optics, kPartCells,
                                            ReachFor(grid.resolution_rad, wavelengths_m_[c], diameter_m_, kPartCells),
                                            groups, shares, tilts);
    const size_t points = size_t(2 * parts_[c].reach + 1) * (2 * parts_[c].reach + 1);
    for (int g = 0; g < groups; ++g) {
      const std::complex<double> at_zero = parts_[c].value(g, 0, 0);
      bool flat = true;
      for (size_t m = 0; m < points && flat; ++m)
        flat = std::abs(parts_[c].values[g * points + m] - at_zero) <= 1e-9 * std::abs(at_zero);
      flat_[g][c] = flat;
    }
  }
  if (double(transformed_groups()) * 3 * bins * sizeof(std::complex<float>) > kWaveWeightBytes) return;
  for (int c = 0; c < 3; ++c) {
    weights_[c].resize(groups);
    for (int g = 0; g < groups; ++g) {
      if (flat_[g][c]) continue;
      std::vector<std::complex<float>> w(bins);  // read from the lattice until it is moved in
#pragma omp parallel for
      for (int i = 0; i < field_rows_; ++i)
        for (int j = 0; j < half; ++j) w[size_t(i) * half + j] = Weight(c, g, i, j);
      weights_[c][g] = std::move(w);
    }
  }
}

std::vector<std::complex<float>> EyeOptics::MtfOnHalfSpectrum(int c) const {
  const int half = field_cols_ / 2 + 1;
  std::vector<std::complex<float>> w(size_t(half) * field_rows_);
#pragma omp parallel for
  for (int i = 0; i < field_rows_; ++i) {
    const int ki = i <= field_rows_ / 2 ? i : i - field_rows_;
    for (int j = 0; j < half; ++j)
      w[size_t(i) * half + j] = static_cast<float>(DiffractionOtf(shape_, diameter_m_, wavelengths_m_[c],
                                                                  j / (field_cols_ * grid_.resolution_rad),
                                                                  ki / (field_rows_ * grid_.resolution_rad)));
  }
  return w;
}

std::complex<float> EyeOptics::Weight(int c, size_t g, int i, int j) const {
  const int half = field_cols_ / 2 + 1;
  if (!weights_[c].empty() && !weights_[c][g].empty()) return weights_[c][g][size_t(i) * half + j];
  const int ki = i <= field_rows_ / 2 ? i : i - field_rows_;
  const double fy = -ki / (field_rows_ * grid_.resolution_rad);  // rows run toward -y
  return std::complex<float>(parts_[c].at(static_cast<int>(g), j / (field_cols_ * grid_.resolution_rad), fy));
}

size_t EyeOptics::transformed_groups() const {
  if (mode_ != EyeDiffraction::kPupilFunction) return mode_ == EyeDiffraction::kNone ? 0 : 1;
  size_t n = 0;
  for (const std::array<bool, 3>& f : flat_) n += !(f[0] && f[1] && f[2]);
  return n;
}

Image EyeOptics::See(const TraceGroup& trace) const {
  std::vector<Image> images;
  images.reserve(groups_.size());
  for (const std::vector<PupilPoint>& g : groups_) images.push_back(trace(traced_, g));
  return Combine(images);
}

Image EyeOptics::Combine(const std::vector<Image>& images) const {
  if (images.size() != groups_.size()) throw Error("eye optics: one image per pupil group is needed");
  for (const Image& image : images)
    if (image.width != traced_.cols || image.height != traced_.rows || image.channels.size() != 3)
      throw Error("eye optics: a group's image is not an RGB image of the traced grid");
  if (mode_ == EyeDiffraction::kNone) return images[0];
  Image out{grid_.cols, grid_.rows, {"R", "G", "B"}, std::vector<float>(size_t(grid_.cols) * grid_.rows * 3, 0.0f)};
  // The transformed field of channel c of a traced image.
  auto fill = [&](const Image& image, int c, auto* field) {
#pragma omp parallel for
    for (int r = 0; r < field_rows_; ++r)
      for (int j = 0; j < field_cols_; ++j) (*field)[size_t(r) * field_cols_ + j] = image.at(r, j, c);
  };
  auto crop = [&](const auto& field, int c, double scale) {
#pragma omp parallel for
    for (int i = 0; i < grid_.rows; ++i)
      for (int j = 0; j < grid_.cols; ++j)
        out.pixels[(size_t(i) * grid_.cols + j) * 3 + c] +=
            static_cast<float>(scale * std::real(field[size_t(top_ + i) * field_cols_ + left_ + j]));
  };
  const RealFft2d fft(field_cols_, field_rows_);
  const int half = fft.half();
  std::vector<float> field(size_t(field_cols_) * field_rows_);
  std::vector<std::complex<float>> spectrum(size_t(half) * field_rows_), sum(spectrum.size());
  for (int c = 0; c < 3; ++c) {
    std::fill(sum.begin(), sum.end(), std::complex<float>(0));
    bool any = false;
    for (size_t g = 0; g < groups_.size(); ++g) {
      if (flat_[g][c]) {
        fill(images[g], c, &field);
        crop(field, c, parts_[c].value(static_cast<int>(g), 0, 0).real());
        continue;
      }
      any = true;
      fill(images[g], c, &field);
      fft.Forward(field.data(), spectrum.data());
#pragma omp parallel for
      for (int i = 0; i < field_rows_; ++i)
        for (int j = 0; j < half; ++j) sum[size_t(i) * half + j] += Weight(c, g, i, j) * spectrum[size_t(i) * half + j];
    }
    if (!any) continue;
    fft.Inverse(sum.data(), field.data());
    crop(field, c, 1.0);
  }
  return out;
}

}  // namespace layerlab
