// backlight: the light source at the back of a panel stack (no outputs).
//
// | key       | type      | default  | meaning                          |
// |-----------|-----------|----------|----------------------------------|
// | luminance | luminance | required | "300 cd/m2"; a bare number is cd/m^2 |
#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"

namespace layerlab {
namespace {

std::unique_ptr<Element> MakeBacklight(Params& p) {
  double luminance = p.quantity("luminance", Dimension::kLuminance);
  p.require_range("luminance", luminance, 0.0, 1e7, true, false);
  return std::make_unique<BacklightElement>(luminance);
}

}  // namespace

ElementType BacklightType() { return {"backlight", ElementKind::kBacklight, "uniform white backlight", MakeBacklight}; }

}  // namespace layerlab
