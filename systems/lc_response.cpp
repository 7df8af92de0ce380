#include "layerlab/systems/lc_response.h"

#include <array>
#include <cmath>
#include <map>
#include <numbers>

#include "layerlab/framework/error.h"

namespace layerlab {
namespace {

// x after `s` seconds from x0 toward t.
double Relaxed(double x0, double t, double s, double rise_s, double fall_s) {
  const double time = t > x0 ? rise_s : fall_s;
  if (time <= 0) return t;
  return t + (x0 - t) * std::exp(-s * kTenToNinetyPerTau / time);
}

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
    for (size_t j = 0; j < k; ++j) y = Relaxed(y, driven[j], subframe_s, rise_s, fall_s);
    const bool repeats = std::abs(y - x) <= 1e-15;
    x = y;
    if (repeats) break;
  }
  std::vector<double> start(k, x);
  for (size_t j = 1; j < k; ++j) start[j] = Relaxed(start[j - 1], driven[j - 1], subframe_s, rise_s, fall_s);
  return start;
}

std::vector<ShownInstant> ShownOverTime(const DisplaySystem& system, const Patterns& driven) {
  if (driven.size() != system.layers.size()) throw Error("LC response: the patterns are not the display's layers");
  if (!ResponseMatters(system)) return {{1.0, driven}};
  const int K = system.subframes;
  const double T = 1 / (K * system.frame_rate_hz);
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
  static const std::array<std::array<double, 2>, kResponseNodes> nodes = GaussLegendre();
  std::vector<ShownInstant> out(kResponseNodes);
  for (int m = 0; m < kResponseNodes; ++m) out[m] = {nodes[m][1], driven};
  for (const auto& panel_layers : panels) {  // (no structured binding: OpenMP's region below reads them)
    const std::string& element = panel_layers.first;
    const std::vector<int>& layers = panel_layers.second;
    for (int l : layers)
      if (l < 0) throw Error("internal error: panel \"" + element + "\" is missing a subframe");
    const PanelSpec& panel = system.layers[layers[0]].panel;
    const size_t values = driven[layers[0]].rgb.size();
    for (int l : layers)
      if (driven[l].rgb.size() != values) throw Error("LC response: a panel's subframes differ in size");
#pragma omp parallel for schedule(static)
    for (size_t v = 0; v < values; ++v) {
      std::vector<double> cycle(K);
      for (int k = 0; k < K; ++k) cycle[k] = driven[layers[k]].rgb[v];
      const std::vector<double> start = SteadyStartValues(cycle, T, panel.rise_time_s, panel.fall_time_s);
      for (int m = 0; m < kResponseNodes; ++m)
        for (int k = 0; k < K; ++k)
          out[m].patterns[layers[k]].rgb[v] =
              static_cast<float>(Relaxed(start[k], cycle[k], nodes[m][0] * T, panel.rise_time_s, panel.fall_time_s));
    }
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
  return SeenOverTime(system, driven, PanelDiffraction(system));
}

}  // namespace layerlab
