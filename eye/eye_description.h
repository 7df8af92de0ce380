// The eye model in one line of text, for reports and the command line.
#pragma once

#include <string>

#include "layerlab/elements/element.h"

namespace layerlab {

// The eye model in one line, for info and the reports: "ideal eye: ..." or "physiological eye: ...".
std::string EyeModelLine(const EyeModel& eye);

}  // namespace layerlab
