// The report of `layerlab run`: one self-contained index.html (inline CSS
// and JS, no network, opens from the file system) that shows what the run
// wrote, each picture linked to its file. Paths in the page are relative to
// the output folder.
//
// With ?selftest=1 in its URL the page checks itself once loaded (every image
// decoded, no script or resource error, moving the accommodation slider
// changes the retinal image shown) and writes "PASS ..." or "FAIL ..." into
// <pre id="selftest">, for headless browser tests.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "analysis/compare.h"
#include "analysis/contrast.h"
#include "systems/display_system.h"

namespace layerlab {

struct ReportImage {
  std::string caption;
  std::string src;                                         // the PNG or SVG shown
  std::vector<std::pair<std::string, std::string>> links;  // label, path: "EXR", "retina/display/0.40D.exr"
  std::string href;                                        // where a click on it goes; empty: src
};

ReportImage Picture(std::string caption, std::string src, std::vector<std::pair<std::string, std::string>> links = {},
                    std::string href = "");

struct ReportRetinaState {
  double diopters = 0;
  bool declared = false;         // one of the listed accommodation states (not only the focal stack)
  ReportImage display, natural;  // natural.src empty without natural viewing
  double display_mean_cd_m2 = 0, natural_mean_cd_m2 = 0;
};

struct RunReportPage {
  std::string title, scene_file, description, command;
  std::string version;  // framework/version.h VersionLine()
  const DisplaySystem* system = nullptr;
  std::vector<std::pair<std::string, std::string>> system_links;  // system.txt, system.json

  std::vector<std::pair<std::string, double>> steps;  // what ran, wall seconds
  std::vector<std::string> warnings;

  std::string target_source;  // "" when there is no target
  ReportImage target;         // its center view

  bool solved = false;
  std::string solve_brief;
  ReportImage psnr_plot;
  std::vector<ReportImage> patterns, panels;
  std::vector<std::pair<std::string, std::string>> solve_links;

  std::vector<ReportRetinaState> retina;
  std::vector<std::pair<std::string, std::string>> retina_links;
  double white_cd_m2 = 0;  // what 1 means in the retinal images

  ReportImage contrast_plot;  // src empty when not run
  std::vector<ContrastCurve> contrast;

  ReportImage compare_plot;  // src empty when not run
  std::vector<CompareResult> compare;
};

std::string RenderRunReport(const RunReportPage& page);

}  // namespace layerlab
