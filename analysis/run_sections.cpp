#include "layerlab/analysis/run_steps.h"

// Each section, in the order it runs and the page shows it: NameRunSection()
// is defined in its own file (analysis/run_<name>_section.cpp).
#define LAYERLAB_RUN_SECTIONS(X) X(Target) X(Solve) X(Retina) X(Contrast) X(Compare) X(Frames)

namespace layerlab {

#define LAYERLAB_DECLARE(name) RunSection name##RunSection();
LAYERLAB_RUN_SECTIONS(LAYERLAB_DECLARE)
#undef LAYERLAB_DECLARE

const std::vector<RunSection>& RunSections() {
#define LAYERLAB_LIST(name) name##RunSection(),
  static const std::vector<RunSection> sections = {LAYERLAB_RUN_SECTIONS(LAYERLAB_LIST)};
#undef LAYERLAB_LIST
  return sections;
}

}  // namespace layerlab
