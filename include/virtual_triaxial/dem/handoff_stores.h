// How the integrator stores the chunks whose particles another thread's
// pair loop reads (issue 13: two threads on a host whose two vCPUs are
// sometimes near each other and sometimes far apart).
//
// On several threads each thread's integrator stores the positions,
// velocities and spins of its run (thread_runs.h). The chunks at the ends
// of a run hold particles the other thread read in the pair loop just
// before (SplitSums::shared_chunks), so those stores first take the lines
// back from the other core. With the two vCPUs near each other (a line's
// round trip about 120 ns) that is cheap; far apart (about 500 ns) it
// made the integration take 76 us a step per thread instead of 44 at
// 12 000 dense spheres, the pair loop unchanged. Streaming stores
// (streaming_copy.h) do not wait, but the lines then come from memory at
// the next read: the whole step took 0.961 of the plain stores' time far
// apart and 1.020 near (bench/results/2026-12-05-s40/ab_nt_outer1_b.txt).
// So Auto chooses at run time, from what the stores cost. Over a window of
// kWindowSteps steps with plain stores, each thread t times its shared
// chunks and its other chunks; with t_s, n_s the seconds and particles of
// the shared ones and t_o, n_o of the others,
//     r_t = (t_s / n_s) / (t_o / n_o)                     (dimensionless)
// is what a particle of a shared chunk costs against one of the others
// (measured 1.2-1.5 near, 3.75 far apart). If max_t r_t > kSlowRatio the next
// kProbeWindows windows stream the shared chunks, then one window is
// plain again to measure; else the stores stay plain. Plain and Streaming
// force the mode (A/B benchmarks, tests). The mode changes where the same
// values are stored from, never the values: results do not depend on it.
// Measured (150 interleaved rounds, 12 000 dense spheres on two threads,
// ab3_base_plain_auto.txt): Auto 0.963 of the time per step of the plain
// stores far apart (59 rounds), 1.002 near (74); the timing itself costs
// nothing measurable (plain stores with it against the code before: 1.002).
// Only spheres without local damping take this path (LeapfrogIntegrator).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vt::dem {

class HandoffStores {
 public:
  enum class Mode { Auto, Plain, Streaming };
  static constexpr int kWindowSteps = 20;
  static constexpr int kProbeWindows = 50;
  static constexpr double kSlowRatio = 2.5;

  void set_mode(Mode m);
  Mode mode() const { return mode_; }
  /// Whether this step streams the shared chunks.
  bool streaming() const { return streaming_; }

  /// Per-thread sums for `threads` threads (serially, before a team
  /// records); another count than before starts a new window.
  void ensure_threads(int threads);
  /// Thread t spent `seconds` on `particles` particles of shared chunks
  /// (shared = true) or of other chunks, with plain stores. Thread t only.
  void record(int t, bool shared, double seconds, std::size_t particles);
  /// Thread t streamed one chunk. Thread t only.
  void count_streamed(int t) { ++sums_[static_cast<std::size_t>(t)].streamed_chunks; }
  /// After each step of a team of the planned size (serially): closes the
  /// window when due and chooses the stores of the next steps.
  void end_step();

  /// max_t r_t of the last plain window (0 before one closes).
  double last_ratio() const { return last_ratio_; }
  /// Steps that streamed the shared chunks.
  std::int64_t streamed_steps() const { return streamed_steps_; }
  /// Chunks streamed, all threads (since the mode or the thread count was set).
  std::int64_t streamed_chunks() const;
  /// Steps counted by end_step.
  std::int64_t steps() const { return steps_; }

 private:
  struct Window {  // one thread's plain stores in the current window
    double shared_seconds = 0.0, other_seconds = 0.0;
    std::size_t shared_particles = 0, other_particles = 0;
  };
  struct alignas(64) Sums {  // one cache line per thread
    Window window;
    std::int64_t streamed_chunks = 0;
  };
  std::vector<Sums> sums_;
  Mode mode_ = Mode::Auto;
  bool streaming_ = false;
  int window_steps_ = 0;
  int streamed_windows_ = 0;
  double last_ratio_ = 0.0;
  std::int64_t streamed_steps_ = 0;
  std::int64_t steps_ = 0;
};

}  // namespace vt::dem
