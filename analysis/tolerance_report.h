// What `layerlab tolerance` writes: every sample (samples.csv, draws.csv), the
// sensitivity pass (sensitivity.csv) and the summary (tolerance.md, also on
// stdout, and tolerance.json): per layer the Monte Carlo distribution (mean,
// standard deviation, 90th percentile, worst), the dominant tolerance, and
// whether the calibration fit can measure each tolerance.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "layerlab/analysis/tolerance.h"

namespace layerlab {

struct SampleStats {
  double mean = 0, sd = 0, p90 = 0, worst = 0;  // worst: the largest (or, for PSNR, the smallest)
  int count = 0;
};
// Which way a value gets worse: up (misregistration), down (PSNR: p90 is the
// value 90 % of samples reach or exceed), or away from 0 (a signed
// distortion: p90 and worst are of the magnitude, with the worst's sign).
enum class Worse { kHigher, kLower, kFartherFromZero };
// Of the finite values.
SampleStats Stats(std::vector<double> values, Worse worse = Worse::kHigher);

// A limit in the unit people state it in: "0.050 mm", "0.20 deg", "1.0 %".
std::string FormatLimit(ToleranceKind kind, double limit);

struct ToleranceReportInput {
  std::string scene, command;
  const ToleranceModel* model = nullptr;
  const ToleranceRun* run = nullptr;
  uint64_t seed = 1;
  std::string psnr_note;  // how the PSNR was measured, or why not
};

std::string ToleranceMarkdown(const ToleranceReportInput& in);
nlohmann::json ToleranceJson(const ToleranceReportInput& in);
// Writes samples.csv, draws.csv and sensitivity.csv into `folder`.
void WriteToleranceCsv(const ToleranceReportInput& in, const std::string& folder);

}  // namespace layerlab
