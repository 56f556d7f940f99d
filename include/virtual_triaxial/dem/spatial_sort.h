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

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"

namespace vt::dem {

/// New storage order: order[k] = old index of the particle stored at k.
std::vector<std::int32_t> spatial_order(const Particles& p, const PeriodicCell& cell);

/// Permute every array of p: new[k] = old[order[k]]. `order` must be a
/// permutation of 0..N-1.
void permute(Particles& p, const std::vector<std::int32_t>& order);

/// permute(p, spatial_order(p, cell)).
void spatial_sort(Particles& p, const PeriodicCell& cell);

}  // namespace vt::dem
