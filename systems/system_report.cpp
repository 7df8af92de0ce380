#include "layerlab/systems/system_report.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <numbers>
#include <optional>

#include "layerlab/eye/eye_description.h"
#include "layerlab/framework/warnings.h"
#include "layerlab/systems/intermediate_images.h"
#include "layerlab/systems/lens_aberrations.h"
#include "layerlab/systems/world_view.h"

namespace layerlab {
namespace {

double Deg(double rad) { return rad * 180.0 / std::numbers::pi; }

std::string F(double v, int decimals) { return FormatFixed(v, decimals); }

std::string Rgb3(const Rgb& v, int decimals) {
  return F(v[0], decimals) + " " + F(v[1], decimals) + " " + F(v[2], decimals);
}

std::string Row(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string Row(const char* format, ...) {
  char buf[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buf, sizeof buf, format, args);
  va_end(args);
  return std::string(buf) + "\n";
}

std::string FlipName(const VirtualLayer& l) {
  if (l.flip_x && l.flip_y) return "x,y";
  if (l.flip_x) return "x";
  if (l.flip_y) return "y";
  return "-";
}

std::string Length(double meters) {
  if (std::isinf(meters)) return meters > 0 ? "infinity" : "-infinity";
  return F(meters * 1e3, 2) + " mm";
}

// Each branch's path, element by element (unfolded, positions from the pupil),
// with the image each panel forms after each lens or curved mirror.
std::string FormatOpticalPaths(const DisplaySystem& s) {
  std::string out = "\noptical paths (unfolded from the eye; position = path length from the pupil)\n";
  for (const Branch& b : s.branches) {
    const VirtualLayer& back = s.layers[b.layers.back()];
    out += "  branch \"" + b.name + "\"\n";
    std::optional<double> previous;
    auto element_row = [&](const std::string& what, std::optional<double> position, const std::string& detail) {
      std::string place = position ? Length(*position) : "(flat, unplaced)";
      std::string gap = position && previous ? "gap " + Length(*position - *previous) : "";
      out += Row("    %-34s %16s  %-14s %s", what.c_str(), place.c_str(), gap.c_str(), detail.c_str());
      if (position) previous = position;
    };
    element_row("eye \"" + s.eye_name + "\"", 0.0, "pupil");
    previous = 0.0;
    auto panel_row = [&](const VirtualLayer& l) {
      element_row((l.panel.emitter ? "backlight \"" : "panel \"") + l.name + "\"", l.position_m,
                  "image at " + F(l.diopters, 3) + " D");
    };
    for (const PathStep& step : back.path) {
      if (step.kind == ElementKind::kPanel) {
        for (int k : b.layers)
          if (s.layers[k].name == step.element) panel_row(s.layers[k]);
        continue;
      }
      std::string detail;
      if (step.power_diopters != 0)
        detail = "f " + Length(1.0 / step.power_diopters) + " (" + F(step.power_diopters, 2) + " D)";
      if (!step.port.empty()) detail += (detail.empty() ? "" : ", ") + std::string("port ") + step.port;
      if (step.flips_x || step.flips_y)
        detail += (detail.empty() ? "" : ", ") + std::string("mirrors ") + (step.flips_x ? "x" : "y");
      element_row(step.type + " \"" + step.element + "\"", step.position_m, detail);
    }
    panel_row(back);
    for (int k : b.layers) {
      const VirtualLayer& l = s.layers[k];
      std::string chain;
      for (const IntermediateImage& image : IntermediateImages(l))
        chain += (chain.empty() ? "" : "; ") + std::string("after \"") + image.after + "\" " +
                 (std::isinf(image.position_m) ? std::string("at infinity") : "at " + Length(image.position_m)) + " (" +
                 (image.real ? "real" : "virtual") + ", M " + F(image.magnification, 2) + ")";
      if (!chain.empty()) out += "    images of \"" + l.name + "\": " + chain + "\n";
    }
  }
  return out;
}

}  // namespace

nlohmann::json JsonNumber(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  return value;
}

double EveryLayerMaxCpd(const DisplaySystem& s) {
  double lowest = INFINITY;
  for (const VirtualLayer& l : s.layers)
    if (!l.panel.emitter) lowest = std::min(lowest, l.max_cpd);  // a backlight's grid is no image's
  return lowest == INFINITY ? 0 : lowest;
}

// Behind real lenses: what each layer's lens does at its field edge (lens_aberrations.h).
std::string FormatAberrations(const DisplaySystem& s) {
  if (std::none_of(s.layers.begin(), s.layers.end(), [](const VirtualLayer& l) { return l.ray_map != nullptr; }))
    return "";
  std::string out =
      "\nmapped layers (real lenses, tilted panels), each at its field edge (the chief ray; the focus from rays "
      "through the pupil's edge)\n";
  out += Row("%-3s %-12s %9s %11s %18s %22s %16s %10s", "#", "panel", "edge", "distortion", "lateral color R-B",
             "focus tan. / sag.", "field curvature", "map bound");
  out += Row("%-3s %-12s %9s %11s %18s %22s %16s %10s", "", "", "(deg)", "(%)", "(px / arcmin)", "(D)", "(D)", "(px)");
  for (size_t k = 0; k < s.layers.size(); ++k) {
    const VirtualLayer& l = s.layers[k];
    if (!l.ray_map) continue;
    const LayerAberrations a = MeasureAberrations(l, s.eye.pupil_diameter_m);
    out += Row("%-3zu %-12s %9s %11s %18s %22s %16s %10s", k, l.name.c_str(), F(a.field_edge_deg, 2).c_str(),
               F(a.distortion_percent, 2).c_str(),
               (F(a.lateral_color_px, 2) + " / " + F(a.lateral_color_arcmin, 2)).c_str(),
               (F(a.tangential_diopters, 3) + " / " + F(a.sagittal_diopters, 3)).c_str(),
               F(a.field_curvature_diopters, 3).c_str(), F(a.map_bound_px, 4).c_str());
  }
  return out;
}

namespace {

// The worlds a see-through display is seen against, and its full white's contrast against them.
std::string FormatSeeThrough(const DisplaySystem& s) {
  if (s.worlds.empty()) return "";
  std::string out = "\nsee-through (the world's light added at the eye; the solve leaves it out)\n";
  for (const WorldView& w : s.worlds) {
    Rgb at_eye;
    for (int c = 0; c < 3; ++c) at_eye[c] = w.luminance_cd_m2 * w.efficiency[c];
    out += Row("  world %-16s through %-20s %s cd/m2 x efficiency %s = %s cd/m2 at the eye",
               ("\"" + w.element + "\"").c_str(), w.name.c_str(), F(w.luminance_cd_m2, 1).c_str(),
               Rgb3(w.efficiency, 4).c_str(), Rgb3(at_eye, 2).c_str());
    if (!w.scene_file.empty())
      out += "    its scene " + w.scene_file + " (radiance 1: the luminance above), traced for the retinal images\n";
  }
  out += Row("  ambient contrast       %s: the display's full white over the world, (%s + %s) / %s cd/m2",
             F(AmbientContrastRatio(s), 3).c_str(), F(LuminanceOf(s.peak_luminance_cd_m2), 2).c_str(),
             F(LuminanceOf(WorldAtEye(s)), 2).c_str(), F(LuminanceOf(WorldAtEye(s)), 2).c_str());
  return out;
}

// A folded path's ghosts: each stack seen again by another route, its depths and its light against the branch's.
std::string FormatGhosts(const DisplaySystem& s) {
  if (s.ghosts.empty()) return "";
  std::string out =
      "\nghosts (the same patterns seen by another route of a folded path; added in the retinal images, "
      "left out of the solve)\n";
  for (const Ghost& g : s.ghosts) {
    const Branch& b = s.branches[g.branch];
    std::string depths;
    for (const VirtualLayer& l : g.layers) depths += (depths.empty() ? "" : ", ") + F(l.diopters, 3);
    Rgb relative;
    for (int c = 0; c < 3; ++c) relative[c] = b.efficiency[c] > 0 ? g.efficiency[c] / b.efficiency[c] : 0;
    out += Row("  of %-20s by %s", ("\"" + b.name + "\"").c_str(), g.name.c_str());
    out += Row("    at %s D (the branch's at its own depths), efficiency %s = %s of the branch's", depths.c_str(),
               Rgb3(g.efficiency, 5).c_str(), Rgb3(relative, 4).c_str());
  }
  return out;
}

nlohmann::json GhostsToJson(const DisplaySystem& s) {
  nlohmann::json ghosts = nlohmann::json::array();
  for (const Ghost& g : s.ghosts) {
    std::vector<double> diopters;
    for (const VirtualLayer& l : g.layers) diopters.push_back(l.diopters);
    ghosts.push_back({{"branch", g.branch},
                      {"route", g.name},
                      {"layer_diopters", diopters},
                      {"optics_efficiency_rgb", g.optics_efficiency},
                      {"efficiency_rgb", g.efficiency}});
  }
  return ghosts;
}

// The virtual layers, farthest first, and which of them show a fixed pattern.
std::string FormatLayerTable(const DisplaySystem& s) {
  std::string out;
  out += "\nvirtual layers (farthest first; depth from the eye, distance from the nearest lens in front)\n";
  out += Row("%-3s %-12s %-24s %8s %9s %10s %8s %10s %11s %15s %7s %5s", "#", "panel", "branch", "depth", "depth",
             "distance", "magnif.", "pixel", "pixels", "field of view", "max f", "flip");
  out += Row("%-3s %-12s %-24s %8s %9s %10s %8s %10s %11s %15s %7s %5s", "", "", "", "(D)", "(m)", "(mm)", "", "(mm)",
             "", "(deg)", "(cpd)", "");
  for (size_t k = 0; k < s.layers.size(); ++k) {
    const VirtualLayer& l = s.layers[k];
    std::string pixels = std::to_string(l.cols) + " x " + std::to_string(l.rows);
    std::string fov = F(Deg(l.fov_x_rad), 2) + " x " + F(Deg(l.fov_y_rad), 2);
    out += Row("%-3zu %-12s %-24s %8s %9s %10s %8s %10s %11s %15s %7s %5s", k, l.name.c_str(),
               s.branches[l.branch].name.c_str(), F(l.diopters, 3).c_str(), F(l.depth_m, 4).c_str(),
               F(l.panel_distance_m * 1e3, 2).c_str(), F(l.magnification, 2).c_str(), F(l.pitch_x_m * 1e3, 3).c_str(),
               pixels.c_str(), fov.c_str(), F(l.max_cpd, 2).c_str(), FlipName(l).c_str());
  }
  for (size_t k = 0; k < s.layers.size(); ++k) {
    const PanelSpec& panel = s.layers[k].panel;
    if (panel.emitter)
      out +=
          Row("%-3zu %s emits %s%s", k, s.layers[k].name.c_str(), panel.emitter->description.c_str(),
              panel.emitter->solved() ? ": their values are solved with the panels" : ": the solve leaves it as it is");
    else if (panel.fixed_pattern)
      out += Row("%-3zu %s shows a fixed pattern, %s: the solve leaves it as it is", k, s.layers[k].name.c_str(),
                 panel.fixed_pattern_file.c_str());
  }

  return out;
}

}  // namespace

std::string FormatSystemTable(const DisplaySystem& s) {
  const EyeModel& eye = s.eye;
  std::string out;
  out += s.file + (s.name.empty() ? "" : ": " + s.name) + "\n\n";
  const std::string relief = s.lens.empty() ? "" : "; eye relief " + F(eye.eye_relief_m * 1e3, 2) + " mm";
  out +=
      Row("eye      pupil %s mm %s, %d x %d samples%s; eyebox %s x %s mm, %d x %d views;\n"
          "         accommodation %s to %s D",
          F(eye.pupil_diameter_m * 1e3, 2).c_str(), eye.pupil_shape == PupilShape::kSquare ? "square" : "round",
          eye.pupil_samples_x, eye.pupil_samples_y, relief.c_str(), F(eye.eyebox_width_m * 1e3, 2).c_str(),
          F(eye.eyebox_height_m * 1e3, 2).c_str(), eye.views_x, eye.views_y,
          F(eye.accommodation_min_diopters, 2).c_str(), F(eye.accommodation_max_diopters, 2).c_str());
  out += Row("         %s", EyeModelLine(eye).c_str());
  if (eye.binocular) {  // the vergence-accommodation conflict if the eye accommodated to each layer
    std::string conflicts;
    for (const VirtualLayer& l : s.layers)
      conflicts += (conflicts.empty() ? "" : ", ") + l.name + " " + F(VergenceDiopters(*eye.binocular) - l.diopters, 3);
    out += Row("         vergence-accommodation conflict (D) accommodated to each layer: %s", conflicts.c_str());
  }
  if (s.subframes > 1)
    out += Row("time     %d subframes per frame at %s Hz: the panels refresh at %s Hz; the eye sees the mean",
               s.subframes, F(s.frame_rate_hz, 1).c_str(), F(s.subframes * s.frame_rate_hz, 1).c_str());
  if (!s.lens.empty()) {
    std::string aperture = "clear aperture unlimited";
    if (s.clear_aperture_m)
      aperture = "clear aperture " + F(*s.clear_aperture_m * 1e3, 2) + " mm (vignetting-free field " +
                 F(Deg(*s.vignetting_free_fov_x_rad), 1) + " x " + F(Deg(*s.vignetting_free_fov_y_rad), 1) + " deg)";
    out += Row("lens     \"%s\": focal length %s mm, %s", s.lens.c_str(), F(s.focal_length_m * 1e3, 2).c_str(),
               aperture.c_str());
  }
  out += FormatOpticalPaths(s);
  out += FormatLayerTable(s);
  out += FormatAberrations(s);

  out += "\nbranches (added at the eye; each the product of its layers, nearest the eye first)\n";
  out += Row("%-3s %-24s %-10s %-22s %-22s %-12s %10s", "#", "name", "layers", "optics eff. (R G B)",
             "efficiency (R G B)", "backlight", "(cd/m2)");
  for (size_t b = 0; b < s.branches.size(); ++b) {
    const Branch& br = s.branches[b];
    std::string layers;
    for (int k : br.layers) {
      if (!layers.empty()) layers += ',';
      layers += std::to_string(k);
    }
    out += Row("%-3zu %-24s %-10s %-22s %-22s %-12s %10s", b, br.name.c_str(), layers.c_str(),
               Rgb3(br.optics_efficiency, 4).c_str(), Rgb3(br.efficiency, 4).c_str(), br.backlight.c_str(),
               F(br.backlight_luminance_cd_m2, 1).c_str());
  }
  out += FormatGhosts(s);
  out += FormatSeeThrough(s);

  out += "\nsystem\n";
  out += Row("  field of view          %s x %s deg (the smallest layer's, Eq. 2)", F(Deg(s.fov_x_rad), 2).c_str(),
             F(Deg(s.fov_y_rad), 2).c_str());
  out +=
      Row("  highest frequency      %s cpd on every layer (the coarsest layer's Nyquist); %s cpd on the finest layer "
          "(both at the layer's center)",
          F(EveryLayerMaxCpd(s), 2).c_str(), F(s.max_cpd, 2).c_str());
  out += Row("  peak luminance         %s cd/m2 (R G B, full white on every panel)",
             Rgb3(s.peak_luminance_cd_m2, 2).c_str());
  out += Row("  brightness efficiency  %s (luminance-weighted; R G B %s): light at the eye / light the backlights emit",
             F(s.luminance_efficiency, 4).c_str(), Rgb3(s.brightness_efficiency, 4).c_str());
  out += "  components             ";
  for (size_t i = 0; i < s.components.size(); ++i) out += (i ? "\n                         " : "") + s.components[i];
  out += "\n";
  out += WarningLines(s.warnings);
  return out;
}

nlohmann::json SystemToJson(const DisplaySystem& s) {
  using nlohmann::json;
  const EyeModel& eye = s.eye;
  json j;
  j["file"] = s.file;
  j["name"] = s.name;
  j["eye"] = {{"pupil_diameter_m", eye.pupil_diameter_m},
              {"pupil_shape", eye.pupil_shape == PupilShape::kSquare ? "square" : "round"},
              {"pupil_samples", {eye.pupil_samples_x, eye.pupil_samples_y}},
              {"eye_relief_m", eye.eye_relief_m},
              {"eyebox_m", {eye.eyebox_width_m, eye.eyebox_height_m}},
              {"views", {eye.views_x, eye.views_y}},
              {"accommodation_range_D", {eye.accommodation_min_diopters, eye.accommodation_max_diopters}},
              {"model", EyeModelLine(eye)}};
  j["lens"] = {{"name", s.lens},
               {"focal_length_m", s.focal_length_m},
               {"clear_aperture_m", s.clear_aperture_m ? json(*s.clear_aperture_m) : json(nullptr)}};
  for (const VirtualLayer& l : s.layers) {
    j["layers"].push_back({{"name", l.name},
                           {"element", l.element},
                           {"subframe", l.subframe},
                           {"branch", l.branch},
                           {"position_in_branch", l.position_in_branch},
                           {"diopters", l.diopters},
                           {"depth_m", JsonNumber(l.depth_m)},
                           {"panel_distance_m", l.panel_distance_m},
                           {"magnification", JsonNumber(l.magnification)},
                           {"pixel_pitch_m", {JsonNumber(l.pitch_x_m), JsonNumber(l.pitch_y_m)}},
                           {"tan_pitch", {l.tan_pitch_x, l.tan_pitch_y}},
                           {"pixels", {l.cols, l.rows}},
                           {"offset_tan", {l.eye_from_layer_tan_x, l.eye_from_layer_tan_y}},
                           {"rotation_rad", l.rotation_rad},
                           {"flip", {l.flip_x, l.flip_y}},
                           {"fov_deg", {Deg(l.fov_x_rad), Deg(l.fov_y_rad)}},
                           {"max_cpd", l.max_cpd}});
    if (l.ray_map) {
      const LayerAberrations a = MeasureAberrations(l, s.eye.pupil_diameter_m);
      j["layers"].back()["real_lens"] = {{"field_edge_deg", a.field_edge_deg},
                                         {"distortion_percent", a.distortion_percent},
                                         {"lateral_color_px", a.lateral_color_px},
                                         {"lateral_color_arcmin", a.lateral_color_arcmin},
                                         {"focus_tangential_D", a.tangential_diopters},
                                         {"focus_sagittal_D", a.sagittal_diopters},
                                         {"field_curvature_D", a.field_curvature_diopters},
                                         {"ray_map_bound_px", a.map_bound_px}};
    }
  }
  for (const Branch& b : s.branches)
    j["branches"].push_back({{"name", b.name},
                             {"layers", b.layers},
                             {"optics_efficiency_rgb", b.optics_efficiency},
                             {"efficiency_rgb", b.efficiency},
                             {"backlight", b.backlight},
                             {"backlight_luminance_cd_m2", b.backlight_luminance_cd_m2}});
  for (const WorldView& w : s.worlds)
    j["worlds"].push_back({{"element", w.element},
                           {"path", w.name},
                           {"luminance_cd_m2", w.luminance_cd_m2},
                           {"efficiency_rgb", w.efficiency}});
  if (!s.worlds.empty()) j["ambient_contrast_ratio"] = AmbientContrastRatio(s);
  if (!s.ghosts.empty()) j["ghosts"] = GhostsToJson(s);
  j["subframes"] = s.subframes;
  j["frame_rate_hz"] = s.frame_rate_hz;
  j["panel_refresh_rate_hz"] = s.subframes * s.frame_rate_hz;
  j["fov_deg"] = {Deg(s.fov_x_rad), Deg(s.fov_y_rad)};
  j["max_cpd"] = s.max_cpd;  // the finest layer's
  j["max_cpd_every_layer"] = EveryLayerMaxCpd(s);
  if (s.vignetting_free_fov_x_rad)
    j["vignetting_free_fov_deg"] = {Deg(*s.vignetting_free_fov_x_rad), Deg(*s.vignetting_free_fov_y_rad)};
  j["peak_luminance_cd_m2_rgb"] = s.peak_luminance_cd_m2;
  j["brightness_efficiency_rgb"] = s.brightness_efficiency;
  j["brightness_efficiency"] = s.luminance_efficiency;
  j["polarization_tracked"] = s.polarization_tracked;
  j["components"] = s.components;
  j["warnings"] = s.warnings;
  return j;
}

}  // namespace layerlab

namespace layerlab {

std::vector<LayerCoverage> Coverage(const DisplayModel& model) {
  std::vector<LayerCoverage> out;
  for (size_t k = 0; k < model.layer_count(); ++k) {
    std::vector<uint8_t> reached = model.projection(k).ReachedPixels();
    out.push_back({model.system().layers[k].name, static_cast<size_t>(std::count(reached.begin(), reached.end(), 1)),
                   reached.size()});
  }
  return out;
}

std::string FormatCoverage(const DisplayModel& model, const std::vector<LayerCoverage>& coverage) {
  const LightFieldGeometry& g = model.geometry();
  std::string out = "\nlight field\n";
  out += Row("  %d x %d views over %s x %s mm, %d x %d pixels each, origin plane %s D (%s m): %s M rays", g.views_x,
             g.views_y, F(g.eyebox_width_m * 1e3, 2).c_str(), F(g.eyebox_height_m * 1e3, 2).c_str(), g.cols, g.rows,
             F(1 / g.origin_z_m, 3).c_str(), F(g.origin_z_m, 4).c_str(), F(g.ray_count() / 1e6, 2).c_str());
  out += Row("  window on the origin plane %s x %s mm, top left (%s, %s) mm", F(g.window_width_m * 1e3, 2).c_str(),
             F(g.window_height_m * 1e3, 2).c_str(), F(g.window_left_m * 1e3, 2).c_str(),
             F(g.window_top_m * 1e3, 2).c_str());
  out += "\nlayer pixels some ray reads (solvers touch only these)\n";
  out += Row("%-3s %-12s %10s %10s %8s", "#", "panel", "reached", "pixels", "share");
  for (size_t k = 0; k < coverage.size(); ++k)
    out += Row("%-3zu %-12s %10zu %10zu %7s%%", k, coverage[k].name.c_str(), coverage[k].reached, coverage[k].total,
               F(100.0 * coverage[k].reached / coverage[k].total, 1).c_str());
  return out;
}

nlohmann::json CoverageToJson(const DisplayModel& model, const std::vector<LayerCoverage>& coverage) {
  const LightFieldGeometry& g = model.geometry();
  nlohmann::json j;
  j["light_field"] = {{"origin_plane_z_m", g.origin_z_m},
                      {"window_m",
                       {{"left", g.window_left_m},
                        {"top", g.window_top_m},
                        {"width", g.window_width_m},
                        {"height", g.window_height_m}}},
                      {"pixels", {g.cols, g.rows}},
                      {"views", {g.views_x, g.views_y}},
                      {"eyebox_m", {g.eyebox_width_m, g.eyebox_height_m}},
                      {"rays", g.ray_count()}};
  for (const LayerCoverage& c : coverage)
    j["layer_coverage"].push_back({{"name", c.name}, {"reached_pixels", c.reached}, {"pixels", c.total}});
  return j;
}

}  // namespace layerlab
