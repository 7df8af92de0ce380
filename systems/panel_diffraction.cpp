#include "layerlab/systems/panel_diffraction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

double Sinc(double x) { return x == 0 ? 1.0 : std::sin(std::numbers::pi * x) / (std::numbers::pi * x); }

// One axis: the orders of a panel of `pitch` and `fill` seen `gap` in front of a layer of `layer_pitch`.
DiffractionAxis Axis(double pitch, double fill, double wavelength, double gap, double layer_pitch, double coherence) {
  if (fill >= 1) return {0, {1.0}};
  const int most = static_cast<int>(std::ceil(2 / (std::numbers::pi * std::numbers::pi * kDiffractionTail * fill)));
  const std::vector<GratingOrder> orders = GratingOrders(pitch, fill, wavelength, most);
  // A coherent backlight spreads each order over the angles lambda / w: sigma in the layer's pixels.
  const double sigma = coherence > 0 ? gap * wavelength / (2 * std::numbers::pi * coherence) / layer_pitch : 0;
  double total = 0, farthest = 0;
  for (const GratingOrder& o : orders) {
    total += o.efficiency;
    farthest = std::max(farthest, std::abs(gap * std::tan(o.angle_rad) / layer_pitch));
  }
  DiffractionAxis axis;
  axis.reach = static_cast<int>(std::ceil(farthest + 4 * sigma)) + 1;
  axis.weight.assign(2 * axis.reach + 1, 0.0);
  for (const GratingOrder& o : orders) {
    const double shift = gap * std::tan(o.angle_rad) / layer_pitch, w = o.efficiency / total;
    if (sigma > 0) {
      double sum = 0;
      std::vector<double> spread(axis.weight.size());
      for (int k = -axis.reach; k <= axis.reach; ++k)
        sum += spread[k + axis.reach] = std::exp(-0.5 * (k - shift) * (k - shift) / (sigma * sigma));
      for (size_t k = 0; k < spread.size(); ++k) axis.weight[k] += w * spread[k] / sum;
    } else {
      const int below = static_cast<int>(std::floor(shift));
      const double t = shift - below;
      axis.weight[below + axis.reach] += w * (1 - t);
      axis.weight[below + 1 + axis.reach] += w * t;
    }
  }
  return axis;
}

// A rows x cols x 3 image convolved with each channel's kernel along x (`axis` 0) or y (1) into `out` (not
// `in`), zero beyond the layer; `transposed`: with the kernels flipped, the convolution's transpose. A row at
// a time, tap by tap: each tap adds a shifted run of the input (contiguous, all three channels), in double.
template <typename In, typename Out>
void Convolve(const In* in, int rows, int cols, const std::array<std::array<DiffractionAxis, 2>, 3>& axes, int axis,
              bool transposed, Out* out) {
  const int sign = transposed ? -1 : 1;
  int reach = 0;
  for (int c = 0; c < 3; ++c) reach = std::max(reach, axes[c][axis].reach);
  const size_t row = size_t(cols) * 3;
#pragma omp parallel
  {
    std::vector<double> sum(row);
#pragma omp for schedule(static)
    for (int i = 0; i < rows; ++i) {
      std::fill(sum.begin(), sum.end(), 0.0);
      for (int k = -reach; k <= reach; ++k) {
        double w[3];
        for (int c = 0; c < 3; ++c) {
          const DiffractionAxis& a = axes[c][axis];
          w[c] = std::abs(k) <= a.reach ? a.weight[k + a.reach] : 0.0;
        }
        if (w[0] == 0 && w[1] == 0 && w[2] == 0) continue;
        // A ghost moved by +k pixels shows at j the pattern at j - k.
        const int shift = sign * k;
        int j0 = 0, j1 = cols;  // the pixels of the row this tap reaches; `source` is the input at j0
        const In* source = nullptr;
        if (axis == 0) {
          j0 = std::max(0, shift), j1 = std::min(cols, cols + shift);
          if (j0 >= j1) continue;
          source = in + size_t(i) * row + size_t(j0 - shift) * 3;
        } else {
          const int si = i - shift;
          if (si < 0 || si >= rows) continue;
          source = in + size_t(si) * row;
        }
        double* target = sum.data() + size_t(j0) * 3;
        for (size_t j = 0, n = size_t(j1 - j0); j < n; ++j)
          for (int c = 0; c < 3; ++c) target[j * 3 + c] += w[c] * source[j * 3 + c];
      }
      Out* o = out + size_t(i) * row;
      for (size_t e = 0; e < row; ++e) o[e] = static_cast<Out>(sum[e]);
    }
  }
}

