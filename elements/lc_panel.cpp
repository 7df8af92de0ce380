// lc_panel: a transmissive liquid-crystal attenuator panel.
//
// | key               | type                 | default        | meaning                                      |
// |-------------------|----------------------|----------------|----------------------------------------------|
// | pixel_pitch       | length or [x, y]     | required       | "117 um"                                     |
// | resolution        | [cols, rows]         | required       | the whole panel                              |
// | active_region     | {cols, rows, left, top} | whole panel | the pixels the images use; left/top default to centered |
// | distance          | length               | one of three   | from the nearest lens or curved mirror in front of it (physical) |
// | virtual_depth     | depth                | one of three   | of its final image, from the eye ("0.4 D"); compile solves for the physical place |
// | gap               | length               | one of three   | path length from the element before it (the panel in front, a mirror, a lens) |
// | max_transmittance | fraction or [r,g,b]  | 0.3            | transmittance at full input                  |
// | gamma             | number               | 2.2            | transmittance = (input)^gamma                |
// | black_level       | fraction             | 0              | transmittance at input 0, relative to max ([r,g,b]: equal values) |
// | reversed          | boolean              | false          | mounted back to front (mirrored about its vertical axis) |
// | offset            | [length, length]     | [0, 0]         | lateral shift in the panel plane (eye-space x right, y up) |
// | rotation          | angle                | 0              | in-plane, counterclockwise as the eye sees it |
// | tilt              | [angle, angle]       | [0, 0]         | turned about x, then about y, through the active region's centre (as mounted off true); its rays are traced to the tilted plane |
// | polarization      | angle                | 0 deg          | axis of the exit polarizer, from eye-space x |
// | fill_factor       | fraction or [x, y]   | 1              | the open width of a pixel's aperture over its pitch (the black matrix is the rest): below 1 the grid diffracts the light of the layers behind it (systems/panel_diffraction.h) |
// | rise_time         | time                 | 0 s (instant)  | the liquid crystal's 10 to 90 % response to rising transmittance; a time-multiplexed display's light is the time average of what the panels show (systems/lc_response.h) |
// | fall_time         | time                 | rise_time      | the same for falling transmittance |
// | fixed_pattern     | path (OpenEXR)       | none (solved)  | a pattern the layer always shows instead of a solved one (a printed mask, a panel held at one image), relative to the scene file: the active region's size, channels R, G, B (or Y), linear transmittance relative to max_transmittance in [0, 1], in the panel's own pixel order |
// | next              | name                 | required       | the panel behind, or the backlight           |
#include <algorithm>
#include <cmath>
#include <memory>

#include "layerlab/elements/element.h"
#include "layerlab/elements/pattern_file.h"
#include "layerlab/elements/registry.h"

