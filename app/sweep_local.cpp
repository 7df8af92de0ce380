// The process pool of `layerlab sweep --local -j N`: each job is this
// executable run again with --job, so that a job that crashes or is killed
// takes only itself down, and its job.json says what happened.
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>

#include "layerlab/app/sweep_runners.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/interrupt.h"

extern char** environ;

namespace layerlab::app {

std::string SelfExecutable() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error("cannot find this executable (/proc/self/exe): " + ec.message());
  return self.string();
}

namespace {

pid_t Spawn(const std::string& exe, const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (int e = posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), environ); e != 0)
    throw Error(exe + ": cannot start a job process: " + std::strerror(e));
  return pid;
}

}  // namespace

size_t RunSweepLocally(const SweepSpec& spec, const std::vector<SweepJob>& jobs, const std::string& out,
                       int processes) {
  InstallInterruptHandler();
  const std::string exe = SelfExecutable();
  std::deque<const SweepJob*> todo;
  size_t skipped = 0, failed = 0;
  for (const SweepJob& job : jobs) {
    if (ReadJobState(out, job).complete)
      ++skipped;
    else
      todo.push_back(&job);
  }
  if (skipped) std::fprintf(stderr, "sweep: %zu of %zu jobs already complete, skipped\n", skipped, jobs.size());
  std::map<pid_t, const SweepJob*> running;
  while (!todo.empty() || !running.empty()) {
    while (!todo.empty() && static_cast<int>(running.size()) < processes && !Interrupted()) {
      const SweepJob* job = todo.front();
      todo.pop_front();
      running[Spawn(exe, {exe, "sweep", spec.file, "--out", out, "--job", job->id, "--quiet"})] = job;
    }
    if (running.empty()) break;  // interrupted before anything more started
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw Error(std::string("waiting for the job processes: ") + std::strerror(errno));
    }
    auto it = running.find(pid);
    if (it == running.end()) continue;
    const SweepJob* job = it->second;
    running.erase(it);
    SweepJobState s = ReadJobState(out, *job);
    if (!s.complete && Interrupted() && WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) {
      std::fprintf(stderr, "sweep: job %s interrupted; it runs again on resume\n", job->id.c_str());  // not a failure
      continue;
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
  }
  if (Interrupted())
    throw InterruptedError("sweep: interrupted; the finished jobs are kept, run the same command again to resume");
  return failed;
}

}  // namespace layerlab::app
