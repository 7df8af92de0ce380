#include "layerlab/solvers/trace_columns.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "layerlab/framework/error.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/systems/system_report.h"

namespace layerlab {

const std::vector<TraceColumn>& TraceColumns() {
  using R = IterationRecord;
  static const std::vector<TraceColumn> columns = {
      {"iteration", "", "the iteration; 0 is the initial guess", TraceValueKind::kCount,
       [](const R& r) { return double(r.iteration); }, [](R* r, double v) { r->iteration = static_cast<int>(v); },
       false},
      {"seconds", "s", "wall time since the solve started", TraceValueKind::kSeconds,
       [](const R& r) { return r.seconds; }, [](R* r, double v) { r->seconds = v; }, false},
      {"objective", "", "the minimized objective: a sum of squared errors over rays (or retinal pixels) and channels",
       TraceValueKind::kObjective, [](const R& r) { return r.objective; }, [](R* r, double v) { r->objective = v; },
       false},
      {"psnr_db", "dB", "the light field's PSNR, peak 1", TraceValueKind::kDecibels,
       [](const R& r) { return r.psnr_db; }, [](R* r, double v) { r->psnr_db = v; }, false},
      {"focal_stack_psnr_db", "dB", "the retinal PSNR, mean over accommodation states", TraceValueKind::kDecibels,
       [](const R& r) { return r.focal_stack_psnr_db; }, [](R* r, double v) { r->focal_stack_psnr_db = v; }, true},
      // The focal stack's perceptual metrics: "focal_stack_" and the metric's column (metrics/retinal_metrics.h).
      {"focal_stack_ssim", "", "the retinal SSIM, mean over accommodation states", TraceValueKind::kScore,
       [](const R& r) { return r.focal_stack_ssim; }, [](R* r, double v) { r->focal_stack_ssim = v; }, true},
      {"focal_stack_ms_ssim", "", "the retinal MS-SSIM, mean over accommodation states", TraceValueKind::kScore,
       [](const R& r) { return r.focal_stack_ms_ssim; }, [](R* r, double v) { r->focal_stack_ms_ssim = v; }, true},
      {"focal_stack_jnd", "JND", "the retinal CSF-weighted difference, mean over accommodation states",
       TraceValueKind::kScore, [](const R& r) { return r.focal_stack_jnd; },
       [](R* r, double v) { r->focal_stack_jnd = v; }, true},
  };
  return columns;
}

const TraceColumn& FocalStackColumn(const RetinalMetric& metric) {
  const std::string name = "focal_stack_" + metric.column;
  for (const TraceColumn& c : TraceColumns())
    if (name == c.name) return c;
  throw Error("internal error: no trace column for the metric " + metric.name);
}

bool Measured(const TraceColumn& column, const std::vector<IterationRecord>& trace) {
  return !column.measured_only || std::any_of(trace.begin(), trace.end(),
                                              [&](const IterationRecord& r) { return !std::isnan(column.value(r)); });
}

std::vector<const TraceColumn*> WrittenColumns(const std::vector<IterationRecord>& trace) {
  std::vector<const TraceColumn*> out;
  for (const TraceColumn& c : TraceColumns())
    if (Measured(c, trace)) out.push_back(&c);
  return out;
}

std::string TraceField(const TraceColumn& column, double value, int decibel_decimals, bool nan_as_empty) {
  if (nan_as_empty && std::isnan(value)) return "";
  char text[64];
  switch (column.kind) {
    case TraceValueKind::kCount:
      std::snprintf(text, sizeof text, "%d", static_cast<int>(value));
      break;
    case TraceValueKind::kSeconds:
      std::snprintf(text, sizeof text, "%.6f", value);
      break;
    case TraceValueKind::kObjective:
      std::snprintf(text, sizeof text, "%.9g", value);
      break;
    case TraceValueKind::kDecibels:
      return FormatPsnr(value, decibel_decimals);
    case TraceValueKind::kScore:
      std::snprintf(text, sizeof text, "%.6f", value);
      break;
  }
  return text;
}

nlohmann::json TraceJson(const TraceColumn& column, const IterationRecord& row) {
  const double v = column.value(row);
  return column.kind == TraceValueKind::kCount ? nlohmann::json(static_cast<int>(v)) : JsonNumber(v);
}

}  // namespace layerlab
