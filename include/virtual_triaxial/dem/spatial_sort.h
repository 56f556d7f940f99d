// Spatial (bin, slab-order) sort of the particle storage order.
//
// The DEM core walks particles in storage order and, for each one, its
// neighbours; when storage order follows space, those neighbours sit close by
// in memory and the force loop and the integrator stream through
// the caches. generate_cloud() returns particles by decreasing radius, i.e.
// spatially random, which at 1e5 particles makes almost every neighbour
// access a cache (and TLB) miss.
//
// spatial_sort() permutes every array of Particles together so that storage
// follows a bin grid in the cell's fractional coordinates, bins about one
// largest bounding diameter wide (SortGrid), in slab order: by the bin along
// the axis with the most bins (the cell's longest, in bins), then along the
// next, then the last,
//     key = (b_slab nb_mid + b_mid) nb_fast + b_fast,
// and within a bin the previous order is kept (stable). Two touching
// particles are at most one bin apart on each axis, so away from the
// cell's periodic wrap across the slabs a particle's neighbours are stored
// within two slabs of bins of it (about 2 N / nb_slab particles): the loops
// stream through a window of three slabs (at 10^5 spheres tiled 5x5x4,
// 40 x 40 x 32 bins, about 7500 particles, 1 MB of positions, radii,
// velocities, spins, forces and torques: about the L2 cache), and no
// partner is a random jump in memory. A Z
// (Morton) order, used up to session 23, keeps most neighbours closer
// still but sends the pairs across its coarse bins' faces far away (8 % of
// the list entries more than 4096 particles apart at 10^5 spheres), each a
// miss to memory. Several threads take consecutive runs of storage, i.e.
// slabs that meet across planes normal to the slab axis: slabbing across
// the cell's longest axis makes those planes, and the pairs that cross the
// threads' runs, the fewest (12 000 spheres tiled 3x2x2: 1057 particles at
// the cut, then counted as 560 edge particles and 497 tails, instead of
// 819 + 856 with slabs across the shorter s_3).
// Measured interleaved (bench/ab_builds.sh as fixed in session 25, us per
// particle-step; bench/results/2026-12-03-s25/experiments.txt R1), Morton
// -> slabs across the longest axis: 10^5 spheres 0.945x and 0.964x on one
// thread, 0.827x on two; 12 000 spheres 0.996x on one, 0.866x on two;
// 12 000 spheroids 1.001x on one. (Session 24's figures, 0.786x at 10^5 on
// one thread and others, were measured on another host with the script's
// bias: each row compared one build's mean with the other's median step.)
// Ids travel with their particles, so contact history (keyed by ids) and
// thread-count independence are unaffected. It does change the list order,
// which is the order of the per-particle force sums, and which particles
// share a 512-particle reduction chunk, so a sorted and an unsorted copy of
// one scene agree only to round-off (forces, stress, energies): sort once,
// when a scene is built, before constructing the Simulation -- never in the
// middle of a run. Deterministic; O(N log N).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"

namespace vt::dem {

struct SimulationState;

/// The bin grid of spatial_order: bins about one largest bounding diameter
/// (2 max(a, R)) wide along each axis of the fractional coordinates, at
/// least 1 and at most 2^21 per axis, and the axes in storage order.
struct SortGrid {
  int bins[3] = {1, 1, 1};  ///< bins along s_1, s_2, s_3
  /// Axes from the slowest-varying in storage (the slabs' axis: the most
  /// bins) to the fastest; equal counts keep s_3, s_2, s_1.
  int axes[3] = {2, 1, 0};
  /// The bins along s_1, s_2, s_3 of fractional position s (wrapped into
  /// [0, 1) once).
  std::array<int, 3> bins_of(const Vec3& s) const;
  /// The bin along `axis` of fractional position s: bins_of(s)[axis].
  int bin(const Vec3& s, int axis) const { return bins_of(s)[static_cast<std::size_t>(axis)]; }
};
SortGrid sort_grid(const Particles& p, const PeriodicCell& cell);

/// New storage order: order[k] = old index of the particle stored at k.
std::vector<std::int32_t> spatial_order(const Particles& p, const PeriodicCell& cell);

/// Permute every array of p: new[k] = old[order[k]]. `order` must be a
/// permutation of 0..N-1.
void permute(Particles& p, const std::vector<std::int32_t>& order);

/// permute(p, spatial_order(p, cell)).
void spatial_sort(Particles& p, const PeriodicCell& cell);
/// spatial_sort of a state's particles in its cell (contact histories are
/// keyed by ids and need no change).
void spatial_sort(SimulationState& s);

/// The storage order of a NEW specimen: one generated from a scene's
/// particle list or cloud (io::build_simulation), the cloud a sample
/// preparation starts from (so the prepared sample stays close to slab
/// order, and its criteria are judged on the state it saves) and a packing
/// imported from LAMMPS (triax_import). Never a sample file being loaded: a sample file
/// may hold a state saved mid-run that a protocol continues bit for bit
/// (rig checkpoints, save_sample, last_good), and a resume continues the
/// order of its state. A specimen of more than kSortFromParticles particles
/// (enough for two threads: 2 threads x ThreadGovernor::kMinChunksPerThread
/// chunks of 512) is sorted: its threads' runs then meet across a face in
/// space, not everywhere (generate_cloud returns particles by decreasing
/// radius, spatially random). Measured on the shipped dense_4000.h5 as
/// prepared before session 14 (triax_bench, 3 rounds, us per
/// particle-step): as stored, two threads 0.107-0.109 (7878-9280 of its
/// 16 952 list entries, 4.238 per particle, cross the runs), one 0.080-0.082;
/// sorted in the Morton order of then, two 0.067-0.073 (1614-1621 cross),
/// one 0.077-0.080 (the slab order since session 24 is faster again, see
/// above). Smaller specimens run on
/// one thread in cache, where the order costs nothing, and keep their order
/// (and results) bit for bit. The threshold is fixed here, not derived from
/// the governor's tuning, because it changes results.
constexpr std::size_t kSortFromParticles = 1536;
bool sorts_new_specimen(std::size_t n);
/// spatial_sort when sorts_new_specimen(n).
void order_new_specimen(Particles& p, const PeriodicCell& cell);
void order_new_specimen(SimulationState& s);

}  // namespace vt::dem
