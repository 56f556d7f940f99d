// The DEM specimen in its periodic cell: owns the particles, the cell and the
// per-step machinery (neighbour list, contact forces, leapfrog integrator,
// energy budget, stability monitor) and advances them one step at a time.
//
// A step at time t: (re)build the neighbour list if stale; evaluate contact
// forces at x(t); add the boundary work -sum_c F_c . (L d_c) dt; deform the
// cell to t+dt (eq. 131); advance velocities with eq. 2 and positions.
// Spheres and prolate spheroids (chapter 4): a sample without spheroids runs
// the sphere code only (contact_forces.h, leapfrog_integrator.h); with
// spheroids, pairs with a spheroid take the common-normal contact path and
// spheroids rotate by Euler's equations (eq. 43). The contact solver's
// fallbacks/failures are counted over the run (spheroid_contact_stats()).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "virtual_triaxial/dem/contact_forces.h"
#include "virtual_triaxial/dem/contact_time_step.h"
#include "virtual_triaxial/dem/energy_budget.h"
#include "virtual_triaxial/dem/hertz_mindlin.h"
#include "virtual_triaxial/dem/leapfrog_integrator.h"
#include "virtual_triaxial/dem/mass_damping.h"
#include "virtual_triaxial/dem/material.h"
#include "virtual_triaxial/dem/measures.h"
#include "virtual_triaxial/dem/neighbor_list.h"
#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"
#include "virtual_triaxial/dem/stability_monitor.h"
#include "virtual_triaxial/dem/thread_governor.h"
#include "virtual_triaxial/dem/time_scale.h"

namespace vt::dem {

struct SimulationSettings {
  Material material;
  MassDamping damping;
  double time_step_ratio = 0.3;  ///< c_t (dt = c_t T0 with TimeStepBasis::ReferenceTime)
  /// Contacts: dt = min(s dt_crit, r_max T0) from the contacts, refreshed
  /// every check_interval steps (contact_time_step.h).
  TimeStepBasis time_step_basis = TimeStepBasis::ReferenceTime;
  double time_step_safety = 0.35;    ///< s [-]
  double time_step_max_ratio = 2.0;  ///< r_max [-]
  double skin_ratio = 0.15;      ///< Verlet skin / L0
  StabilityLimits limits;
  std::int64_t check_interval = 100;  ///< steps between stability checks
};

/// Everything needed to continue a run exactly (what a sample file holds).
struct SimulationState {
  Particles particles;
  Mat3 h, h_reference, velocity_gradient;
  std::vector<ContactHistory> contacts;
  double time = 0;
  std::int64_t step = 0;
  double time_step = 0;  ///< dt in use [s] (contacts basis: restored; 0 = derive it)
  double contact_critical_step = 0;  ///< contacts basis: dt_crit of the last refresh [s] (+inf: no contacts)
  double contact_refresh_virial = 0;  ///< contacts basis: ||sum d (x) F||_F at that refresh [N m]
  EnergyBudget energy;
  SimulationSettings settings;
};

class Simulation {
 public:
  Simulation(Particles particles, const PeriodicCell& cell, const SimulationSettings& settings);
  explicit Simulation(const SimulationState& state);

  /// Advance one step. `measure` also computes the kinetic energy and the
  /// per-contact norms needed by measures(). Returns false (and stops
  /// stepping) when the stability monitor reports a numerical failure.
  bool step(bool measure = false);
  /// Choose the OpenMP thread count per step at run time (ThreadGovernor;
  /// results are bit-identical for any count); std::nullopt switches it off
  /// (the caller's count is used). The governor is capped to the
  /// specimen's chunks first (ThreadGovernor::limit_to_chunks): a specimen
  /// too small for its threads runs one thread every step. Each step runs
  /// the governor's count and restores the caller's.
  void set_thread_governor(std::optional<ThreadGovernor> g);
  const std::optional<ThreadGovernor>& thread_governor() const { return governor_; }
  /// Advance n steps; stops early on instability. Returns steps done.
  std::int64_t run(std::int64_t n);

  /// Measures of the last measured step (call step(true) first).
  Measures measures() const;
  /// The contact sums of the last force evaluation when that step was
  /// measured (step(true)), else nullptr.
  const ContactSums* last_evaluation_sums() const {
    return last_step_ >= 0 && last_step_ + 1 == steps_ ? &last_contacts_ : nullptr;
  }
  /// The cell's volume at the last measured step's force evaluation [m^3].
  double last_measured_volume() const { return last_volume_; }
  /// Stress [Pa] of the last force evaluation (every step, cheap):
  /// Love-Weber average (eq. 127), symmetrised, compression positive.
  Mat3 current_stress() const;
  double current_mean_stress() const { return current_stress().trace() / 3.0; }
  /// True once a force evaluation has run (the pair states hold forces).
  bool has_forces() const { return last_force_volume_ > 0.0; }
  bool unstable() const { return !failure_.empty(); }
  const std::string& failure() const { return failure_; }

  const Particles& particles() const { return particles_; }
  const PeriodicCell& cell() const { return cell_; }
  const TimeScale& time_scale() const { return time_scale_; }
  const SimulationSettings& settings() const { return settings_; }
  const EnergyBudget& energy() const { return energy_; }
  const NeighborList& neighbor_list() const { return list_; }
  const std::vector<Vec3>& forces() const { return force_; }
  const std::vector<Vec3>& torques() const { return torque_; }
  /// Spheroid contact-solver counters summed over every step since
  /// construction (all zero for spheres).
  const SpheroidContactStats& spheroid_contact_stats() const { return spheroid_stats_; }
  double time() const { return time_; }
  std::int64_t steps() const { return steps_; }
  double dt() const { return time_scale_.dt; }
  /// Critical step of the contacts at the last refresh (contacts basis only;
  /// dt = +inf before the first refresh or without contacts).
  const ContactCriticalStep& contact_critical_step() const { return critical_; }

