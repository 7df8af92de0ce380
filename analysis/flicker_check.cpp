#include "layerlab/analysis/flicker_check.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "layerlab/eye/temporal_csf.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/framework/polarization.h"
#include "layerlab/kernels/synthesis.h"
#include "layerlab/systems/lc_response.h"
#include "layerlab/systems/panel_diffraction.h"
#include "layerlab/systems/source_spread.h"

namespace layerlab {
namespace {

constexpr double kDegPerRad = 180 / std::numbers::pi;

// One region's luminance samples over a frame: [subframe][node] (one node per subframe for instant panels).
struct RegionSignal {
  std::vector<std::vector<double>> luminance;
  size_t rays = 0;
  double x_deg = 0, y_deg = 0, w_deg = 0, h_deg = 0;  // centre and extent

  // Another region's rays added: the signal of both together.
  void Add(const RegionSignal& other) {
    if (luminance.empty()) luminance.assign(other.luminance.size(), std::vector<double>(other.luminance[0].size()));
    for (size_t k = 0; k < luminance.size(); ++k)
      for (size_t m = 0; m < luminance[k].size(); ++m) luminance[k][m] += other.luminance[k][m];
    rays += other.rays;
  }
};

// Checks the harmonics n = 1..K of a region's signal; updates *worst where this one is more visible.
void CheckSignal(const RegionSignal& r, int K, double frame_rate_hz, bool instant, FlickerVerdict* worst) {
  const auto& nodes = ResponseNodes();
  double mean = 0;
  std::vector<std::complex<double>> c(K + 1);
  for (int k = 0; k < K; ++k)
    for (size_t m = 0; m < r.luminance[k].size(); ++m) {
      const double s = instant ? 0 : nodes[m][0], w = instant ? 1 : nodes[m][1];
      const double value = r.luminance[k][m] / r.rays;
      mean += w / K * value;
      for (int n = 1; n <= K; ++n) {
        if (instant) {  // held over the subframe: int_0^1 exp(-2 pi i n (k + s) / K) ds
          const double a = 2 * std::numbers::pi * n / K;
          c[n] += value / K * std::exp(std::complex<double>(0, -a * k)) *
                  (std::complex<double>(1, 0) - std::exp(std::complex<double>(0, -a))) / std::complex<double>(0, a);
        } else {
          c[n] += w / K * value * std::exp(std::complex<double>(0, -2 * std::numbers::pi * n * (k + s) / K));
        }
      }
    }
  if (!(mean > 0)) return;
  const FlickerConditions at{mean, r.w_deg * r.h_deg, std::hypot(r.x_deg, r.y_deg)};
  for (int n = 1; n <= K; ++n) {
    const double modulation = 2 * std::abs(c[n]) / mean, hz = n * frame_rate_hz;
    const double visibility = modulation * TemporalContrastSensitivity(hz, at);
    if (visibility > worst->visibility) {
      worst->visibility = visibility, worst->frequency_hz = hz, worst->modulation = modulation;
      worst->luminance_cd_m2 = mean, worst->x_deg = r.x_deg, worst->y_deg = r.y_deg;
      worst->region_w_deg = r.w_deg, worst->region_h_deg = r.h_deg;
      worst->cff_hz = modulation > 0 ? CriticalFlickerFrequency(at, modulation) : 0;
    }
  }
}

// The rays' regions: squares of region_deg over their directions (with a 1 deg margin about the window).
struct RegionGrid {
  int nx = 0, ny = 0;
  double half_x = 0, half_y = 0;  // deg
  std::vector<int> region_of;     // [ray]
  std::vector<RegionSignal> regions;

