// The options of the scene's "run" section, described once, a table per
// struct: "run" (RunConfig), "run.retina" (RetinaRunConfig), "run.compare"
// (CompareRunConfig) and "run.frames" (FramesRunConfig); "run.contrast" is the contrast option table's
// (analysis/contrast_option_table.h). The section's reader
// (analysis/run_config.cpp), the structs' IsValid and docs/scene-reference.md
// are made from them; tests/run_option_table_test.cpp and
// reference_tests fail when one of them disagrees. The run section has no
// flags or Python keywords of its own: `layerlab run` and Python's run() take
// a scene (their --iterations and --threads are the solver option table's).
#pragma once

#include <string>
#include <vector>

#include "layerlab/analysis/run_options.h"
#include "layerlab/framework/option_table.h"

namespace layerlab {

using RunOptionEntry = OptionEntry<RunConfig>;
using RetinaRunOptionEntry = OptionEntry<RetinaRunConfig>;
using CompareRunOptionEntry = OptionEntry<CompareRunConfig>;
using FramesRunOptionEntry = OptionEntry<FramesRunConfig>;

const std::vector<RunOptionEntry>& RunOptionTable();
const std::vector<RetinaRunOptionEntry>& RetinaRunOptionTable();
const std::vector<CompareRunOptionEntry>& CompareRunOptionTable();
const std::vector<FramesRunOptionEntry>& FramesRunOptionTable();

// The entry of `key` in its table; throws layerlab::Error when there is none.
const RetinaRunOptionEntry& RetinaRunOption(const std::string& key);
const CompareRunOptionEntry& CompareRunOption(const std::string& key);

}  // namespace layerlab
