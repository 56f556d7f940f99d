// Runtime choice of the OpenMP thread count (issue 13: graceful under load).
//
// On a machine with other busy processes, T threads on T cores can be far
// slower than one (each barrier waits for a thread the kernel has
// descheduled). Results do not depend on the thread count (bit for bit:
// fixed 512-particle chunks, chunked.h), so the count may change from one
// step to the next at no cost to reproducibility. The governor picks it by
// measurement:
//   - steps are timed in blocks of at least `min_block_steps` steps and
//     `min_block_seconds` of wall time (so a block spans several scheduler
//     quanta);
//   - cost c_T = block wall time / block steps, kept per candidate count
//     T in {1, max_threads}: the latest block with that count, or the lower
//     of the latest two when both ran back to back (so one block slowed by
//     something else does not flip the count: session 15 saw about one
//     two-thread block in 30 cost 1.1-1.4x the others, a hiccup of the
//     host; a lasting change shows in the second block). A probe block
//     (below) gives its count's cost alone;
//   - only regular steps are timed: a step that rebuilt the neighbour list
//     (record_step(s, false): rebuilds come at irregular intervals and cost
//     several steps, so a block that happens to hold one looks dearer than
//     its count is) and the first step after a change of count (it may
//     remake the threads' plan, split_sums.h) are counted but not timed, up to
//     kMaxUntimed min_block_steps per block (a run that rebuilds at every
//     step is timed as it is). Session 15, a 16 670-step shear of
//     dense_4000.h5 on two vCPUs whose steps cost 1.11x more on one thread
//     than on two: with those steps timed and one block per count, the
//     governor ran 12-28 % of the steps on one thread, now 5-12 % (8 runs);
//   - start: the run's first block (min_block_steps and min_block_seconds,
//     on max_threads) is counted, not timed: it pays for the start (the
//     team's threads, the thread runs' first cut by speed, thread_runs.h,
//     the first touch of the sums' pages). Session 16: timed, it made the
//     first two-thread block of a 3470-step shear of dense_4000.h5 cost 346
//     us per step against 186-190 for every later one, so the one-thread
//     probe (339) won and 1184 of the 3470 steps ran on one thread;
//   - probe: the first timed block runs max_threads, the second 1 (when
//     there is no room after the first block, below: one thread, and
//     max_threads once there is); afterwards the cheaper count runs, and after ceil(exploit_blocks r b) blocks, r = cost
//     ratio worse/better clamped to [1, 64], the other count runs one block
//     so that its cost is current;
//   - backoff b: 1 at the start; a probe that confirms the running count
//     doubles it, up to kMaxProbeBackoff = 4 (not max_threads' first cost,
//     measured by a probe after no room at the start: it confirms nothing
//     yet); a probe that wins, or the
//     running count turning dearer than the other's last cost, sets it
//     back to 1. A rise of the running count's cost is seen in its own
//     blocks; a fall of the other's, at the next probe, within
//     exploit_blocks r b + 2 blocks (at most 4 exploit_blocks r + 2: at
//     12 000 spheres, blocks of about 22 ms, r = 2.5, 6.6 s). After a
//     switch because the running count got dearer, the count of blocks
//     since the last probe is kept, so the count just left is probed again
//     soon (often at the next block): a second look, since the change may
//     be a hiccup of the host (two slow blocks); when that probe confirms
//     the switch, b becomes 2.
//   - recheck (session 37): when max_threads loses the first comparison of
//     the two counts (the start's blocks, or its first measurement after no
//     room), it is probed again kStartRecheck = 8 times sooner (after
//     ceil(exploit_blocks r / 8) blocks); that probe leaves b as it was.
//     The start's transients lift the team's first timed blocks: with the
//     vCPUs far apart (session 35: the cache-line round trip ~500 ns, not
//     ~120) the run's first block of a drained shear of dense_4000.h5 with
//     the time step from the contacts cost ~580 us a step on two threads,
//     the next ~320, against ~300 on one thread and ~225-250 on two later
//     on: in 10 of 22 far-apart runs (none of 26 near) one thread won the
//     start and then ran 500-2300 of the 3470 steps
//     (bench/results/2026-12-05-s37/). A lost start is rechecked; a won one
//     is not (in a quiet run the probes' spacing is unchanged).
// The probes take about 1/(exploit_blocks b + 1) of the run's wall time at
// most (a little more for the untimed first step of a block after a switch)
// (up to r = 64; measured under load, a 2-thread block can cost 40x a
// 1-thread block, and a fixed spacing then lets the probes dominate), and
// make a run about (r - 1)/(exploit_blocks r b + 1) longer than one on the
// cheaper count alone. exploit_blocks defaults to 30
// (session 16; 15 before): with one busy process beside 12 000 spheres
// (r ~ 2.5), 15 gave the probes about 5 % of the time, the measured
// excess of `auto` over one thread; 30 halves it. The backoff (session
// 17): beside one busy process, 12 000 spheres, 12 000 steps, 12
// interleaved rounds (bench/beside_busy.sh), the runs took 82-166 steps on
// two threads (median 103, about 40 of them the start's) against 187-290
// (218) without it: 115 fewer steps at r = 2.5, about 1.4 % of the run's
// time saved; the rounds' time ratio with / without had
// a median of 0.98 (0.85-1.13, the host's noise), and either build's
// `auto` 1.007x one thread. Quiet (dense_4000.h5, 6000 steps, 10 rounds)
// the choices were the same: 82-114 steps on one thread against 82-115,
// and 502 against 512 in one round that hit a slow phase of the host.
//   - room (session 18): before it runs max_threads where one thread would
//     do, the governor asks whether an extra thread finds a free core
//     (set_room_check; machine_load.h on this machine: fewer other runnable
//     tasks than the other cores): at the end of the run's first block (which runs
//     max_threads) and when a probe of max_threads is due. No room: one
//     thread goes on (after the first block with max_threads unmeasured, a
//     probe due at once), and the question is asked again after 1, 2, 4, ..
//     blocks, at most exploit_blocks apart, back to 1 once there is room.
//     Beside one busy process the runs then take no two-thread step after
//     the first block. The answer is a snapshot, so it is not asked before
//     the first step: there, in quiet runs of dense_4000.h5 (session 18),
//     the shell reading triax_bench's output was often runnable, waiting
//     for the core this process's OpenMP thread still spun on after the
//     preparation, and a run that started on one thread then spent about
//     two blocks more on it; the short first waits keep such a "no" to a
//     block or two. Without a check (the default, and in tests unless
//     set) there is always room. A switch to max_threads because the
//     timings say one thread got dearer (a load on this process's core) is
//     not asked about: the timings decide it, and the waits start again
//     at 1 for the next probe of max_threads.
// With max_threads == 1 it never changes anything.
//
// Too little work for the threads: a thread takes whole 512-particle chunks
// (chunked.h), and the sphere pair loop evaluates every pair that crosses
// two threads' runs twice (split_sums.h). Below kMinChunksPerThread chunks
// per thread more threads cannot win, so the count is capped first
// (useful_threads; Simulation::set_thread_governor applies it to the
// specimen) and no probe block is spent on them. Measured (dense_1000.h5,
// session 14, 4 interleaved rounds, us per particle-step, 1 / 2 threads):
// N = 1000 (2 chunks) 0.081 / 0.132, two threads 1.6x slower, so the
// governor's probes cost the main job 2-4 % of its wall time; N = 2000 (4
// chunks) 0.079-0.091 / 0.072-0.091, either may win; N = 4000 (8 chunks)
// 0.078-0.115 / 0.071-0.082.
#pragma once

