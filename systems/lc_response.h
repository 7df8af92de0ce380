// The liquid crystal's response: what a time-multiplexed display's panels
// actually show. A panel driven to transmittance t in a subframe of length
// T = 1 / (K frame_rate) relaxes toward it from where the subframe before
// left it, as a first-order system:
//   x(s) = t + (x0 - t) exp(-s / tau),   0 <= s < T,
// tau = time / ln 9 from the panel's 10 to 90 % rise_time (t > x0) or
// fall_time (t < x0), on transmittance, per pixel and channel. The frame
// repeats, so each pixel's start values are the periodic steady state of
// its K driven values (found by running the cycle until it repeats). The
// eye sees the time average of the light, a product of the stack's x(s):
//   L = sum_k w_k (1/T) int_0^T prod_{j in k} P_j x_j(s) ds,
// taken by Gauss-Legendre quadrature in s (kResponseNodes nodes: the
// integrand is a sum of exponentials exp(-a s / T), a up to the layers'
// sum of T / tau; 8 nodes integrate one within 1e-11 at a = 6.6, 3e-8 at
// a = 13, 1e-4 at a = 36: accurate while the panels relax slowly against a
// subframe, as 4 and 8 ms panels at 180 Hz do (a <= 9); a panel much faster
// than its subframe is nearly instant, but its transient is then integrated
// coarsely). A display of one subframe, or with instant panels, shows its
// driven patterns: one node of weight 1.
#pragma once

#include <array>
#include <vector>

#include "layerlab/systems/display_model.h"
#include "layerlab/systems/panel_diffraction.h"

namespace layerlab {

inline constexpr int kResponseNodes = 8;
// tau = (10 to 90 % time) / ln 9.
inline constexpr double kTenToNinetyPerTau = 2.1972245773362196;

// What the panels show at one instant of every subframe, and its share of the frame's time.
struct ShownInstant {
  double weight = 1;  // the quadrature weight; the instants' weights sum to 1
  Patterns patterns;  // every layer's transmittance at that instant of its subframe
};

// Whether any panel of the display responds in finite time across subframes.
bool ResponseMatters(const DisplaySystem& system);

// The instants of a frame (kResponseNodes of them, or the driven patterns alone when the response does not
// matter). Throws layerlab::Error when the patterns are not the display's layers.
std::vector<ShownInstant> ShownOverTime(const DisplaySystem& system, const Patterns& driven);
// Those instants each as the eye sees them through `diffraction` (systems/panel_diffraction.h; default: the
// display's own, SeenKernels(system, true): its LED arrays' spread and its panels' diffraction): what every
// retinal image of the display reads.
std::vector<ShownInstant> SeenOverTime(const DisplaySystem& system, const Patterns& driven,
                                       const std::vector<LayerDiffraction>& diffraction);
std::vector<ShownInstant> SeenOverTime(const DisplaySystem& system, const Patterns& driven);

// The response of one driven frame as maps of the driven patterns: the
// shown patterns at each node, and their transposes for the chain rule.
class ResponseMap {
 public:
  // Throws layerlab::Error when the patterns are not the display's layers.
  ResponseMap(const DisplaySystem& system, const Patterns& driven);
  // kResponseNodes, or 1 (the driven patterns) when the response does not matter.
  int instants() const { return static_cast<int>(weights_.size()); }
  double weight(int m) const { return weights_[m]; }
  // The patterns the panels show at node m, into *shown (sized like the driven ones).
  void Shown(int m, Patterns* shown) const;
  // out[l] += scale R_m^T g[l] for every layer of the panels whose layers `summed` ([layer], nonzero:
  // needed; null: all) holds; the other layers' out is left as it is. Throws layerlab::Error for a panel of
  // which `summed` holds some layers only (the response couples them).
  void AddTransposed(int m, const std::vector<std::vector<double>>& g, double scale, const std::vector<char>* summed,
                     std::vector<std::vector<double>>* out) const {
    AddTransposed(m, scale, summed, {{&g, out}});
  }
  // The same for several sums at once (a pass's residual and denominator): R_m built once per value for all.
  struct TransposedSums {
    const std::vector<std::vector<double>>* g;
    std::vector<std::vector<double>>* out;
  };
  void AddTransposed(int m, double scale, const std::vector<char>* summed,
                     const std::vector<TransposedSums>& sums) const;

 private:
  struct Panel {
    std::vector<int> layers;   // [subframe]
    double a[2] = {0, 0};      // exp(-T / tau) of a fall (0) and a rise (1)
    std::vector<double> e[2];  // [node]: exp(-s_m / tau) of a fall and a rise
  };
  const Patterns& driven_;
  std::vector<double> weights_;
  std::vector<Panel> panels_;
  std::vector<std::vector<double>> start_;  // [layer][value]: x0, the steady state's start of its subframe
};

// The quadrature's nodes on [0, 1] of a subframe (fraction of it) and their weights (summing to 1).
const std::array<std::array<double, 2>, kResponseNodes>& ResponseNodes();
// A pixel's transmittance `s` seconds into a subframe driven to `t` from `x0` (rising in rise_s, falling in
// fall_s, 10 to 90 %).
double RelaxedTransmittance(double x0, double t, double s, double rise_s, double fall_s);

// One pixel's transmittance at the start of each of its K subframes in the periodic steady state (the
// building block of ShownOverTime, for tests): driven[k], subframe length T, rise and fall times (10 to 90 %).
std::vector<double> SteadyStartValues(const std::vector<double>& driven, double subframe_s, double rise_s,
                                      double fall_s);

}  // namespace layerlab
