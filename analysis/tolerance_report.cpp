#include "layerlab/analysis/tolerance_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

std::string F(double v, int decimals) { return std::isfinite(v) ? FormatFixed(v, decimals) : "n/a"; }

nlohmann::json J(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

std::string StatsCells(const SampleStats& s, int decimals) {
  return F(s.mean, decimals) + " | " + F(s.sd, decimals) + " | " + F(s.p90, decimals) + " | " + F(s.worst, decimals);
}

nlohmann::json StatsJson(const SampleStats& s) {
  return {{"mean", J(s.mean)}, {"sd", J(s.sd)}, {"p90", J(s.p90)}, {"worst", J(s.worst)}, {"samples", s.count}};
}

// Over the samples, one value per sample for layer k (or the display when k < 0).
template <class Get>
std::vector<double> Column(const ToleranceRun& run, Get get) {
  std::vector<double> values;
  for (const ToleranceResult& r : run.samples)
    if (r.error.empty()) values.push_back(get(r));
  return values;
}

int Failed(const ToleranceRun& run) {
  return static_cast<int>(
      std::count_if(run.samples.begin(), run.samples.end(), [](const ToleranceResult& r) { return !r.error.empty(); }));
}

size_t DofCount(const ToleranceModel& model, ToleranceKind kind) {
  return std::count_if(model.dofs().begin(), model.dofs().end(), [&](const ToleranceDof& d) { return d.kind == kind; });
}

std::string Csv(const std::string& text) {
  std::string out = "\"";
  for (char c : text) out += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
  return out + "\"";
}

std::string ResultRows(const std::string& key, const ToleranceResult& r) {
  std::string out;
  if (!r.error.empty()) return key + ",,,,,,,," + F(r.psnr_db, 3) + "," + Csv(r.error) + "\n";
  for (const LayerResult& l : r.layers) {
    const Misregistration& m = l.misregistration;
    out += key + "," + l.layer + "," + F(m.rms_px, 6) + "," + F(m.max_px, 6) + "," + F(m.channel_rms_px[0], 6) + "," +
           F(m.channel_rms_px[1], 6) + "," + F(m.channel_rms_px[2], 6) + "," + F(l.distortion_percent, 6) + "," +
           F(r.psnr_db, 4) + ",\n";
  }
  return out;
}

const char* kResultHeader =
    "misregistration_rms_px,misregistration_max_px,rms_red_px,rms_green_px,rms_blue_px,distortion_percent,psnr_db,"
    "error\n";

std::string SensitivityTable(const ToleranceReportInput& in) {
  const ToleranceRun& run = *in.run;
  std::string out =
      "| tolerance | limit | worst layer's RMS misregistration at +limit / -limit (px) | PSNR at +limit / "
      "-limit (dB) | calibration can measure it |\n|---|---|---|---|---|\n";
  for (const SensitivityRow& s : run.sensitivity)
    out += "| " + ToleranceKey(s.kind) + " | " + FormatLimit(s.kind, s.limit) + " | " + F(WorstRmsPx(s.plus), 3) +
           " / " + F(WorstRmsPx(s.minus), 3) + " | " + F(s.plus.psnr_db, 2) + " / " + F(s.minus.psnr_db, 2) + " | " +
           CalibrationMeasures(s.kind) + " |\n";
  const int by_pixels = DominantByMisregistration(run), by_psnr = DominantByPsnr(run);
  out += "\nDominant tolerance: " +
         (by_pixels < 0 ? std::string("none measured") : ToleranceKey(run.sensitivity[by_pixels].kind)) +
         " by misregistration; " +
         (by_psnr < 0 ? std::string("not measured") : ToleranceKey(run.sensitivity[by_psnr].kind)) + " by PSNR.\n";
  return out;
}

std::string MonteCarloTable(const ToleranceReportInput& in) {
  const ToleranceRun& run = *in.run;
  std::string out =
      "| layer | RMS misregistration mean | sd | p90 | worst (px) | max misregistration p90 | worst (px) | "
      "distortion (nominal) | mean | sd | p90 of magnitude | worst (%) "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (size_t k = 0; k < run.nominal.layers.size(); ++k) {
    const SampleStats rms =
        Stats(Column(run, [&](const ToleranceResult& r) { return r.layers[k].misregistration.rms_px; }));
    const SampleStats most =
        Stats(Column(run, [&](const ToleranceResult& r) { return r.layers[k].misregistration.max_px; }));
    const SampleStats distortion = Stats(
        Column(run, [&](const ToleranceResult& r) { return r.layers[k].distortion_percent; }), Worse::kFartherFromZero);
    out += "| " + run.nominal.layers[k].layer + " | " + StatsCells(rms, 3) + " | " + F(most.p90, 3) + " | " +
           F(most.worst, 3) + " | " + F(run.nominal.layers[k].distortion_percent, 3) + " | " +
           StatsCells(distortion, 3) + " |\n";
  }
  const SampleStats psnr = Stats(Column(run, [](const ToleranceResult& r) { return r.psnr_db; }), Worse::kLower);
  if (psnr.count > 0)
    out += "\nPSNR of the nominal factorization (nominal display " + F(run.nominal.psnr_db, 2) + " dB): mean " +
           F(psnr.mean, 2) + " dB, sd " + F(psnr.sd, 2) + ", 90 % of builds at least " + F(psnr.p90, 2) +
           " dB, worst " + F(psnr.worst, 2) + " dB.\n";
  if (Failed(run))
    out += "\n" + std::to_string(Failed(run)) + " samples would not compile or measure (samples.csv says why).\n";
  return out;
}

}  // namespace

