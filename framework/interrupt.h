// Ctrl-C during a long run: the first SIGINT asks the work to stop at the
// next safe point (a solver between iterations), so the last complete
// outputs can be written; a second one ends the process at once.
#pragma once

#include "layerlab/framework/error.h"

namespace layerlab {

void InstallInterruptHandler();
bool Interrupted();  // a SIGINT arrived since InstallInterruptHandler()

// Thrown after the outputs of an interrupted run were written; the command
// line exits with 130 (128 + SIGINT), as shells expect.
class InterruptedError : public Error {
 public:
  using Error::Error;
};

}  // namespace layerlab
