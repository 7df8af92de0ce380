// A pool of child processes on this machine: the runner of `sweep --local` and
// `optimize --local`, where each job or start is this executable run again,
// so that one that crashes or is killed takes only itself down.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace layerlab::app {

// This executable, for the pool's children and the Slurm scripts.
std::string SelfExecutable();

// Runs each command (its argv; argv[0] is the executable's path) as a child
// process, at most `processes` at a time (posix_spawn), and calls
// `ended(i, status)` with command i's wait status as it ends. After an
// interrupt (framework/interrupt.h) no more commands start; the running ones
// are waited for. Throws layerlab::Error when a child cannot be started.
// Whether a child's wait status says it ended on Ctrl-C: killed by SIGINT, or
// exited with kExitInterrupted after keeping what was complete (app/exit_status.h).
bool EndedByInterrupt(int status);

void RunProcessPool(const std::vector<std::vector<std::string>>& commands, int processes,
                    const std::function<void(size_t, int)>& ended);

}  // namespace layerlab::app
