// Automatic three-phase sample preparation (chapter 4.3 of the dissertation).
//
// Phase 1, generation (4.3.1): random non-overlapping placement of the
//   particles, largest first, in a box with the requested aspect ratios, as
//   small as will hold them (dem::generate_cloud), seeded.
// Phase 2, shrinkage (4.3.2): strain controlled, friction mu1. Cycles of
//   `shrink_steps` steps of equal inward strain rate on all axes followed by
//   `balance_steps` balancing steps (no boundary motion); after each cycle
//   the normal stresses are checked. When any axis exceeds the target, the
//   last good state (end of the previous cycle) is restored and the rate is
//   halved; at the minimum rate an overshoot ends the phase, again from the
//   last good state. Keeping the last good state avoids the
//   overconsolidation an outward release would leave (4.3.2). c_t = 0.1.
// Phase 3, compression (4.3.3): friction set to its final value; a servo
//   (control::ServoStrategy, stiffness-normalised proportional law) drives
//   each axis to the target stress for `servo_steps` steps, then
//   `balance_steps` balancing steps; repeat until every axis is within
//   `tolerance` of the target and the unbalanced force ratio of eq. 54
//   (mean squared out-of-balance force over mean squared contact force,
//   = I_uf^2 of eq. 65) is below `ufr_threshold` (0.1 %, as in 4.3.3).
// Deterministic: the same settings and seed give a bit-identical sample.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "virtual_triaxial/dem/simulation.h"

namespace vt::protocol {

struct PreparationSettings {
  std::vector<double> radii;            ///< nominal radius per particle [m]
  /// Spheroid aspect ratio a/b >= 1 per particle (same order as radii);
  /// empty = all spheres. Each becomes a prolate spheroid of nominal radius
  /// radii[i] and random orientation (dem::generate_cloud).
  std::vector<double> aspect_ratios;
  dem::Material material;               ///< friction = final value (default 0.5)
  double mu1 = 0.3;                     ///< friction during shrinkage
  double pressure = 100e3;              ///< target stress on every axis [Pa]
  dem::Vec3 aspect{1, 1, 1};            ///< cell edge ratios
  std::uint64_t seed = 1;
  double initial_void_ratio = 1.5;      ///< phase-1 box; grown until the cloud fits
  dem::MassDamping damping{dem::DampingModel::OD, 0.003};  ///< 0.3 %: fastest settling measured
  double time_step_ratio = 0.1;         ///< c_t in every phase (4.3.4)
  // phase 2
  double shrink_rate = 1e-3;            ///< initial eps' (compression)
  double shrink_rate_min = 1e-6;        ///< minimum eps'
  std::int64_t shrink_steps = 200;
  std::int64_t balance_steps = 300;
  // phase 3
  double tolerance = 0.005;             ///< relative stress tolerance per axis
  double ufr_threshold = 1e-3;         ///< on eq. 54 (= I_uf^2)
  double servo_gain = 0.5;
  double servo_max_rate = 2e-4;         ///< eps' cap of the servo
  std::int64_t servo_steps = 200;
  std::int64_t max_cycles = 3000;       ///< per phase

  /// Empty when valid, otherwise "field: reason".
  std::string validate() const;
};

struct PhaseReport {
  std::string name;
  std::int64_t steps = 0;
  std::int64_t cycles = 0;
  double seconds = 0;
};

struct PreparationResult {
  bool converged = false;
  std::string failure;
  dem::SimulationState state;           ///< the prepared sample
  std::vector<PhaseReport> phases;
  dem::Measures final;                  ///< measures of the prepared sample
  dem::Vec3 aspect;                     ///< achieved edge ratios (normalised like the request)
  std::int64_t steps = 0;
  double wall_seconds = 0;
};

/// progress receives one line per cycle or phase event.
PreparationResult prepare_sample(const PreparationSettings& s,
                                 const std::function<void(const std::string&)>& progress = {});

}  // namespace vt::protocol
