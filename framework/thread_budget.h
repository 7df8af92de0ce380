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

// This process's CPU time (s, all threads); -1 where it cannot be read.
double ProcessCpuSeconds();

// The threads for the next stretch of at most `parts` (>= 1): the cores this
// process may run on less the other runnable tasks, at least 1; `parts`
// where the load cannot be read. The load is read at most every
// kLoadCheckSeconds (per calling thread; about 30 us a read), and the smaller
// of the last two readings counts, so that a task runnable for an instant
// does not take a thread away.
int ThreadsForLoad(int parts);
inline constexpr double kLoadCheckSeconds = 0.01;

// Tests replace the choice (ThreadsForLoad and IterationThreads) with a schedule of their own (nullptr: the
// load and the timings again).
void SetThreadBudgetForTesting(std::function<int(int parts)> budget);

// The threads of each iteration of a loop: the load's count, or one thread
// where iterations timed on one thread ran faster. A core can be shared with
// work this process cannot see (another virtual machine on the host): a team
// then waits at every barrier as it does under a visible load, while no task
// shows in /proc. An iteration now and then runs on the other choice, so
// that both stay timed, as long as a team of more threads was kept waiting
// (it ran less CPU time than its threads x wall time; kBusyTeam): once
// early, then kProbeEvery iterations on, the
// interval doubling (up to kProbeEveryMost) while probes confirm the team
// and back to kProbeEvery when one overturns it; while one thread is
// preferred, the team is probed every kProbeEvery iterations. A probe's iteration times
// its choice afresh; the choice in use keeps a running mean. The choice
// never changes a result (framework/fixed_parts.h), only how long it takes.
class IterationThreads {
 public:
  static constexpr int kProbeEvery = 16, kProbeEveryMost = 256;
  // A team whose threads ran at least this share of its wall time (CPU time over threads x wall time) is
  // not waiting on a shared core: one thread is then not probed.
  static constexpr double kBusyTeam = 0.85;
  static constexpr double kSmoothing = 0.3;  // weight of the newest iteration in the mean of the choice in use

  // `load`: the count the load allows (ThreadsForLoad, or a test's).
  explicit IterationThreads(int parts, std::function<int(int parts)> load = ThreadsForLoad);
  // The threads of the next iteration, given the seconds of the iteration just run and the CPU seconds this
  // process spent in it (negative: not measured).
  int Next(double last_seconds, double last_cpu_seconds = -1);

 private:
  int parts_;
  std::function<int(int)> load_;
  int running_ = 0;                   // the threads of the iteration under way (0: none yet)
  bool probing_ = false;              // the iteration under way runs on the choice not preferred
  double seconds_[2] = {-1.0, -1.0};  // seconds per iteration: [0] on the load's count, [1] on one thread
  int since_probe_ = 0, probe_every_ = kProbeEvery;
  double busy_ = -1;  // the last timed team's CPU time over its threads x wall time (-1: unknown)
};

}  // namespace layerlab
