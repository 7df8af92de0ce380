// The metrics a design is judged by (design/design_spec.h): each read from
// the row an evaluation's run adds to a sweep table (analysis/sweep_jobs.h).
//
// | metric | unit | better | needs | value |
// | --- | --- | --- | --- | --- |
// | psnr | dB | higher | solve | the solve's light-field PSNR |
// | focal_stack_<m> | m's | m's | solve, retina | retinal metric m (psnr, ssim, jnd, ...) against natural viewing, mean over the retinal states |
// | brightness | cd/m2 | higher | solve, retina | mean retinal luminance over the retinal states |
// | accommodation_error | D | lower | contrast | mean over target depths and frequencies of |peak accommodation - target depth| |
// | peak_contrast | 1 | higher | contrast | mean over target depths and frequencies of the retinal contrast at its peak |
// | solve_time | s | lower | solve | the solve's wall time |
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "layerlab/analysis/sweep_jobs.h"

namespace layerlab {

struct DesignMetric {
  std::string name{};  // "psnr", "focal_stack_ssim"
  std::string unit{};  // "dB", "1"
  bool higher_is_better = true;
  bool solve = false, retina = false, contrast = false;  // the work it needs
  std::string retinal_metric{};                          // focal_stack_<m>: m, which run.retina.metrics must list
  std::string column() const;                            // "psnr (dB)"
};

// The metric of this name, or an error message listing the known ones.
std::optional<DesignMetric> FindDesignMetric(const std::string& name, std::string* error);

// The metric's value in one evaluation's row; nothing when the row lacks it.
std::optional<double> MetricValue(const DesignMetric& metric, const std::vector<SweepResult>& row);

}  // namespace layerlab
