// backlight: the light source at the back of a panel stack (no outputs).
//
// | key       | type      | default  | meaning                          |
// |-----------|-----------|----------|----------------------------------|
// | luminance | luminance | required | "300 cd/m2"; a bare number is cd/m^2; with a pattern, the luminance where it emits fully |
// | coherence_width | length | 0 (incoherent) | the width over which the light at the panels is spatially coherent (a collimated or laser backlight): each diffraction order of a panel's pixel grid spreads over lambda / width (systems/panel_diffraction.h) |
// | pattern   | {file, pixel_pitch} | none (uniform) | a fixed emission image: an OpenEXR beside the scene (R, G, B or Y, each in [0, 1] of the luminance), its pixels `pixel_pitch` apart (length or [x, y]), centred on the axis |
// | pinlights | {pitch, diameter, count} | none | a fixed array of count [cols, rows] round point sources `diameter` wide, `pitch` apart (length or [x, y]), centred on the axis: a pinlight display (Maimone et al. 2014) |
// | leds      | {pitch, count, spread_fwhm} | none | an array of count [cols, rows] LEDs `pitch` apart behind a diffuser that spreads each into a Gaussian of full width `spread_fwhm` at half maximum: a locally dimmed backlight, whose LED values are solved with the panels |
// | gap       | length    | required with a pattern | from the panel in front to the emitting plane (pattern, pinlights, leds only: a uniform backlight's place does not matter) |
//
// At most one of pattern, pinlights and leds. The emission is a layer at the
// backlight's plane, the farthest of its stack (docs/optics.md, "Sources").
#include <algorithm>
#include <cmath>
#include <string>

#include "layerlab/elements/element.h"
#include "layerlab/elements/pattern_file.h"
#include "layerlab/elements/registry.h"
#include "layerlab/framework/units.h"

