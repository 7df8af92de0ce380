#include <cmath>

#include "layerlab/calibration/calibration.h"
#include "layerlab/framework/params.h"

namespace layerlab {
namespace {

template <typename Enum, size_t N>
Enum FromString(const std::string& name, const std::string& what, const std::pair<const char*, Enum> (&table)[N]) {
  std::vector<std::string> names;
  for (const auto& [text, value] : table) {
    if (name == text) return value;
    names.push_back(text);
  }
  std::string msg = what + ": \"" + name + "\" is not one of " + JoinWords(names);
  if (auto near = ClosestWord(name, names)) msg += "; did you mean \"" + *near + "\"?";
  throw Error(msg);
}

constexpr std::pair<const char*, RobustLoss> kLosses[] = {
    {"none", RobustLoss::kNone}, {"huber", RobustLoss::kHuber}, {"cauchy", RobustLoss::kCauchy}};
constexpr std::pair<const char*, AxisReference> kReferences[] = {{"camera", AxisReference::kCamera},
                                                                 {"farthest-panel", AxisReference::kFarthestPanel}};

constexpr std::pair<const char*, FitChoice> kFitChoices[] = {
    {"auto", FitChoice::kAuto}, {"fit", FitChoice::kFit}, {"hold", FitChoice::kHold}};

std::string Number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

}  // namespace

std::string ToString(RobustLoss loss) {
  for (const auto& [text, value] : kLosses)
    if (value == loss) return text;
  return "?";
}

RobustLoss RobustLossFromString(const std::string& name) { return FromString(name, "robust loss", kLosses); }

std::string ToString(AxisReference reference) {
  for (const auto& [text, value] : kReferences)
    if (value == reference) return text;
  return "?";
}

AxisReference AxisReferenceFromString(const std::string& name) {
  return FromString(name, "axis reference", kReferences);
}

std::string ToString(FitChoice choice) {
  for (const auto& [text, value] : kFitChoices)
    if (value == choice) return text;
  return "?";
}

FitChoice FitChoiceFromString(const std::string& name) { return FromString(name, "fit choice", kFitChoices); }

std::string ToString(ParameterStatus status) {
  switch (status) {
    case ParameterStatus::kFitted:
      return "fitted";
    case ParameterStatus::kUndetermined:
      return "undetermined";
    case ParameterStatus::kReference:
      return "reference";
    case ParameterStatus::kNotFitted:
      return "not fitted";
    case ParameterStatus::kUnresolved:
      return "undetermined by the fit";
  }
  return "?";
}

bool CalibrationOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& field, double value, const std::string& constraint) {
    *error = field + ": " + Number(value) + ": " + constraint;
    return false;
  };
  if (!(marker_loss_scale_rad > 0) || !std::isfinite(marker_loss_scale_rad))
    return fail("marker_loss_scale", marker_loss_scale_rad, "must be a positive angle (rad)");
  if (!(luminance_loss_scale > 0) || !std::isfinite(luminance_loss_scale))
    return fail("luminance_loss_scale", luminance_loss_scale, "must be positive (relative to the brightest reading)");
  if (!(model_error_level > 0 && model_error_level < 0.5))
    return fail("model_error_level", model_error_level, "must lie in (0, 0.5)");
  if (!(model_error_min_ratio >= 1) || !std::isfinite(model_error_min_ratio))
    return fail("model_error_min_ratio", model_error_min_ratio, "must be at least 1");
  if (max_iterations < 1) return fail("max_iterations", max_iterations, "must be at least 1");
  if (!(function_tolerance >= 0)) return fail("function_tolerance", function_tolerance, "must be non-negative");
  if (!(parameter_tolerance >= 0)) return fail("parameter_tolerance", parameter_tolerance, "must be non-negative");
  return true;
}

}  // namespace layerlab
