#include "layerlab/systems/lc_response.h"

#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include "layerlab/framework/error.h"
#include "layerlab/systems/source_spread.h"

namespace layerlab {
namespace {

// Gauss-Legendre nodes and weights on [0, 1].
std::array<std::array<double, 2>, kResponseNodes> GaussLegendre() {
  std::array<std::array<double, 2>, kResponseNodes> out{};
  const int n = kResponseNodes;
  for (int i = 0; i < n; ++i) {
    double x = std::cos(std::numbers::pi * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int iteration = 0; iteration < 100; ++iteration) {  // Newton on P_n
      double p0 = 1, p1 = x;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
        p0 = p1, p1 = p2;
      }
      dp = n * (x * p1 - p0) / (x * x - 1);
      const double step = p1 / dp;
      x -= step;
      if (std::abs(step) < 1e-16) break;
    }
    out[i] = {0.5 * (1 - x), 1 / ((1 - x * x) * dp * dp)};  // node on [0, 1], weight 2 / ... halved
  }
  return out;
}

}  // namespace

double RelaxedTransmittance(double x0, double t, double s, double rise_s, double fall_s) {
  const double time = t > x0 ? rise_s : fall_s;
  if (time <= 0) return t;
  return t + (x0 - t) * std::exp(-s * kTenToNinetyPerTau / time);
}

const std::array<std::array<double, 2>, kResponseNodes>& ResponseNodes() {
  static const std::array<std::array<double, 2>, kResponseNodes> nodes = GaussLegendre();
  return nodes;
}

bool ResponseMatters(const DisplaySystem& system) {
  if (system.subframes < 2) return false;
  for (const VirtualLayer& layer : system.layers)
    if (layer.panel.rise_time_s > 0 || layer.panel.fall_time_s > 0) return true;
  return false;
}

std::vector<double> SteadyStartValues(const std::vector<double>& driven, double subframe_s, double rise_s,
                                      double fall_s) {
  const size_t k = driven.size();
  if (k == 0) return {};
  // The value at the start of the cycle: the fixed point of one cycle, which contracts toward it by
  // prod exp(-T / tau) (the last subframe's value held, to begin).
  double x = driven.back();
  for (int cycle = 0; cycle < 1000000; ++cycle) {
    double y = x;
    for (size_t j = 0; j < k; ++j) y = RelaxedTransmittance(y, driven[j], subframe_s, rise_s, fall_s);
    const bool repeats = std::abs(y - x) <= 1e-15;
    x = y;
    if (repeats) break;
  }
  std::vector<double> start(k, x);
  for (size_t j = 1; j < k; ++j)
    start[j] = RelaxedTransmittance(start[j - 1], driven[j - 1], subframe_s, rise_s, fall_s);
  return start;
}

ResponseMap::ResponseMap(const DisplaySystem& system, const Patterns& driven) : driven_(driven) {
  if (driven.size() != system.layers.size()) throw Error("LC response: the patterns are not the display's layers");
  if (!ResponseMatters(system)) {
    weights_ = {1.0};
    return;
  }
  const int K = system.subframes;
  const double T = 1 / (K * system.frame_rate_hz);
  const std::array<std::array<double, 2>, kResponseNodes>& nodes = ResponseNodes();
  for (const auto& node : nodes) weights_.push_back(node[1]);
  // Each panel's layers in subframe order: one physical panel shows them in turn.
  std::map<std::string, std::vector<int>> panels;
  for (size_t l = 0; l < system.layers.size(); ++l) {
    const VirtualLayer& layer = system.layers[l];
    std::vector<int>& of = panels[layer.element];
    if (of.empty()) of.assign(K, -1);
    if (layer.subframe < 0 || layer.subframe >= K || of[layer.subframe] >= 0)
      throw Error("internal error: panel \"" + layer.element + "\" has no single layer per subframe");
    of[layer.subframe] = static_cast<int>(l);
  }
  start_.resize(driven.size());
  for (const auto& panel_layers : panels) {  // (no structured binding: OpenMP's region below reads them)
    const std::string& element = panel_layers.first;
    const std::vector<int>& layers = panel_layers.second;
    for (int l : layers)
      if (l < 0) throw Error("internal error: panel \"" + element + "\" is missing a subframe");
    const PanelSpec& spec = system.layers[layers[0]].panel;
    Panel panel;
    panel.layers = layers;
    const double times[2] = {spec.fall_time_s, spec.rise_time_s};
    for (int d = 0; d < 2; ++d) {
      // As RelaxedTransmittance computes them, bit for bit.
      panel.a[d] = times[d] <= 0 ? 0.0 : std::exp(-T * kTenToNinetyPerTau / times[d]);
      for (const auto& node : nodes)
        panel.e[d].push_back(times[d] <= 0 ? 0.0 : std::exp(-(node[0] * T) * kTenToNinetyPerTau / times[d]));
    }
    const size_t values = driven[layers[0]].rgb.size();
    for (int l : layers) {
      if (driven[l].rgb.size() != values) throw Error("LC response: a panel's subframes differ in size");
      start_[l].resize(values);
    }
#pragma omp parallel for schedule(static)
    for (size_t v = 0; v < values; ++v) {
      std::vector<double> cycle(K);
      for (int k = 0; k < K; ++k) cycle[k] = driven[layers[k]].rgb[v];
      const std::vector<double> start = SteadyStartValues(cycle, T, spec.rise_time_s, spec.fall_time_s);
      for (int k = 0; k < K; ++k) start_[layers[k]][v] = start[k];
    }
    panels_.push_back(std::move(panel));
  }
}

