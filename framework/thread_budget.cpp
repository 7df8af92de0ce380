#include "layerlab/framework/thread_budget.h"

#include <dirent.h>
#include <sched.h>

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

int OtherRunnableTasks() {
  const int runnable = RunnableTasks(), own = OwnRunningThreads();
  if (runnable < 0 || own < 0) return -1;
  return std::max(0, runnable - own);
}

int ThreadsForLoad(int parts) {
  {
    std::lock_guard<std::mutex> lock(budget_mutex);
    if (budget_for_testing) return std::clamp(budget_for_testing(parts), 1, std::max(parts, 1));
  }
  if (parts <= 1) return 1;
  // The load read at most every kLoadCheckSeconds per thread; in between, the last answer.
  thread_local std::chrono::steady_clock::time_point checked{};
  thread_local int others = -1;
  const auto now = std::chrono::steady_clock::now();
  if (now - checked >= std::chrono::duration<double>(kLoadCheckSeconds)) {
    checked = now;
    others = OtherRunnableTasks();
  }
  if (others < 0) return parts;
  return std::clamp(UsableCores() - others, 1, parts);
}

void SetThreadBudgetForTesting(std::function<int(int parts)> budget) {
  std::lock_guard<std::mutex> lock(budget_mutex);
  budget_for_testing = std::move(budget);
}

}  // namespace layerlab
