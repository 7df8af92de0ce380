// world: what an optical see-through display shows behind its image, reached
// through a combiner's port (or any optics without power from one): natural,
// unpolarized light of one luminance (no outputs).
//
// | key       | type      | default  | meaning                          |
// |-----------|-----------|----------|----------------------------------|
// | luminance | luminance | required | the world's, "500 cd/m2" (an overcast day outdoors is about 2000, an office 100); a bare number is cd/m^2 |
//
// The eye sees it through the path's efficiency for unpolarized light, added
// to the display's light; the solve leaves it out (it shows what the display
// adds), the retinal images and the report add it (systems/world_view.h).
#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"

namespace layerlab {
namespace {

std::unique_ptr<Element> MakeWorld(Params& p) {
  const double luminance = p.quantity("luminance", Dimension::kLuminance);
  p.require_range("luminance", luminance, 0.0, 1e7, false, false);
  return std::make_unique<WorldElement>(luminance);
}

}  // namespace

ElementType WorldType() {
  return {"world", ElementKind::kWorld, "the world seen through a see-through combiner, of uniform luminance",
          MakeWorld};
}

}  // namespace layerlab
