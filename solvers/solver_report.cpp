#include <algorithm>
#include <cmath>
#include <cstdio>

#include "layerlab/framework/warnings.h"
#include "layerlab/solvers/objective.h"
#include "layerlab/solvers/solver.h"

namespace layerlab {
namespace {

std::string Db(double psnr) { return FormatPsnr(psnr, 2) + " dB"; }

}  // namespace

bool SolverReport::IsSolutionUsable() const {
  return termination == Termination::kIterationLimit || termination == Termination::kTimeBudget ||
         termination == Termination::kConverged || termination == Termination::kInterrupted;
}

std::string SolverReport::BriefReport() const {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s: %s after %d iterations in %.3f s, PSNR %s (objective %.6g -> %.6g)",
                solver.c_str(), ToString(termination).c_str(), iterations, seconds, Db(final_psnr_db).c_str(),
                initial_objective, final_objective);
  std::string brief = buf;
  if (!std::isnan(shown_psnr_db)) brief += ", shown through the panels' response " + Db(shown_psnr_db);
  return brief;
}

std::string SolverReport::FullReport() const {
  std::string out = "solver               " + solver + "\n";
  out += "termination          " + ToString(termination) + (message.empty() ? "" : " (" + message + ")") + "\n";
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "iterations           %d\nwall time            %.3f s (after %.3f s of set-up) on %d thread%s\n"
                "rays x channels      %zu\n",
                iterations, seconds, setup_seconds, threads, threads == 1 ? "" : "s", rays * 3);
  out += buf;
  std::string what;
  if (objective == "retinal") {
    what = contrast_sensitivity ? " over the focal stack's retinal samples, weighted by contrast sensitivity"
                                : " over the focal stack's retinal samples";
    if (retinal_target == "traced") what += ", against the traced target scene";
    if (pupil_positions > 1) what += ", from " + std::to_string(pupil_positions) + " pupil positions";
  }
  if (panel_diffraction) what += ", seen through the panels' diffraction";
  if (lc_response) what += ", shown through the panels' liquid-crystal response";
  std::snprintf(buf, sizeof buf, "objective            %.9g -> %.9g (sum of squared errors%s)\n", initial_objective,
                final_objective, what.c_str());
  out += buf;
  out += "PSNR                 " + Db(trace.empty() ? 0 : trace.front().psnr_db) + " -> " + Db(final_psnr_db) +
         " (light field; peak 1 = display white)\n";
  if (!std::isnan(shown_psnr_db))
    out += "shown PSNR           " + Db(shown_psnr_db) +
           " (light field of what the panels show through their liquid-crystal response; the solve assumes "
           "instant panels)\n";
  if (!trace.empty() && !std::isnan(trace.back().focal_stack_psnr_db))
    out += "focal-stack PSNR     " + Db(trace.front().focal_stack_psnr_db) + " -> " +
           Db(trace.back().focal_stack_psnr_db) +
           (pupil_positions > 1 ? " (mean over accommodation states of the pupil positions' weighted mean error)\n"
                                : " (mean over accommodation states)\n");
  std::snprintf(buf, sizeof buf, "target out of range  %zu values; scale %.6g\n", out_of_range, target_scale);
  out += buf;
  if (flicker) out += "flicker              " + flicker->Describe() + "\n";
  out += WarningLines(warnings);
  out += "\niteration  seconds     objective        PSNR (dB)\n";
  for (const IterationRecord& r : trace) {
    std::snprintf(buf, sizeof buf, "%9d  %8.3f  %14.6f  %s\n", r.iteration, r.seconds, r.objective,
                  Db(r.psnr_db).c_str());
    out += buf;
  }
  return out;
}

std::string TimeBudgetMessage(double seconds) { return "stopped after " + std::to_string(seconds) + " s"; }

std::optional<SolverReport> ReportWithTimeBudget(const SolverReport& report, double time_budget) {
  if (!report.IsSolutionUsable() || report.termination == Termination::kInterrupted) return std::nullopt;
  if (time_budget <= 0)  // no budget
    return report.termination == Termination::kTimeBudget ? std::nullopt : std::optional<SolverReport>(report);
  auto at = std::find_if(report.trace.begin(), report.trace.end(),
                         [&](const IterationRecord& r) { return r.iteration > 0 && r.seconds >= time_budget; });
  if (at == report.trace.end()) {
    if (report.termination == Termination::kTimeBudget) return std::nullopt;  // its own budget was shorter
    return report;
  }
  if (at + 1 == report.trace.end() && report.termination == Termination::kTimeBudget) return report;
  SolverReport cut = report;
  cut.trace.assign(report.trace.begin(), at + 1);
  cut.termination = Termination::kTimeBudget;
  cut.message = TimeBudgetMessage(at->seconds);
  cut.iterations = at->iteration;
  cut.seconds = at->seconds;
  cut.final_objective = at->objective;
  cut.final_psnr_db = at->psnr_db;
  return cut;
}

}  // namespace layerlab
