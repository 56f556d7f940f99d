// Run planner: what a shearing stage costs at a chosen dimensionless rate.
//
//   DEM steps  n = eps_final / (c_t eps')      (dt = c_t T0, eps' = epsdot T0,
//                                               so one step strains c_t eps')
//   wall time  t = n N c_p                     c_p: measured cost per
//                                               particle-step on this machine [s]
//
// Units: eps_final, eps', c_t [-]; N particles; c_p [s]; t [s]. The wall time
// is an estimate for the DEM steps only (no output, no rig overhead); the
// cost per particle-step comes from `triax_bench` (README, "Benchmarks") and
// is about 2.5-3x higher for spheroids than for spheres.
#pragma once

#include <cstdint>

namespace vt::quasi_static {

struct RunPlan {
  double steps = 0.0;          ///< DEM steps to reach eps_final [-]
  double wall_seconds = 0.0;   ///< estimated wall time [s]
};

/// Throws std::invalid_argument naming a non-positive argument.
RunPlan plan_run(double final_strain, double eps_prime, double time_step_ratio,
                 std::int64_t particles, double seconds_per_particle_step);

}  // namespace vt::quasi_static
