// Quasi-static advice for a loaded protocol: the sample's e0, sigma_bar0 and
// dispersity index, the eq. 84/85 prediction and the eq. 72 inertial-number
// rate (quasi_static/), and the run plan of its shear stage at the requested
// rate and at the predicted eps'_QS. Shared by `triax_qs predict` and the
// rig's test_protocol_node service, so both answer with the same numbers.
//
// sigma_c is the first shear stage's confining_pressure (else the sample's
// mean stress); e0 and Delta are measured on the loaded sample (one
// measured step of a copy; the scene's simulation is not touched). The
// cost per particle-step is measured on a copy of the sample (a short run,
// at the process's OpenMP thread count) unless given. Units SI.
#pragma once

#include <string>
#include <vector>

#include "virtual_triaxial/dem/simulation.h"
#include "virtual_triaxial/io/scene_config.h"
#include "virtual_triaxial/quasi_static/qs_rate_prediction.h"
#include "virtual_triaxial/quasi_static/run_plan.h"

namespace vt::io {

struct QsAdvice {
  std::size_t particles = 0;
  bool spheroids = false;
  double void_ratio = 0.0;          ///< e0 [-]
  double confining_pressure = 0.0;  ///< sigma_c [Pa]
  double young_modulus = 0.0;       ///< [Pa]
  double density = 0.0;             ///< [kg/m^3]
  double sigma_bar0 = 0.0;          ///< sigma_c / E [-]
  double dispersity_index = 1.0;    ///< eq. 80 [-]
  double d_min = 0.0, d_avg = 0.0;  ///< nominal diameters [m]
  double t0 = 0.0;                  ///< [s]
  double time_step_ratio = 0.0;     ///< c_t
  quasi_static::QsDamping damping = quasi_static::QsDamping::OD;
  double damping_ratio = 0.0;
  double threshold = 1e-3;          ///< I_QS (control.quasi_static_threshold)
  quasi_static::QsRatePrediction prediction;        ///< eq. 84, this damping model
  double eps_prime_qs_other_model = 0.0;            ///< eq. 84 with the other model
  double eps_prime_eq72 = 0.0;      ///< eq. 72 with section 6.15's fitted I [-]
  double inertial_threshold = 0.0;  ///< that I [-]
  // shear stage
  std::string shear_stage;          ///< its name
  double shear_eps_prime = 0.0;     ///< requested [-]
  double final_strain = 0.0;        ///< its stop.axial_strain [-]
  double seconds_per_particle_step = 0.0;
  bool cost_measured = false;
  quasi_static::RunPlan plan_requested, plan_at_qs;
  std::vector<std::string> warnings;
};

/// Throws SceneError naming the field (stages: no shear stage;
/// stages[i].stop.axial_strain: missing) and std::invalid_argument for
/// impossible sample values. seconds_per_particle_step <= 0: measure it.
QsAdvice build_qs_advice(const SceneConfig& scene, const dem::Simulation& sim,
                         double seconds_per_particle_step = 0.0);

/// One JSON object, keys named with their units.
std::string qs_advice_json(const QsAdvice& a);

}  // namespace vt::io
