// Phase 1 of sample preparation (chapter 4.3.1): a loose cloud of spheres
// placed at random without overlap in a box with the requested aspect
// ratios, largest particles first (random sequential addition with a bin
// grid). The box starts at volume (1 + e_target) V_solids and grows by 5 %
// (same aspect) whenever a particle cannot be placed, so it is as small as
// will hold the cloud. Velocities start at zero. Deterministic for a seed.
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"

namespace vt::dem {

struct CloudRequest {
  std::vector<double> radii;      ///< one per particle [m]
  double density = 2650;          ///< [kg/m^3]
  Vec3 aspect{1, 1, 1};           ///< box edge ratios
  double void_ratio = 2.0;        ///< initial target e = V_box / V_solids - 1
  std::uint64_t seed = 1;
  int attempts_per_particle = 2000;
};

struct Cloud {
  Particles particles;   ///< ids 0..N-1 in order of decreasing radius
  PeriodicCell cell;
  int box_growths = 0;
};

Cloud generate_cloud(const CloudRequest& req);

/// Radii for `count` particles uniform in [rmin, rmax], deterministic.
std::vector<double> uniform_radii(std::int64_t count, double rmin, double rmax, std::uint64_t seed);
/// Radii from a table of (radius, number fraction), count particles in total
/// (largest-remainder rounding so the counts sum to `count`).
std::vector<double> table_radii(std::int64_t count, const std::vector<std::pair<double, double>>& types);

}  // namespace vt::dem
