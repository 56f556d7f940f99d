// Spheroid scenes shared by the spheroid tests (and, through
// state_compare.h, the bit-for-bit state comparison)
// (test_spheroid_simulation, test_spheroid_restart_sleep).
#pragma once

#include <cstdint>

#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"
#include "virtual_triaxial/dem/quaternion.h"
#include "support/state_compare.h"
#include "virtual_triaxial/dem/simulation.h"

namespace vt::test {

/// Two-particle scene in a large cubic cell (no periodic image within reach).
struct PairScene {
  dem::Particles p;
  dem::PeriodicCell cell{dem::Vec3{0.02, 0.02, 0.02}};
};

/// Spheroid (a, b, q) of density 2650 at world position x [m] in the pair scene's cell.
void add_at(PairScene& s, std::int64_t id, double a, double b, const dem::Quaternion& q, const dem::Vec3& x,
            const dem::Vec3& v = {}, const dem::Vec3& w = {});

/// Rotation by phi [rad] about the direction u (any length).
dem::Quaternion axis_rotation(const dem::Vec3& u, double phi);

/// 200 spheroids of aspect 1.2 (nominal radii 0.8-1.2 mm / 1.2^(1/3)),
/// compressed (damped, frictionless) from a loose cloud to void ratio 1.6,
/// then given random velocities (10 m/s) and spins (2000 rad/s) in a fixed
/// cell at c_t = ct: a dense gas, as the sphere gas of test_energy_conservation.
dem::SimulationState dense_spheroid_gas(double ct);

/// 300 spheroids of aspect 1.2 compressed until the contact network holds
/// 1.3 contacts per particle, then set to shear (eps'_z = -2e-4).
dem::SimulationState loaded_spheroid_packing();

}  // namespace vt::test