SampleStats Stats(std::vector<double> values, Worse worse) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }), values.end());
  SampleStats s;
  s.count = static_cast<int>(values.size());
  if (values.empty()) return {NAN, NAN, NAN, NAN, 0};
  double sum = 0;
  for (double v : values) sum += v;
  s.mean = sum / s.count;
  double square = 0;
  for (double v : values) square += (v - s.mean) * (v - s.mean);
  s.sd = s.count > 1 ? std::sqrt(square / (s.count - 1)) : 0;
  if (worse == Worse::kFartherFromZero) {
    std::sort(values.begin(), values.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
    s.worst = values.back();
    for (double& v : values) v = std::abs(v);
  } else {
    std::sort(values.begin(), values.end());
    s.worst = worse == Worse::kLower ? values.front() : values.back();
  }
  const double at = (worse == Worse::kLower ? 0.1 : 0.9) * (s.count - 1);
  const size_t below = static_cast<size_t>(std::floor(at));
  const size_t above = std::min(below + 1, values.size() - 1);
  s.p90 = values[below] + (at - below) * (values[above] - values[below]);
  return s;
}

std::string FormatLimit(ToleranceKind kind, double limit) {
  switch (kind) {
    case ToleranceKind::kPanelTilt:
    case ToleranceKind::kLensTilt:
      return FormatFixed(limit * kDegreesPerRadian, 3) + " deg";
    case ToleranceKind::kFocalLength:
      return FormatFixed(limit * 100, 2) + " %";
    default:
      return FormatFixed(limit * 1e3, 3) + " mm";
  }
}

std::string ToleranceMarkdown(const ToleranceReportInput& in) {
  const ToleranceModel& model = *in.model;
  std::string out = "# Tolerances of " + in.scene + "\n\n    " + in.command + "\n\n";
  out += "Tolerances from " + model.spec().source +
         ", each drawn independently for every element it applies to (per axis for decentres and tilts) from a "
         "normal distribution with the limit as 2 sigma, truncated at the limit (as Zemax's Monte Carlo draws); " +
         std::to_string(in.run->samples.size()) + " samples, seed " + std::to_string(in.seed) + ".\n\n";
  out += "| tolerance | limit | degrees of freedom | calibration can measure it |\n|---|---|---|---|\n";
  for (const Tolerance& t : model.spec().tolerances)
    out += "| " + ToleranceKey(t.kind) + " | " + FormatLimit(t.kind, t.limit) + " | " +
           std::to_string(DofCount(model, t.kind)) + " | " + CalibrationMeasures(t.kind) + " |\n";
  for (const std::string& note : model.notes()) out += "\nNot applied: " + note + ".\n";
  out +=
      "\nMisregistration: where an eye ray lands on the panel, in panel pixels, perturbed against nominal, over 3 x 3 "
      "pupil points across the eyebox and 5 x 5 directions across 90 % of each layer's field, per channel. " +
      in.psnr_note + "\n";
  out += "\n## Sensitivity: each tolerance alone at + and - its limit (every element it applies to at once)\n\n" +
         SensitivityTable(in);
  out += "\n## Monte Carlo: " + std::to_string(in.run->samples.size()) + " samples\n\n" + MonteCarloTable(in);
  return out;
}