  RegionGrid(const LightFieldGeometry& g, double region_deg, int K) {
    half_x = std::atan(0.5 * g.window_width_m / g.origin_z_m) * kDegPerRad + 1;
    half_y = std::atan(0.5 * g.window_height_m / g.origin_z_m) * kDegPerRad + 1;
    nx = std::max(1, static_cast<int>(std::ceil(2 * half_x / region_deg)));
    ny = std::max(1, static_cast<int>(std::ceil(2 * half_y / region_deg)));
    region_of.resize(g.ray_count());
    regions.resize(static_cast<size_t>(nx) * ny);
    for (int vr = 0; vr < g.views_y; ++vr)
      for (int vc = 0; vc < g.views_x; ++vc)
        for (int row = 0; row < g.rows; ++row)
          for (int col = 0; col < g.cols; ++col) {
            const double x = std::atan((g.pixel_x(col) - g.view_x(vc)) / g.origin_z_m) * kDegPerRad;
            const double y = std::atan((g.pixel_y(row) - g.view_y(vr)) / g.origin_z_m) * kDegPerRad;
            const int ix = std::clamp(static_cast<int>((x + half_x) / region_deg), 0, nx - 1);
            const int iy = std::clamp(static_cast<int>((y + half_y) / region_deg), 0, ny - 1);
            const size_t ray = g.view_index(vr, vc) * g.pixels_per_view() + static_cast<size_t>(row) * g.cols + col;
            region_of[ray] = iy * nx + ix;
            ++regions[region_of[ray]].rays;
          }
    for (int iy = 0; iy < ny; ++iy)
      for (int ix = 0; ix < nx; ++ix) {
        RegionSignal& r = regions[static_cast<size_t>(iy) * nx + ix];
        r.x_deg = -half_x + (ix + 0.5) * region_deg, r.y_deg = -half_y + (iy + 0.5) * region_deg;
        r.w_deg = r.h_deg = region_deg;
        r.luminance.assign(K, {});
      }
  }
};

// Each subframe's light alone at each node of the response, K x its luminance while it shows, into the regions.
void SampleSubframes(const DisplayModel& model, const ResponseMap& map, RegionGrid* grid) {
  const DisplaySystem& system = model.system();
  const LightFieldGeometry& g = model.geometry();
  const double scale = system.subframes * model.white_luminance();
  const std::vector<LayerDiffraction> diffraction = SeenKernels(system, true);  // what the eye sees of them
  Patterns shown, alone;
  LightField light(g);
  for (int m = 0; m < map.instants(); ++m) {
    map.Shown(m, &shown);
    if (!diffraction.empty()) shown = DiffractedPatterns(diffraction, shown);
    for (int k = 0; k < system.subframes; ++k) {
      alone = shown;
      for (size_t l = 0; l < alone.size(); ++l)
        if (system.layers[l].subframe != k) std::fill(alone[l].rgb.begin(), alone[l].rgb.end(), 0.0f);
      Synthesize(model, alone, &light);
      for (RegionSignal& r : grid->regions) r.luminance[k].push_back(0);
      for (size_t ray = 0; ray < g.ray_count(); ++ray) {
        double y = 0;
        for (int c = 0; c < 3; ++c) y += kLuminanceWeights[c] * light.rgb[ray * 3 + c];
        grid->regions[grid->region_of[ray]].luminance[k].back() += scale * y;
      }
    }
  }
}

}  // namespace

std::optional<FlickerVerdict> CheckFlicker(const DisplayModel& model, const Patterns& t, double region_deg) {
  const DisplaySystem& system = model.system();
  const int K = system.subframes;
  if (K < 2) return std::nullopt;
  if (t.size() != model.layer_count()) throw Error("flicker check: the patterns are not the display's layers");
  RegionGrid grid(model.geometry(), region_deg, K);
  const ResponseMap map(system, t);
  const bool instant = map.instants() == 1;
  SampleSubframes(model, map, &grid);
  // A rank's light field is a block of view rows: the regions' sums over every rank's rays.
  std::vector<double> sums;
  for (const RegionSignal& r : grid.regions) {
    sums.push_back(double(r.rays));
    for (const std::vector<double>& subframe : r.luminance) sums.insert(sums.end(), subframe.begin(), subframe.end());
  }
  SumAcrossRanks({std::span<double>(sums)}, 0.0);
  size_t at = 0;
  for (RegionSignal& r : grid.regions) {
    r.rays = static_cast<size_t>(sums[at++]);
    for (std::vector<double>& subframe : r.luminance)
      for (double& v : subframe) v = sums[at++];
  }
  FlickerVerdict worst;
  worst.what = "the solved patterns";
  // At three scales (flicker over a larger area is seen at a smaller modulation: Granit-Harper): the regions,
  // blocks of kBlock x kBlock of them, and the whole field.
  constexpr int kBlock = 4;
  const int nx = grid.nx, ny = grid.ny, bx = (nx + kBlock - 1) / kBlock, by = (ny + kBlock - 1) / kBlock;
  std::vector<RegionSignal> blocks(static_cast<size_t>(bx) * by);
  RegionSignal field;
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const RegionSignal& r = grid.regions[static_cast<size_t>(iy) * nx + ix];
      if (r.rays == 0) continue;
      CheckSignal(r, K, system.frame_rate_hz, instant, &worst);
      blocks[static_cast<size_t>(iy / kBlock) * bx + ix / kBlock].Add(r);
      field.Add(r);
    }
  for (int iy = 0; iy < by; ++iy)
    for (int ix = 0; ix < bx; ++ix) {
      RegionSignal& b = blocks[static_cast<size_t>(iy) * bx + ix];
      if (b.rays == 0) continue;
      b.w_deg = b.h_deg = kBlock * region_deg;
      b.x_deg = -grid.half_x + (ix + 0.5) * b.w_deg, b.y_deg = -grid.half_y + (iy + 0.5) * b.h_deg;
      CheckSignal(b, K, system.frame_rate_hz, instant, &worst);
    }
  field.w_deg = 2 * grid.half_x - 2, field.h_deg = 2 * grid.half_y - 2;  // the window's extent, without the margin
  if (field.rays > 0) CheckSignal(field, K, system.frame_rate_hz, instant, &worst);
  return worst;
}

