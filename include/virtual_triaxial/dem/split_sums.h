// Per-particle force and moment sums of the pair loop on several threads
// (ContactForces::compute), without a gather of every particle.
//
// Thread t takes its run of chunks (thread_runs.h): the particles of the
// run are its "home". Its pair loop evaluates the pairs owned in its run, as
// the one-thread loop does, and adds each to the owner and, when home, to
// the partner, right in the force and moment arrays. Entries are ordered by
// owner and runs are ranges of owners, so a home particle's terms in list
// order are: those of pairs owned in lower runs, then those of its own run,
// then those of pairs owned in higher runs. Its sum is made in that order,
// from zero, as on one thread:
//   - lower runs, spheres: a pair owned in a lower run whose partner is
//     home (a "ghost" of thread t, ghosts_before) is evaluated by thread t
//     again, before its own chunks, from the same inputs, so with the same
//     force and moment bit for bit, and added to the partner only; it is
//     stored (state, spring, chunk sums) by its owner alone. Spheroids (too
//     dear to evaluate twice): such a particle (edge_particles) is gathered
//     again from all its slots once every pair loop is done;
//   - higher runs: once every pair loop is done (a barrier), the terms of
//     the pairs owned in higher runs (ghosts_after) come last, so adding
//     them from their pair states to the pair loop's sum completes it bit
//     for bit (edge_tails).
// Those completions after the barrier are shared among the threads by the
// slots they read, not by run (each writes one particle's sums), and the
// runs are cut by the time of the work before the barrier. The sums
// therefore depend neither on the thread count nor on the runs.
//
// A ghost must see the spring at the start of the step while its owner
// overwrites it, so the owner copies the springs of its boundary entries
// (partner in a higher run) at the end of its pair loop into a write
// buffer, read as the ghosts' springs in the next step (two buffers of one
// slot per ghost, swapped every step). They are refilled from the list
// when the plan is remade (list rebuilt, runs or N changed) or a step was
// taken without it. (NeighborList::restore, which writes springs without a
// rebuild, is called by constructors only, before the first step.)
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/neighbor_list.h"
#include "virtual_triaxial/dem/thread_runs.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

class SplitSums {
 public:
  /// A ghost: its list entry and its slot in the ghost spring buffers (-1
  /// in ghosts_after: the tails read pair states, not springs).
  struct Ghost {
    std::int32_t entry;
    std::int32_t slot;
  };

  /// Whether the plan serves `list` over n particles cut into `runs` and the
  /// ghost springs follow on from step `stamp - 1`.
  bool current(const NeighborList& list, std::size_t n, const ThreadRuns& runs, std::int64_t stamp) const {
    return serves(list, n, runs) && stamp == stamp_ + 1;
  }
  /// Before step `stamp` (serially): remake the plan unless current, and
  /// refill the ghost springs from the list unless they follow on. (The
  /// spheroid path keeps the plan for its completions and never reads
  /// the ghost springs; a plan serves one list build, sphere or spheroid.)
  void prepare(const NeighborList& list, std::size_t n, const ThreadRuns& runs, std::int64_t stamp);
  /// After every step taken with the plan (serially): swaps the buffers.
  void finish_step(std::int64_t stamp);

  /// Entries owned in runs before (after) t whose partner is in run t,
  /// ascending (spheres: the ghosts evaluated again, the terms the tails add).
  const std::vector<Ghost>& ghosts_before(int t) const { return before_[static_cast<std::size_t>(t)]; }
  const std::vector<Ghost>& ghosts_after(int t) const { return after_[static_cast<std::size_t>(t)]; }
  /// Entries owned in run t whose partner is in a higher run (ghosts of
  /// that run), ascending; the k-th has slot boundary_slot(t) + k.
  const std::vector<std::int32_t>& boundary(int t) const { return boundary_[static_cast<std::size_t>(t)]; }
  std::int32_t boundary_slot(int t) const { return boundary_slot_[static_cast<std::size_t>(t)]; }
  /// The completions after the barrier (see the header comment), thread t's
  /// share; the shares split the list of all completions, in particle
  /// order (so a thread mostly completes particles of its own run, which
  /// it integrates next), into consecutive parts of about equal slots
  /// read. Edge particles (lists with spheroids only): partners of pairs
  /// owned in a lower run, gathered again from all their slots; ascending.
  const std::vector<std::int32_t>& edge_particles(int t) const { return edge_[static_cast<std::size_t>(t)]; }
  /// Tails: the other partners of pairs owned in other runs (ghosts_after
  /// of their run), whose terms from other runs come last in list order,
  /// so the pair loop's sum is the gather's partial sum before `slot`, the
  /// first of its gather slots (NeighborList::gather_codes) owned in a
  /// higher run, and adding the slots from there on completes it bit for
  /// bit. Ascending by particle.
  struct Tail {
    std::int32_t particle;
    std::int32_t slot;
  };
  const std::vector<Tail>& edge_tails(int t) const { return tail_[static_cast<std::size_t>(t)]; }
  /// Springs at the start of this step, by ghost slot.
  const Vec3* ghost_springs() const { return spring_[read_].data(); }
  /// Where the owners put the springs of their boundary entries this step, by slot.
  Vec3* next_ghost_springs() { return spring_[1 - read_].data(); }
  /// Pairs the sphere path evaluates twice per step (all ghosts_before).
  std::size_t ghost_count() const { return ghosts_; }

 private:
  /// Whether the plan was made for this list build, n and runs.
  bool serves(const NeighborList& list, std::size_t n, const ThreadRuns& runs) const {
    return list_ == &list && build_ == list.rebuild_count() && n_ == n && runs_version_ == runs.version();
  }

  const NeighborList* list_ = nullptr;
  std::int64_t build_ = -1;
  std::size_t n_ = 0;
  std::int64_t runs_version_ = -1;
  std::int64_t stamp_ = -2;
  std::size_t ghosts_ = 0;
  std::vector<std::vector<Ghost>> before_, after_;
  std::vector<std::vector<std::int32_t>> boundary_;
  std::vector<std::vector<std::int32_t>> edge_;
  std::vector<std::vector<Tail>> tail_;
  std::vector<std::int32_t> boundary_slot_;
  std::vector<Vec3> spring_[2];
  int read_ = 0;
};

}  // namespace vt::dem
