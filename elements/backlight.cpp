// backlight: the light source at the back of a panel stack (no outputs).
//
// | key       | type      | default  | meaning                          |
// |-----------|-----------|----------|----------------------------------|
// | luminance | luminance | required | "300 cd/m2"; a bare number is cd/m^2 |
// | coherence_width | length | 0 (incoherent) | the width over which the light at the panels is spatially coherent (a collimated or laser backlight): each diffraction order of a panel's pixel grid spreads over lambda / width (systems/panel_diffraction.h) |
#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"

namespace layerlab {
namespace {

std::unique_ptr<Element> MakeBacklight(Params& p) {
  double luminance = p.quantity("luminance", Dimension::kLuminance);
  p.require_range("luminance", luminance, 0.0, 1e7, true, false);
  const double coherence = p.quantity("coherence_width", Dimension::kLength, 0.0);
  p.require_range("coherence_width", coherence, 0.0, 1.0, false, false);
  return std::make_unique<BacklightElement>(luminance, coherence);
}

}  // namespace

ElementType BacklightType() { return {"backlight", ElementKind::kBacklight, "uniform white backlight", MakeBacklight}; }

}  // namespace layerlab
