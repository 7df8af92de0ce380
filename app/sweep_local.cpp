// The process pool of `layerlab sweep --local -j N`: each job is this
// executable run again with --job, so that a job that crashes or is killed
// takes only itself down, and its job.json says what happened.
#include <sys/wait.h>

#include <csignal>
#include <cstdio>

#include "layerlab/app/process_pool.h"
#include "layerlab/app/sweep_runners.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/interrupt.h"

namespace layerlab::app {

size_t RunSweepLocally(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out,
                       int processes) {
  InstallInterruptHandler();
  const std::string exe = SelfExecutable();
  std::vector<const SweepJob*> todo;
  std::vector<std::vector<std::string>> commands;
  size_t skipped = 0, failed = 0;
  for (const SweepJob& job : jobs) {
    if (ReadJobState(out, job).complete) {
      ++skipped;
    } else {
      todo.push_back(&job);
      commands.push_back({exe, "sweep", spec.file, "--out", out, "--job", job.id, "--quiet"});
    }
  }
  if (skipped) std::fprintf(stderr, "sweep: %zu of %zu jobs already complete, skipped\n", skipped, jobs.size());
  RunProcessPool(commands, processes, [&](size_t i, int status) {
    const SweepJob* job = todo[i];
    SweepJobState s = ReadJobState(out, *job);
    if (!s.complete && Interrupted() && EndedByInterrupt(status)) {
      std::fprintf(stderr, "sweep: job %s interrupted; it runs again on resume\n", job->id.c_str());  // not a failure
      return;
    }
    if (!s.complete && !s.failed && WIFEXITED(status) && WEXITSTATUS(status) == kJobBusyExit) {
      s.busy = true;  // its child said which process holds it
      s.error = "running in another process; left to it";
    } else if (!s.complete && !s.failed) {
      s.failed = true;
      s.error = WIFSIGNALED(status) ? "the job process was killed by signal " + std::to_string(WTERMSIG(status))
                                    : "the job process exited with status " + std::to_string(WEXITSTATUS(status)) +
                                          " and left no record";
    }
    if (s.failed) ++failed;
    SayJob(spec, *job, s);
  });
  if (Interrupted())
    throw InterruptedError("sweep: interrupted; the finished jobs are kept, run the same command again to resume");
  return failed;
}

}  // namespace layerlab::app