#include <cstdint>
#include <functional>
#include <utility>

namespace vt::dem {

class ThreadGovernor {
 public:
  static constexpr std::int32_t kMinChunksPerThread = 2;
  /// Untimed steps a block may hold, in units of min_block_steps.
  static constexpr std::int64_t kMaxUntimed = 4;
  /// Largest factor by which probes that confirm the count space the next one.
  static constexpr int kMaxProbeBackoff = 4;
  /// How much sooner max_threads is probed again when it lost the first
  /// comparison of the two counts (the recheck, above).
  static constexpr int kStartRecheck = 8;

  explicit ThreadGovernor(int max_threads, std::int64_t min_block_steps = 20, double min_block_seconds = 0.02,
                          int exploit_blocks = 30, double max_spacing_ratio = 64.0);

  /// Threads worth running on `chunks` chunks: min(max_threads, chunks /
  /// kMinChunksPerThread), at least 1.
  static int useful_threads(std::int32_t chunks, int max_threads);
  /// Caps max_threads() at useful_threads(chunks, max_threads()); a cap
  /// that lowers it starts the governor afresh (no cost or block kept).
  void limit_to_chunks(std::int32_t chunks);

  /// Whether running `threads` threads could pay now (asked before running
  /// max_threads where one thread would do; machine_load.h: a free core
  /// for at least one extra thread).
  using RoomCheck = std::function<bool(int threads)>;
  /// Sets the room check (kept by limit_to_chunks); an empty one: always room.
  void set_room_check(RoomCheck room) { room_ = std::move(room); }

