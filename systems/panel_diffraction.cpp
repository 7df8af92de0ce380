#include "layerlab/systems/panel_diffraction.h"

#include <algorithm>
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

// Channel c of `in` convolved with `axis` along x (`along_x`) or y into `out`, zero beyond the layer.
void Convolve(const LayerPattern& in, int c, const DiffractionAxis& axis, bool along_x, LayerPattern* out) {
#pragma omp parallel for
  for (int i = 0; i < in.rows; ++i)
    for (int j = 0; j < in.cols; ++j) {
      double sum = 0;
      for (int k = -axis.reach; k <= axis.reach; ++k) {
        const double w = axis.weight[k + axis.reach];
        if (w == 0) continue;
        // A ghost moved by +k pixels shows at j the pattern at j - k.
        const int si = along_x ? i : i - k, sj = along_x ? j - k : j;
        if (si < 0 || sj < 0 || si >= in.rows || sj >= in.cols) continue;
        sum += w * in.rgb[(size_t(si) * in.cols + sj) * 3 + c];
      }
      out->rgb[(size_t(i) * in.cols + j) * 3 + c] = static_cast<float>(sum);
    }
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

Patterns DiffractedPatterns(const std::vector<LayerDiffraction>& diffraction, const Patterns& t) {
  Patterns seen = t;
  for (const LayerDiffraction& d : diffraction) {
    if (d.layer < 0 || size_t(d.layer) >= t.size()) throw Error("panel diffraction: a layer the patterns do not hold");
    LayerPattern& p = seen[d.layer];
    LayerPattern across = p;
    for (int c = 0; c < 3; ++c) {
      Convolve(p, c, d.axes[c][0], true, &across);
      Convolve(across, c, d.axes[c][1], false, &p);
    }
  }
  return seen;
}

Patterns SeenPatterns(const DisplaySystem& system, const Patterns& t) {
  return DiffractedPatterns(PanelDiffraction(system), t);
}

}  // namespace layerlab
