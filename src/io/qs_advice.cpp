#include "virtual_triaxial/io/qs_advice.h"
#include "virtual_triaxial/io/number_text.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "virtual_triaxial/io/psd_file.h"
#include "virtual_triaxial/io/scene_error.h"
#include "virtual_triaxial/quasi_static/inertial_number.h"
#include "virtual_triaxial/quasi_static/qs_warnings.h"

namespace vt::io {
namespace qs = vt::quasi_static;
namespace {

// Wall seconds per particle-step of a copy of the sample, straining at a
// small rate: 5e5 particle-steps (~0.07 s on a quiet machine), at
// least 20.
double measure_cost(const dem::Simulation& sim) {
  dem::Simulation copy(sim.state());
  const std::size_t n = std::max<std::size_t>(copy.particles().size(), 1);
  const std::int64_t steps = std::max<std::int64_t>(20, static_cast<std::int64_t>(5e5 / n));
  copy.run(5);  // neighbour lists, caches
  const auto t0 = std::chrono::steady_clock::now();
  copy.run(steps);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return s / (static_cast<double>(steps) * static_cast<double>(n));
}

std::string num(double v) { return std::isfinite(v) ? number_text(v, 10) : "null"; }

}  // namespace

QsAdvice build_qs_advice(const SceneConfig& scene, const dem::Simulation& sim,
                         double seconds_per_particle_step) {
  QsAdvice a;
  // the shear stage to plan
  std::size_t k = scene.stages.size();
  for (std::size_t i = 0; i < scene.stages.size(); ++i)
    if (protocol::is_shear(scene.stages[i].type)) { k = i; break; }
  if (k == scene.stages.size())
    throw SceneError("stages", "no drained_shear or undrained_shear stage to predict a rate for");
  const protocol::StageSpec& st = scene.stages[k];
  const std::string path = "stages[" + std::to_string(k) + "]";
  if (!st.stop.axial_strain)
    throw SceneError(path + ".stop.axial_strain", "needed to plan the run (the final axial strain)");

  const dem::Particles& p = sim.particles();
  a.particles = p.size();
  a.spheroids = std::any_of(p.shape.begin(), p.shape.end(),
                            [](dem::Shape s) { return s != dem::Shape::Sphere; });
  a.young_modulus = sim.state().settings.material.young;
  a.density = sim.state().settings.material.density;
  a.t0 = sim.time_scale().t0;
  a.damping = scene.damping.model() == dem::DampingModel::ND ? qs::QsDamping::ND : qs::QsDamping::OD;
  a.damping_ratio = scene.damping.ratio();
  a.threshold = scene.control.quasi_static_threshold;

  dem::Simulation probe(sim.state());
  probe.step(true);
  // dt / T0 of the run: after one step, so that a time step from the contacts
  // (derived at the first force evaluation) is the one planned with.
  a.time_step_ratio = probe.time_scale().ct;
  const dem::Measures m = probe.measures();
  a.void_ratio = m.void_ratio;
  a.confining_pressure = st.confining_pressure ? *st.confining_pressure : m.p;
  a.sigma_bar0 = a.confining_pressure / a.young_modulus;
  a.dispersity_index = dispersity_index(p.radius);
  a.d_min = 2.0 * *std::min_element(p.radius.begin(), p.radius.end());
  a.d_avg = a.dispersity_index * a.d_min;

  const qs::QsSample sample{a.void_ratio, a.sigma_bar0, a.dispersity_index};
  a.prediction = qs::predict_qs_rate(sample, a.damping, a.threshold);
  const qs::QsDamping other = a.damping == qs::QsDamping::ND ? qs::QsDamping::OD : qs::QsDamping::ND;
  a.eps_prime_qs_other_model = qs::predict_qs_rate(sample, other, a.threshold).eps_prime_qs;
  a.inertial_threshold = qs::fitted_inertial_threshold(a.damping);
  a.eps_prime_eq72 = qs::eq72_rate(sample, a.inertial_threshold);

  a.shear_stage = st.name;
  a.shear_eps_prime = st.rate(a.t0) * a.t0;
  a.final_strain = *st.stop.axial_strain;
  a.cost_measured = !(seconds_per_particle_step > 0.0);
  a.seconds_per_particle_step = a.cost_measured ? measure_cost(sim) : seconds_per_particle_step;
  if (a.shear_eps_prime > 0.0)
    a.plan_requested = qs::plan_run(a.final_strain, a.shear_eps_prime, a.time_step_ratio,
                                    static_cast<std::int64_t>(a.particles), a.seconds_per_particle_step);
  a.plan_at_qs = qs::plan_run(a.final_strain, a.prediction.eps_prime_qs, a.time_step_ratio,
                              static_cast<std::int64_t>(a.particles), a.seconds_per_particle_step);

  qs::QsInputs in;
  in.model = a.damping;
  in.damping_ratio = a.damping_ratio;
  in.time_step_ratio = a.time_step_ratio;
  in.shear_eps_prime = a.shear_eps_prime;
  in.predicted_eps_prime_qs = a.prediction.eps_prime_qs;
  a.warnings = qs::qs_warnings(in);
  if (!a.prediction.inside_calibration)
    a.warnings.push_back("sample: e0, sigma_bar0 or Delta outside the range eq. 84 was fitted on "
                         "(table 39: e0 0.31-0.61, sigma_bar0 1e-6 - 8e-5, Delta <= 6.15)");
  if (a.prediction.extrapolated_threshold)
    a.warnings.push_back("control.quasi_static_threshold: below 0.1 %; eq. 84 assumes b_I = 1 and "
                         "overestimates eps'_QS there");
  return a;
}

std::string qs_advice_json(const QsAdvice& a) {
  std::string w = "[";
  for (std::size_t i = 0; i < a.warnings.size(); ++i) {
    std::string e;
    for (char c : a.warnings[i]) {
      if (c == '"' || c == '\\') e += '\\';
      e += c;
    }
    w += (i ? ",\"" : "\"") + e + "\"";
  }
  w += "]";
  return std::string("{") + "\"particles\":" + std::to_string(a.particles) +
         ",\"shape\":\"" + (a.spheroids ? "spheroid" : "sphere") + "\"" +
         ",\"void_ratio\":" + num(a.void_ratio) +
         ",\"confining_pressure_pa\":" + num(a.confining_pressure) +
         ",\"young_modulus_pa\":" + num(a.young_modulus) +
         ",\"density_kg_per_m3\":" + num(a.density) +
         ",\"sigma_bar0\":" + num(a.sigma_bar0) +
         ",\"dispersity_index\":" + num(a.dispersity_index) +
         ",\"d_min_m\":" + num(a.d_min) + ",\"d_avg_m\":" + num(a.d_avg) +
         ",\"t0_s\":" + num(a.t0) + ",\"time_step_ratio\":" + num(a.time_step_ratio) +
         ",\"damping_model\":\"" + qs::to_string(a.damping) + "\"" +
         ",\"damping_ratio\":" + num(a.damping_ratio) +
         ",\"quasi_static_threshold\":" + num(a.threshold) +
         ",\"eps_prime_qs_eq84\":" + num(a.prediction.eps_prime_qs) +
         ",\"strain_rate_qs_eq85_per_s\":" + num(a.prediction.eps_prime_qs / a.t0) +
         ",\"eps_prime_qs_eq84_other_damping\":" + num(a.eps_prime_qs_other_model) +
         ",\"inside_calibration\":" + (a.prediction.inside_calibration ? "true" : "false") +
         ",\"eps_prime_qs_eq72\":" + num(a.eps_prime_eq72) +
         ",\"inertial_number_eq72\":" + num(a.inertial_threshold) +
         ",\"shear_stage\":\"" + a.shear_stage + "\"" +
         ",\"shear_eps_prime\":" + num(a.shear_eps_prime) +
         ",\"final_axial_strain\":" + num(a.final_strain) +
         ",\"cost_per_particle_step_s\":" + num(a.seconds_per_particle_step) +
         ",\"cost_measured\":" + (a.cost_measured ? "true" : "false") +
         ",\"shear_steps\":" + num(a.plan_requested.steps) +
         ",\"shear_wall_s\":" + num(a.plan_requested.wall_seconds) +
         ",\"qs_steps\":" + num(a.plan_at_qs.steps) +
         ",\"qs_wall_s\":" + num(a.plan_at_qs.wall_seconds) +
         ",\"warnings\":" + w + "}";
}

}  // namespace vt::io
