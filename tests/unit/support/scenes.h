// Small scene builders shared by the unit tests.
#pragma once

#include <cstdint>

#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"
#include "virtual_triaxial/dem/simulation.h"

namespace vt::test {

/// Default test material: rho 2650, E 70 GPa, nu 0.3, mu 0.5.
dem::Material test_material(double friction = 0.5);

/// Settings with the given c_t, no damping.
dem::SimulationSettings undamped(double ct, double friction = 0.5);

/// A loose polydisperse cloud (radii uniform in [0.8, 1.2] mm), void ratio e.
struct CloudScene {
  dem::Particles particles;
  dem::PeriodicCell cell;
};
CloudScene polydisperse_cloud(std::int64_t n, double void_ratio, std::uint64_t seed,
                              double length_scale = 1.0, double density = 2650.0);

/// A loose cloud of prolate spheroids: the cloud of polydisperse_cloud(n,
/// void_ratio, seed) (void ratio of the bounding spheres) with every sphere
/// replaced by a spheroid of major semi-axis a = R (so nothing overlaps),
/// b = a / aspect and a random orientation (dem::random_orientation).
CloudScene spheroid_cloud(std::int64_t n, double aspect, double void_ratio, std::uint64_t seed,
                          double density = 2650.0);

/// A polydisperse_cloud(particles, 1.8, 5) compressed isotropically for
/// 1200 steps (c_t 0.3, ND damping 0.02) into a loaded contact network, left
/// shearing at constant volume so that springs keep changing.
dem::SimulationState loaded_packing(int particles = 400);

/// Give every particle a random velocity of size ~speed and random spin.
void randomize_velocities(dem::Particles& p, double speed, double spin, std::uint64_t seed);

/// The state with its particles in spatial (slab) storage order
/// (dem::spatial_sort): storage order then differs from id order, so many
/// particles have list entries of owners stored after them.
dem::SimulationState spatially_sorted(dem::SimulationState s);

/// True when some particle with entries of its own is also the partner of
/// an entry whose owner is stored after it (its sums in list order then take
/// terms of its own entries before those of that owner).
bool has_owner_stored_after(const dem::NeighborList& list);

}  // namespace vt::test
