// Which chunks each OpenMP thread takes in the pair loop (spheres and
// spheroids), its sums (split_sums.h) and the integrator: one run of consecutive chunks per
// thread, cut by measured speed (issue 13: on a shared host one vCPU can be
// 30 % slower than the other for minutes; with equal runs the fast thread
// then waits at every barrier).
//
// Thread t of T takes chunks [b_t, b_t+1). Start, and whenever the chunk
// count, N or T changes: equal runs (chunk_run, chunked.h). Every step each
// thread adds the wall time it spent on its own run (record: its pair loop
// with its ghosts, split_sums.h, and its integration; not its waits at
// barriers). A window
// closes after at least kWindowSteps steps with at least kWindowSeconds of
// work on the busiest thread; then, with
// P_t the particles of run t and B_t its busy time, the speed is
// s_t = P_t / B_t [particles/s] and the runs are re-cut at chunk boundaries
// so that P'_t is proportional to s_t (cumulative targets rounded to the
// nearest boundary, no run empty while there are enough chunks). The new
// cut is taken only when it lowers the predicted time of the slowest thread,
// max_t P'_t / s_t, by at least kMinGain of max_t B_t (so noise does not make
// the cut flip). Results do not depend on the cut (split_sums.h: the sums
// are the one-thread sums bit for bit), only the time does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace vt::dem {

class ThreadRuns {
 public:
  static constexpr int kWindowSteps = 20;
  static constexpr double kWindowSeconds = 0.01;
  static constexpr double kMinGain = 0.03;

  /// Runs for n particles in nchunks chunks on `threads` threads: kept when
  /// all three are unchanged, else equal runs. Call serially.
  void prepare(std::int32_t nchunks, std::size_t n, int threads);
  /// Whether prepare(nchunks, n, threads) would keep the runs.
  bool current(std::int32_t nchunks, std::size_t n, int threads) const {
    return nchunks == nchunks_ && n == n_ && threads == threads_;
  }
  int threads() const { return threads_; }
  std::int32_t chunks() const { return nchunks_; }
  /// Chunks [first, second) of thread t.
  std::pair<std::int32_t, std::int32_t> run(int t) const {
    return {bounds_[static_cast<std::size_t>(t)], bounds_[static_cast<std::size_t>(t) + 1]};
  }
  /// Thread t spent `seconds` on its run (called by thread t only).
  void record(int t, double seconds) { busy_[static_cast<std::size_t>(t)].seconds += seconds; }
  /// After each step (serially): closes the window when due and re-cuts.
  void end_step();
  /// Changes whenever the runs change (prepare or a re-cut).
  std::int64_t version() const { return version_; }
  /// Re-cuts taken so far.
  std::int64_t recuts() const { return recuts_; }

 private:
  std::size_t particles(std::size_t t, const std::vector<std::int32_t>& b) const;

  std::int32_t nchunks_ = 0;
  std::size_t n_ = 0;
  int threads_ = 0;
  std::vector<std::int32_t> bounds_{0, 0};
  struct alignas(64) Busy {  // one cache line per thread
    double seconds = 0.0;
  };
  std::vector<Busy> busy_;
  int window_steps_ = 0;
  std::int64_t version_ = 0;
  std::int64_t recuts_ = 0;
};

}  // namespace vt::dem
