// The exit status of every command (docs/cli.md, "Exit status"), and the
// error of a command line that cannot be run as written.
#pragma once

#include "layerlab/framework/error.h"

namespace layerlab::app {

enum ExitStatus : int {
  kExitDone = 0,
  kExitRefused = 1,       // an input (a file, a value) refused, with where and why
  kExitUsage = 2,         // the command line itself: an unknown command or option, a missing argument
  kExitInternal = 3,      // a fault of layerlab's own
  kExitInterrupted = 130  // Ctrl-C (SIGINT) or SIGTERM, after the last complete step was kept
};

// What each status means, for the man page and `layerlab help`.
struct ExitStatusMeaning {
  int status;
  const char* meaning;
};
inline constexpr ExitStatusMeaning kExitStatusMeanings[] = {
    {kExitDone, "done"},
    {kExitRefused, "an input was refused: a file, a value or a combination the message names, with where"},
    {kExitUsage, "the command line cannot be run as written: an unknown command or option, a missing argument"},
    {kExitInternal, "an internal error of layerlab (a bug: please report it with the command line)"},
    {kExitInterrupted, "interrupted (SIGINT or SIGTERM); what was complete is kept"}};

// A command line that cannot be run as written (exit 2): an unknown command,
// a renamed option, options that exclude each other.
class UsageError : public Error {
 public:
  using Error::Error;
};

}  // namespace layerlab::app
