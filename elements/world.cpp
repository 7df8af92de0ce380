// world: what an optical see-through display shows behind its image, reached
// through a combiner's port (or any optics without power from one): natural,
// unpolarized light of one luminance (no outputs).
//
// | key       | type      | default  | meaning                          |
// |-----------|-----------|----------|----------------------------------|
// | luminance | luminance | required | the world's, "500 cd/m2" (an overcast day outdoors is about 2000, an office 100); a bare number is cd/m^2; with a scene, its radiance 1 |
// | scene     | path      | none (uniform) | a target scene (docs/target-format.md) beside the scene file, traced ray by ray for the retinal images: what the world shows, 1 = luminance |
//
// The eye sees it through the path's efficiency for unpolarized light, added
// to the display's light; the solve leaves it out (it shows what the display
// adds), the retinal images and the report add it (systems/world_view.h).
#include <filesystem>

#include "layerlab/elements/element.h"
#include "layerlab/elements/registry.h"

namespace layerlab {
namespace {

std::unique_ptr<Element> MakeWorld(Params& p) {
  const double luminance = p.quantity("luminance", Dimension::kLuminance);
  p.require_range("luminance", luminance, 0.0, 1e7, true, false);
  std::string scene;
  if (p.has("scene")) {
    scene = (std::filesystem::path(p.where().file).parent_path() / p.string("scene")).string();
    if (!std::filesystem::is_regular_file(scene)) p.fail("scene", "no such file: " + scene);
  }
  return std::make_unique<WorldElement>(luminance, std::move(scene));
}

}  // namespace

ElementType WorldType() {
  return {"world", ElementKind::kWorld, "the world seen through a see-through combiner, of uniform luminance",
          MakeWorld};
}

}  // namespace layerlab