void ResponseMap::Shown(int m, Patterns* shown) const {
  if (shown->size() != driven_.size()) *shown = driven_;
  if (panels_.empty()) {
    for (size_t l = 0; l < driven_.size(); ++l) (*shown)[l].rgb = driven_[l].rgb;
    return;
  }
  for (const Panel& panel : panels_)
    for (int l : panel.layers) {
      const std::vector<float>& t = driven_[l].rgb;
      const std::vector<double>& x0 = start_[l];
      std::vector<float>& out = (*shown)[l].rgb;
      out.resize(t.size());
#pragma omp parallel for schedule(static)
      for (size_t v = 0; v < t.size(); ++v) {
        const double e = panel.e[t[v] > x0[v]][m];
        out[v] = static_cast<float>(t[v] + (x0[v] - t[v]) * e);
      }
    }
}

void ResponseMap::AddTransposed(int m, double scale, const std::vector<char>* summed,
                                const std::vector<TransposedSums>& sums) const {
  if (panels_.empty()) {
    for (const TransposedSums& s : sums)
      for (size_t l = 0; l < s.g->size(); ++l)
        if (!summed || (*summed)[l])
          for (size_t v = 0; v < (*s.g)[l].size(); ++v) (*s.out)[l][v] += scale * (*s.g)[l][v];
    return;
  }
  for (const Panel& panel : panels_) {
    const std::vector<int>& layers = panel.layers;
    const int K = static_cast<int>(layers.size());
    int asked = 0;
    for (int l : layers) asked += !summed || (*summed)[l];
    if (asked == 0) continue;
    if (asked != K)  // the response couples a panel's subframes: their sums come together or not at all
      throw Error("internal error: the LC response's transpose asked for some of a panel's subframes only");
    const size_t values = driven_[layers[0]].rgb.size();
#pragma omp parallel for schedule(static)
    for (size_t v = 0; v < values; ++v) {
      // The directions, then J (x0 = J t) row by row, then out_j += scale ((1 - e_j) g_j + sum_k e_k g_k J_kj).
      double a[kMaxSubframes], e[kMaxSubframes], J[kMaxSubframes][kMaxSubframes];
      double cycle_product = 1;
      for (int k = 0; k < K; ++k) {
        const int rise = driven_[layers[k]].rgb[v] > start_[layers[k]][v];
        a[k] = panel.a[rise], e[k] = panel.e[rise][m], cycle_product *= a[k];
      }
      double tail = 1;  // prod_{j<i<K} a_i
      for (int j = K - 1; j >= 0; --j) J[0][j] = (1 - a[j]) * tail / (1 - cycle_product), tail *= a[j];
      for (int k = 0; k + 1 < K; ++k)
        for (int j = 0; j < K; ++j) J[k + 1][j] = a[k] * J[k][j] + (j == k ? 1 - a[k] : 0.0);
      for (const TransposedSums& s : sums) {
        const std::vector<std::vector<double>>& g = *s.g;
        for (int j = 0; j < K; ++j) {
          double sum = (1 - e[j]) * g[layers[j]][v];
          for (int k = 0; k < K; ++k) sum += e[k] * g[layers[k]][v] * J[k][j];
          (*s.out)[layers[j]][v] += scale * sum;
        }
      }
    }
  }
}

std::vector<ShownInstant> ShownOverTime(const DisplaySystem& system, const Patterns& driven) {
  const ResponseMap map(system, driven);
  std::vector<ShownInstant> out(map.instants());
  for (int m = 0; m < map.instants(); ++m) {
    out[m].weight = map.weight(m);
    map.Shown(m, &out[m].patterns);
  }
  return out;
}

std::vector<ShownInstant> SeenOverTime(const DisplaySystem& system, const Patterns& driven,
                                       const std::vector<LayerDiffraction>& diffraction) {
  std::vector<ShownInstant> shown = ShownOverTime(system, driven);
  if (!diffraction.empty())
    for (ShownInstant& instant : shown) instant.patterns = DiffractedPatterns(diffraction, instant.patterns);
  return shown;
}

std::vector<ShownInstant> SeenOverTime(const DisplaySystem& system, const Patterns& driven) {
  return SeenOverTime(system, driven, SeenKernels(system, true));
}

}  // namespace layerlab
