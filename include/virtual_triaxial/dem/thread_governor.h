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
//     T in {1, max_threads} (the latest block with that count);
//   - probe: the first two blocks run max_threads, then 1; afterwards the
//     cheaper count runs, and after ceil(exploit_blocks r) blocks, r = cost
//     ratio worse/better clamped to [1, 64], the other count runs one block
//     so that its cost is current (a load that came or went is seen within
//     exploit_blocks r + 1 blocks).
// The probes take at most 1/(exploit_blocks + 1) of the run's wall time
// (up to r = 64; measured under load, a 2-thread block can cost 40x a
// 1-thread block, and a fixed spacing then lets the probes dominate).
// With max_threads == 1 it never changes anything.
#pragma once

#include <cstdint>

namespace vt::dem {

class ThreadGovernor {
 public:
  explicit ThreadGovernor(int max_threads, std::int64_t min_block_steps = 20, double min_block_seconds = 0.02,
                          int exploit_blocks = 15, double max_spacing_ratio = 64.0);

  /// Thread count for the next step.
  int threads() const { return current_; }
  /// Account one step of `seconds` wall time (run with threads()).
  void record_step(double seconds);

  int max_threads() const { return max_; }
  /// Latest cost per step [s] with 1 and with max_threads (0 = not measured).
  double cost_one() const { return cost_[0]; }
  double cost_max() const { return cost_[1]; }
  /// Steps run so far with 1 thread and with max_threads.
  std::int64_t steps_one() const { return steps_[0]; }
  std::int64_t steps_max() const { return steps_[1]; }

 private:
  int slot(int t) const { return t == 1 ? 0 : 1; }
  void end_block();

  int max_;
  std::int64_t min_steps_;
  double min_seconds_;
  int exploit_;
  double max_ratio_;  ///< clamp of r (1: fixed spacing, for tests)
  int current_;
  std::int64_t block_steps_ = 0;
  double block_seconds_ = 0;
  double cost_[2] = {0, 0};
  std::int64_t steps_[2] = {0, 0};
  int blocks_since_probe_ = 0;
};

}  // namespace vt::dem
