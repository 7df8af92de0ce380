// Diffraction by the panels' pixel grids (systems/panel_diffraction.h)
// against computations written here: the orders' efficiencies from the FFT
// of a sampled binary grating, their sum (the open fraction), the ghosts'
// places and powers from an angular-spectrum propagation of a point source
// through the grating and back, the no-diffraction limits, and the paper
// prototype's kernels.
#include <cmath>
#include <complex>
#include <numbers>
#include <random>

#include <unsupported/Eigen/FFT>

#include "layerlab/systems/panel_diffraction.h"
#include "layerlab/tests/test_util.h"

namespace layerlab {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(PanelDiffraction, OrdersAreTheSampledGratingsSpectrumAtAsinMLambdaOverP) {
  // 64 periods of 1000 samples, open over fill x 1000 of each (a whole number).
  const int periods = 64, per = 1000, n = periods * per;
  for (double fill : {0.5, 0.75, 0.9}) {
    std::vector<std::complex<double>> t(n), spectrum;
    for (int i = 0; i < n; ++i) t[i] = (i % per) < fill * per ? 1.0 : 0.0;
    Eigen::FFT<double> fft;
    fft.fwd(spectrum, t);
    const std::vector<GratingOrder> orders = GratingOrders(117e-6, fill, 550e-9, 8);
    ASSERT_EQ(orders.size(), 17u);
    for (const GratingOrder& o : orders) {
      // The order's power over the incident's: |c_m|^2, c_m the bin m x periods over n (a sampled box:
      // the Dirichlet kernel, within 1e-5 of the sinc at 1000 samples a period).
      const double power = std::norm(spectrum[size_t(((o.m * periods) % n + n) % n)] / double(n));
      EXPECT_NEAR(o.efficiency, power, 1e-5) << "fill " << fill << ", order " << o.m;
      EXPECT_NEAR(std::sin(o.angle_rad), o.m * 550e-9 / 117e-6, 1e-15);
    }
  }
  // Energy: all orders together carry the open fraction.
  double sum = 0;
  for (const GratingOrder& o : GratingOrders(1.0, 0.7, 1e-6, 200000)) sum += o.efficiency;
  EXPECT_NEAR(sum, 0.7, 1e-5);
  // Only propagating orders: |m| lambda / p < 1.
  EXPECT_EQ(GratingOrders(2e-6, 0.5, 550e-9, 100).size(), 7u);
}

TEST(PanelDiffraction, GhostsSitWhereAnAngularSpectrumPropagationPutsThem) {
  // A 3 um Gaussian source, 2 mm behind a grating of 50 um pitch and 0.6 fill, at 550 nm: propagated to the
  // grating, multiplied by it, propagated back to the source plane (where the eye, focused there, sees it).
  const double lambda = 550e-9, pitch = 50e-6, fill = 0.6, gap = 2e-3, dx = 0.25e-6;
  const int n = 1 << 15;
  std::vector<std::complex<double>> field(n), spectrum, back;
  for (int i = 0; i < n; ++i) {
    const double x = (i - n / 2) * dx;
    field[i] = std::exp(-x * x / (2 * 1.5e-6 * 1.5e-6));
  }
  Eigen::FFT<double> fft;
  auto propagate = [&](std::vector<std::complex<double>>& f, double distance) {
    fft.fwd(spectrum, f);
    for (int k = 0; k < n; ++k) {
      const double fx = (k <= n / 2 ? k : k - n) / (n * dx), s = 1 - lambda * lambda * fx * fx;
      spectrum[k] *= s > 0 ? std::polar(1.0, 2 * kPi / lambda * distance * std::sqrt(s)) : 0.0;
    }
    fft.inv(f, spectrum);
  };
  propagate(field, gap);
  for (int i = 0; i < n; ++i) {
    const double x = (i - n / 2) * dx, phase = x / pitch - std::floor(x / pitch);
    if (phase >= fill) field[i] = 0;
  }
  propagate(field, -gap);
  // Each order's power within 6 um of d tan(theta_m), against the 0th's.
  auto power_near = [&](double at) {
    double p = 0;
    for (int i = 0; i < n; ++i)
      if (std::abs((i - n / 2) * dx - at) < 6e-6) p += std::norm(field[i]);
    return p;
  };
  const std::vector<GratingOrder> orders = GratingOrders(pitch, fill, lambda, 2);
  const double zeroth = power_near(0);
  for (const GratingOrder& o : orders) {
    if (o.m == 0) continue;
    const double at = gap * std::tan(o.angle_rad);
    // The brightest sample near the predicted place.
    int best = 0;
    for (int i = 0; i < n; ++i)
      if (std::abs((i - n / 2) * dx - at) < 6e-6 && std::norm(field[i]) > std::norm(field[best])) best = i;
    EXPECT_NEAR((best - n / 2) * dx, at, 0.5e-6) << "order " << o.m;
    EXPECT_NEAR(power_near(at) / zeroth, o.efficiency / orders[2].efficiency, 0.02) << "order " << o.m;
  }
}

// A stack of two panels `gap` apart, the front one diffracting.
DisplaySystem TwoPanels(double fill, const std::string& pitch) {
  nlohmann::json scene = testing::ReadExample("multiplicative_2layer.json");
  for (nlohmann::json& e : scene["elements"])
    if (e["type"] == "lc_panel") {
      e["fill_factor"] = fill;
      e["pixel_pitch"] = pitch;
    }
  return testing::CompileJson(scene);
}

TEST(PanelDiffraction, TheLayerBehindIsSeenThroughTheFrontPanelsOrders) {
  const DisplaySystem system = TwoPanels(0.75, "117 um");
  const std::vector<LayerDiffraction> d = PanelDiffraction(system);
  ASSERT_EQ(d.size(), 1u);
  const VirtualLayer &front = system.layers[d[0].panel_layer], &back = system.layers[d[0].layer];
  EXPECT_LT(front.position_m, back.position_m);
  EXPECT_NEAR(d[0].gap_m, back.position_m - front.position_m, 1e-15);
  for (int c = 0; c < 3; ++c)
    for (int a = 0; a < 2; ++a) {
      const DiffractionAxis& axis = d[0].axes[c][a];
      double sum = 0, first = 0;
      for (double w : axis.weight) sum += w;
      EXPECT_NEAR(sum, 1.0, 1e-12);
      // The kernel is symmetric; its spread is the orders' (d tan theta_m / p) weighted.
      for (int k = 0; k <= axis.reach; ++k) {
        EXPECT_NEAR(axis.weight[axis.reach + k], axis.weight[axis.reach - k], 1e-12);
        first += 2 * k * k * axis.weight[axis.reach + k];
      }
      // Linear interpolation of a shift s spreads it over floor(s) and floor(s) + 1: second moment
      // s^2 + t (1 - t), t = s - floor(s). The orders kept: |m| <= 2 / (pi^2 tail f), renormalized.
      const double pitch = a == 0 ? front.panel.pitch_x_m : front.panel.pitch_y_m;
      const double layer_pitch = a == 0 ? back.panel.pitch_x_m : back.panel.pitch_y_m;
      const int most = int(std::ceil(2 / (kPi * kPi * kDiffractionTail * 0.75)));
      double expected = 0, total = 0;
      for (const GratingOrder& o : GratingOrders(pitch, 0.75, system.eye.channel_wavelengths_m[c], most)) {
        const double shift = d[0].gap_m * std::tan(o.angle_rad) / layer_pitch, t = shift - std::floor(shift);
        expected += o.efficiency * (shift * shift + t * (1 - t));
        total += o.efficiency;
      }
      EXPECT_NEAR(first, expected / total, 1e-9) << "channel " << c << ", axis " << a;
    }
  // A uniform layer stays uniform away from its border; the front layer is untouched.
  Patterns t;
  for (const VirtualLayer& l : system.layers) t.emplace_back(l.cols, l.rows, 0.6f);
  const Patterns seen = DiffractedPatterns(d, t);
  const LayerPattern& b = seen[d[0].layer];
  const int reach = std::max(d[0].axes[0][0].reach, d[0].axes[0][1].reach);
  for (int i = reach; i < b.rows - reach; ++i)
    for (int j = reach; j < b.cols - reach; ++j) ASSERT_NEAR(b.rgb[(size_t(i) * b.cols + j) * 3], 0.6f, 1e-6);
  EXPECT_LT(b.rgb[0], 0.6f);  // the corner loses the ghosts that fall beyond the layer
  EXPECT_EQ(seen[d[0].panel_layer].rgb, t[d[0].panel_layer].rgb);
}

TEST(PanelDiffraction, WithoutABlackMatrixOrWithCoarsePixelsNothingDiffracts) {
  EXPECT_TRUE(PanelDiffraction(TwoPanels(1.0, "117 um")).empty());
  // As the pitch grows the orders' shifts d lambda / p shrink: the kernel becomes the identity.
  double previous = 0;
  for (const std::string pitch : {"117 um", "1 mm", "10 mm"}) {
    const std::vector<LayerDiffraction> d = PanelDiffraction(TwoPanels(0.75, pitch));
    ASSERT_EQ(d.size(), 1u);
    const DiffractionAxis& axis = d[0].axes[1][0];
    const double centre = axis.weight[axis.reach];
    EXPECT_GT(centre, previous) << pitch;
    previous = centre;
  }
  EXPECT_GT(previous, 0.99);
}

// The solvers map sums over the seen pixels back by DiffractTransposed: it
// must be D's adjoint, <D x, y> = <x, D^T y>, for kernels that are not
// symmetric (a flipped tap fails this), per channel, with two panels in
// front of one layer (their order reversed) and ghosts falling beyond it.
TEST(PanelDiffraction, TheTransposeIsTheAdjoint) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  auto axis = [&](int reach) {
    DiffractionAxis a{reach, std::vector<double>(2 * reach + 1)};
    for (double& w : a.weight) w = u(rng);
    return a;
  };
  std::vector<LayerDiffraction> d(2);
  for (LayerDiffraction& e : d) {
    e.layer = 1;
    for (int c = 0; c < 3; ++c) e.axes[c] = {axis(1 + c), axis(3 - c)};
  }
  const int cols = 9, rows = 7;
  Patterns x{LayerPattern(cols, rows, 0.f), LayerPattern(cols, rows, 0.f)};
  std::vector<double> y(size_t(cols) * rows * 3);
  for (LayerPattern& p : x)
    for (float& v : p.rgb) v = static_cast<float>(u(rng));
  for (double& v : y) v = u(rng) - 0.5;
  const Patterns dx = DiffractedPatterns(d, x);
  EXPECT_EQ(dx[0].rgb, x[0].rgb);  // a layer nothing diffracts
  std::vector<double> dty = y;
  DiffractTransposed(d, 1, rows, cols, &dty);
  double left = 0, right = 0;
  for (size_t i = 0; i < y.size(); ++i) left += dx[1].rgb[i] * y[i], right += x[1].rgb[i] * dty[i];
  EXPECT_NEAR(left, right, 1e-6 * std::abs(left));
  // A layer nothing diffracts keeps its sums.
  std::vector<double> same = y;
  DiffractTransposed(d, 0, rows, cols, &same);
  EXPECT_EQ(same, y);
  EXPECT_TRUE(Diffracts(d, 1) && !Diffracts(d, 0));
}

}  // namespace
}  // namespace layerlab
