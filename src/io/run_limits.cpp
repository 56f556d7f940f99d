// Run limits shared by both runners. See run_limits.h.
#include "virtual_triaxial/io/run_limits.h"
#include "virtual_triaxial/io/number_text.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>

namespace vt::io {

namespace {

std::string num(double v) { return number_text(v, 6); }

double physical_memory() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && size > 0 ? static_cast<double>(pages) * static_cast<double>(size) : 0.0;
}

}  // namespace

std::string check_scene_limits(const SceneConfig& scene, const RunLimits& limits) {
  // The largest dt / T0 the scene allows: c_t, or the contacts basis's ceiling.
  if (scene.time_step_basis == dem::TimeStepBasis::ReferenceTime && scene.time_step_ratio > limits.max_time_step_ratio)
    return "time_step_ratio: " + num(scene.time_step_ratio) + " is above the limit " +
           num(limits.max_time_step_ratio) + " (c_t = dt / T0, eq. 132; the critical estimate is 1, eqs. 91-92)";
  if (scene.time_step_basis == dem::TimeStepBasis::Contacts && scene.time_step_max_ratio > limits.max_time_step_ratio)
    return "time_step_max_ratio: " + num(scene.time_step_max_ratio) + " is above the limit " +
           num(limits.max_time_step_ratio) + " (the largest dt / T0 of the time step from the contacts)";
  double count = 0;
  std::string path;
  if (scene.source == ParticleSource::Distribution) {
    count = static_cast<double>(scene.distribution.count);
    path = "particles.distribution.count";
  } else if (scene.source == ParticleSource::List) {
    count = static_cast<double>(scene.list.size());
    path = "particles.list";
  }
  const double memory = limits.memory_bytes > 0 ? limits.memory_bytes : physical_memory();
  const double need = count * limits.bytes_per_particle;
  if (memory > 0 && need > memory)
    return path + ": " + num(count) + " particles need about " + num(need / 1e9) + " GB (" +
           num(limits.bytes_per_particle) + " B each), more than the " + num(memory / 1e9) + " GB of memory";
  return "";
}

std::string check_rate_limits(const SceneConfig& scene, double t0, const RunLimits& limits) {
  const double max = limits.max_dimensionless_rate;
  for (std::size_t i = 0; i < scene.stages.size(); ++i) {
    const StageSpec& st = scene.stages[i];
    const bool dimensionless = st.strain_rate_dimensionless.has_value();
    if (!dimensionless && (!st.strain_rate || !(t0 > 0))) continue;  // t0 unknown: the dimensionless rates only
    const double eps = dimensionless ? *st.strain_rate_dimensionless : *st.strain_rate * t0;
    if (std::fabs(eps) > max)
      return "stages[" + std::to_string(i) + "]." + (dimensionless ? "strain_rate_dimensionless" : "strain_rate") +
             ": eps' = " + num(std::fabs(eps)) + " is above the limit " + num(max) + " (eps' = eps_dot T0, eq. 31)";
  }
  for (std::size_t i = 0; i < scene.stages.size(); ++i) {  // the adaptive strategy's ceiling
    const StageSpec& st = scene.stages[i];
    if (st.rate_spec.strategy == control::RateStrategyKind::Adaptive && st.rate_spec.adaptive.max_dimensionless > max)
      return "stages[" + std::to_string(i) + "].rate.max: eps' = " + num(st.rate_spec.adaptive.max_dimensionless) +
             " is above the limit " + num(max) + " (eps' = eps_dot T0, eq. 31)";
  }
  if (scene.control.servo.max_dimensionless_rate > max)
    return "control.servo.max_dimensionless_rate: " + num(scene.control.servo.max_dimensionless_rate) +
           " is above the limit " + num(max) + " (eps' = eps_dot T0, eq. 31)";
  return "";
}

}  // namespace vt::io
