// answer_qs_advice: see ros/qs_advice_service.h.
#include "virtual_triaxial/ros/qs_advice_service.h"

#include <cstdio>
#include <exception>

#include "virtual_triaxial/io/qs_advice.h"
#include "virtual_triaxial/io/scene_builder.h"
#include "virtual_triaxial/io/scene_error.h"
#include "virtual_triaxial/io/scene_parser.h"

namespace vt::ros {

void answer_qs_advice(const std::string& path, double cost, virtual_triaxial::PredictQuasiStatic::Response& rs) {
  rs.protocol = path;
  io::QsAdvice a;
  try {
    const io::SceneConfig scene = io::load_scene(path);
    const dem::Simulation sim = io::build_simulation(scene);
    a = io::build_qs_advice(scene, sim, cost > 0.0 ? cost : 0.0);
  } catch (const std::exception& e) {   // SceneError names the field; the others the value
    rs.success = false;
    rs.message = e.what();
    return;
  }
  rs.success = true;
  rs.particles = static_cast<std::uint32_t>(a.particles);
  rs.shape = a.spheroids ? "spheroid" : "sphere";
  rs.void_ratio = a.void_ratio;
  rs.confining_pressure = a.confining_pressure;
  rs.sigma_bar0 = a.sigma_bar0;
  rs.dispersity_index = a.dispersity_index;
  rs.t0 = a.t0;
  rs.time_step_ratio = a.time_step_ratio;
  rs.damping_model = quasi_static::to_string(a.damping);
  rs.damping_ratio = a.damping_ratio;
  rs.quasi_static_threshold = a.threshold;
  rs.eps_prime_qs = a.prediction.eps_prime_qs;
  rs.strain_rate_qs = a.prediction.eps_prime_qs / a.t0;
  rs.eps_prime_qs_other_damping = a.eps_prime_qs_other_model;
  rs.inside_calibration = a.prediction.inside_calibration;
  rs.eps_prime_eq72 = a.eps_prime_eq72;
  rs.inertial_number_eq72 = a.inertial_threshold;
  rs.shear_stage = a.shear_stage;
  rs.shear_eps_prime = a.shear_eps_prime;
  rs.final_axial_strain = a.final_strain;
  rs.cost_per_particle_step = a.seconds_per_particle_step;
  rs.cost_measured = a.cost_measured;
  rs.shear_steps = a.plan_requested.steps;
  rs.shear_wall_time = a.plan_requested.wall_seconds;
  rs.qs_steps = a.plan_at_qs.steps;
  rs.qs_wall_time = a.plan_at_qs.wall_seconds;
  rs.warnings = a.warnings;
  rs.json = io::qs_advice_json(a);
  char m[160];
  std::snprintf(m, sizeof m, "eps'_QS = %.3g (eq. 84, %s, I_QS = %g); shear stage '%s': %.0f steps at eps'_QS",
                a.prediction.eps_prime_qs, rs.damping_model.c_str(), a.threshold, a.shear_stage.c_str(),
                a.plan_at_qs.steps);
  rs.message = m;
}

}  // namespace vt::ros
