#include "layerlab/framework/thread_budget.h"

#include <dirent.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <string>

#include <omp.h>

namespace layerlab {
namespace {

std::mutex budget_mutex;
std::function<int(int)> budget_for_testing;

// The runnable count, the R of /proc/loadavg's "R/T" field; -1 if unread.
int RunnableTasks() {
  std::FILE* f = std::fopen("/proc/loadavg", "r");
  if (!f) return -1;
  double one, five, fifteen;
  int runnable = -1, total = 0;
  if (std::fscanf(f, "%lf %lf %lf %d/%d", &one, &five, &fifteen, &runnable, &total) != 5) runnable = -1;
  std::fclose(f);
  return runnable;
}

// This process's threads in state R; -1 if unread.
int OwnRunningThreads() {
  DIR* tasks = opendir("/proc/self/task");
  if (!tasks) return -1;
  int running = 0;
  while (const dirent* e = readdir(tasks)) {
    if (e->d_name[0] == '.') continue;
    const std::string path = std::string("/proc/self/task/") + e->d_name + "/stat";
    std::FILE* f = std::fopen(path.c_str(), "r");
    if (!f) continue;  // the thread ended meanwhile
    char line[512];
    const size_t n = std::fread(line, 1, sizeof line - 1, f);
    std::fclose(f);
    line[n] = '\0';
    // "pid (comm) S ...": the state follows the last ')' (comm may hold any character).
    const char* close = std::strrchr(line, ')');
    if (close && close[1] == ' ' && close[2] == 'R') ++running;
  }
  closedir(tasks);
  return running;
}

int UsableCores() {
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1, omp_get_num_procs());
}

}  // namespace

double ProcessCpuSeconds() {
  timespec t{};
  if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t) != 0) return -1;
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

int OtherRunnableTasks() {
  // This process's running threads read before and after the machine's: a worker that stops spinning
  // in between counts as running (the larger count), not as another process's task.
  const int own_before = OwnRunningThreads(), runnable = RunnableTasks(), own_after = OwnRunningThreads();
  if (runnable < 0 || own_before < 0 || own_after < 0) return -1;
  return std::max(0, runnable - std::max(own_before, own_after));
}

int ThreadsForLoad(int parts) {
  {
    std::lock_guard<std::mutex> lock(budget_mutex);
    if (budget_for_testing) return std::clamp(budget_for_testing(parts), 1, std::max(parts, 1));
  }
  if (parts <= 1) return 1;
  // The load read at most every kLoadCheckSeconds per thread; in between, the last answer. A task that is
  // runnable for an instant (a kernel worker, a short command) must not cost the solve a thread: the
  // smaller of the last two readings counts (the first time, two readings one after the other).
  thread_local std::chrono::steady_clock::time_point checked{};
  thread_local int previous = -1, others = -1;
  const auto now = std::chrono::steady_clock::now();
  if (now - checked >= std::chrono::duration<double>(kLoadCheckSeconds)) {
    checked = now;
    const int reading = OtherRunnableTasks();
    if (previous < 0) previous = OtherRunnableTasks();
    others = reading < 0 || previous < 0 ? -1 : std::min(reading, previous);
    previous = reading;
  }
  if (others < 0) return parts;
  return std::clamp(UsableCores() - others, 1, parts);
}

IterationThreads::IterationThreads(int parts, std::function<int(int)> load)
    : parts_(std::max(parts, 1)), load_(std::move(load)) {}

int IterationThreads::Next(double last_seconds, double last_cpu_seconds) {
  {
    std::lock_guard<std::mutex> lock(budget_mutex);
    if (budget_for_testing) return std::clamp(budget_for_testing(parts_), 1, parts_);
  }
  if (parts_ == 1) return 1;
  const auto preferred = [&] { return seconds_[0] >= 0 && seconds_[1] >= 0 && seconds_[1] < seconds_[0] ? 1 : 0; };
  const int before = preferred();
  if (last_seconds >= 0 && running_ > 0) {
    // A probe times its choice afresh (its mean is old by then); the choice in use is averaged.
    double& mean = seconds_[running_ == 1 ? 1 : 0];
    mean = mean < 0 || probing_ ? last_seconds : (1 - kSmoothing) * mean + kSmoothing * last_seconds;
    // A probe that confirms the team makes the next one further off; one that overturns it, near. One
    // thread preferred, the team is probed every kProbeEvery iterations: a shared core is often shared for
    // a while only, and the team is what an idle machine runs fastest.
    if (probing_ && seconds_[0] >= 0 && seconds_[1] >= 0)
      probe_every_ =
          preferred() == before && preferred() == 0 ? std::min(2 * probe_every_, kProbeEveryMost) : kProbeEvery;
    // How busy the team was: a thread descheduled by work this process cannot see runs no CPU time.
    if (running_ > 1 && last_cpu_seconds >= 0 && last_seconds > 0) busy_ = last_cpu_seconds / (running_ * last_seconds);
  }
  probing_ = false;
  const int load = std::clamp(load_(parts_), 1, parts_);
  if (load == 1) return running_ = 1;
  ++since_probe_;
  const int choice = preferred(), other = 1 - choice;
  // One thread is worth timing only where a team of more was kept waiting (or where that is unknown).
  const bool worth = other == 0 || busy_ < 0 || busy_ < kBusyTeam;
  if (worth && seconds_[choice] >= 0 && (seconds_[other] < 0 || since_probe_ >= probe_every_)) {
    probing_ = true;
    since_probe_ = 0;
  }
  return running_ = (probing_ ? other : choice) == 1 ? 1 : load;
}

void SetThreadBudgetForTesting(std::function<int(int parts)> budget) {
  std::lock_guard<std::mutex> lock(budget_mutex);
  budget_for_testing = std::move(budget);
}

}  // namespace layerlab
