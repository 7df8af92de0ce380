// The model-error test of calibration.h: a fit whose residuals exceed the
// noise detect measured in the photographs (calibration/detection_noise.h)
// describes the display wrongly, whatever its parameters absorbed.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "layerlab/calibration/fit_steps.h"
#include "layerlab/calibration/variance_ratio.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

std::string PercentOf(double fraction) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g %%", 100 * fraction);
  return buf;
}

std::string Millimeters(const std::array<double, 2>& p) {
  return "(" + FormatFixed(1e3 * p[0], 1) + ", " + FormatFixed(1e3 * p[1], 1) + ") mm";
}

// The photographs whose residual exceeds their own noise the most, as "name (ratio x)".
std::string WorstPhotographs(const std::vector<MarkerBlock>& blocks, size_t count) {
  std::vector<std::pair<double, const MarkerBlock*>> ratio;
  for (const MarkerBlock& b : blocks)
    if (b.markers > 0) ratio.push_back({std::sqrt(b.squared_error_rad2 / (2.0 * b.markers)) / b.noise->sigma_rad, &b});
  std::sort(ratio.begin(), ratio.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<std::string> named;
  for (size_t k = 0; k < std::min(count, ratio.size()); ++k) {
    const MarkerBlock& b = *ratio[k].second;
    named.push_back(
        "panel \"" + b.panel + "\" from " + Millimeters(b.camera_position) +
        (b.where.file.empty() ? "" : " (" + (b.where.pointer.empty() ? b.where.file : b.where.str()) + ")") + ": " +
        FormatFixed(ratio[k].first, 1) + " x its noise");
  }
  return JoinedBySemicolons(named);
}

}  // namespace

bool CheckModelError(const std::vector<MarkerBlock>& blocks, int free_parameters, const CalibrationOptions& options,
                     CalibrationReport* report, const ModelErrorRemedies& remedies) {
  if (!report->noise_from_detection) return true;
  double chi_square = 0;
  int residuals = 0, noise_dof = 0;
  bool noise_exact = false;
  for (const MarkerBlock& b : blocks) {
    chi_square += b.squared_error_rad2 / (b.noise->sigma_rad * b.noise->sigma_rad);
    residuals += 2 * b.markers;
    noise_dof += b.noise->degrees_of_freedom;
    noise_exact = noise_exact || b.noise->degrees_of_freedom == 0;
  }
  const int dof = residuals - free_parameters;
  if (dof <= 0) return true;
  report->residual_degrees_of_freedom = dof;
  report->noise_degrees_of_freedom = noise_exact ? 0 : noise_dof;
  report->variance_ratio = chi_square / dof;
  report->critical_variance_ratio =
      std::max(CriticalVarianceRatio(dof, report->noise_degrees_of_freedom, options.model_error_level),
               options.model_error_min_ratio * options.model_error_min_ratio);
  if (report->variance_ratio <= report->critical_variance_ratio) return true;

  report->model_error = "the markers' residual is " + FormatFixed(std::sqrt(report->variance_ratio), 2) +
                        " times the noise measured in the photographs (" + Arcmin(report->marker_noise_rad) +
                        " per axis; the variance ratio " + FormatFixed(report->variance_ratio, 2) + " lies above " +
                        FormatFixed(report->critical_variance_ratio, 2) + " (the " +
                        PercentOf(options.model_error_level) + " significance level for " + std::to_string(dof) +
                        " and " + (noise_exact ? std::string("infinitely many") : std::to_string(noise_dof)) +
                        " degrees of freedom, and at least " + FormatFixed(options.model_error_min_ratio, 2) +
                        " squared)): the display model does not describe these photographs (" +
                        (remedies.surfaces ? "a lens other than its surfaces in the scene say, " : "") +
                        (remedies.focal_lengths ? "a focal length held at a wrong value, " : "") +
                        (remedies.distortions ? "a lens's distortion, " : "") +
                        "a tilted panel, the camera's intrinsics). It is largest in " + WorstPhotographs(blocks, 3);
  if (options.accept_model_error) {
    report->warnings.push_back("model error: " + report->model_error +
                               ". Accepted (--accept-model-error): the uncertainties are those of the noise alone "
                               "and understate the error");
    return true;
  }
  std::vector<std::string> free_more;
  if (options.focal_length != FitChoice::kFit && remedies.focal_lengths) free_more.push_back("--focal-length fit");
  if (options.lens_gaps != FitChoice::kFit) free_more.push_back("--lens-gaps fit");
  if (options.distortion == FitChoice::kHold && remedies.distortions) free_more.push_back("--distortion fit");
  report->message = "model error: " + report->model_error +
                    ". The parameters below are what the wrong model fitted; check the scene against the display" +
                    (free_more.empty() ? "" : " (or fit what it holds: " + JoinWords(free_more, ", ") + ")") +
                    ", or write the calibrated scene anyway with --accept-model-error";
  return false;
}

}  // namespace layerlab