  /// One ended block, for a log of the governor's choices (triax_run
  /// --governor-log). The run's first block (start = true) is counted, not
  /// timed: its cost is the start's.
  struct Block {
    std::int64_t end_step = 0;  ///< steps run so far, this block's included
    int threads = 0;            ///< the count it ran
    bool start = false;         ///< the run's first block
    bool probe = false;         ///< it probed the other count
    std::int64_t timed_steps = 0;
    std::int64_t untimed_steps = 0;  ///< counted, not timed (rebuilds, first after a switch)
    double seconds_per_step = 0;     ///< its timed steps' mean wall time [s]
    double cost_one = 0, cost_max = 0;  ///< the counts' costs after it [s per step]
    int next = 0;                       ///< the count of the next block
  };
  using BlockLog = std::function<void(const Block&)>;
  /// Calls `log` at the end of every block (kept by limit_to_chunks).
  void set_block_log(BlockLog log) { log_ = std::move(log); }

  /// Thread count for the next step.
  int threads() const { return current_; }
  /// Account one step of `seconds` wall time (run with threads()).
  /// regular = false: a step whose cost is not the count's (it rebuilt the
  /// neighbour list); counted, not timed.
  void record_step(double seconds, bool regular = true);

  int max_threads() const { return max_; }
  /// Cost per step [s] with 1 and with max_threads, as described above (0 =
  /// not measured).
  double cost_one() const { return cost_[0]; }
  double cost_max() const { return cost_[1]; }
  /// Steps run so far with 1 thread and with max_threads.
  std::int64_t steps_one() const { return steps_[0]; }
  std::int64_t steps_max() const { return steps_[1]; }

 private:
  int slot(int t) const { return t == 1 ? 0 : 1; }
  void end_block();
  /// The ended block `b` to the log, with the step count, the costs and the
  /// next count as they are now.
  void report(Block b) const;
  void choose_next();  ///< the count of the next block
  bool room() const { return !room_ || room_(max_); }
  /// room(), asked after 1, 2, 4, .. exploit_ blocks while it says no (a
  /// block's end that does not ask says no)
  bool room_after_wait();

  int max_;
  std::int64_t min_steps_;
  double min_seconds_;
  int exploit_;
  double max_ratio_;  ///< clamp of r (1: fixed spacing, for tests)
  int current_;
  std::int64_t block_steps_ = 0;
  double block_seconds_ = 0;
  double cost_[2] = {0, 0};
  double previous_block_ = 0;  ///< cost per step of the latest block (0: none yet)
  int previous_slot_ = 0;      ///< its count's slot
  std::int64_t untimed_ = 0;   ///< steps of this block counted but not timed
  std::int64_t steps_[2] = {0, 0};
  int blocks_since_probe_ = 0;
  bool switched_ = false;  ///< the next step is the first after a change of count
  RoomCheck room_;
  BlockLog log_;
  int room_wait_ = 1;         ///< blocks from a "no room" to the next question (1, 2, 4, .. exploit_)
  int room_blocks_left_ = 0;  ///< blocks before the next question
  bool warming_ = true;    ///< in the run's first block (counted, not timed)
  bool probing_ = false;   ///< the running block probes the other count (whose cost is known)
  bool compared_ = false;  ///< both counts' costs have been known
  bool recheck_ = false;   ///< the next probe of max_threads is the start's recheck
  int backoff_ = 1;        ///< factor of the probe spacing (1, 2, .., kMaxProbeBackoff)
  std::int64_t warm_steps_ = 0;  ///< steps of the first block so far
  double warm_seconds_ = 0;      ///< their wall time [s]
};

}  // namespace vt::dem