namespace layerlab {
namespace {

// The most pixels along one side, and in all, of an emission layer.
constexpr int64_t kMaxSidePixels = 1 << 15;
constexpr int64_t kMaxEmissionPixels = int64_t(1) << 24;
// Pinlights are drawn with this many grid pixels across their diameter, each pixel's coverage from
// kCoverageSamples^2 points.
constexpr int kPixelsPerPinlight = 4;
constexpr int kCoverageSamples = 16;
// An LED's spread is sampled at least this finely (grid pixels per FWHM).
constexpr int kPixelsPerSpread = 4;
constexpr int kMaxLedStride = 33;
constexpr double kWidestSpreadInPitches = 16;

std::string Mm(double m, int decimals = 2) { return FormatFixed(m * 1e3, decimals) + " mm"; }

// The grid of an emission layer: an active region of cols x rows pixels of the given pitch, linear values.
// (The sides are doubles until checked: a pinlight far smaller than its pitch asks for more pixels than an
// integer holds.)
PanelSpec EmissionGrid(Params& p, const std::string& key, double pitch_x, double pitch_y, double cols_wanted,
                       double rows_wanted) {
  if (!(cols_wanted <= kMaxSidePixels && rows_wanted <= kMaxSidePixels &&
        cols_wanted * rows_wanted <= double(kMaxEmissionPixels)))
    p.fail(key, "its emission would need a grid of " + FormatFixed(cols_wanted, 0) + " x " +
                    FormatFixed(rows_wanted, 0) + " pixels; layerlab draws at most " + std::to_string(kMaxSidePixels) +
                    " per side and " + std::to_string(kMaxEmissionPixels) + " in all");
  const int64_t cols = static_cast<int64_t>(cols_wanted), rows = static_cast<int64_t>(rows_wanted);
  PanelSpec s;
  s.pitch_x_m = pitch_x;
  s.pitch_y_m = pitch_y;
  s.resolution_cols = s.active_cols = cols;
  s.resolution_rows = s.active_rows = rows;
  s.max_transmittance = {1, 1, 1};
  s.gamma = 1;  // an emission is written as linear drive values
  return s;
}

// A pitch in [1 um, max_m]: finer than any emitter's grid needs.
std::array<double, 2> PositivePitch(Params& q, const std::string& key, double max_m) {
  const std::array<double, 2> pitch = q.quantity_pair(key, Dimension::kLength, {0.0, 0.0});
  if (!q.has(key)) q.raw(key);  // reports the missing key
  for (double v : pitch) q.require_range(key, v, 1e-6, max_m, false, false);
  return pitch;
}

PanelSpec ImagePattern(Params& p) {
  Params q = p.object("pattern");
  const std::array<double, 2> pitch = PositivePitch(q, "pixel_pitch", 0.1);
  PatternFile file = ReadPatternFile(q, "file", "emission");
  q.check_all_read();
  PanelSpec s = EmissionGrid(p, "pattern", pitch[0], pitch[1], file.cols, file.rows);
  s.fixed_pattern = std::move(file.rgb);
  s.fixed_pattern_file = file.name;
  EmitterSpec e;
  e.kind = EmitterSpec::Kind::kImage;
  e.description = "the emission image " + file.name + " (" + std::to_string(file.cols) + " x " +
                  std::to_string(file.rows) + " pixels, " + Mm(pitch[0], 3) + " apart)";
  s.emitter = e;
  return s;
}

// The share of the pixel [x0, x0 + hx] x [y0, y0 + hy] covered by the disk of radius r centred at (cx, cy).
float DiskCoverage(double cx, double cy, double r, double x0, double y0, double hx, double hy) {
  int inside = 0;
  for (int a = 0; a < kCoverageSamples; ++a)
    for (int b = 0; b < kCoverageSamples; ++b) {
      const double x = x0 + (a + 0.5) * hx / kCoverageSamples - cx, y = y0 + (b + 0.5) * hy / kCoverageSamples - cy;
      inside += x * x + y * y <= r * r;
    }
  return static_cast<float>(inside) / (kCoverageSamples * kCoverageSamples);
}

PanelSpec Pinlights(Params& p) {
  Params q = p.object("pinlights");
  const std::array<double, 2> pitch = PositivePitch(q, "pitch", 0.1);
  const double diameter = q.quantity("diameter", Dimension::kLength);
  q.require_range("diameter", diameter, 0.0, std::min(pitch[0], pitch[1]), true, false);
  const std::array<int64_t, 2> count = q.integer_pair("count", 1, 10000);
  q.check_all_read();
  // Each cell of the array is a whole number of grid pixels, none wider than diameter / kPixelsPerPinlight.
  const double h_max = diameter / kPixelsPerPinlight;
  const double nx = std::ceil(pitch[0] / h_max - 1e-9), ny = std::ceil(pitch[1] / h_max - 1e-9);
  const double hx = pitch[0] / nx, hy = pitch[1] / ny;
  PanelSpec s = EmissionGrid(p, "pinlights", hx, hy, count[0] * nx, count[1] * ny);
  auto pattern = std::make_shared<std::vector<float>>(static_cast<size_t>(s.active_cols * s.active_rows) * 3, 0.0f);
  const double r = diameter / 2;
  // In the layer's own frame: x right from its left edge, y down from its top edge, m.
  for (int64_t i = 0; i < count[1]; ++i)
    for (int64_t j = 0; j < count[0]; ++j) {
      const double cx = (j + 0.5) * pitch[0], cy = (i + 0.5) * pitch[1];
      const int64_t c0 = std::max<int64_t>(0, static_cast<int64_t>(std::floor((cx - r) / hx)));
      const int64_t c1 = std::min<int64_t>(s.active_cols - 1, static_cast<int64_t>(std::floor((cx + r) / hx)));
      const int64_t r0 = std::max<int64_t>(0, static_cast<int64_t>(std::floor((cy - r) / hy)));
      const int64_t r1 = std::min<int64_t>(s.active_rows - 1, static_cast<int64_t>(std::floor((cy + r) / hy)));
      for (int64_t row = r0; row <= r1; ++row)
        for (int64_t col = c0; col <= c1; ++col) {
          const float v = DiskCoverage(cx, cy, r, col * hx, row * hy, hx, hy);
          for (int c = 0; c < 3; ++c) {  // a pixel two disks touch (diameter = pitch) keeps the larger share
            float& at = (*pattern)[static_cast<size_t>(row * s.active_cols + col) * 3 + c];
            at = std::max(at, v);
          }
        }
    }
  s.fixed_pattern = std::move(pattern);
  s.fixed_pattern_file = "its pinlight array";
  EmitterSpec e;
  e.kind = EmitterSpec::Kind::kPinlights;
  e.description = "an array of " + std::to_string(count[0]) + " x " + std::to_string(count[1]) + " pinlights " +
                  Mm(diameter, 3) + " wide, " + Mm(pitch[0]) + (pitch[1] != pitch[0] ? " x " + Mm(pitch[1]) : "") +
                  " apart, lighting " + FormatFixed(100 * std::acos(-1.0) * r * r / (pitch[0] * pitch[1]), 2) +
                  " % of their plane";
  s.emitter = e;
  return s;
}

PanelSpec Leds(Params& p) {
  Params q = p.object("leds");
  const std::array<double, 2> pitch = PositivePitch(q, "pitch", 0.1);
  const std::array<int64_t, 2> count = q.integer_pair("count", 1, 1000);
  const double fwhm = q.quantity("spread_fwhm", Dimension::kLength);
  const double narrowest = std::max(pitch[0], pitch[1]) * kPixelsPerSpread / kMaxLedStride;
  const double widest = kWidestSpreadInPitches * std::min(pitch[0], pitch[1]);
  if (!(fwhm >= narrowest && fwhm <= widest))
    q.fail("spread_fwhm", "must lie in " + Mm(narrowest, 3) + " to " + Mm(widest, 3) + ", got " + Mm(fwhm, 3) +
                              ": the grid draws an LED's spread with " + std::to_string(kPixelsPerSpread) +
                              " pixels across its FWHM and at most " + std::to_string(kMaxLedStride) +
                              " pixels per LED, and a spread over more than " + FormatFixed(kWidestSpreadInPitches, 0) +
                              " LEDs dims nothing locally");
  q.check_all_read();
  // An odd stride puts each LED on the centre pixel of its cell.
  int stride = static_cast<int>(std::ceil(std::max(pitch[0], pitch[1]) * kPixelsPerSpread / fwhm - 1e-9));
  stride = std::max(1, stride | 1);
  PanelSpec s = EmissionGrid(p, "leds", pitch[0] / stride, pitch[1] / stride, count[0] * stride, count[1] * stride);
  EmitterSpec e;
  e.kind = EmitterSpec::Kind::kLeds;
  e.led_stride = stride;
  e.led_cols = static_cast<int>(count[0]);
  e.led_rows = static_cast<int>(count[1]);
  e.spread_fwhm_m = fwhm;
  e.description = "an array of " + std::to_string(count[0]) + " x " + std::to_string(count[1]) + " LEDs " +
                  Mm(pitch[0]) + (pitch[1] != pitch[0] ? " x " + Mm(pitch[1]) : "") + " apart, each spread over " +
                  Mm(fwhm) + " (FWHM)";
  s.emitter = e;
  return s;
}

std::unique_ptr<Element> MakeBacklight(Params& p) {
  double luminance = p.quantity("luminance", Dimension::kLuminance);
  p.require_range("luminance", luminance, 0.0, 1e7, true, false);
  const double coherence = p.quantity("coherence_width", Dimension::kLength, 0.0);
  p.require_range("coherence_width", coherence, 0.0, 1.0, false, false);
  const char* kinds[] = {"pattern", "pinlights", "leds"};
  std::optional<PanelSpec> emission;
  std::string given;
  for (const char* kind : kinds) {
    if (!p.has(kind)) continue;
    if (!given.empty())
      p.fail(kind, "a backlight emits one pattern: give one of \"pattern\", \"pinlights\" and \"leds\", not both \"" +
                       given + "\" and \"" + kind + "\"");
    given = kind;
    emission = given == "pattern" ? ImagePattern(p) : given == "pinlights" ? Pinlights(p) : Leds(p);
  }
  if (emission && !p.has("gap"))
    p.fail(given, "a backlight's " + given + " lies at a place on the path: give its \"gap\" from the panel in front");
  if (!emission && p.has("gap"))
    p.fail("gap",
           "a uniform backlight's place does not change what the eye sees; \"gap\" places a \"pattern\", "
           "\"pinlights\" or \"leds\"");
  return std::make_unique<BacklightElement>(luminance, coherence, std::move(emission));
}

}  // namespace

ElementType BacklightType() {
  return {"backlight", ElementKind::kBacklight, "the light source behind a stack: uniform, an image, pinlights or LEDs",
          MakeBacklight};
}

}  // namespace layerlab
