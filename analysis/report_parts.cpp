#include "layerlab/analysis/report_parts.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <optional>

#include "layerlab/analysis/contrast_eyebox.h"
#include "layerlab/analysis/report_sections.h"
#include "layerlab/framework/atomic_file.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/shown_image.h"
#include "layerlab/framework/units.h"
#include "layerlab/framework/version.h"
#include "layerlab/metrics/retinal_metrics.h"
#include "layerlab/solvers/solution_writer.h"
#include "layerlab/solvers/trace_columns.h"

namespace layerlab {
namespace {

namespace fs = std::filesystem;

using Links = std::vector<std::pair<std::string, std::string>>;

void MakeFolder(const fs::path& folder) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw Error(folder.string() + ": cannot create the folder: " + ec.message());
}

// A value with its unit for the summary: "31.25 dB", "0.9412".
std::string WithUnit(double value, const std::string& unit) {
  if (!std::isfinite(value)) return "not measured";
  return unit == "dB" || unit == "D" ? FormatFixed(value, 2) + " " + unit
                                     : FormatFixed(value, 4) + (unit.empty() ? "" : " " + unit);
}

// The solve's key numbers: the solver and its time, the final light-field PSNR, and the focal stack's
// PSNR and perceptual metrics where the solve measured them.
void AddSolveSummary(const SolverReport& report, RunReportPage* page) {
  page->summary.push_back({"solver",
                           report.solver + ", " + std::to_string(report.iterations) + " iterations in " +
                               FormatFixed(report.seconds, 2) + " s (" + ToString(report.termination) + ")",
                           "solve"});
  page->summary.push_back({"light-field PSNR", WithUnit(report.final_psnr_db, "dB"), "solve"});
  const CompareResult self{"", report.solver, report, {}, 0};
  for (const TraceColumn* c : MeasuredMetricColumns({self}))
    page->summary.push_back(
        {"focal stack, " + MetricHeading(*c), WithUnit(FinalTraceValue(*c, report), c->unit), "solve"});
}

// "+0.03", "-0.15", "0.00" (no sign where it rounds to zero).
std::string Signed(double value, int decimals) {
  const std::string text = FormatFixed(std::abs(value), decimals);
  if (text.find_first_not_of("0.") == std::string::npos) return text;
  return (value < 0 ? "-" : "+") + text;
}

// Each display's contrast peak against the target depth, one line per display and frequency: the
// accommodation it draws, less where the grating is (the eye's pupil at its place).
void AddContrastSummary(const std::vector<ContrastCurve>& curves, RunReportPage* page) {
  std::vector<std::pair<std::string, std::string>> lines;  // (display at f, "+0.05 D at 0.70 D, ...")
  for (const ContrastCurve& c : curves) {
    if (c.display.rfind("natural", 0) == 0 || c.pupil_moved) continue;
    const std::string what =
        "contrast peak minus target depth: " + c.display + " at " + FormatFixed(c.frequency, 1) + " cpd";
    const std::string value =
        (c.estimate.flat ? std::string("flat") : Signed(c.estimate.at - c.target_diopters, 2) + " D") + " at " +
        FormatFixed(c.target_diopters, 2) + " D";
    auto line = std::find_if(lines.begin(), lines.end(), [&](const auto& l) { return l.first == what; });
    if (line == lines.end())
      lines.push_back({what, value});
    else
      line->second += ", " + value;
  }
  for (const auto& [what, value] : lines) page->summary.push_back({what, value, "contrast"});
}

// ", PNG at 1/3 of the samples (EXR: all)" for a picture reduced to fit its place on the page.
std::string Reduced(int factor) {
  return factor > 1 ? ", PNG at 1/" + std::to_string(factor) + " of the samples (EXR: all)" : "";
}

ReportImage Shown(ReportImage image, const ShownPng& png) {
  image.width = png.width, image.height = png.height;
  return image;
}

}  // namespace

RunReportPage CommandPage(const std::string& command, const std::string& scene_file, const std::string& name,
                          const std::string& description, const std::string& command_line) {
  RunReportPage page;
  page.title = "layerlab " + command + (name.empty() ? "" : ": " + name);
  page.scene_file = scene_file;
  page.description = description;
  page.command = command_line;
  page.version = VersionLine();
  return page;
}

