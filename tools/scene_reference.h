// docs/scene-reference.md, made from the key tables (tools/key_tables.h) of
// the scene reader, the element registry, each built-in element type and the
// depth_range reader, and the sections made from option tables: solve
// (solvers/solver_option_table.h), run, run.retina, run.compare
// (analysis/run_option_table.h) and run.contrast
// (analysis/contrast_option_table.h).
#pragma once

#include <string>
#include <vector>

#include "layerlab/tools/key_tables.h"

namespace layerlab {

// In the document's order: scene, element, the element types (by name), solve,
// run, run.retina, run.contrast, run.compare, depth_range. Throws
// layerlab::Error when a source file lacks its table.
std::vector<KeyTable> SceneReferenceTables(const std::string& source_dir);

std::string SceneReferenceMarkdown(const std::string& source_dir);

}  // namespace layerlab
