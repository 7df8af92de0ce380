#include "layerlab/design/design_metrics.h"

#include <cmath>

#include "layerlab/framework/params.h"
#include "layerlab/metrics/retinal_metrics.h"

namespace layerlab {
namespace {

bool StartsWith(const std::string& text, const std::string& prefix) { return text.rfind(prefix, 0) == 0; }

std::vector<DesignMetric> FixedMetrics() {
  std::vector<DesignMetric> m(5);
  m[0] = {.name = "psnr", .unit = "dB", .higher_is_better = true, .solve = true};
  m[1] = {.name = "brightness", .unit = "cd/m2", .higher_is_better = true, .solve = true, .retina = true};
  m[2] = {.name = "accommodation_error", .unit = "D", .higher_is_better = false, .contrast = true};
  m[3] = {.name = "peak_contrast", .unit = "1", .higher_is_better = true, .contrast = true};
  m[4] = {.name = "solve_time", .unit = "s", .higher_is_better = false, .solve = true};
  return m;
}

// The mean over the row's columns that start with `prefix`, of the value or
// (with `error`) of |value - ideal|.
std::optional<double> MeanOf(const std::vector<SweepResult>& row, const std::string& prefix, bool error) {
  double sum = 0;
  size_t n = 0;
  for (const SweepResult& r : row) {
    if (!StartsWith(r.column, prefix) || !r.value.is_number()) continue;
    const double v = r.value.get<double>();
    if (error && !r.ideal) continue;
    sum += error ? std::abs(v - *r.ideal) : v;
    ++n;
  }
  if (n == 0) return std::nullopt;
  return sum / static_cast<double>(n);
}

std::optional<double> Column(const std::vector<SweepResult>& row, const std::string& column) {
  for (const SweepResult& r : row)
    if (r.column == column && r.value.is_number()) return r.value.get<double>();
  return std::nullopt;
}

}  // namespace

std::string DesignMetric::column() const { return name + " (" + unit + ")"; }

std::optional<DesignMetric> FindDesignMetric(const std::string& name, std::string* error) {
  std::vector<std::string> known;
  for (const DesignMetric& m : FixedMetrics()) {
    if (m.name == name) return m;
    known.push_back(m.name);
  }
  for (const RetinalMetric& r : RetinalMetrics()) {
    DesignMetric m{.name = "focal_stack_" + r.name,
                   .unit = r.unit.empty() ? "1" : r.unit,
                   .higher_is_better = r.higher_is_better,
                   .solve = true,
                   .retina = true,
                   .retinal_metric = r.name};
    if (m.name == name) return m;
    known.push_back(m.name);
  }
  if (error) {
    *error = "unknown metric \"" + name + "\"; known: " + JoinWords(known, ", ");
    if (auto near = ClosestWord(name, known)) *error += " (did you mean \"" + *near + "\"?)";
  }
  return std::nullopt;
}

std::optional<double> MetricValue(const DesignMetric& metric, const std::vector<SweepResult>& row) {
  if (metric.name == "psnr") return Column(row, kPsnrColumn);
  if (metric.name == "solve_time") return Column(row, kSolveTimeColumn);
  if (metric.name == "brightness") return MeanOf(row, kRetinalMeanColumn, false);
  if (metric.name == "accommodation_error") return MeanOf(row, kPeakAccommodationColumn, true);
  if (metric.name == "peak_contrast") return MeanOf(row, kPeakContrastColumn, false);
  if (!metric.retinal_metric.empty()) {
    for (const RetinalMetric& r : RetinalMetrics())
      if (r.name == metric.retinal_metric) return Column(row, FocalStackColumn(r.name, r.unit));
  }
  return std::nullopt;
}

}  // namespace layerlab
