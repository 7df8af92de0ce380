#include <algorithm>
#include <cmath>
#include <set>

#include <ceres/ceres.h>

#include "layerlab/calibration/fit_steps.h"
#include "layerlab/calibration/luminance_model.h"
#include "layerlab/calibration/scalar_fit.h"
#include "layerlab/framework/params.h"

namespace layerlab {
namespace {

struct LuminanceCost {
  double level, luminance;

  template <typename T>
  bool operator()(const T* max_luminance, const T* black_level, const T* gamma, T* residual) const {
    residual[0] = ModelLuminance(level, *max_luminance, *black_level, *gamma) - luminance;
    return true;
  }
};

using LuminanceCostFunction = ceres::AutoDiffCostFunction<LuminanceCost, 1, 1, 1, 1>;

double Rms(const std::vector<LuminanceSample>& samples, double scale, double max_luminance, double black,
           double gamma) {
  double sum = 0;
  for (const LuminanceSample& s : samples)
    sum += std::pow(ModelLuminance(s.level, max_luminance, black, gamma) - s.luminance / scale, 2);
  return std::sqrt(sum / samples.size());
}

// One panel's curve; readings are divided by the brightest, so residuals are relative to it.
bool FitCurve(const VirtualLayer& layer, const PanelLuminance& curve, const CalibrationOptions& options,
              CalibratedPanel* out, PanelResiduals* residuals, CalibrationReport* report) {
  const std::string panel = "panel \"" + layer.name + "\"";
  double scale = 0;
  for (const LuminanceSample& s : curve.samples) scale = std::max(scale, s.luminance);
  const double gamma0 = layer.panel.gamma, black0 = layer.panel.black_level;

  // The scene's curve at its best brightness, for the residual before the fit.
  double gg = 0, gl = 0;
  for (const LuminanceSample& s : curve.samples) {
    const double g = ModelLuminance(s.level, 1.0, black0, gamma0);
    gg += g * g, gl += g * s.luminance / scale;
  }
  const double max0 = gg > 0 ? gl / gg : 1.0;
  residuals->luminance_samples = static_cast<int>(curve.samples.size());
  residuals->luminance_rms_before = Rms(curve.samples, scale, max0, black0, gamma0);

  ScalarFit fit;
  const int max_luminance = fit.Add({"the maximum luminance of " + panel, max0, 2, 1e-12, std::nullopt});
  const int black = fit.Add({"the black level of " + panel, black0, 1, 0.0, 0.999});
  const int gamma = fit.Add({"the gamma of " + panel, gamma0, 0, 0.1, 10.0});
  std::vector<ParameterStatus> status(3, ParameterStatus::kFitted);

  std::set<double> levels;
  bool between = false;
  for (const LuminanceSample& s : curve.samples) {
    levels.insert(s.level);
    between = between || (s.level > 0 && s.level < 1);
  }
  if (levels.size() < 3 || !between) {
    fit.Hold(black), fit.Hold(gamma);
    status[black] = status[gamma] = ParameterStatus::kUndetermined;
    report->warnings.push_back(panel +
                               ": luminance at fewer than three distinct input levels, or at none strictly "
                               "between black and full, cannot fix gamma and black level: they keep their "
                               "scene values (" +
                               ShowValue("gamma", gamma0) + ", " + ShowValue("black_level", black0) +
                               "); only the maximum luminance is fitted");
  }
  for (const LuminanceSample& s : curve.samples)
    fit.AddResidual(new LuminanceCostFunction(new LuminanceCost{s.level, s.luminance / scale}),
                    MakeLoss(options.loss, options.luminance_loss_scale), {max_luminance, black, gamma});

  ScalarFitResult result = fit.Solve(ScalarFitOptionsOf(options));
  if (!report->luminance_solver.empty()) report->luminance_solver += "\n";
  report->luminance_solver += layer.name + ": " + result.summary.BriefReport();
  if (!result.usable) {
    report->message = "the luminance fit of " + panel + " failed: " + result.summary.message;
    return false;
  }
  const std::string names[3] = {"max_luminance", "black_level", "gamma"};
  for (const UndeterminedParameter& u : result.undetermined) {
    status[u.index] = ParameterStatus::kUndetermined;
    report->warnings.push_back(UndeterminedWarning(fit, u, names[u.index]));
  }
  if (result.covariance.size() == 0)
    report->warnings.push_back("no uncertainties for the luminance of " + panel + ": " + result.covariance_message);
  residuals->luminance_rms_after =
      Rms(curve.samples, scale, fit.value(max_luminance), fit.value(black), fit.value(gamma));

  for (int i : {max_luminance, black, gamma}) {
    ParameterEstimate p;
    p.element = layer.name;
    p.quantity = names[i];
    const double unit = i == max_luminance ? scale : 1.0;  // back to the measurements' unit
    p.scene_value = fit.parameter(i).start * unit;
    p.value = fit.value(i) * unit;
    p.status = status[i];
    if (p.status == ParameterStatus::kFitted && result.covariance.size())
      p.std_dev = std::sqrt(result.covariance(i, i)) * unit;
    report->parameters.push_back(p);
  }
  out->luminance_measured = true;
  out->max_luminance = fit.value(max_luminance) * scale;
  out->black_level = fit.value(black);
  out->gamma = fit.value(gamma);
  return true;
}

}  // namespace

bool FitLuminance(const DisplaySystem& system, const Measurements& measurements, const CalibrationOptions& options,
                  CalibratedDisplay* display, CalibrationReport* report) {
  report->luminance_samples = static_cast<int>(measurements.luminance_sample_count());
  double sum_before = 0, sum_after = 0;
  // In the system's layer order, as the report lists panels.
  for (size_t k = 0; k < system.layers.size(); ++k) {
    auto curve_it = std::find_if(measurements.luminance.begin(), measurements.luminance.end(),
                                 [&](const PanelLuminance& c) { return c.panel == system.layers[k].name; });
    if (curve_it == measurements.luminance.end()) continue;
    const PanelLuminance& curve = *curve_it;
    PanelResiduals& residuals = report->panels[k];
    if (!FitCurve(system.layers[k], curve, options, &display->panels[k], &residuals, report)) return false;
    sum_before += std::pow(residuals.luminance_rms_before, 2) * residuals.luminance_samples;
    sum_after += std::pow(residuals.luminance_rms_after, 2) * residuals.luminance_samples;
  }
  if (report->luminance_samples) {
    report->luminance_rms_before = std::sqrt(sum_before / report->luminance_samples);
    report->luminance_rms_after = std::sqrt(sum_after / report->luminance_samples);
  }
  return true;
}

}  // namespace layerlab
