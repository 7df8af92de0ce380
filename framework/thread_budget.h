// How many threads to run the next stretch of work on when other processes
// keep the cores busy: a team whose thread shares a core with a busy process
// waits at every barrier for the slice the scheduler gives that thread
// (milliseconds) while a region's work is a fraction of that; one thread
// per free core pays no such wait (docs/performance.md, "A busy machine").
#pragma once

#include <functional>

namespace layerlab {

// The runnable tasks of the machine that are not this process's: the
// runnable count of /proc/loadavg less this process's running threads
// (/proc/self/task/*/stat), at least 0; -1 where /proc cannot tell.
int OtherRunnableTasks();

// The threads for the next stretch of at most `parts` (>= 1): the cores this
// process may run on less the other runnable tasks, at least 1; `parts`
// where the load cannot be read. The load is read at most every
// kLoadCheckSeconds (per calling thread; about 30 us a read).
int ThreadsForLoad(int parts);
inline constexpr double kLoadCheckSeconds = 0.01;

// Tests replace ThreadsForLoad with a schedule of their own (nullptr: the load again).
void SetThreadBudgetForTesting(std::function<int(int parts)> budget);

}  // namespace layerlab