void RequireLayer(const LayerDiffraction& d, size_t layers) {
  if (d.layer < 0 || size_t(d.layer) >= layers) throw Error("panel diffraction: a layer the patterns do not hold");
}

}  // namespace

std::vector<GratingOrder> GratingOrders(double pitch_m, double fill, double wavelength_m, int max_order) {
  if (!(pitch_m > 0) || !(fill > 0 && fill <= 1) || !(wavelength_m > 0) || max_order < 0)
    throw Error("grating orders need a pitch > 0, a fill factor in (0, 1], a wavelength > 0 and max_order >= 0");
  std::vector<GratingOrder> orders;
  for (int m = -max_order; m <= max_order; ++m) {
    const double s = m * wavelength_m / pitch_m;
    if (std::abs(s) >= 1) continue;
    orders.push_back({m, std::asin(s), fill * fill * Sinc(m * fill) * Sinc(m * fill)});
  }
  return orders;
}

std::vector<LayerDiffraction> PanelDiffraction(const DisplaySystem& system) {
  std::vector<LayerDiffraction> out;
  for (const Branch& branch : system.branches)
    for (size_t front = 0; front < branch.layers.size(); ++front) {
      const VirtualLayer& j = system.layers[branch.layers[front]];
      if (!j.panel.diffracts()) continue;
      for (size_t back = front + 1; back < branch.layers.size(); ++back) {
        const VirtualLayer& k = system.layers[branch.layers[back]];
        const double gap = k.position_m - j.position_m;
        // A panel's next is a panel or a backlight (elements/lc_panel.cpp): nothing with power lies between
        // two panels of a stack, so both are measured from the same lens or mirror.
        if (!(gap > 0) || std::abs((k.panel_distance_m - j.panel_distance_m) - gap) > 1e-9)
          throw Error("internal error: panels \"" + j.name + "\" and \"" + k.name + "\" of one stack are not " +
                      "a straight gap apart");
        LayerDiffraction d{branch.layers[back], branch.layers[front], gap, {}};
        for (int c = 0; c < 3; ++c) {
          const double lambda = system.eye.channel_wavelengths_m[c];
          d.axes[c][0] = Axis(j.panel.pitch_x_m, j.panel.fill_factor[0], lambda, gap, k.panel.pitch_x_m,
                              branch.backlight_coherence_width_m);
          d.axes[c][1] = Axis(j.panel.pitch_y_m, j.panel.fill_factor[1], lambda, gap, k.panel.pitch_y_m,
                              branch.backlight_coherence_width_m);
        }
        out.push_back(std::move(d));
      }
    }
  return out;
}

void DiffractPatterns(const std::vector<LayerDiffraction>& diffraction, const Patterns& t, Patterns* seen) {
  *seen = t;
  std::vector<float> across;
  for (const LayerDiffraction& d : diffraction) {
    RequireLayer(d, t.size());
    LayerPattern& p = (*seen)[d.layer];
    across.resize(p.rgb.size());
    Convolve(p.rgb.data(), p.rows, p.cols, d.axes, 0, false, across.data());
    Convolve(across.data(), p.rows, p.cols, d.axes, 1, false, p.rgb.data());
  }
}

Patterns DiffractedPatterns(const std::vector<LayerDiffraction>& diffraction, const Patterns& t) {
  Patterns seen;
  DiffractPatterns(diffraction, t, &seen);
  return seen;
}

void DiffractTransposed(const std::vector<LayerDiffraction>& diffraction, int layer, int rows, int cols,
                        std::vector<double>* sums) {
  if (sums->size() != size_t(rows) * cols * 3) throw Error("panel diffraction: sums not of the layer's size");
  std::vector<double> across;
  for (auto d = diffraction.rbegin(); d != diffraction.rend(); ++d) {  // D = D_n ... D_1, so D^T = D_1^T ... D_n^T
    if (d->layer != layer) continue;
    across.resize(sums->size());
    Convolve(sums->data(), rows, cols, d->axes, 1, true, across.data());
    Convolve(across.data(), rows, cols, d->axes, 0, true, sums->data());
  }
}

bool Diffracts(const std::vector<LayerDiffraction>& diffraction, int layer) {
  for (const LayerDiffraction& d : diffraction)
    if (d.layer == layer) return true;
  return false;
}

}  // namespace layerlab
