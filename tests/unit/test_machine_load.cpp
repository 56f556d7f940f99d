// Room for more threads (dem/machine_load.h): the parts of /proc it reads,
// the rule others <= cpus - 2, and on this machine: this process's
// running threads are not others, busy processes are, and a governor
// beside cpus - 1 of them runs one thread after its first block.
#include <gtest/gtest.h>
#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "virtual_triaxial/dem/machine_load.h"

using namespace vt::dem;

TEST(MachineLoad, ReadsTheRunningCountOfLoadavg) {
  EXPECT_EQ(loadavg_running("0.50 0.40 0.30 2/345 6789"), 2);
  EXPECT_EQ(loadavg_running("12.00 8.10 3.02 17/1024 1\n"), 17);
  EXPECT_FALSE(loadavg_running(""));
  EXPECT_FALSE(loadavg_running("0.50 0.40 0.30 /345 6789"));
  EXPECT_FALSE(loadavg_running("0.50 0.40 0.30 2/ 6789"));
  EXPECT_FALSE(loadavg_running("0.50 0.40 0.30 2x/345 6789"));
  EXPECT_FALSE(loadavg_running("0.50 0.40 2/345"));
}

TEST(MachineLoad, StealShareIsTheStealOfAllTimeBetweenTwoStatLines) {
  // 1000 jiffies pass: 600 user, 100 system, 200 idle, 100 steal (guest is not added again)
  const std::string before = "cpu  1000 0 500 8000 10 0 5 50 0 0";
  const std::string after = "cpu  1600 0 600 8200 10 0 5 150 600 0";
  ASSERT_TRUE(steal_share(before, after));
  EXPECT_DOUBLE_EQ(*steal_share(before, after), 0.1);
  EXPECT_DOUBLE_EQ(*steal_share(before, "cpu  1600 0 600 8200 10 0 5 50"), 0.0);
  EXPECT_FALSE(steal_share(before, before));                        // no time passed
  EXPECT_FALSE(steal_share(after, before));                         // counters went back
  // iowait may go back (proc(5)): it counts as none, the rest as usual
  EXPECT_DOUBLE_EQ(*steal_share("cpu  1000 0 500 8000 10 0 5 50", "cpu  1600 0 600 8200 4 0 5 150"), 0.1);
  EXPECT_FALSE(steal_share("cpu0 1000 0 500 8000 10 0 5 50", after));  // a per-CPU line
  EXPECT_FALSE(steal_share(before, "cpu  1600 0 600 8200 10 0 5"));    // steal missing
  EXPECT_FALSE(steal_share(before, "cpu  1600 0 x 8200 10 0 5 150"));
}

TEST(MachineLoad, ReadsTheStateAfterTheCommand) {
  EXPECT_EQ(task_state("4242 (triax_bench) R 1 4242 4242 0 -1"), 'R');
  EXPECT_EQ(task_state("4243 (a) b) S 1 4242"), 'S');  // a command may hold ") "
  EXPECT_EQ(task_state("4243 (a"), '\0');
  EXPECT_EQ(task_state("4243 (a)"), '\0');
  EXPECT_EQ(task_state("4243 (a)R"), '\0');
}

TEST(MachineLoad, ChecksAProcessThatMayRunOnEveryCpu) {
  // the online CPUs when the affinity mask holds them all, else 0
  cpu_set_t mask;
  CPU_ZERO(&mask);
  ASSERT_EQ(sched_getaffinity(0, sizeof(mask), &mask), 0);
  const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  EXPECT_EQ(checked_cpus(), CPU_COUNT(&mask) >= cpus ? cpus : 0);
  if (CPU_COUNT(&mask) < 2) return;  // bound to one CPU already: the narrowing below needs two
  cpu_set_t one;
  CPU_ZERO(&one);
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &mask)) {
      CPU_SET(c, &one);
      break;
    }
  ASSERT_EQ(sched_setaffinity(0, sizeof(one), &one), 0);
  const int narrowed = checked_cpus();
  ASSERT_EQ(sched_setaffinity(0, sizeof(mask), &mask), 0);
  EXPECT_EQ(narrowed, 0);  // bound to one of several CPUs: no check
}