nlohmann::json ToleranceJson(const ToleranceReportInput& in) {
  const ToleranceRun& run = *in.run;
  nlohmann::json j = {{"scene", in.scene},
                      {"command", in.command},
                      {"seed", in.seed},
                      {"samples", run.samples.size()},
                      {"source", in.model->spec().source},
                      {"distribution", "normal, limit = 2 sigma, truncated at the limit"}};
  for (const Tolerance& t : in.model->spec().tolerances)
    j["tolerances"].push_back({{"key", ToleranceKey(t.kind)},
                               {"limit_si", t.limit},
                               {"degrees_of_freedom", DofCount(*in.model, t.kind)},
                               {"calibration_can_measure", CalibrationCanMeasure(t.kind)},
                               {"calibration", CalibrationMeasures(t.kind)}});
  for (const SensitivityRow& s : run.sensitivity)
    j["sensitivity"].push_back({{"key", ToleranceKey(s.kind)},
                                {"plus_worst_rms_px", J(WorstRmsPx(s.plus))},
                                {"minus_worst_rms_px", J(WorstRmsPx(s.minus))},
                                {"plus_psnr_db", J(s.plus.psnr_db)},
                                {"minus_psnr_db", J(s.minus.psnr_db)}});
  const int by_pixels = DominantByMisregistration(run), by_psnr = DominantByPsnr(run);
  j["dominant_by_misregistration"] =
      by_pixels < 0 ? nlohmann::json(nullptr) : nlohmann::json(ToleranceKey(run.sensitivity[by_pixels].kind));
  j["dominant_by_psnr"] =
      by_psnr < 0 ? nlohmann::json(nullptr) : nlohmann::json(ToleranceKey(run.sensitivity[by_psnr].kind));
  for (size_t k = 0; k < run.nominal.layers.size(); ++k)
    j["layers"].push_back(
        {{"layer", run.nominal.layers[k].layer},
         {"misregistration_rms_px",
          StatsJson(Stats(Column(run, [&](const ToleranceResult& r) { return r.layers[k].misregistration.rms_px; })))},
         {"misregistration_max_px",
          StatsJson(Stats(Column(run, [&](const ToleranceResult& r) { return r.layers[k].misregistration.max_px; })))},
         {"distortion_percent",
          StatsJson(Stats(Column(run, [&](const ToleranceResult& r) { return r.layers[k].distortion_percent; }),
                          Worse::kFartherFromZero))}});
  j["psnr_db"] = StatsJson(Stats(Column(run, [](const ToleranceResult& r) { return r.psnr_db; }), Worse::kLower));
  j["nominal_psnr_db"] = J(run.nominal.psnr_db);
  j["failed_samples"] = Failed(run);
  return j;
}

void WriteToleranceCsv(const ToleranceReportInput& in, const std::string& folder) {
  const ToleranceRun& run = *in.run;
  std::string samples = std::string("sample,layer,") + kResultHeader;
  for (size_t k = 0; k < run.samples.size(); ++k) samples += ResultRows(std::to_string(k), run.samples[k]);
  WriteFileAtomically(folder + "/samples.csv", samples);
  std::string draws = "sample";
  for (const ToleranceDof& d : in.model->dofs()) draws += "," + Csv(d.Name() + " (SI)");
  draws += "\n";
  for (size_t k = 0; k < run.draws.size(); ++k) {
    draws += std::to_string(k);
    for (double v : run.draws[k]) {
      char cell[40];
      std::snprintf(cell, sizeof cell, ",%.9g", v);
      draws += cell;
    }
    draws += "\n";
  }
  WriteFileAtomically(folder + "/draws.csv", draws);
  std::string sensitivity = std::string("tolerance,side,layer,") + kResultHeader;
  for (const SensitivityRow& s : run.sensitivity) {
    sensitivity += ResultRows(ToleranceKey(s.kind) + ",+", s.plus);
    sensitivity += ResultRows(ToleranceKey(s.kind) + ",-", s.minus);
  }
  WriteFileAtomically(folder + "/sensitivity.csv", sensitivity);
}

}  // namespace layerlab