void AddSolveToPage(const DisplaySystem& system, const Patterns& patterns, const SolverReport& report,
                    const std::string& folder, const std::string& prefix, bool with_lightfield, RunReportPage* page) {
  const fs::path out(folder);
  std::vector<ReportImage> patterns_shown, panels;
  std::vector<std::string> files;
  MakeFolder(out / "pattern_previews");
  MakeFolder(out / "panel_previews");
  for (size_t k = 0; k < system.layers.size(); ++k) {
    const VirtualLayer& layer = system.layers[k];
    const std::string preview = "pattern_previews/" + layer.name + ".png";
    const ShownPng pattern = WriteShownSrgbPng((out / preview).string(), patterns[k].cols, patterns[k].rows,
                                               AsTheEyeSeesIt(layer, patterns[k]), kPreviewWidthPx);
    files.push_back(prefix + preview);
    patterns_shown.push_back(
        Shown(Picture(layer.name + " (" + FormatFixed(layer.diopters, 2) + " D)" + Reduced(pattern.factor),
                      prefix + preview, {{"EXR", prefix + "patterns/" + layer.name + ".exr"}}),
              pattern));
    // The panel-ready image cropped to the pixels the layer drives; the full panel is a click away.
    const PanelEncoding e = EncodeForPanel(layer, patterns[k]);
    std::vector<uint8_t> active(static_cast<size_t>(e.active_cols) * e.active_rows * 3);
    for (int row = 0; row < e.active_rows; ++row)
      for (int col = 0; col < e.active_cols * 3; ++col)
        active[static_cast<size_t>(row) * e.active_cols * 3 + col] =
            e.pixels[((static_cast<size_t>(row) + e.active_top) * e.cols + e.active_left) * 3 + col];
    const std::string cropped = "panel_previews/" + layer.name + ".png";
    const ShownPng drive =
        WriteShownPng8((out / cropped).string(), e.active_cols, e.active_rows, active, kPreviewWidthPx);
    const std::string full = prefix + "panels/" + layer.name + ".png";
    files.push_back(prefix + cropped);
    panels.push_back(Shown(Picture(layer.name + ": active " + std::to_string(e.active_cols) + " x " +
                                       std::to_string(e.active_rows) + " of the " + std::to_string(e.cols) + " x " +
                                       std::to_string(e.rows) + " panel" + Reduced(drive.factor),
                                   prefix + cropped, {{"full panel PNG", full}}, full),
                           drive));
  }
  CompareResult self{fs::path(system.file).stem().string(), report.solver, report, system.brightness_efficiency,
                     system.luminance_efficiency};
  WriteFileAtomically((out / "psnr_vs_time.svg").string(), PsnrAgainstTimeSvg({self}));
  const ReportImage plot = Picture("PSNR against wall time", prefix + "psnr_vs_time.svg",
                                   {{"SVG", prefix + "psnr_vs_time.svg"}, {"CSV", prefix + "trace.csv"}});
  Links links = {{"report.txt", prefix + "report.txt"},
                 {"report.json", prefix + "report.json"},
                 {"trace.csv", prefix + "trace.csv"}};
  if (with_lightfield) links.push_back({"synthesized light field", prefix + "lightfield/lightfield.json"});
  files.push_back(prefix + "psnr_vs_time.svg");
  AddSolveSummary(report, page);
  page->sections.push_back(
      {"solve", "Factorization", files,
       SolveHtml(report.BriefReport() + (report.flicker ? "; " + report.flicker->Describe() : std::string()), links,
                 plot, patterns_shown, panels)});
}

