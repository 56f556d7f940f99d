// Is there a free core for more threads of this process now? (issue 13,
// graceful under load; used by ThreadGovernor before it runs max_threads.)
//
// Beside one busy process on two cores, every block the governor runs on two
// threads costs about 2.5x a one-thread block at 12 000 spheres: the start's
// two-thread blocks (about 40 steps) and the probes of two threads (one block
// every 30 r b, thread_governor.h) made `auto` about 1 % slower than one
// thread (session 17: 1.012x, 28 rounds, bench/beside_busy.sh). Those blocks
// cannot win while every other core holds a runnable task, so the governor
// asks first and runs them only when there is room:
//
//   others = R - R_self                       (tasks)
//   room for T > 1 threads  <=>  others <= C - 2
//
// i.e. at least one core besides the caller's is free for an extra thread.
// Not "a core for each of the T threads": on 8 cores with one other busy
// task, 8 threads, one of them sharing a core, still beat one thread by
// several times, and the governor's timings say so; and T may exceed C
// (OMP_NUM_THREADS above the CPUs), where the timings decide as well (on
// C >= 2; one CPU never has room for an extra thread).
//
// R: the tasks runnable on the machine now (/proc/loadavg, 4th field
// "R/total", every CPU, this process's running threads included); R_self:
// this process's threads in state R (/proc/self/task/*/stat); C: the online
// CPUs. A snapshot: a load that runs part of the time is seen at that share
// of the checks, and the governor's timings still decide once the threads
// run. No check (room assumed, the behaviour before session 18) when this
// process may run on fewer CPUs than are online (an affinity mask or a
// cpuset, e.g. a Slurm job on some cores of a node: the system-wide count
// does not say which cores are busy) or /proc cannot be read. A question
// costs about 25 us (a one-thread process; the governor asks at most once
// a block, and beside a busy process once in 30 blocks).
//
// Measured (session 18, bench/beside_busy.sh, 12 000 spheres, 12 000
// steps, `yes` beside): 20 of 12 051 steps on two threads (the first
// block), session 17's build 82-187; `auto` 1.012x one thread over 24
// interleaved rounds, 13 of them slower (rounds scatter by 5-10 %).
#pragma once

#include <optional>
#include <string>

#include "virtual_triaxial/dem/thread_governor.h"

namespace vt::dem {

/// The running count R of a /proc/loadavg line ("0.50 0.40 0.30 2/345 6789");
/// nullopt when the line is not of that form.
std::optional<int> loadavg_running(const std::string& line);
/// The state letter of a /proc/<pid>/task/<tid>/stat line (the field after
/// the command's closing parenthesis, which may itself hold ") "); '\0' when
/// malformed.
char task_state(const std::string& stat_line);
/// This process's threads in state R now; nullopt when /proc cannot be read.
std::optional<int> own_running_threads();
/// others = R - R_self now, at least 0; nullopt when /proc cannot be read.
std::optional<int> other_runnable_tasks();
/// The rule above: room for `threads` (> 1) threads when others <= cpus - 2.
bool room_for(int threads, int others, int cpus);
/// The share of CPU time the hypervisor took from this machine (steal)
/// between two aggregate /proc/stat lines ("cpu  user nice system idle
/// iowait irq softirq steal ..."): d(steal) / d(user + nice + system + idle +
/// iowait + irq + softirq + steal), in [0, 1]; nullopt when a line is not of
/// that form, a counter other than iowait went back, or no time passed (an
/// iowait that went back, which proc(5) allows, counts as none). A busy host shows it; bench/host_scaling
/// prints it beside the two CPUs' scaling.
std::optional<double> steal_share(const std::string& stat_before, const std::string& stat_after);
/// The online CPUs when this process may run on all of them (the room is
/// checked), else 0 (an affinity mask or cpuset: no check).
int checked_cpus();
/// A governor up to max_threads whose room check is the rule above on this
/// machine (the one used by the DEM node, triax_run and triax_bench).
ThreadGovernor governor_on_this_machine(int max_threads);

}  // namespace vt::dem