  /// Per-axis strain rates [1/s], extension positive (mechanics convention).
  void set_strain_rates(const Vec3& rates) { cell_.set_strain_rates(rates); }
  Vec3 strain_rates() const { return cell_.strain_rates(); }
  /// Throws std::invalid_argument ("damping.<parameter>: reason") when the
  /// parameter does not suit the model (nothing changes then).
  void set_damping(const MassDamping& d);
  void set_friction(double mu);
  void set_time_step_ratio(double ct);
  /// Reset the cell's strain reference to the current shape.
  void reset_strain_reference() { cell_.reset_reference(); }

  SimulationState state() const;
  /// The same into `s`, reusing its storage (its particle arrays and
  /// contact list keep their capacity; NeighborList::histories_into): what
  /// a runner that keeps the last good state at every sample calls, with
  /// `sorted_contacts` = false (the contacts in list order until it sorts
  /// them by sort_histories).
  void state_into(SimulationState& s, bool sorted_contacts = true) const;

  /// Spheroid samples: let pairs found apart sleep (ContactForces::
  /// set_motion_clock; on by default). Particle states and contact histories
  /// are bit-identical either way; the solver counters (solves, iterations)
  /// are not, as sleeping pairs are not solved.
  void set_sleep_apart_pairs(bool on) { sleep_apart_ = on; }
  /// Pairs evaluated twice on several threads (ghosts, ContactForces::ghost_pairs).
  std::size_t ghost_pairs() const { return contact_forces_.ghost_pairs(); }
  /// Particles with a pair owned in another thread's run (ContactForces::cut_particles).
  std::size_t cut_particles() const { return contact_forces_.cut_particles(); }
  /// Whether the last step summed in each thread's pair loop (several threads).
  bool split_used() const { return contact_forces_.split_used(); }
  /// Chunks per thread of the pair loop and the integrator (thread_runs.h).
  const ThreadRuns& thread_runs() const { return contact_forces_.thread_runs(); }
  /// The same, mutable: for tests that steer the cut (a thread's busy time
  /// recorded between steps, support/thread_switching.h); the cut changes
  /// the time only, never the results. Not for use between a step's phases.
  ThreadRuns& thread_runs() { return contact_forces_.thread_runs(); }
  /// How the integrator stores the particles another thread reads
  /// (handoff_stores.h): its mode and statistics.
  HandoffStores& handoff_stores() { return integrator_.handoff(); }
  const HandoffStores& handoff_stores() const { return integrator_.handoff(); }
  /// Where the steps' time went per thread and phase since the last reset
  /// (phase_times.h: preparation, pair loop, integration, barrier waits).
  const PhaseTimes& phase_times() const { return contact_forces_.phase_times(); }
  void reset_phase_times() { contact_forces_.phase_times().reset(); }

 private:
  void initialize();
  bool advance(bool measure);
  void update_damping();
  /// Contacts basis: dt from the pair states of the last force evaluation
  /// (contacts = true; else the last dt_crit is kept) and the impact bound.
  void refresh_time_step(bool contacts);
  double impact_speed(double max_speed2) const;
  /// Back the large per-particle arrays with transparent huge pages (huge_pages.h).
  void use_huge_pages();

  Particles particles_;
  PeriodicCell cell_;
  SimulationSettings settings_;
  TimeScale time_scale_;
  HertzMindlin law_;
  std::optional<ThreadGovernor> governor_;
  ContactTimeStep auto_step_;
  ContactCriticalStep critical_;
  bool dt_pending_ = false;  ///< contacts basis: refresh on the next step
  double refresh_virial_ = 0;  ///< contacts basis: ||W||_F at the last dt_crit refresh [N m]
  double impact_u_ = 0;      ///< contacts basis: relative speed bound of the last step [m/s]
  double impact_v2_ = 0;     ///< max |v|^2 at construction [m^2/s^2]
  std::size_t lightest_ = 0;  ///< index of the lightest particle (impact bound)
  NeighborList list_;
  ContactForces contact_forces_;
  LeapfrogIntegrator integrator_;
  StabilityMonitor monitor_;
  EnergyBudget energy_;
  std::vector<Vec3> force_, torque_;
  SpheroidContactStats spheroid_stats_;
  double time_ = 0;
  std::int64_t steps_ = 0;
  double last_max_disp2_ = 0;
  bool sleep_apart_ = true;
  double motion_clock_ = 0;      ///< [m], see ContactForces::set_motion_clock
  double motion_clock_carry_ = 0;  ///< compensated (Kahan) summation of the clock
  double max_bounding_ = 0;      ///< max a [m]
  double max_elongation_ = 0;    ///< max (a - b) [m]
  Mat3 last_virial_;
  double last_force_volume_ = 0;
  // Data of the last measured step.
  ContactSums last_contacts_;
  IntegrationSums last_integration_;
  double last_volume_ = 0;
  double last_time_ = 0;
  std::int64_t last_step_ = -1;
  std::string failure_;
};

/// The time step in words for the runners' banners: "dt from the contacts
/// (safety s, at most r_max T0)" or "dt = ... s (c_t = ...)".
std::string describe_time_step(const Simulation& sim);

}  // namespace vt::dem