namespace layerlab {
namespace {

constexpr int64_t kMaxPixels = 1 << 15;

// The fixed pattern's file, relative to the scene file: the active region's size.
void ReadFixedPattern(Params& p, PanelSpec* s) {
  PatternFile file = ReadPatternFile(p, "fixed_pattern", "transmittance");
  if (file.cols != s->active_cols || file.rows != s->active_rows)
    p.fail("fixed_pattern", file.path + " is " + std::to_string(file.cols) + " x " + std::to_string(file.rows) +
                                " pixels; the panel's active region is " + std::to_string(s->active_cols) + " x " +
                                std::to_string(s->active_rows));
  s->fixed_pattern_file = file.name;
  s->fixed_pattern = std::move(file.rgb);
}

std::unique_ptr<Element> MakeLcPanel(Params& p) {
  PanelSpec s;
  auto pitch = p.quantity_pair("pixel_pitch", Dimension::kLength, {0.0, 0.0});
  if (!p.has("pixel_pitch")) p.raw("pixel_pitch");  // reports the missing key
  p.require_range("pixel_pitch", std::min(pitch[0], pitch[1]), 0.0, 0.01, true, false);
  p.require_range("pixel_pitch", std::max(pitch[0], pitch[1]), 0.0, 0.01, true, false);
  s.pitch_x_m = pitch[0];
  s.pitch_y_m = pitch[1];

  auto resolution = p.integer_pair("resolution", 1, kMaxPixels);
  s.resolution_cols = resolution[0];
  s.resolution_rows = resolution[1];
  s.active_cols = s.resolution_cols;
  s.active_rows = s.resolution_rows;
  p.mark_read("active_region");
  if (p.has("active_region")) {
    Params region = p.object("active_region");
    s.active_cols = region.integer("cols", 1, s.resolution_cols);
    s.active_rows = region.integer("rows", 1, s.resolution_rows);
    s.active_left =
        region.integer("left", 0, s.resolution_cols - s.active_cols, (s.resolution_cols - s.active_cols) / 2);
    s.active_top = region.integer("top", 0, s.resolution_rows - s.active_rows, (s.resolution_rows - s.active_rows) / 2);
    region.check_all_read();
  }

  s.distance_m = p.optional_quantity("distance", Dimension::kLength);
  s.virtual_depth = p.optional_depth("virtual_depth");
  if (s.distance_m && s.virtual_depth)
    p.fail("virtual_depth", "give either \"distance\" (from the lens) or \"virtual_depth\" (from the eye), not both");
  if (p.has("gap") && (s.distance_m || s.virtual_depth))
    p.fail("gap", std::string("give one placement: \"gap\" (from the element before) or \"") +
                      (s.distance_m ? "distance\" (from the lens)" : "virtual_depth\" (from the eye)") + ", not both");
  if (!s.distance_m && !s.virtual_depth && !p.has("gap"))
    p.fail("distance",
           "missing placement: give \"distance\" (from the lens, e.g. \"72.81 mm\") or "
           "\"virtual_depth\" (from the eye, e.g. \"0.4 D\")");
  if (s.distance_m && !(*s.distance_m > 0))
    p.fail("distance", "the panel must be behind the lens (distance > 0), got " + FormatFixed(*s.distance_m, 6) + " m");

  s.max_transmittance = p.fraction_rgb("max_transmittance", 0.3);
  for (double t : s.max_transmittance)
    if (!(t > 0)) p.fail("max_transmittance", "a panel that passes no light cannot show an image");
  s.gamma = p.quantity("gamma", Dimension::kFraction, s.gamma);
  p.require_range("gamma", s.gamma, 0.1, 10.0, false, false);
  // One black level for all channels is what the panel model (and the
  // panel-image encoding) holds: an [r, g, b] of different values is refused,
  // not cut to its red.
  const Rgb black = p.fraction_rgb("black_level", 0.0);
  if (black[1] != black[0] || black[2] != black[0])
    p.fail("black_level", "one value for all channels, got [" + FormatFixed(black[0], 4) + ", " +
                              FormatFixed(black[1], 4) + ", " + FormatFixed(black[2], 4) +
                              "] (a per-channel black level is not modelled)");
  s.black_level = black[0];
  if (s.black_level >= 1.0) p.fail("black_level", "must be below 1 (the panel's maximum)");
  s.reversed = p.boolean("reversed", false);
  s.eye_from_panel_m = p.quantity_pair("offset", Dimension::kLength, {0.0, 0.0});
  p.require_range("offset", std::abs(s.eye_from_panel_m[0]) + std::abs(s.eye_from_panel_m[1]), 0.0, 1.0, false, false);
  s.rotation_rad = p.quantity("rotation", Dimension::kAngle, 0.0);
  p.require_range("rotation", s.rotation_rad, -3.2, 3.2, false, false);
  s.tilt_rad = p.quantity_pair("tilt", Dimension::kAngle, {0.0, 0.0});
  for (double t : s.tilt_rad)
    if (!(std::abs(t) < 0.5)) p.fail("tilt", "at most 0.5 rad (28.6 deg) either way, about each axis");
  s.polarization_angle_rad = p.quantity("polarization", Dimension::kAngle, 0.0);
  s.fill_factor = p.quantity_pair("fill_factor", Dimension::kFraction, {1.0, 1.0});
  p.require_range("fill_factor", std::min(s.fill_factor[0], s.fill_factor[1]), 0.0, 1.0, true, false);
  p.require_range("fill_factor", std::max(s.fill_factor[0], s.fill_factor[1]), 0.0, 1.0, true, false);
  s.rise_time_s = p.quantity("rise_time", Dimension::kTime, 0.0);
  p.require_range("rise_time", s.rise_time_s, 0.0, 1.0, false, false);
  s.fall_time_s = p.quantity("fall_time", Dimension::kTime, s.rise_time_s);
  p.require_range("fall_time", s.fall_time_s, 0.0, 1.0, false, false);
  if (p.has("fixed_pattern")) ReadFixedPattern(p, &s);
  return std::make_unique<PanelElement>(s);
}

}  // namespace

ElementType LcPanelType() { return {"lc_panel", ElementKind::kPanel, "transmissive LC attenuator panel", MakeLcPanel}; }

}  // namespace layerlab
