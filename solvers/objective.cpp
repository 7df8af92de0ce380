#include "layerlab/solvers/objective.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "layerlab/framework/error.h"
#include "layerlab/framework/mpi_ranks.h"
#include "layerlab/framework/polarization.h"
#include "layerlab/framework/random.h"
#include "layerlab/kernels/view_synthesizer.h"
#include "layerlab/systems/source_spread.h"

namespace layerlab {

std::array<float, 3> DisplayMaximum(const DisplayModel& model) {
  std::array<float, 3> max{0, 0, 0};
  for (size_t b = 0; b < model.branch_count(); ++b)
    for (int c = 0; c < 3; ++c) max[c] += model.weight(b)[c];
  return max;
}

std::optional<LightField> PrepareTarget(const DisplayModel& model, const LightField& target, TargetRange range,
                                        SolverReport* report) {
  const std::array<float, 3> max = DisplayMaximum(model);
  size_t beyond = 0;
  double worst = 1.0;  // largest value / maximum
  for (size_t k = 0; k < target.rgb.size(); ++k) {
    float v = target.rgb[k], m = max[k % 3];
    if (v > m) {
      ++beyond;
      worst = std::max(worst, double(v) / m);
    }
  }
  // Over every rank's views: one scale for the whole target.
  beyond = static_cast<size_t>(SumAcrossRanks(double(beyond)));
  worst = MaxAcrossRanks(worst);
  const double values = SumAcrossRanks(double(target.rgb.size()));
  report->out_of_range = beyond;
  report->target_scale = 1.0;
  if (beyond == 0) return std::nullopt;
  LightField out = target;
  char share[64];
  std::snprintf(share, sizeof share, "%.4f%%", 100.0 * beyond / values);
  if (range == TargetRange::kClip) {
    for (size_t k = 0; k < out.rgb.size(); ++k) out.rgb[k] = std::min(out.rgb[k], max[k % 3]);
    report->warnings.push_back(std::to_string(beyond) + " target values (" + share +
                               ") exceed what the display can show (up to " + std::to_string(worst) +
                               " times its maximum); clipped (target_range: clip)");
  } else {
    float scale = static_cast<float>(1.0 / worst);
    // Rounding may leave the brightest value a hair above the maximum.
    for (size_t k = 0; k < out.rgb.size(); ++k) out.rgb[k] = std::min(out.rgb[k] * scale, max[k % 3]);
    report->target_scale = scale;
    report->warnings.push_back(std::to_string(beyond) + " target values (" + share +
                               ") exceed what the display can show; the whole target was scaled by " +
                               std::to_string(scale) + " (target_range: scale)");
  }
  return out;
}

std::optional<std::string> FarBelowWarning(const DisplayModel& model, const SolverReport& report) {
  if (report.trace.empty() || !(report.final_psnr_db < kFarBelowPsnrDb)) return std::nullopt;
  std::vector<std::string> causes;
  const double share = report.rays ? double(report.out_of_range) / (3.0 * report.rays) : 0.0;
  if (share > kOutOfRangeCause)
    causes.push_back(FormatFixed(100 * share, 1) + " % of the target's values are above what the display can show " +
                     (report.target_scale < 1 ? "(the target was scaled down)" : "(they were clipped)"));
  size_t brightest = 0;
  std::vector<double> luminance(model.branch_count());
  for (size_t b = 0; b < luminance.size(); ++b) {
    for (int c = 0; c < 3; ++c) luminance[b] += kLuminanceWeights[c] * model.weight(b)[c];
    if (luminance[b] > luminance[brightest]) brightest = b;
  }
  const std::vector<Branch>& branches = model.system().branches;
  for (size_t b = 0; b < luminance.size(); ++b)
    if (luminance[b] < kDimBranchCause * luminance[brightest])
      causes.push_back("unequal branch brightness: branch \"" + branches[b].name + "\" gives " +
                       FormatFixed(100 * luminance[b] / luminance[brightest], 1) + " % of the light of \"" +
                       branches[brightest].name + "\"");
  for (const VirtualLayer& layer : model.system().layers)
    if (layer.panel.emitter && layer.panel.fixed_pattern) {
      double lit = 0;
      for (float v : *layer.panel.fixed_pattern) lit += v;
      lit /= static_cast<double>(layer.panel.fixed_pattern->size());
      if (lit < kDarkEmissionCause)
        causes.push_back("the backlight \"" + layer.name + "\" emits on " + FormatFixed(100 * lit, 2) +
                         " % of its plane (" + layer.panel.emitter->description +
                         "): most of the light field's rays meet none of its light, so judge the display by its "
                         "retinal images (layerlab retina)");
    }
  std::string text = "the solve ended at " + FormatPsnr(report.final_psnr_db, 2) +
                     " dB, far below what the display can reach (under " + FormatFixed(kFarBelowPsnrDb, 0) +
                     " dB: 10 dB below the lowest shipped display on the dice); ";
  if (causes.empty())
    return text + "no cause found in the target's range or the branches' brightness (" +
           std::to_string(report.iterations) + (report.iterations == 1 ? " iteration" : " iterations") +
           ": more may help)";
  for (size_t k = 0; k < causes.size(); ++k) text += (k ? "; " : "") + causes[k];
  return text;
}

double Objective(const DisplayModel& model, const LightField& target, const Patterns& t) {
  SolveWorkspace workspace(model, omp_get_max_threads(), kSynthesisPass);
  return Objective(model, target, t, &workspace);
}

double Objective(const DisplayModel& model, const LightField& target, const Patterns& t, SolveWorkspace* workspace) {
  const ViewSynthesizer synthesizer(model, t, workspace);
  // Per view, then summed in view order: the same value for any thread count.
  std::vector<double> per_view(model.geometry().view_count());
#pragma omp parallel for schedule(static)
  for (size_t k = 0; k < per_view.size(); ++k) {
    const size_t v = synthesizer.ViewInColumnOrder(k);
    per_view[v] = synthesizer.SquaredError(v, target.view(v));
  }
  double total = 0;
  for (double e : per_view) total += e;
  return SumAcrossRanks(total);
}

std::string FormatPsnr(double db, int decimals) {
  if (std::isinf(db)) return "inf";
  char text[32];
  std::snprintf(text, sizeof text, "%.*f", decimals, db);
  return text;
}

bool IsConstrainedLayer(const DisplayModel& model, size_t k) {
  return IsFixedLayer(model, k) || IsSolvedEmitter(model.system().layers[k]);
}

void HoldLayerConstraints(const DisplayModel& model, Patterns* t) {
  for (size_t k = 0; k < t->size(); ++k) {
    const VirtualLayer& layer = model.system().layers[k];
    if (const auto& fixed = layer.panel.fixed_pattern) {
      if (fixed->size() != (*t)[k].rgb.size())
        throw Error("layer " + layer.name + ": its fixed pattern is not its size");
      (*t)[k].rgb = *fixed;
    }
    KeepEmitterSites(layer, &(*t)[k].rgb);
  }
}

namespace {

Patterns StartingPatterns(const DisplayModel& model, const SolverOptions& options);

}  // namespace

Patterns InitialPatterns(const DisplayModel& model, const SolverOptions& options) {
  Patterns t = StartingPatterns(model, options);
  HoldLayerConstraints(model, &t);
  return t;
}

namespace {

Patterns StartingPatterns(const DisplayModel& model, const SolverOptions& options) {
  if (options.initial_value >= 0 && model.system().subframes > 1) {
    // Subframes that start equal get equal updates and stay equal (a rank-1
    // display K times over): each starts a little apart, the same on every machine.
    Patterns t = model.UniformPatterns(static_cast<float>(options.initial_value));
    const std::vector<VirtualLayer>& layers = model.system().layers;
    for (size_t k = 0; k < t.size(); ++k) {
      SplitMix64 random(options.seed * 1000003u + static_cast<uint64_t>(layers[k].subframe) * 131u + k);
      for (float& v : t[k].rgb) v = std::clamp(static_cast<float>(v * (0.8 + 0.4 * random.uniform())), 0.0f, 1.0f);
    }
    return t;
  }
  if (options.initial_value >= 0) return model.UniformPatterns(static_cast<float>(options.initial_value));
  Patterns t = model.UniformPatterns(0.5f);
  SplitMix64 rng(options.seed);  // the same patterns with every standard library
  for (LayerPattern& p : t)
    for (float& v : p.rgb) v = static_cast<float>(0.25 + 0.5 * rng.uniform());
  return t;
}

}  // namespace

void RequireSameRays(const DisplayModel& model, const LightField& target) {
  const LightFieldGeometry &a = model.geometry(), &b = target.geometry;
  const bool same = a == b;
  if (!same || target.rgb.size() != b.ray_count() * 3)
    throw Error("the display model is bound to other rays than the target's light field");
}

}  // namespace layerlab
