#include "layerlab/analysis/report_sections.h"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

#include "layerlab/analysis/svg_plot.h"
#include "layerlab/solvers/trace_columns.h"

namespace layerlab {
namespace {

std::string F(double v, int decimals) { return HtmlNumber(v, decimals); }

std::string Rgb3(const Rgb& v, int decimals) { return HtmlRgb(v, decimals); }

// Channels relative to the strongest: how far white drifts in color.
std::string Balance(const Rgb& v) {
  double m = std::max({v[0], v[1], v[2]});
  if (!(m > 0)) return "&ndash;";
  return F(v[0] / m, 3) + " : " + F(v[1] / m, 3) + " : " + F(v[2] / m, 3);
}

}  // namespace

std::string TargetHtml(const std::string& source, const ReportImage& center_view) {
  return "<section id=\"target\"><h2>Target</h2><p>" + Escape(source) + "</p><div class=\"grid\">" +
         HtmlFigure(center_view, "", "panel") + "</div></section>\n";
}

std::string SolveHtml(const std::string& brief, const ReportLinks& links, const ReportImage& psnr_plot,
                      const std::vector<ReportImage>& patterns, const std::vector<ReportImage>& panels) {
  std::string h = "<section id=\"solve\"><h2>Factorization</h2><p>" + Escape(brief) + HtmlLinks(links) + "</p>\n";
  h += "<div class=\"grid\">" + HtmlFigure(psnr_plot, "", "plot") + "</div>\n";
  h += "<h3>Layer patterns as the eye sees them (linear transmittance; a mirror-reversed layer is turned back, so "
       "that neighbouring layers line up; the EXRs and the panel-ready images are in the panel's pixel order)</h3>"
       "<div class=\"grid\">\n";
  for (const ReportImage& p : patterns) h += HtmlFigure(p, "", "small");
  h += "</div>\n<h3>Panel-ready images (gamma- and black-level-encoded; the active region, a click shows the full "
       "panel)</h3><div class=\"grid\">\n";
  for (const ReportImage& p : panels) h += HtmlFigure(p, "", "panel");
  h += "</div></section>\n";
  return h;
}
// The mean retinal luminance over accommodation, display and natural viewing, as a small plot inline in the
// page (a table of nearly equal numbers took a screen); the table stays, folded, below it.
std::string MeanLuminancePlot(const std::vector<ReportRetinaState>& states) {
  PlotPanel panel;
  panel.x_label = "accommodation (D)";
  panel.y_label = "mean luminance (cd/m\u00b2)";
  PlotLine display{"display", "#d62728", false, {}, {}}, natural{"natural viewing", "#1f77b4", true, {}, {}};
  double lo = INFINITY, hi = -INFINITY;
  for (const ReportRetinaState& s : states) {
    display.x.push_back(s.diopters), display.y.push_back(s.display_mean_cd_m2);
    lo = std::min(lo, s.display_mean_cd_m2), hi = std::max(hi, s.display_mean_cd_m2);
    if (std::isfinite(s.natural_mean_cd_m2)) {
      natural.x.push_back(s.diopters), natural.y.push_back(s.natural_mean_cd_m2);
      lo = std::min(lo, s.natural_mean_cd_m2), hi = std::max(hi, s.natural_mean_cd_m2);
    }
  }
  panel.lines.push_back(std::move(display));
  if (!natural.x.empty()) panel.lines.push_back(std::move(natural));
  panel.x_min = states.front().diopters, panel.x_max = std::max(states.back().diopters, panel.x_min + 0.1);
  const double pad = std::max(0.1 * (hi - lo), 0.02 * std::max(hi, 1e-9));  // nearly equal values stay readable
  panel.y_min = std::max(0.0, lo - pad), panel.y_max = hi + pad;
  std::string svg = RenderSvg({panel}, 1, "mean retinal luminance against accommodation");
  const std::string xmlns = " xmlns=\"http://www.w3.org/2000/svg\"";  // inline in HTML it needs none
  if (const size_t at = svg.find(xmlns); at != std::string::npos) svg.erase(at, xmlns.size());
  return svg;
}

std::string RetinaHtml(const std::vector<ReportRetinaState>& states, const ReportLinks& links, double white_cd_m2) {
  std::string h = "<section id=\"retina\"><h2>What the eye sees: retinal images over accommodation</h2>\n";
  h += "<p class=\"muted\">Drag the slider to focus the eye (a focal stack). Linear values are display-relative (1 = " +
       F(white_cd_m2, 1) + " cd/m&sup2;, the brightest branch at full white); the PNGs are sRGB with 1 as white." +
       HtmlLinks(links) + "</p>\n";
  size_t start = 0;
  for (size_t k = 0; k < states.size(); ++k)
    if (states[k].declared) {
      start = k;
      break;
    }
  h += "<div class=\"slider\"><label for=\"accommodation\">accommodation</label><div class=\"track\"><input "
       "type=\"range\" id=\"accommodation\" min=\"0\" max=\"" +
       std::to_string(states.size() - 1) + "\" step=\"1\" value=\"" + std::to_string(start) +
       "\" list=\"declared-states\"><div class=\"ticks\">";
  // A label under each declared state, where the thumb's center (16 px wide in Chromium) stands.
  const double last = std::max<double>(1, double(states.size() - 1));
  for (size_t k = 0; k < states.size(); ++k)
    if (states[k].declared)
      h += "<span style=\"left:calc(" + F(100 * k / last, 3) + "% + " + F(8 - 16 * k / last, 2) + "px)\">" +
           F(states[k].diopters, 2) + " D</span>";
  h += "</div></div><span id=\"state\"></span></div>\n<datalist id=\"declared-states\">";
  for (size_t k = 0; k < states.size(); ++k)
    if (states[k].declared) h += "<option value=\"" + std::to_string(k) + "\"></option>";
  h += "</datalist>\n<div class=\"grid\">\n";
  const ReportRetinaState& first = states[start];
  h += HtmlFigure(first.display, "retina-display", "retina");
  if (!first.natural.src.empty()) h += HtmlFigure(first.natural, "retina-natural", "retina");
  h += "</div>\n<h3>Mean luminance at the retina</h3>\n<figure class=\"plot\">" + MeanLuminancePlot(states) +
       "</figure>\n<details><summary>each state's mean luminance and its images</summary>\n<table><tr><th>"
       "accommodation (D)</th><th>display (cd/m&sup2;)</th><th>natural viewing (cd/m&sup2;)</th><th "
       "class=\"l\">images</th></tr>\n";
  nlohmann::json shown = nlohmann::json::array();
  for (const ReportRetinaState& s : states) {
    h += "<tr><td>" + F(s.diopters, 2) + (s.declared ? " &#9679;" : "") + "</td><td>" + F(s.display_mean_cd_m2, 2) +
         "</td><td>" + F(s.natural_mean_cd_m2, 2) + "</td><td class=\"l\">display" + HtmlLinks(s.display.links) +
         (s.natural.links.empty() ? "" : " &middot; natural" + HtmlLinks(s.natural.links)) + "</td></tr>\n";
    nlohmann::json j = {{"diopters", s.diopters},
                        {"display", s.display.src},
                        {"display_caption", s.display.caption},
                        {"display_links", s.display.links}};
    if (!s.natural.src.empty()) {
      j["natural"] = s.natural.src;
      j["natural_caption"] = s.natural.caption;
      j["natural_links"] = s.natural.links;
    }
    shown.push_back(j);
  }
  h += "</table>\n<p class=\"muted\">&#9679; a declared accommodation state (the slider's tick marks); the others are "
       "the focal stack.</p>\n</details>\n";
  std::string data = shown.dump();
  for (size_t at = data.find("</"); at != std::string::npos; at = data.find("</", at + 3)) data.replace(at, 2, "<\\/");
  h += "<script>window.layerlabStates = " + data + ";</script>\n";
  return h + "</section>\n";
}

std::string ContrastHtml(const ReportImage& plot, const std::vector<ContrastCurve>& curves, const ReportImage* eyebox) {
  std::string h = "<section id=\"contrast\"><h2>Accommodation support: normalized contrast (Fig. 5)</h2>\n";
  h += "<p class=\"muted\">A cosine grating on a plane at each target depth; each display is factorized for it and the "
       "eye "
       "sweeps its focus. A display supports accommodation when its peak follows the target depth (the grey "
       "band).</p>\n";
  h += "<div class=\"grid\">" + HtmlFigure(plot, "", "plot") + "</div>\n";
  if (eyebox)
    h += "<p class=\"muted\">Each display's curves seen again from each pupil position of the eyebox grid, with the "
         "same factorizations: the peak's error against where the pupil is.</p>\n<div class=\"grid\">" +
         HtmlFigure(*eyebox, "", "plot") + "</div>\n";
  if (!curves.empty()) h += "<p class=\"muted\">" + Escape(curves.front().convention) + ".</p>\n";
  if (const std::string note = AboveOneNote(curves); !note.empty())
    h += "<p class=\"muted\" id=\"contrast-above-one\">" + Escape(note) + "</p>\n";
  std::vector<std::string> eyes;  // the eye model of the curves, each once
  for (const ContrastCurve& c : curves)
    if (std::find(eyes.begin(), eyes.end(), c.eye) == eyes.end()) eyes.push_back(c.eye);
  for (const std::string& eye : eyes) h += "<p class=\"muted\">Eye: " + Escape(eye) + ".</p>\n";
  // A binocular eye's vergence-accommodation conflict: the vergence on the target less the peak.
  const bool binocular = std::any_of(curves.begin(), curves.end(),
                                     [](const ContrastCurve& c) { return !std::isnan(c.vergence_diopters); });
  h += "<h3>Peaks</h3>\n<table><tr><th class=\"l\">display</th><th>target (D)</th><th>f (cpd)</th><th>peak (D)</th>"
       "<th>peak contrast</th><th>at target</th><th class=\"l\">solver</th><th>PSNR (dB)</th><th>solve (s)</th>" +
       std::string(binocular ? "<th>vergence (D)</th><th>VAC (D)</th>" : "") + "</tr>\n";
  for (const ContrastCurve& c : curves) {
    h += "<tr><td class=\"l\">" + Escape(c.display) + "</td><td>" + F(c.target_diopters, 2) + "</td><td>" +
         F(c.frequency, 1) + "</td><td>" + F(c.estimate.at, 3) + " &plusmn; " + F(c.estimate.uncertainty, 3) +
         (c.estimate.flat ? " (flat)" : "") + "</td><td>" + F(c.peak.value, 3) + "</td><td>" + F(c.at_target, 3) +
         "</td><td class=\"l\">" + Escape(c.solver) + "</td><td>" + (c.solver == "-" ? "&ndash;" : F(c.psnr_db, 2)) +
         "</td><td>" + F(c.solve_seconds, 2) + "</td>";
    if (binocular)
      h += "<td>" + HtmlNumber(c.vergence_diopters, 3) + "</td><td>" +
           (c.estimate.flat ? "&ndash;" : HtmlNumber(c.vergence_diopters - c.estimate.at, 3)) + "</td>";
    h += "</tr>\n";
  }
  return h + "</table>\n</section>\n";
}

std::string CompareHtml(const std::vector<CompareResult>& results, const ReportImage& plot) {
  std::string h = "<section id=\"compare\"><h2>Displays side by side on the same target</h2>\n";
  h +=
      "<p class=\"muted\">Brightness efficiency: light at the eye per light the backlights emit. Balance: the channels "
      "relative to the strongest (1 : 1 : 1 keeps white white; the factorization compensates the rest). Solver "
      "options: "
      "<i>shared</i>, the same for every row (the solver's defaults and the command's overrides); <i>scene</i>, the "
      "scene's own \"solve\" section.</p>\n";
  h += "<table><tr><th class=\"l\">display</th><th class=\"l\">solver</th><th class=\"l\">objective</th>"
       "<th>PSNR (dB)</th><th>focal-stack PSNR (dB)</th><th>seconds</th><th>iterations</th><th>brightness "
       "(luminance)</th><th>brightness R / G / B</th><th>balance R : G : B</th>"
       "<th class=\"l\">termination</th><th class=\"l\">solver options</th>";
  const std::vector<const TraceColumn*> metrics = MeasuredMetricColumns(results);
  for (const TraceColumn* c : metrics)
    h += "<th>focal-stack " + MetricHeading(*c) +
         (std::string(c->unit).empty() ? "" : " (" + std::string(c->unit) + ")") + "</th>";
  h += "</tr>\n";
  for (const CompareResult& r : results) {
    const double focal_stack = FinalFocalStackPsnr(r.report);
    h += "<tr><td class=\"l\">" + Escape(r.display) + "</td><td class=\"l\">" + Escape(r.solver) +
         "</td><td class=\"l\">" + Escape(r.report.objective) + "</td><td>" + F(r.report.final_psnr_db, 2) +
         "</td><td>" + (std::isnan(focal_stack) ? "&ndash;" : F(focal_stack, 2)) + "</td><td>" +
         F(r.report.seconds, 2) + "</td><td>" + std::to_string(r.report.iterations) + "</td><td>" +
         F(r.luminance_efficiency, 4) + "</td><td>" + Rgb3(r.brightness_efficiency, 4) + "</td><td>" +
         Balance(r.brightness_efficiency) + "</td><td class=\"l\">" + Escape(ToString(r.report.termination)) +
         "</td><td class=\"l\">" + Escape(r.options_from) + "</td>";
    for (const TraceColumn* c : metrics) {
      const double v = FinalTraceValue(*c, r.report);
      h += "<td>" + (std::isnan(v) ? std::string("&ndash;") : F(v, std::string(c->unit) == "JND" ? 2 : 4)) + "</td>";
    }
    h += "</tr>\n";
  }
  h += "</table>\n<div class=\"grid\">" + HtmlFigure(plot, "", "plot") + "</div>\n";
  return h + "</section>\n";
}

}  // namespace layerlab
