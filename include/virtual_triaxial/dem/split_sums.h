// Per-particle force and moment sums of the pair loop on several threads
// (ContactForces::compute), without a gather of every particle.
//
// Thread t takes its run of chunks (thread_runs.h): the particles of the
// run are its "home". Its pair loop evaluates the pairs owned in its run, as
// the one-thread loop does, and adds each to the owner and, when home, to
// the partner, right in the force and moment arrays. Entries are ordered by
// owner and runs are ranges of owners, so a home particle's terms in list
// order are: those of pairs owned in lower runs, then those of its own run,
// then those of pairs owned in higher runs. The pair loop's sum of a home
// particle is therefore its one-thread sum as far as its own run's terms
// go. The terms of pairs owned in other runs come from ghosts: such a pair
// is evaluated again by its partner's thread, those owned in lower runs
// before the thread's own chunks and those owned in higher runs after
// them, each in list order, so every home particle's sum is made in the
// one-thread order by its own thread and is done when that thread's pair
// loop is: no completions, no barrier after the pair loops. A ghost runs
// the owner's pair kernel itself (the same function, so the same code) on
// the same inputs, from the thread's own copies of the pair's per-entry
// state (spring, pair state, contact flag and, for spheroids, the contact
// solver's cache and wake time; ContactForces keeps them, taken from the
// list when a plan starts or the last step was not a team's with this
// plan), so its force, moments and new state are the owner's bit for bit;
// it adds only to its home partner, and only the owner stores into the
// list and counts the chunk sums. Two assumptions this rests on: (1) a
// pair's results depend on its own inputs only, not on which lane or
// group of the kernels' SIMD loops takes it (a ghost sits in other groups
// than its owner's entry): the lane loops have fixed trip counts, unused
// lanes repeat a used one, and no loop has a scalar peel or epilogue that
// would treat some lanes apart; (2) the list's per-entry state changes
// only in compute() or by a rebuild (which makes a new plan):
// NeighborList::restore writes springs and caches without a rebuild, so
// it may only be called on a list no team has evaluated since its build
// (today: Simulation's constructor and specimen_snapshot, both on a fresh
// list). The pair states then never change
// cores: only the particles' positions, velocities and spins (and, for
// spheroids, their support data) at the cut do. The sums therefore depend
// neither on the thread count nor on the runs.
//
// History. Sessions 13-20 had sphere ghosts that read their springs from
// buffers the owners filled every step; session 21 replaced them by
// completions after a barrier (edge particles gathered again from the
// pair states, tails added from them), as spheroids had had since session
// 16: the same time within the host's noise with the host's two vCPUs near
// each other (0.96-1.05 at 12 000 dense spheres, 0.88-1.00 at 10^5;
// bench/results/2026-12-03-s21/). Session 36 brought the ghosts back for
// both, with per-entry state of their own: the completions read the
// crossing pairs' states, which the owner's thread must take back from the
// other core's cache in its next pair loop, and with the vCPUs far apart
// (different sockets, session 35) those writes cost 15-19 ns a line
// against 4-5 near; at 12 000 dense spheres on two threads the sphere
// ghosts took 0.869 of the completions' time far apart and 1.002 near (27
// and 11 interleaved rounds; bench/results/2026-12-05-s36/experiments.txt).
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/neighbor_list.h"
#include "virtual_triaxial/dem/thread_runs.h"

namespace vt::dem {

class SplitSums {
 public:
  /// Whether the plan serves `list` (this build) over n particles cut into `runs`.
  bool current(const NeighborList& list, std::size_t n, const ThreadRuns& runs) const {
    return list_ == &list && build_ == list.rebuild_count() && n_ == n && runs_version_ == runs.version() &&
           threads_ == runs.threads();
  }
  /// Remakes the plan unless current (serially).
  void prepare(const NeighborList& list, std::size_t n, const ThreadRuns& runs);

  /// The ghosts of thread t: the entries owned in another run whose
  /// partner is in run t, which thread t evaluates again
  /// (ContactForces::compute): first those owned in lower runs
  /// (ghosts_lower(t) of them), then those owned in higher runs, each part
  /// ascending (list order).
  const std::vector<std::int32_t>& ghosts(int t) const { return ghost_[static_cast<std::size_t>(t)]; }
  std::size_t ghosts_lower(int t) const { return ghost_lower_[static_cast<std::size_t>(t)]; }
  /// Ghosts of all threads (pairs evaluated twice a step).
  std::size_t ghost_count() const { return ghosts_; }
  /// The particles at the cut: partners of a pair owned in another run.
  std::size_t cut_count() const { return cut_; }
  /// Per chunk: 1 when it holds the owner or the partner of a pair that
  /// crosses runs, i.e. a particle another thread's pair loop reads
  /// (handoff_stores.h), else 0.
  const std::vector<std::uint8_t>& shared_chunks() const { return shared_chunk_; }

 private:
  const NeighborList* list_ = nullptr;
  std::int64_t build_ = -1;
  std::size_t n_ = 0;
  std::int64_t runs_version_ = -1;
  int threads_ = 0;
  std::size_t ghosts_ = 0;
  std::size_t cut_ = 0;
  std::vector<std::vector<std::int32_t>> ghost_;
  std::vector<std::size_t> ghost_lower_;
  std::vector<std::uint8_t> shared_chunk_;
};

}  // namespace vt::dem