std::optional<FlickerVerdict> WorstCaseFlicker(const DisplaySystem& system, double region_deg) {
  const int K = system.subframes;
  if (K < 2) return std::nullopt;
  double rise = 1e300, fall = 1e300;  // the fastest panel's
  for (const VirtualLayer& layer : system.layers)
    if (!layer.panel.emitter && layer.panel.rise_time_s + layer.panel.fall_time_s < rise + fall)
      rise = layer.panel.rise_time_s, fall = layer.panel.fall_time_s;
  double white = 0;
  for (int c = 0; c < 3; ++c) white += kLuminanceWeights[c] * system.peak_luminance_cd_m2[c];
  // One pixel driven to 1 in the first subframe and 0 in the others: the full white luminance while it shows.
  std::vector<double> cycle(K, 0.0);
  cycle[0] = 1;
  const double T = 1 / (K * system.frame_rate_hz);
  const std::vector<double> start = SteadyStartValues(cycle, T, rise, fall);
  const bool instant = !ResponseMatters(system);
  RegionSignal r;
  r.rays = 1;
  r.w_deg = r.h_deg = region_deg;
  r.luminance.assign(K, {});
  for (int k = 0; k < K; ++k)
    for (const auto& node : ResponseNodes()) {
      r.luminance[k].push_back(white * RelaxedTransmittance(start[k], cycle[k], node[0] * T, rise, fall));
      if (instant) break;
    }
  FlickerVerdict worst;
  worst.what = "the worst case, a region at peak white in one subframe of " + std::to_string(K) +
               " and dark in the others, in the middle of the field";
  CheckSignal(r, K, system.frame_rate_hz, instant, &worst);
  // And the whole field so (the larger the area, the lower the threshold).
  r.w_deg = system.fov_x_rad * kDegPerRad, r.h_deg = system.fov_y_rad * kDegPerRad;
  if (r.w_deg * r.h_deg > region_deg * region_deg) CheckSignal(r, K, system.frame_rate_hz, instant, &worst);
  return worst;
}

void AddFlickerCheck(const DisplayModel& model, const Patterns& t, SolverReport* report) {
  if (!report->IsSolutionUsable()) return;
  try {
    report->flicker = CheckFlicker(model, t);
  } catch (const Error& e) {
    report->warnings.push_back(std::string("the flicker check failed: ") + e.what());
  }
}

}  // namespace layerlab
