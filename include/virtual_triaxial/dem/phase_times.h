// Where a step's time goes (issue 13: "find where the time goes"): the
// wall-clock seconds each OpenMP thread spends in each phase of the force
// evaluation and the integration, summed over steps, and the wall time of
// each parallel region as its caller saw it.
//
// For thread t, summed over the steps since reset():
//   busy_t  = sum over phases of seconds(t, phase)                     [s]
//   waits_t = region(ForceRegion) + region(IntegrationRegion) - busy_t [s]
// waits_t is what thread t spent outside its own work inside the regions:
// forming the team, waiting at barriers for the other threads (the
// step-by-step imbalance) and joining. On one thread waits_0 is the cost of
// the timing and of the code between the phases. A thread that was not in
// every team since reset() (a thread governor switching counts) counts the
// regions it missed as waits.
//
// Phases (ContactForces::compute and LeapfrogIntegrator::advance):
//   Prepare   zeroing the thread's force and torque sums; spheroids:
//             their support data (SpheroidSupport) for this evaluation; several
//             threads: the plan of runs and ghosts when it is remade, and
//             the ghosts' per-entry state taken from the list (one thread
//             does it while the others wait)
//   Pairs     the thread's own pair loop (its run of chunks; on several
//             threads with its ghosts, split_sums.h)
//   Integrate the leapfrog step of the thread's particles (eq. 2)
// Waits, step by step (add_region, once per region and step, serially):
// with b_t the busy seconds thread t added since the last add_region (this
// region's step) over the threads of the team (b_t > 0) and w the region's
// wall time,
//   imbalance(r) = sum over steps of (max_t b_t - mean_t b_t)          [s]
//   overhead(r)  = sum over steps of (w - max_t b_t)                   [s]
// so the team's mean waits are the sum over regions of imbalance +
// overhead (when every thread was in every team). Imbalance is what the
// threads lost waiting for the slowest at the region's end; overhead is
// forming and joining the team, the timing and, in a region with barriers
// inside (the force region of spheroids on several threads: after the
// support data), the waits at those barriers
// beyond that lead (a barrier's slowest thread need not be the region's).
// The part of the imbalance a better fixed cut of the runs could recover is
//   steady_imbalance(r) = max_t B_t - mean_t B_t, B_t = sum of b_t   [s];
// the rest, imbalance - steady, moves from step to step (one thread slowed
// this step, the other the next: only balancing within the step recovers
// it). steady <= imbalance holds when the team was the same in every step.
// The timing reads omp_get_wtime() (25-30 ns a call here) a few times per
// thread and step; results never depend on it.
#pragma once

#include <vector>

namespace vt::dem {

class PhaseTimes {
 public:
  enum Phase : int { Prepare = 0, Pairs, Integrate, kPhaseCount };
  enum Region : int { ForceRegion = 0, IntegrationRegion, kRegionCount };

  /// Slots for at least `threads` threads (call serially, before a region).
  void ensure_threads(int threads);
  /// Thread t spent `seconds` in phase p (thread t only: one cache line per thread).
  void add(int t, Phase p, double seconds) { slots_[static_cast<std::size_t>(t)].s[p] += seconds; }
  /// The caller's wall time of one parallel region (serially, after the
  /// region): also closes the region's step for imbalance and overhead.
  void add_region(Region r, double seconds);
  /// Zero every sum (keeps the slots).
  void reset();

  int threads() const { return static_cast<int>(slots_.size()); }
  /// Seconds of thread t in phase p; 0 for a thread without a slot.
  double seconds(int t, Phase p) const;
  /// Sum over phases of thread t [s].
  double busy(int t) const;
  /// Region wall time [s].
  double region(Region r) const { return regions_[r]; }
  /// Both regions less busy(t) [s] (see the header comment).
  double waits(int t) const { return region(ForceRegion) + region(IntegrationRegion) - busy(t); }
  /// Sum over steps of the slowest thread's lead on the team's mean in region r [s].
  double imbalance(Region r) const { return imbalance_[r]; }
  /// The same of the threads' totals in region r [s] (<= imbalance(r) with
  /// the same team in every step).
  double steady_imbalance(Region r) const;
  /// Sum over steps of region r's wall time less its slowest thread's busy time [s].
  double overhead(Region r) const { return overhead_[r]; }
  /// "prepare", "pairs", "integrate".
  static const char* name(Phase p);

 private:
  struct alignas(64) Slot {
    double s[kPhaseCount] = {};
    double mark = 0.0;                     // busy at the last add_region
    double step = 0.0;                     // busy between the last two add_region calls (b_t)
    double region_busy[kRegionCount] = {};  // busy per region (B_t)
  };
  static double busy_of(const Slot& slot);
  std::vector<Slot> slots_;
  double regions_[kRegionCount] = {};
  double imbalance_[kRegionCount] = {};
  double overhead_[kRegionCount] = {};
};

}  // namespace vt::dem
