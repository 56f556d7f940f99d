// Phase 1 of sample preparation (chapter 4.3.1): a loose cloud of spheres
// placed at random without overlap in a box with the requested aspect
// ratios, largest particles first (random sequential addition with a bin
// grid). The box starts at volume (1 + e_target) V_solids and grows by 5 %
// (same aspect) whenever a particle cannot be placed, so it is as small as
// will hold the cloud. Velocities start at zero. Deterministic for a seed.
//
// Spheroids (chapter 4): with aspect_ratio = a/b > 1 every particle becomes a
// prolate spheroid whose nominal (equal-volume) radius is the requested
// radius r: a = r k^(2/3), b = a / k (k the aspect ratio, so cbrt(a b^2) = r
// and the void ratio refers to the true solid volume). The cloud is placed
// with the bounding spheres (radius a), so nothing overlaps, and each
// spheroid gets a uniformly random orientation (Shoemake) from a stream
// derived from the seed. aspect_ratio = 1 gives spheres, exactly as before.
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"
#include "virtual_triaxial/dem/random_stream.h"

namespace vt::dem {

struct CloudRequest {
  std::vector<double> radii;      ///< one per particle [m]
  double density = 2650;          ///< [kg/m^3]
  Vec3 aspect{1, 1, 1};           ///< box edge ratios
  double void_ratio = 2.0;        ///< initial target e = V_box / V_solids - 1
  std::uint64_t seed = 1;
  int attempts_per_particle = 2000;
  double aspect_ratio = 1.0;      ///< spheroid a/b >= 1; 1 = spheres
  /// Per-particle a/b (same order as radii; overrides aspect_ratio when not
  /// empty), e.g. from a PSD whose types have different aspect ratios.
  std::vector<double> aspect_ratios;
};

struct Cloud {
  Particles particles;   ///< ids 0..N-1 in order of decreasing radius
  PeriodicCell cell;
  int box_growths = 0;
};

Cloud generate_cloud(const CloudRequest& req);

/// Uniformly random rotation (Shoemake 1992) from three uniforms of rng.
Quaternion random_orientation(RandomStream& rng);

/// Radii for `count` particles uniform in [rmin, rmax], deterministic.
std::vector<double> uniform_radii(std::int64_t count, double rmin, double rmax, std::uint64_t seed);
/// Radii from a table of (radius, number fraction), count particles in total
/// (largest-remainder rounding so the counts sum to `count`).
std::vector<double> table_radii(std::int64_t count, const std::vector<std::pair<double, double>>& types);

}  // namespace vt::dem
