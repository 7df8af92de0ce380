// The parts of a report page (analysis/html_report.h) for what one step
// wrote: the files the page shows beyond the step's own results (previews,
// plots) are written here, and the page's fields filled with paths relative
// to the page. The `run` report and each command's own index.html are built
// from the same parts: `prefix` is the step's folder as the page sees it
// ("solve/" in the run report, "" in the index.html of `layerlab solve`).
#pragma once

#include <string>
#include <vector>

#include "layerlab/analysis/compare.h"
#include "layerlab/analysis/contrast.h"
#include "layerlab/analysis/html_report.h"
#include "layerlab/analysis/retina_sweep.h"
#include "layerlab/solvers/solver.h"

namespace layerlab {

// A page for one command: its title, the scene, the command line and the version.
RunReportPage CommandPage(const std::string& command, const std::string& scene_file, const std::string& name,
                          const std::string& description, const std::string& command_line);

// Writes pattern_previews/ (sRGB previews of the transmittance),
// panel_previews/ (each panel's active region) and psnr_vs_time.svg into
// `folder`, where WriteSolution wrote the patterns, panels and trace.
void AddSolveToPage(const DisplaySystem& system, const Patterns& patterns, const SolverReport& report,
                    const std::string& folder, const std::string& prefix, bool with_lightfield, RunReportPage* page);

// The retinal images WriteRetinaSweep wrote; `declared` are the states the slider marks.
void AddRetinaToPage(const std::vector<RetinaStateResult>& states, const std::vector<double>& declared, bool natural,
                     double white_cd_m2, const std::string& prefix, RunReportPage* page);

// Writes contrast.csv, peaks.txt and contrast.svg into `folder`.
void AddContrastToPage(const std::vector<ContrastCurve>& curves, const std::string& folder, const std::string& prefix,
                       RunReportPage* page);

// Writes compare.txt, compare.csv, traces.csv and psnr_vs_time.svg into `folder`.
void AddCompareToPage(const std::vector<CompareResult>& results, const std::string& folder, const std::string& prefix,
                      RunReportPage* page);

// Writes the page as folder/index.html.
void WriteReportPage(const RunReportPage& page, const std::string& folder);

}  // namespace layerlab