TEST(MachineLoad, RoomWhenAnExtraThreadFindsAFreeCore) {
  EXPECT_TRUE(room_for(2, 0, 2));
  EXPECT_FALSE(room_for(2, 1, 2));
  EXPECT_FALSE(room_for(2, 0, 1));  // one CPU: no core for an extra thread
  // 8 threads on 8 cores beside one busy task: one shares a core, the
  // other seven have theirs
  EXPECT_TRUE(room_for(8, 1, 8));
  EXPECT_TRUE(room_for(8, 6, 8));
  EXPECT_FALSE(room_for(8, 7, 8));
  EXPECT_TRUE(room_for(4, 0, 2));  // more threads than CPUs: the timings decide
  EXPECT_FALSE(room_for(1, 0, 8));
}

TEST(MachineLoad, ThisProcesssRunningThreadsAreItsOwn) {
  const std::optional<int> alone = own_running_threads();
  ASSERT_TRUE(alone);
  EXPECT_GE(*alone, 1);  // the caller runs
  std::atomic<bool> stop{false};
  std::thread spinner([&] {
    while (!stop.load(std::memory_order_relaxed)) {
    }
  });
  const std::optional<int> two = own_running_threads();  // a spinning thread is R, running or queued
  stop = true;
  spinner.join();
  ASSERT_TRUE(two);
  EXPECT_GE(*two, 2);
}

namespace {

/// `n` child processes that spin until killed (or until this process ends).
struct BusyChildren {
  explicit BusyChildren(int n) {
    const pid_t parent = getpid();
    for (int k = 0; k < n; ++k) {
      const pid_t pid = fork();
      if (pid == 0) {
        prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (getppid() != parent) _exit(0);  // the parent ended before prctl
        for (volatile unsigned long x = 0;; x = x + 1) {
        }
      }
      if (pid > 0) pids.push_back(pid);
    }
  }
  ~BusyChildren() {
    for (pid_t p : pids) kill(p, SIGKILL);
    for (pid_t p : pids) waitpid(p, nullptr, 0);
  }
  std::vector<pid_t> pids;
};

/// The most others seen in `looks` snapshots 5 ms apart (a container's CPU
/// quota takes throttled tasks off the run queue for part of each period).
int most_others(int looks) {
  int most = -1;
  for (int k = 0; k < looks; ++k) {
    if (k > 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (const std::optional<int> o = other_runnable_tasks()) most = std::max(most, *o);
  }
  return most;
}

}  // namespace

TEST(MachineLoad, BusyProcessesAreOthersAndLeaveNoRoom) {
  const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  ASSERT_GE(cpus, 1);
  if (cpus > 64) GTEST_SKIP() << "would fork " << cpus - 1 << " busy children; this test runs up to 64 CPUs";
  const int busy = static_cast<int>(std::max(1L, cpus - 1));
  BusyChildren children(busy);
  ASSERT_EQ(static_cast<int>(children.pids.size()), busy);
  EXPECT_GE(most_others(20), busy);
  // beside cpus - 1 busy processes no extra thread finds a free core, so a
  // governor on this machine goes to one thread after its first block (20
  // steps and 0.02 s; a fresh governor each try, at most 5, in case a quota
  // hid the children at that instant); a process bound to some of the CPUs
  // is not checked (the count is the machine's), and times two threads next
  const bool checked = checked_cpus() > 0;
  int after_first_block = 0;
  for (int attempt = 0; attempt < 5 && after_first_block != 1; ++attempt) {
    ThreadGovernor g = governor_on_this_machine(2);
    ASSERT_EQ(g.threads(), 2);
    for (int k = 0; k < 20; ++k) g.record_step(2e-3);
    after_first_block = g.threads();
    if (!checked) break;
  }
  EXPECT_EQ(after_first_block, checked ? 1 : 2);
}
