// Spatial (bin, Morton-order) sort of the particle storage order.
//
// The DEM core walks particles in storage order and, for each one, its
// neighbours; when storage order follows space, those neighbours sit close by
// in memory and the force loop, the gather and the integrator stream through
// the caches. generate_cloud() returns particles by decreasing radius, i.e.
// spatially random, which at 1e5 particles makes almost every neighbour
// access a cache (and TLB) miss.
//
// spatial_sort() permutes every array of Particles together so that storage
// follows the Z (Morton) order of a bin grid in the cell's fractional
// coordinates, bins about one largest diameter wide; within a bin the
// previous order is kept (stable). Ids travel with their particles, so
// contact history (keyed by ids) and thread-count independence are
// unaffected. It does change the list order, which is the order of the
// per-particle force sums, and which particles share a 512-particle
// reduction chunk, so a sorted and an unsorted copy of one scene agree only
// to round-off (forces, stress, energies): sort once, when a scene is built,
// before constructing the Simulation -- never in the middle of a run.
// Deterministic; O(N log N).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"

namespace vt::dem {

struct SimulationState;

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
/// preparation starts from (so the prepared sample stays close to Morton
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
/// 16 952 list entries, 4.238 per particle, cross the runs), one 0.080-0.082; sorted, two
/// 0.067-0.073 (1614-1621 cross), one 0.077-0.080. Smaller specimens run on
/// one thread in cache, where the order costs nothing, and keep their order
/// (and results) bit for bit. The threshold is fixed here, not derived from
/// the governor's tuning, because it changes results.
constexpr std::size_t kSortFromParticles = 1536;
bool sorts_new_specimen(std::size_t n);
/// spatial_sort when sorts_new_specimen(n).
void order_new_specimen(Particles& p, const PeriodicCell& cell);
void order_new_specimen(SimulationState& s);

}  // namespace vt::dem
