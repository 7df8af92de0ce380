// The HTML of each kind of report section (analysis/html_report.h), from
// what its step computed; analysis/report_parts.h wraps each in a
// ReportSection with its id, title and files.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "layerlab/analysis/compare.h"
#include "layerlab/analysis/contrast.h"
#include "layerlab/analysis/html_report.h"

namespace layerlab {

using ReportLinks = std::vector<std::pair<std::string, std::string>>;  // label, path

std::string TargetHtml(const std::string& source, const ReportImage& center_view);
std::string SolveHtml(const std::string& brief, const ReportLinks& links, const ReportImage& psnr_plot,
                      const std::vector<ReportImage>& patterns, const std::vector<ReportImage>& panels);
std::string RetinaHtml(const std::vector<ReportRetinaState>& states, const ReportLinks& links, double white_cd_m2);
// `eyebox`: the peaks' error across the eyebox (analysis/contrast_eyebox.h), when the curves were seen from it.
std::string ContrastHtml(const ReportImage& plot, const std::vector<ContrastCurve>& curves,
                         const ReportImage* eyebox = nullptr);
std::string CompareHtml(const std::vector<CompareResult>& results, const ReportImage& plot);

}  // namespace layerlab
