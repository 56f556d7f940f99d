// Measures of the specimen (DESIGN §5), geomechanics sign convention:
// compression positive for stress and strain.
//
// stress        Love-Weber average sigma = (1/V) sum_c d_c (x) F_c (eq. 127),
//               symmetrised; F_c the force on the particle the branch d_c points to
// p, q, phi     p = tr(sigma)/3; q = sigma_axial - min(lateral); phi =
//               asin((s1 - s3)/(s1 + s3)) from the principal stresses
// strain        eps_i = -ln(L_i / L_i0) per axis; eps_v = -ln(V / V0)
// void ratio    e = V / V_solids - 1
// UFR           (sum_p |f_p| / n_p) / (sum_c |f_c| / n_c)                (eq. 66)
// I_uf          sqrt((sum_p |f_p|^2 / n_p) / (sum_c |f_c|^2 / n_c))    (eq. 65)
// I_mom         sum_p |M_p| / (V |sigma_oct|),                          (eq. 67)
//               |sigma_oct| = sqrt(s1^2 + s2^2 + s3^2) / sqrt(3)         (eq. 68)
// I_in          sum_p |I_p dw_p/dt| / (V |sigma_oct|)              (section 5.3.3)
// coordination  mechanical coordination number after iterative removal of
//               idle particles (< 3 contacts) and their contacts (section 4.5);
//               idle fraction by mass
// spheroid contact fallbacks / failures: counters of the common-normal
//               solver (spheroid_contact.h), summed since the run started
// f_p, M_p are the resultant contact force and moment (about the centroid)
// on particle p; contacts are pairs with positive overlap.
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/energy_budget.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

struct Measures {
  double time = 0;               ///< [s]
  std::int64_t step = 0;
  Mat3 stress;                   ///< [Pa], compression positive, symmetric
  Vec3 principal_stress;         ///< descending s1 >= s2 >= s3 [Pa]
  double p = 0, q = 0;           ///< [Pa]
  double phi = 0;                ///< mobilized friction angle [rad]
  Vec3 strain;                   ///< per-axis log strain, compression positive
  double volumetric_strain = 0;  ///< compression positive
  double volume = 0;             ///< cell volume [m^3]
  double void_ratio = 0;
  double ufr = 0, iuf = 0, moment_index = 0, inertia_index = 0;
  double coordination_number = 0;       ///< mechanical, idle particles removed
  double raw_coordination_number = 0;   ///< 2 contacts / particles
  double idle_mass_fraction = 0;
  std::int64_t contacts = 0;
  std::int64_t sliding_contacts = 0;
  double max_overlap_ratio = 0;
  /// Spheroid contact solver, counted since the Simulation was constructed:
  /// solves that needed the fallback, and solves that did not converge.
  std::int64_t spheroid_contact_fallbacks = 0;
  std::int64_t spheroid_contact_failures = 0;
  EnergyBudget energy;
};

/// Principal values (descending) of the symmetric part of s.
Vec3 principal_values(const Mat3& s);

/// Result of the iterative idle-particle removal.
struct Coordination {
  double mechanical = 0;      ///< 2 N_c' / N_p' over the non-idle set (0 if empty)
  double idle_mass_fraction = 0;
  std::int64_t active_particles = 0;
  std::int64_t active_contacts = 0;
};

/// Idle particles of section 4.5: 1 for a particle removed by the iterative
/// removal of particles with fewer than 3 contacts (and their contacts), 0
/// for the rest (the 3-core of the contact graph). contacts: index pairs.
std::vector<std::uint8_t> idle_particles(std::size_t n_particles,
                                         const std::vector<std::pair<std::int32_t, std::int32_t>>& contacts);

/// contacts as index pairs (a, b); mass per particle.
Coordination mechanical_coordination(std::size_t n_particles,
                                     const std::vector<std::pair<std::int32_t, std::int32_t>>& contacts,
                                     const std::vector<double>& mass);

}  // namespace vt::dem
