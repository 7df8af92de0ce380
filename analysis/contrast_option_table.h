// Every option of the contrast sweep (ContrastOptions, analysis/contrast.h),
// described once: its key in a run section's "contrast" object, type, unit,
// range, default, meaning, `layerlab contrast` flag and keyword of Python's
// contrast(). The "run.contrast" reader (analysis/run_config.cpp),
// ContrastOptions::IsValid, the command's flags (app/cmd_contrast.cpp),
// Python's keywords and docstring (python/src/analysis.cpp) and
// docs/scene-reference.md are made from it; tests/contrast_option_table_test.cpp,
// tests/cli/option_table_flags.py and python/tests/test_option_tables.py fail
// when one of them disagrees with it.
#pragma once

#include <string>
#include <vector>

#include "layerlab/analysis/contrast.h"
#include "layerlab/framework/option_table.h"

namespace layerlab {

using ContrastOptionEntry = OptionEntry<ContrastOptions>;

// In the reference's order: the scene's keys, then the options it does not set.
const std::vector<ContrastOptionEntry>& ContrastOptionTable();
// The entry of `key`, or nullptr.
const ContrastOptionEntry* FindContrastOption(const std::string& key);

}  // namespace layerlab
