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

#include "layerlab/systems/display_system.h"

namespace layerlab {

struct ReportImage {
  std::string caption;
  std::string src;                                         // the PNG or SVG shown
  std::vector<std::pair<std::string, std::string>> links;  // label, path: "EXR", "retina/display/0.40D.exr"
  std::string href;                                        // where a click on it goes; empty: src
  int width = 0, height = 0;  // a PNG's pixels, shown one to one; 0: as the page lays it out
};

ReportImage Picture(std::string caption, std::string src, std::vector<std::pair<std::string, std::string>> links = {},
                    std::string href = "");

struct ReportRetinaState {
  double diopters = 0;
  bool declared = false;         // one of the listed accommodation states (not only the focal stack)
  ReportImage display, natural;  // natural.src empty without natural viewing
  double display_mean_cd_m2 = 0, natural_mean_cd_m2 = 0;
};

// One section of a page: what one step showed (analysis/report_sections.h builds them).
struct ReportSection {
  std::string id;                  // the anchor: <section id="retina">, the navigation's #retina
  std::string title;               // the navigation's link text
  std::vector<std::string> files;  // what the section wrote for the page, relative to the page
  std::string html;                // the <section> element
};

// One number of the page's summary, first on the page: what it is, its value with its unit, and the
// section that shows where it comes from.
struct SummaryItem {
  std::string what, value, section;
};

// The page's frame (header, summary, steps, the display system) and its sections in order.
struct RunReportPage {
  std::string title, scene_file, description, command;
  std::string version;  // framework/version.h VersionLine()
  const DisplaySystem* system = nullptr;
  std::vector<std::pair<std::string, std::string>> system_links;  // system.txt, system.json

  std::vector<std::pair<std::string, double>> steps;  // what ran, wall seconds
  std::vector<std::string> warnings;

  std::vector<ReportSection> sections;
  std::vector<SummaryItem> summary;  // each section adds its key numbers
};

// The pieces of a section's HTML: a number ("&ndash;" for NaN), file links, a linked figure.
std::string HtmlNumber(double v, int decimals);
std::string HtmlRgb(const Rgb& v, int decimals);  // "R / G / B"
std::string HtmlLinks(const std::vector<std::pair<std::string, std::string>>& links);
std::string HtmlFigure(const ReportImage& image, const std::string& id = "", const std::string& extra_class = "");

std::string RenderRunReport(const RunReportPage& page);

}  // namespace layerlab
