#include "layerlab/analysis/html_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <nlohmann/json.hpp>

#include "layerlab/analysis/layout_svg.h"
#include "layerlab/analysis/svg_plot.h"
#include "layerlab/eye/eye_description.h"
#include "layerlab/framework/units.h"
#include "layerlab/retina/retina.h"
#include "layerlab/systems/system_report.h"

namespace layerlab {
namespace {

std::string F(double v, int decimals) { return HtmlNumber(v, decimals); }
std::string Links(const std::vector<std::pair<std::string, std::string>>& links) { return HtmlLinks(links); }

std::string Rgb3(const Rgb& v, int decimals) { return HtmlRgb(v, decimals); }

constexpr const char* kStyle = R"CSS(
body{font:14px/1.45 system-ui,-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;margin:0;color:#1b1b1b;background:#f6f6f4}
header{background:#20303c;color:#fff;padding:18px 28px}
header h1{margin:0 0 4px;font-size:22px}
header p{margin:2px 0;color:#cfd8df}
header code{color:#fff}
nav{margin-top:8px}
nav a{color:#9fd0ff;margin-right:14px;text-decoration:none}
main{padding:8px 28px 40px;max-width:1500px}
section{background:#fff;border:1px solid #ddd;border-radius:6px;margin:18px 0;padding:6px 18px 16px}
h2{font-size:18px;margin:12px 0 8px;border-bottom:1px solid #eee;padding-bottom:4px}
h3{font-size:15px;margin:14px 0 6px}
table{border-collapse:collapse;margin:6px 0 10px;font-variant-numeric:tabular-nums;display:block;overflow-x:auto;max-width:100%}
th,td{border:1px solid #ddd;padding:3px 7px;text-align:right;white-space:nowrap}
th{background:#f0f2f4;font-weight:600;white-space:normal;vertical-align:bottom;max-width:9em}
table.summary th{max-width:none;min-width:22em;vertical-align:middle}
table.summary td{text-align:left;font-weight:600}
td.l,th.l{text-align:left}
.grid{display:flex;flex-wrap:wrap;gap:14px;align-items:flex-start}
figure{margin:0;max-width:100%}
figure img{display:block;max-width:100%;height:auto;border:1px solid #ccc;background:#000;image-rendering:pixelated}
figure.plot img{background:#fff;image-rendering:auto}
figure.layout svg{display:block;max-width:100%;height:auto;border:1px solid #ccc}
figure.small,figure.panel,figure.retina{display:table}
figure.small figcaption,figure.panel figcaption,figure.retina figcaption{display:table-caption;caption-side:bottom}
figcaption{font-size:12px;color:#444;margin-top:3px}
a.file{font-size:12px;margin-left:4px;padding:0 4px;border:1px solid #b8c4ce;border-radius:3px;text-decoration:none;color:#20507a}
.slider{display:flex;align-items:center;gap:12px;margin:8px 0 12px;flex-wrap:wrap}
.slider .track{flex:1 1 420px;position:relative;padding-bottom:20px}
.slider input{width:100%;margin:0}
.ticks span{position:absolute;top:22px;transform:translateX(-50%);font-size:12px;color:#333;white-space:nowrap}
.ticks span:before{content:"";position:absolute;left:50%;top:-6px;height:5px;border-left:1px solid #777}
#state{font-size:18px;font-weight:600;min-width:190px}
.warn{color:#8a4b00}
pre{background:#f4f4f4;padding:8px;overflow:auto;font-size:12px}
.muted{color:#666}
)CSS";

// Runs before anything loads, so that every script and resource error is counted.
constexpr const char* kErrorCatcher = R"JS(
window.layerlabErrors = [];
window.addEventListener('error', function (e) {
  var t = e.target;
  window.layerlabErrors.push(t && t !== window && (t.src || t.href) ? 'could not load ' + (t.src || t.href)
                                                                     : String(e.message || e.type));
}, true);
)JS";

constexpr const char* kScript = R"JS(
(function () {
  var states = window.layerlabStates || [];
  var slider = document.getElementById('accommodation');
  function setImage(id, src, links) {
    var img = document.getElementById(id);
    if (!img) return;
    img.src = src;
    document.getElementById(id + '-link').href = src;
    var caption = document.getElementById(id + '-caption');
    caption.innerHTML = '';
    caption.appendChild(document.createTextNode(links.caption));
    links.files.forEach(function (f) {
      var a = document.createElement('a');
      a.className = 'file'; a.href = f[1]; a.textContent = f[0];
      caption.appendChild(document.createTextNode(' ')); caption.appendChild(a);
    });
  }
  function show(k) {
    var s = states[k];
    if (!s) return;
    document.getElementById('state').textContent = 'focused at ' + s.diopters.toFixed(2) + ' D' +
        (s.diopters > 0 ? ' (' + (1 / s.diopters).toFixed(2) + ' m)' : ' (infinity)');
    setImage('retina-display', s.display, {caption: s.display_caption, files: s.display_links});
    if (s.natural) setImage('retina-natural', s.natural, {caption: s.natural_caption, files: s.natural_links});
  }
  if (slider) {
    slider.addEventListener('input', function () { show(+slider.value); });
    show(+slider.value);
  }
  window.layerlabShow = show;

  if (new URLSearchParams(location.search).get('selftest') !== '1') return;
  function imageReady(img) {
    return new Promise(function (resolve) {
      if (img.complete) return resolve();
      img.addEventListener('load', resolve); img.addEventListener('error', resolve);
    });
  }
  window.addEventListener('load', function () {
    var out = document.getElementById('selftest');
    var problems = [];
    var images = Array.prototype.slice.call(document.images);
    Promise.all(images.map(imageReady)).then(function () {
      var one_to_one = 0;
      images.forEach(function (img) {
        if (!(img.naturalWidth > 0)) problems.push('image not shown: ' + img.getAttribute('src'));
        // A PNG written at the size the page shows it: its declared size is its own, and it is shown so
        // wherever the window has room (framework/shown_image.h).
        if (!img.hasAttribute('width')) {
          if (/\.png$/.test(img.getAttribute('src'))) problems.push(img.getAttribute('src') + ' has no declared size');
          return;
        }
        if (!(img.naturalWidth > 0)) return;
        var w = +img.getAttribute('width'), h = +img.getAttribute('height');
        if (img.naturalWidth !== w || img.naturalHeight !== h)
          problems.push(img.getAttribute('src') + ' is ' + img.naturalWidth + ' x ' + img.naturalHeight +
                        ' but declared ' + w + ' x ' + h);
        else if (img.parentElement.parentElement.parentElement.clientWidth >= w + 40 &&
                 Math.abs(img.clientWidth - w) > 0.5)
          problems.push(img.getAttribute('src') + ' is shown ' + img.clientWidth + ' px wide, not its ' + w);
        else one_to_one++;
      });
      var detail = images.length + ' images, ' + one_to_one + ' shown one to one';
      var first = document.querySelector('main section');
      if (document.getElementById('summary')) {
        if (first.id !== 'summary') problems.push('the summary is not the first section (' + first.id + ')');
        detail += ', a summary of ' + document.querySelectorAll('#summary tr').length + ' numbers';
      }
      var layout = document.querySelector('#layout svg');
      if (!document.getElementById('system')) detail += ', no display section';
      else if (!layout) problems.push('no optical layout diagram');
      else if (!(layout.getBoundingClientRect().width > 100) || layout.querySelectorAll('rect').length < 2)
        problems.push('the optical layout diagram is not drawn');
      else detail += ', the layout diagram';
      var shown = document.getElementById('retina-display');
      if (slider && shown && states.length > 1) {
        var before = shown.getAttribute('src');
        var to = (+slider.value + 1) % states.length;
        slider.value = String(to);
        slider.dispatchEvent(new Event('input', {bubbles: true}));
        var after = shown.getAttribute('src');
        if (after === before) problems.push('moving the slider did not change the retinal image (' + before + ')');
        detail += '; slider moved from ' + before + ' to ' + after;
        return imageReady(shown).then(function () {
          if (!(shown.naturalWidth > 0)) problems.push('the image after the slider moved did not load: ' + after);
          return detail;
        });
      }
      if (document.getElementById('retina')) problems.push('the retina section has no working slider');
      return detail + '; no retina slider';
    }).then(function (detail) {
      problems = problems.concat(window.layerlabErrors);
      out.textContent = (problems.length ? 'FAIL ' + problems.join('; ') : 'PASS') + ' (' + detail + ')';
      out.hidden = false;
    });
  });
})();
)JS";

// The key numbers first, each linked to the section it comes from; the display's brightness with them.
std::string SummarySection(const RunReportPage& page) {
  std::vector<SummaryItem> items = page.summary;
  if (page.system)
    items.push_back({"brightness efficiency (eye over backlight luminance)",
                     FormatFixed(page.system->luminance_efficiency, 4), "system"});
  if (items.empty()) return "";
  std::string h = "<section id=\"summary\"><h2>Summary</h2><table class=\"summary\">\n";
  for (const SummaryItem& item : items)
    h += "<tr><th class=\"l\"><a href=\"#" + Escape(item.section) + "\">" + Escape(item.what) + "</a></th><td>" +
         Escape(item.value) + "</td></tr>\n";
  return h + "</table></section>\n";
}

std::string SystemSection(const RunReportPage& page) {
  const DisplaySystem& s = *page.system;
  std::string h = "<section id=\"system\"><h2>Display system</h2>\n";
  h += "<p>" + Escape(s.name.empty() ? s.file : s.name) + Links(page.system_links) + "</p>\n";
  h += "<figure class=\"layout\" id=\"layout\">" + RenderLayoutSvg(s, false) + "</figure>\n";
  h += "<table><tr><th class=\"l\">field of view</th><td>" + F(s.fov_x_rad / kRadiansPerDegree, 2) + " &times; " +
       F(s.fov_y_rad / kRadiansPerDegree, 2) + " deg</td></tr>\n";
  h += "<tr><th class=\"l\">highest frequency</th><td>" + F(EveryLayerMaxCpd(s), 2) + " cpd on every layer, " +
       F(s.max_cpd, 2) + " cpd on the finest</td></tr>\n";
  h += "<tr><th class=\"l\">peak luminance (R / G / B)</th><td>" + Rgb3(s.peak_luminance_cd_m2, 1) +
       " cd/m&sup2;</td></tr>\n";
  h += "<tr><th class=\"l\">brightness efficiency</th><td>" + F(s.luminance_efficiency, 4) + " (R / G / B " +
       Rgb3(s.brightness_efficiency, 4) + ")</td></tr>\n";
  h += "<tr><th class=\"l\">eye</th><td>pupil " + F(s.eye.pupil_diameter_m * 1e3, 1) + " mm, eyebox " +
       F(s.eye.eyebox_width_m * 1e3, 1) + " &times; " + F(s.eye.eyebox_height_m * 1e3, 1) + " mm, " +
       std::to_string(s.eye.views_x) + " &times; " + std::to_string(s.eye.views_y) + " views</td></tr>\n";
  h += "<tr><th class=\"l\">eye model</th><td>" + Escape(EyeModelLine(s.eye)) + "</td></tr>\n";
  if (!s.lens.empty())
    h += "<tr><th class=\"l\">lens</th><td>" + Escape(s.lens) + ", f = " + F(s.focal_length_m * 1e3, 2) +
         " mm</td></tr>\n";
  h += "</table>\n";

  h += "<h3>Virtual layers (farthest first)</h3>\n<table><tr><th>#</th><th class=\"l\">panel</th><th "
       "class=\"l\">branch</th>"
       "<th>depth (D)</th><th>depth (m)</th><th>panel distance (mm)</th><th>magnification</th><th>virtual pixel "
       "(mm)</th>"
       "<th>pixels</th><th>field of view (deg)</th><th>max f (cpd)</th></tr>\n";
  for (size_t k = 0; k < s.layers.size(); ++k) {
    const VirtualLayer& l = s.layers[k];
    h += "<tr><td>" + std::to_string(k) + "</td><td class=\"l\">" + Escape(l.name) + "</td><td class=\"l\">" +
         Escape(s.branches[l.branch].name) + "</td><td>" + F(l.diopters, 3) + "</td><td>" + F(l.depth_m, 4) +
         "</td><td>" + F(l.panel_distance_m * 1e3, 2) + "</td><td>" + F(l.magnification, 2) + "</td><td>" +
         F(l.pitch_x_m * 1e3, 3) + "</td><td>" + std::to_string(l.cols) + " &times; " + std::to_string(l.rows) +
         "</td><td>" + F(l.fov_x_rad / kRadiansPerDegree, 2) + " &times; " + F(l.fov_y_rad / kRadiansPerDegree, 2) +
         "</td><td>" + F(l.max_cpd, 2) + "</td></tr>\n";
  }
  h += "</table>\n<h3>Branches (added at the eye)</h3>\n<table><tr><th>#</th><th class=\"l\">name</th><th "
       "class=\"l\">layers</th>"
       "<th>optics efficiency (R / G / B)</th><th>efficiency (R / G / B)</th><th class=\"l\">backlight</th>"
       "<th>luminance (cd/m&sup2;)</th></tr>\n";
  for (size_t b = 0; b < s.branches.size(); ++b) {
    const Branch& br = s.branches[b];
    std::string layers;
    for (int k : br.layers) layers += (layers.empty() ? "" : ", ") + s.layers[k].name;
    h += "<tr><td>" + std::to_string(b) + "</td><td class=\"l\">" + Escape(br.name) + "</td><td class=\"l\">" +
         Escape(layers) + "</td><td>" + Rgb3(br.optics_efficiency, 4) + "</td><td>" + Rgb3(br.efficiency, 4) +
         "</td><td class=\"l\">" + Escape(br.backlight) + "</td><td>" + F(br.backlight_luminance_cd_m2, 1) +
         "</td></tr>\n";
  }
  h += "</table>\n";
  for (const std::string& w : s.warnings) h += "<p class=\"warn\">warning: " + Escape(w) + "</p>\n";
  return h + "</section>\n";
}

}  // namespace

std::string HtmlNumber(double v, int decimals) {
  if (std::isnan(v)) return "&ndash;";
  if (std::isinf(v)) return v > 0 ? "&infin;" : "&minus;&infin;";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, v);
  return text;
}

std::string HtmlLinks(const std::vector<std::pair<std::string, std::string>>& links) {
  std::string out;
  for (const auto& [label, path] : links)
    out += " <a class=\"file\" href=\"" + Escape(path) + "\">" + Escape(label) + "</a>";
  return out;
}

std::string HtmlFigure(const ReportImage& image, const std::string& id, const std::string& extra_class) {
  std::string id_attr = id.empty() ? "" : " id=\"" + id + "\"";
  // A PNG is shown one image pixel to one CSS pixel, at the size it was written (framework/shown_image.h).
  const std::string size =
      image.width > 0 ? " width=\"" + std::to_string(image.width) + "\" height=\"" + std::to_string(image.height) + "\""
                      : "";
  return "<figure class=\"" + extra_class + "\"><a" + (id.empty() ? "" : " id=\"" + id + "-link\"") + " href=\"" +
         Escape(image.href.empty() ? image.src : image.href) + "\"><img" + id_attr + " src=\"" + Escape(image.src) +
         "\"" + size + " alt=\"" + Escape(image.caption) + "\"></a><figcaption" +
         (id.empty() ? "" : " id=\"" + id + "-caption\"") + ">" +
         // A plot carries its own title: the caption only links its files.
         (extra_class == "plot" ? std::string() : Escape(image.caption)) + HtmlLinks(image.links) +
         "</figcaption></figure>\n";
}

std::string HtmlRgb(const Rgb& v, int decimals) {
  return HtmlNumber(v[0], decimals) + " / " + HtmlNumber(v[1], decimals) + " / " + HtmlNumber(v[2], decimals);
}

ReportImage Picture(std::string caption, std::string src, std::vector<std::pair<std::string, std::string>> links,
                    std::string href) {
  return {std::move(caption), std::move(src), std::move(links), std::move(href)};
}

std::string RenderRunReport(const RunReportPage& page) {
  std::string h = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" + Escape(page.title) +
                  "</title>\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<style>" +
                  kStyle + "</style>\n<script>" + kErrorCatcher + "</script>\n</head><body>\n";
  // One scene file, or a command's several ("a.json, b.json"); the command line always.
  const std::string scenes =
      page.scene_file.empty() ? ""
                              : (page.scene_file.find(", ") == std::string::npos ? "scene <code>" : "scenes <code>") +
                                    Escape(page.scene_file) + "</code> &middot; ";
  h += "<header><h1>" + Escape(page.title) + "</h1><p>" + Escape(page.description) + "</p><p>" + scenes + "<code>" +
       Escape(page.command) + "</code></p>\n<p id=\"version\">" + Escape(page.version) + "</p>\n<nav>";
  if (!page.summary.empty() || page.system) h += "<a href=\"#summary\">Summary</a>";
  h += "<a href=\"#steps\">Steps</a>";
  if (page.system) h += "<a href=\"#system\">Display system</a>";
  for (const ReportSection& section : page.sections) h += "<a href=\"#" + section.id + "\">" + section.title + "</a>";
  h += "</nav></header>\n<main>\n";
  h += "<pre id=\"selftest\" hidden></pre>\n";
  h += SummarySection(page);
  h += "<section id=\"steps\"><h2>Steps</h2><table><tr><th class=\"l\">step</th><th>wall time (s)</th></tr>\n";
  for (const auto& [step, seconds] : page.steps)
    h += "<tr><td class=\"l\">" + Escape(step) + "</td><td>" + F(seconds, 2) + "</td></tr>\n";
  h += "</table>\n";
  for (const std::string& w : page.warnings) h += "<p class=\"warn\">warning: " + Escape(w) + "</p>\n";
  h += "</section>\n";
  if (page.system) h += SystemSection(page);
  for (const ReportSection& section : page.sections) h += section.html;
  h += "</main>\n<script>" + std::string(kScript) + "</script>\n</body></html>\n";
  return h;
}

}  // namespace layerlab
