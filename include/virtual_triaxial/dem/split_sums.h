// Per-particle force and moment sums of the sphere pair loop on several
// threads without a gather for most particles (ContactForces::compute).
//
// Thread t runs the pair loop over its run of chunks (thread_runs.h)
// and adds each contact to both particles in its own buffers, in list order,
// as the one-thread pair loop does. A particle all of whose list entries are
// owned by particles of its own thread's run ("sole") gets every term from
// that thread, in list order, so its buffer sum is the one-thread sum bit
// for bit and is copied out. The others (near the runs' ends in storage
// order, which follows space: spatial_sort.h) take the gather from the
// stored pair states, which gives the same bits again (contact_forces.h).
// So the sums depend neither on the thread count nor on this plan.
//
// The plan (runs, sole flags, and for each thread the particles outside its
// run that its pairs touch, whose buffer slots it zeroes) is remade when
// the neighbour list is rebuilt or the runs or N change.
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/neighbor_list.h"
#include "virtual_triaxial/dem/thread_runs.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

class SplitSums {
 public:
  /// Remake the plan for `list` over n particles cut into `runs` unless it
  /// is current (same list build, n and runs).
  void prepare(const NeighborList& list, std::size_t n, const ThreadRuns& runs);

  /// Whether every list entry of particle p is owned within p's thread run.
  bool sole(std::int32_t p) const { return sole_[static_cast<std::size_t>(p)] != 0; }
  /// Particles outside thread t's run that the pairs it owns touch.
  const std::vector<std::int32_t>& foreign(int t) const { return foreign_[static_cast<std::size_t>(t)]; }
  /// Thread t's force and moment buffers (n entries each).
  Vec3* force(int t) { return force_[static_cast<std::size_t>(t)].data(); }
  Vec3* torque(int t) { return torque_[static_cast<std::size_t>(t)].data(); }
  /// Number of particles that are not sole (take the gather).
  std::size_t gathered() const { return gathered_; }

 private:
  const NeighborList* list_ = nullptr;
  std::int64_t build_ = -1;
  std::size_t n_ = 0;
  std::int64_t runs_version_ = -1;
  std::size_t gathered_ = 0;
  std::vector<std::uint8_t> sole_;
  std::vector<std::vector<std::int32_t>> foreign_;
  std::vector<std::vector<Vec3>> force_, torque_;
};

}  // namespace vt::dem
