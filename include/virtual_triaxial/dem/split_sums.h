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
// go. The terms of pairs owned in other runs are added in one of two ways:
//
// Spheres: ghosts (ghosts). A pair owned in another run is evaluated again
// by its partner's thread, as a "ghost": those owned in lower runs before
// the thread's own chunks, those owned in higher runs after them, each in
// list order, so every home particle's sum is made in the one-thread order
// by its own thread and is done when that thread's pair loop is; no
// completions, no barrier after the pair loops. A ghost runs the owner's
// contact test and lane code on the same inputs, from the thread's own
// copy of the pair's spring (ContactForces keeps it; taken from the list
// when a plan starts or the last step was not a team's with this plan), so
// its force, moment and spring are the owner's bit for bit; only the owner
// stores the pair state, spring and chunk sums. The pair states then never
// change cores: only the particles' positions, velocities and spins at the
// cut do.
//
// Spheroids: completions (edge_particles, edge_tails). Once every pair loop
// is done (a barrier) the particles with terms from other runs are
// completed from the pair states, in list order:
//   - edge particles (edge_particles): partners of a pair owned in a lower
//     run, whose first terms the pair loop could not add; gathered again
//     from all their slots (the one-thread gather, bit for bit its sum);
//   - tails (edge_tails): the other partners of pairs owned in higher runs,
//     whose terms from other runs all come last, so adding the slots from
//     the first one owned in a higher run to the pair loop's sum completes
//     it bit for bit.
// Those completions are shared among the threads by the slots they read,
// not by run (each writes one particle's sums), and the runs are cut by
// the time of the work before the barrier. (A spheroid ghost would need
// its own copy of the contact solver's cache too.)
//
// Either way the sums depend neither on the thread count nor on the runs.
//
// History. Sessions 13-20 had sphere ghosts that read their springs from
// buffers the owners filled every step, and tails; session 21 replaced
// them by the completions (the same time within the host's noise with the
// two vCPUs near each other: 0.96-1.05 at 12 000 dense spheres, 0.88-1.00
// at 10^5; bench/results/2026-12-03-s21/). Session 36 brought the ghosts
// back with springs of their own: the completions read the crossing pairs'
// states, which the owner's thread must take back from the other core's
// cache in its next pair loop, and with the host's two vCPUs far apart
// (different sockets, session 35) those writes cost 15-19 ns a line
// against 4-5 near; at 12 000 dense spheres on two threads the ghosts take
// 0.869 of the time far apart and 1.002 near (27 and 11 interleaved
// rounds; bench/results/2026-12-05-s36/experiments.txt).
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

  /// Spheres (a list without spheroids; no completions then): the ghosts
  /// of thread t, the entries owned in another run whose partner is in
  /// run t, which thread t evaluates again (ContactForces::compute): first
  /// those owned in lower runs (ghosts_lower(t) of them), then those owned
  /// in higher runs, each part ascending (list order). Empty for spheroids.
  const std::vector<std::int32_t>& ghosts(int t) const { return ghost_[static_cast<std::size_t>(t)]; }
  std::size_t ghosts_lower(int t) const { return ghost_lower_[static_cast<std::size_t>(t)]; }
  /// Ghosts of all threads (pairs evaluated twice a step).
  std::size_t ghost_count() const { return ghosts_; }
  /// The particles at the cut: partners of a pair owned in another run
  /// (spheroids: the edge particles and tails; spheres: those the ghosts
  /// add to).
  std::size_t cut_count() const { return cut_; }

 private:
  const NeighborList* list_ = nullptr;
  std::int64_t build_ = -1;
  std::size_t n_ = 0;
  std::int64_t runs_version_ = -1;
  int threads_ = 0;
  std::size_t edges_ = 0, tails_ = 0;
  std::vector<std::vector<std::int32_t>> edge_;
  std::vector<std::vector<Tail>> tail_;
  std::size_t ghosts_ = 0;
  std::size_t cut_ = 0;
  std::vector<std::vector<std::int32_t>> ghost_;
  std::vector<std::size_t> ghost_lower_;
};

}  // namespace vt::dem