void AddRetinaToPage(const std::vector<RetinaStateResult>& states, const std::vector<double>& declared, bool natural,
                     double white_cd_m2, const std::string& prefix, RunReportPage* page) {
  std::vector<ReportRetinaState> shown;
  std::vector<std::string> files = {prefix + "retina.csv"};
  for (const RetinaStateResult& s : states) {
    ReportRetinaState rs;
    rs.diopters = s.diopters;
    for (double d : declared) rs.declared |= std::abs(d - s.diopters) < 1e-9;
    const std::string d = prefix + "display/" + s.name, n = prefix + "natural/" + s.name;
    const std::string at = FormatFixed(s.diopters, 2) + " D";
    rs.display = Picture("the display, focused at " + at + Reduced(s.png_factor), d + ".png",
                         {{"PNG", d + ".png"}, {"EXR", d + ".exr"}});
    if (s.world_cd_m2 > 0) {  // see-through: the same with the world's light added
      const std::string w = prefix + "see_through/" + s.name;
      rs.display.links.push_back({"with the world, PNG", w + ".png"});
      rs.display.links.push_back({"EXR", w + ".exr"});
    }
    if (natural)
      rs.natural = Picture("natural viewing of the target, focused at " + at + Reduced(s.png_factor), n + ".png",
                           {{"PNG", n + ".png"}, {"EXR", n + ".exr"}});
    for (ReportImage* image : {&rs.display, &rs.natural}) image->width = s.png_width, image->height = s.png_height;
    for (const ReportImage* image : {&rs.display, &rs.natural})
      for (const auto& [label, path] : image->links) files.push_back(path);
    rs.display_mean_cd_m2 = s.display_mean_cd_m2;
    rs.natural_mean_cd_m2 = s.natural_mean_cd_m2;
    shown.push_back(rs);
  }
  if (shown.empty()) return;
  if (states.front().world_cd_m2 > 0) {
    double sum = 0;
    for (const RetinaStateResult& s : states) sum += s.contrast_against_world;
    page->summary.push_back({"contrast against the world, (display + world) / world (mean of " +
                                 std::to_string(states.size()) + " accommodation states; the world " +
                                 FormatFixed(states.front().world_cd_m2, 1) + " cd/m2 at the eye)",
                             FormatFixed(sum / double(states.size()), 3), "retina"});
  }
  for (const MeanScore& s : MeanScoresOverStates(states)) {
    std::string name = s.metric->name;
    for (char& ch : name) ch = ch == '_' ? '-' : static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    page->summary.push_back({"retinal " + name + " against natural viewing (mean of " + std::to_string(states.size()) +
                                 " accommodation states)",
                             WithUnit(s.mean, s.metric->unit), "retina"});
  }
  page->sections.push_back(
      {"retina", "Retinal images", files, RetinaHtml(shown, {{"retina.csv", prefix + "retina.csv"}}, white_cd_m2)});
}

void AddContrastToPage(const std::vector<ContrastCurve>& curves, const std::string& folder, const std::string& prefix,
                       RunReportPage* page) {
  const fs::path out(folder);
  MakeFolder(out);
  WriteFileAtomically((out / "contrast.csv").string(), ContrastCsv(curves));
  WriteFileAtomically((out / "peaks.txt").string(), PeakTable(curves));
  WriteFileAtomically((out / "contrast.svg").string(), ContrastSvg(curves));
  const ReportImage plot =
      Picture("normalized contrast against accommodation", prefix + "contrast.svg",
              {{"SVG", prefix + "contrast.svg"}, {"CSV", prefix + "contrast.csv"}, {"peaks", prefix + "peaks.txt"}});
  std::vector<std::string> files = {prefix + "contrast.csv", prefix + "peaks.txt", prefix + "contrast.svg"};
  std::optional<ReportImage> eyebox;
  if (std::any_of(curves.begin(), curves.end(), [](const ContrastCurve& c) { return c.pupil_moved; })) {
    WriteFileAtomically((out / "eyebox_peaks.csv").string(), ContrastEyeboxCsv(curves));
    WriteFileAtomically((out / "eyebox_peaks.svg").string(), ContrastEyeboxSvg(curves));
    files.push_back(prefix + "eyebox_peaks.csv");
    files.push_back(prefix + "eyebox_peaks.svg");
    eyebox = Picture("the contrast peak's error across the eyebox", prefix + "eyebox_peaks.svg",
                     {{"SVG", prefix + "eyebox_peaks.svg"}, {"CSV", prefix + "eyebox_peaks.csv"}});
  }
  AddContrastSummary(curves, page);
  page->sections.push_back({"contrast", "Contrast", files, ContrastHtml(plot, curves, eyebox ? &*eyebox : nullptr)});
}

void AddCompareToPage(const std::vector<CompareResult>& results, const std::string& folder, const std::string& prefix,
                      RunReportPage* page) {
  const fs::path out(folder);
  MakeFolder(out);
  WriteFileAtomically((out / "compare.txt").string(), CompareTable(results));
  WriteFileAtomically((out / "compare.csv").string(), CompareCsv(results));
  WriteFileAtomically((out / "traces.csv").string(), TracesCsv(results));
  WriteFileAtomically((out / "psnr_vs_time.svg").string(), PsnrAgainstTimeSvg(results));
  const ReportImage plot = Picture(
      "PSNR against wall time, every display and solver", prefix + "psnr_vs_time.svg",
      {{"SVG", prefix + "psnr_vs_time.svg"}, {"CSV", prefix + "compare.csv"}, {"traces", prefix + "traces.csv"}});
  page->sections.push_back(
      {"compare",
       "Comparison",
       {prefix + "compare.txt", prefix + "compare.csv", prefix + "traces.csv", prefix + "psnr_vs_time.svg"},
       CompareHtml(results, plot)});
}

void WriteReportPage(const RunReportPage& page, const std::string& folder) {
  WriteFileAtomically((fs::path(folder) / "index.html").string(), RenderRunReport(page));
}

}  // namespace layerlab
