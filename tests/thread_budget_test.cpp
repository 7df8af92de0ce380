// framework/thread_budget.h and framework/fixed_parts.h: the static schedule's shares, the load read from
// /proc, and IterationThreads choosing between the load's count and one thread by timed iterations.
#include "layerlab/framework/thread_budget.h"

#include <gtest/gtest.h>
#include <omp.h>
#include <unistd.h>

#include <sys/wait.h>
#include <csignal>

#include "layerlab/framework/fixed_parts.h"

namespace layerlab {
namespace {

// OpenMP's static schedule as the runtime hands it out (teams of up to 3: larger ones leave the runtime's
// thread pool grown past what LeakSanitizer accepts at exit), and written out for more parts: n items over
// T, the first n % T one more each, in order.
TEST(FixedParts, StaticShareIsOpenMpsStaticSchedule) {
  for (size_t n : {0, 1, 5, 13, 169, 1000}) {
    for (int parts : {1, 2, 3}) {
      std::vector<int> owner(n, -1);
#pragma omp parallel for schedule(static) num_threads(parts)
      for (size_t i = 0; i < n; ++i) owner[i] = omp_get_thread_num();
      for (int p = 0; p < parts; ++p) {
        const ItemRange r = StaticShare(n, p, parts);
        for (size_t i = 0; i < n; ++i) EXPECT_EQ(owner[i] == p, i >= r.begin && i < r.end) << n << " " << p;
      }
    }
    for (int parts : {4, 7, 13}) {
      size_t next = 0;
      for (int p = 0; p < parts; ++p) {
        const size_t size = n / parts + (size_t(p) < n % parts ? 1 : 0);
        const ItemRange r = StaticShare(n, p, parts);
        EXPECT_EQ(r.begin, next) << n << " " << p;
        EXPECT_EQ(r.end, next + size) << n << " " << p;
        next += size;
      }
      EXPECT_EQ(next, n);
    }
  }
}

TEST(FixedParts, EachPartOnceWhateverTheTeam) {
  for (int threads : {1, 2, 3}) {
    std::vector<int> done(5, 0);
#pragma omp parallel num_threads(threads)
    ForEachPartOfThread(5, [&](int p) {
#pragma omp atomic
      ++done[p];
    });
    for (int d : done) EXPECT_EQ(d, 1) << threads << " threads";
  }
}

TEST(FixedParts, ScopedPartsSetsAndRestores) {
  const int outside = FixedParts();
  {
    ScopedParts three(3);
    EXPECT_EQ(FixedParts(), 3);
    {
      ScopedParts one(1);
      EXPECT_EQ(FixedParts(), 1);
    }
    EXPECT_EQ(FixedParts(), 3);
  }
  EXPECT_EQ(FixedParts(), outside);
}

// Busy children are other runnable tasks: two of them show as at least two (they may share the count with
// the machine's own), and the threads for the load then leave them their cores.
TEST(ThreadBudget, BusyProcessesAreCounted) {
  const int before = OtherRunnableTasks();
  if (before < 0) GTEST_SKIP() << "no /proc/loadavg here";
  pid_t children[2];
  for (pid_t& c : children) {
    c = fork();
    if (c == 0) {
      volatile unsigned long spin = 0;
      for (;;) {
        const unsigned long next = spin + 1;
        spin = next;
      }
    }
  }
  usleep(200000);
  int seen = 0;
  for (int k = 0; k < 20 && seen < 2; ++k, usleep(5000)) seen = std::max(seen, OtherRunnableTasks());
  for (pid_t c : children) kill(c, SIGKILL), waitpid(c, nullptr, 0);
  EXPECT_GE(seen, 2);
}

// Iterations whose seconds depend on the threads they ran on, the load allowing two: the choice settles on
// the faster, and runs the other only to probe it: once early, then kProbeEvery on, further apart while
// the probes confirm the choice.
// `busy`: the team's CPU time over its threads x wall time (negative: not measured).
int OneThreadShare(double seconds_on_two, double seconds_on_one, double busy = -1) {
  IterationThreads choice(2, [](int) { return 2; });
  int threads = choice.Next(-1), on_one = 0;
  for (int k = 0; k < 160; ++k) {
    const double seconds = threads == 1 ? seconds_on_one : seconds_on_two;
    threads = choice.Next(seconds, busy < 0 ? -1 : busy * threads * seconds);
    on_one += threads == 1;
  }
  return on_one;
}

TEST(ThreadBudget, IterationThreadsKeepsTheFasterAndProbesTheOther) {
  // Two threads faster: one thread probed early, then 32 and 64 iterations on (each confirming probe
  // doubles the interval): 3 in 160. A shared core: one thread, the team probed every 16 iterations.
  EXPECT_EQ(OneThreadShare(0.6, 1.0), 3);
  EXPECT_EQ(OneThreadShare(1.5, 1.0), 160 - 9);
}

// A team that ran its threads' whole time was waiting on nobody: one thread is not probed at all. A team
// kept waiting (60 % busy) is, and one thread kept where it is faster.
TEST(ThreadBudget, IterationThreadsProbesOnlyATeamKeptWaiting) {
  EXPECT_EQ(OneThreadShare(0.6, 1.0, 0.95), 0);
  EXPECT_EQ(OneThreadShare(1.5, 1.0, 0.6), 160 - 9);
}

// A machine that changes: one thread faster for 100 iterations, then two threads. The first probe after
// the change overturns the choice, and the probes come near again.
TEST(ThreadBudget, IterationThreadsFollowsAChange) {
  IterationThreads choice(2, [](int) { return 2; });
  int threads = choice.Next(-1), soon_on_two = 0, late_on_two = 0;
  for (int k = 0; k < 600; ++k) {
    const bool shared = k < 100;
    const double seconds = threads == 1 ? 1.0 : shared ? 1.5 : 0.6;
    threads = choice.Next(seconds);
    if (k >= 100 && k < 160) soon_on_two += threads == 2;
    if (k >= 400) late_on_two += threads == 2;
  }
  // The first probe after the change (within 16 iterations) turns it: a probe averaged into the team's old
  // mean would take three probes, some 48 iterations.
  EXPECT_GE(soon_on_two, 40);
  EXPECT_GE(late_on_two, 190);  // settled on two threads, probing one now and then
}

TEST(ThreadBudget, OneThreadWhereTheLoadLeavesOne) {
  IterationThreads choice(4, [](int) { return 1; });
  for (int k = 0; k < 40; ++k) EXPECT_EQ(choice.Next(k ? 0.1 : -1), 1);
  IterationThreads single(1);
  EXPECT_EQ(single.Next(-1), 1);
}

}  // namespace
}  // namespace layerlab
