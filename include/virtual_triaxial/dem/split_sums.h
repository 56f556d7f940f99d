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
// go, and once every pair loop is done (a barrier) the particles with terms
// from other runs are completed from the pair states, in list order:
//   - edge particles (edge_particles): partners of a pair owned in a lower
//     run, whose first terms the pair loop could not add; gathered again
//     from all their slots (the one-thread gather, bit for bit its sum);
//   - tails (edge_tails): the other partners of pairs owned in higher runs,
//     whose terms from other runs all come last, so adding the slots from
//     the first one owned in a higher run to the pair loop's sum completes
//     it bit for bit.
// Those completions are shared among the threads by the slots they read,
// not by run (each writes one particle's sums), and the runs are cut by
// the time of the work before the barrier. The sums therefore depend
// neither on the thread count nor on the runs.
//
// (Until session 21 a sphere pair owned in a lower run was evaluated again
// by its partner's thread before its own chunks, a "ghost", instead of the
// edge particle's gather. On two threads the gathers took the same time
// within the host's noise: 0.96-1.05 of it at 12 000 dense spheres, 0.88-1.00
// at 10^5, in sets of 8-20 interleaved rounds; bench/results/2026-12-03-s21/.)
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

  /// The completions after the barrier (see the header comment), thread t's
  /// share; the shares split the list of all completions, in particle
  /// order (so a thread mostly completes particles of its own run, which
  /// it integrates next), into consecutive parts of about equal slots
  /// read. Edge particles: partners of pairs owned in a lower run,
  /// gathered again from all their slots; ascending.
  const std::vector<std::int32_t>& edge_particles(int t) const { return edge_[static_cast<std::size_t>(t)]; }
  /// Tails: the other partners of pairs owned in higher runs, whose terms
  /// from other runs come last in list order, so the pair loop's sum is
  /// the gather's partial sum before `slot`, the first of its gather slots
  /// (NeighborList::gather_codes) owned in a higher run, and adding the
  /// slots from there on completes it bit for bit. Ascending by particle.
  struct Tail {
    std::int32_t particle;
    std::int32_t slot;
  };
  const std::vector<Tail>& edge_tails(int t) const { return tail_[static_cast<std::size_t>(t)]; }
  /// Edge particles and tails of all threads.
  std::size_t edge_count() const { return edges_; }
  std::size_t tail_count() const { return tails_; }

 private:
  const NeighborList* list_ = nullptr;
  std::int64_t build_ = -1;
  std::size_t n_ = 0;
  std::int64_t runs_version_ = -1;
  int threads_ = 0;
  std::size_t edges_ = 0, tails_ = 0;
  std::vector<std::vector<std::int32_t>> edge_;
  std::vector<std::vector<Tail>> tail_;
};

}  // namespace vt::dem
