// The limits of a run, in one place: both runners (triax_run and the rig's
// test_protocol_node) check a scene against them before the run starts, so
// both refuse the same scene with the same one-line message
// "<dotted.path>: <reason>".
//   - strain rate: |eps'| = |eps_dot| T0 (eq. 31) of every stage, the
//     ceiling of an adaptive rate strategy (rate.max) and the
//     servo limit (control.servo.max_dimensionless_rate) at most
//     max_dimensionless_rate, which is also dem_node's
//     ~max_dimensionless_rate default (the limit on its commands);
//   - time step: c_t = dt / T0 (eq. 132), or with the time step from the
//     contacts its ceiling time_step_max_ratio, at most max_time_step_ratio
//     (c_t >= 1 runs with a warning: the step exceeds the critical estimate
//     of eqs. 91-92; far above it every contact blows up at once);
//   - particle count and memory: count x bytes_per_particle must fit into
//     memory_bytes (0 = this machine's physical memory). bytes_per_particle
//     is an upper bound of the measured footprint (README Benchmarks: 728 B
//     to 1110 B per sphere, 1717 B per spheroid).
#pragma once

#include <string>

#include "virtual_triaxial/io/scene_config.h"

namespace vt::io {

struct RunLimits {
  double max_dimensionless_rate = 1e-3;   ///< |eps'| [1]
  double max_time_step_ratio = 10.0;      ///< c_t [1]
  double bytes_per_particle = 2048.0;     ///< [B]
  double memory_bytes = 0.0;              ///< [B]; 0 = physical memory (sysconf)
};

/// Before the specimen is built: time step, particle count and memory.
/// "" when the scene is within the limits, else "<dotted.path>: <reason>".
std::string check_scene_limits(const SceneConfig& scene, const RunLimits& limits = {});

/// Once the specimen exists (T0 [s] known), before the first step: the
/// strain rate of every stage and the servo's rate limit. t0 = 0 (not known
/// yet, e.g. triax_run --check, which builds no specimen): the rates given
/// as strain_rate [1/s] are not checked.
std::string check_rate_limits(const SceneConfig& scene, double t0, const RunLimits& limits = {});

}  // namespace vt::io
