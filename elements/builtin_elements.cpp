#include "layerlab/elements/registry.h"

namespace layerlab {

#define LAYERLAB_ELEMENT(Name) ElementType Name##Type();
#include "layerlab/elements/builtin_elements.def"
#undef LAYERLAB_ELEMENT

ElementRegistry ElementRegistry::WithBuiltins() {
  ElementRegistry registry;
#define LAYERLAB_ELEMENT(Name) registry.add(Name##Type());
#include "layerlab/elements/builtin_elements.def"
#undef LAYERLAB_ELEMENT
  return registry;
}

}  // namespace layerlab
