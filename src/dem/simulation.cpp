#include "virtual_triaxial/dem/simulation.h"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/huge_pages.h"

namespace vt::dem {

Simulation::Simulation(Particles particles, const PeriodicCell& cell, const SimulationSettings& settings)
    : particles_(std::move(particles)), cell_(cell), settings_(settings) {
  initialize();
}

Simulation::Simulation(const SimulationState& s)
    : particles_(s.particles), cell_(s.h, s.h_reference), settings_(s.settings) {
  cell_.set_velocity_gradient(s.velocity_gradient);
  time_ = s.time;
  steps_ = s.step;
  energy_ = s.energy;
  initialize();
  if (settings_.time_step_basis == TimeStepBasis::Contacts && s.time_step > 0.0 && s.contact_critical_step > 0.0) {
    time_scale_.dt = s.time_step;  // continue exactly with the step in use
    time_scale_.ct = s.time_step / time_scale_.t0;
    critical_.dt = s.contact_critical_step;
    refresh_virial_ = s.contact_refresh_virial;
    dt_pending_ = false;
    update_damping();
  }
  const std::size_t missing = list_.restore(particles_, s.contacts);
  if (missing > 0)
    throw std::runtime_error("contacts: " + std::to_string(missing) +
                             " stored contact(s) join particles that are not within reach");
}

void Simulation::initialize() {
  if (particles_.size() < 2) throw std::invalid_argument("particles: at least 2 particles are needed");
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    const Vec3& a = particles_.semi_axes[i];
    if (particles_.shape[i] == Shape::Sphere) continue;
    if (particles_.shape[i] != Shape::Spheroid)
      throw std::invalid_argument("particles.shape: entry " + std::to_string(i) + " is neither sphere nor spheroid");
    if (!(a.y > 0.0 && a.x >= a.y && a.z == a.y))
      throw std::invalid_argument("particles.semi_axes: entry " + std::to_string(i) +
                                  " must be (a, b, b) with a >= b > 0 (prolate spheroid)");
  }
  for (std::size_t i = 0; i < particles_.size(); ++i) {
    if (particles_.shape[i] != Shape::Spheroid) continue;
    const Quaternion& q = particles_.orientation[i];
    const double n2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
    if (!(std::fabs(n2 - 1.0) <= 1e-6))  // the rotation step renormalises by a Newton step
      throw std::invalid_argument("particles.orientation: entry " + std::to_string(i) +
                                  " is not a unit quaternion (|q|^2 = " + std::to_string(n2) + ")");
  }
  const std::string bad = settings_.material.validate();
  if (!bad.empty()) throw std::invalid_argument("material." + bad);
  if (!(settings_.time_step_ratio > 0.0)) throw std::invalid_argument("time_step_ratio: must be > 0");
  law_.set_material(settings_.material);
  monitor_ = StabilityMonitor(settings_.limits);
  time_scale_ = TimeScale::from(particles_.min_minor_semi_axis(), settings_.material.density,
                                settings_.material.young, settings_.time_step_ratio);
  list_.set_skin(settings_.skin_ratio * time_scale_.l0);
  if (settings_.time_step_basis == TimeStepBasis::Contacts) {
    auto_step_ = ContactTimeStep(settings_.time_step_safety, settings_.time_step_max_ratio);
    dt_pending_ = true;
    // The velocities are those of the last half step (what the integrator's
    // max_speed2 saw), so a restarted run takes the same impact bound.
    double v2 = 0.0;
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      v2 = std::max(v2, norm2(particles_.velocity[i]));
      if (particles_.mass[i] < particles_.mass[lightest_]) lightest_ = i;
    }
    impact_v2_ = v2;
  }
  max_bounding_ = particles_.max_bounding_radius();
  for (std::size_t i = 0; i < particles_.size(); ++i)
    max_elongation_ = std::max(max_elongation_, particles_.semi_axes[i].x - particles_.semi_axes[i].y);
  if (settings_.time_step_basis == TimeStepBasis::Contacts) impact_u_ = impact_speed(impact_v2_);
  use_huge_pages();
  list_.build(particles_, cell_);
  update_damping();
}

void Simulation::use_huge_pages() {
  Particles& p = particles_;
  collapse_huge(p.frac);
  collapse_huge(p.velocity);
  collapse_huge(p.omega);
  collapse_huge(p.radius);
  collapse_huge(p.semi_axes);
  collapse_huge(p.orientation);
  reserve_huge(force_, p.size());
  reserve_huge(torque_, p.size());
}

namespace {
void check_damping(const MassDamping& d) {
  const std::string bad = damping_parameter_error(d.model(), d.ratio());
  if (!bad.empty()) throw std::invalid_argument(std::string("damping.") + damping_parameter_name(d.model()) + ": " + bad);
}
}  // namespace

void Simulation::update_damping() {
  const MassDamping& d = settings_.damping;
  check_damping(d);
  std::vector<double> alpha(particles_.size());
  const Material& m = settings_.material;
  for (std::size_t i = 0; i < particles_.size(); ++i)
    alpha[i] = d.alpha(particles_.radius[i], time_scale_.t0, m.young, m.density);
  integrator_.set_coefficients(particles_, alpha, time_scale_.dt);
  integrator_.set_local_damping(d.model() == DampingModel::Local ? LocalDamping(d.ratio()) : LocalDamping());
  contact_forces_.set_viscous_damping(d.model() == DampingModel::Viscous ? ViscousContactDamping(d.ratio())
                                                                         : ViscousContactDamping());
}

void Simulation::set_damping(const MassDamping& d) {
  check_damping(d);  // before anything changes
  settings_.damping = d;
  update_damping();
}

void Simulation::set_friction(double mu) {
  settings_.material.friction = mu;
  law_.set_friction(mu);
}

void Simulation::set_time_step_ratio(double ct) {
  settings_.time_step_ratio = ct;
  const double dt = time_scale_.dt;
  time_scale_ = TimeScale::from(particles_.min_minor_semi_axis(), settings_.material.density,
                                settings_.material.young, ct);
  if (settings_.time_step_basis == TimeStepBasis::Contacts) time_scale_.dt = dt;  // c_t unused there
  update_damping();
}

double Simulation::impact_speed(double max_speed2) const {
  return 2.0 * std::sqrt(max_speed2) + 2.0 * max_bounding_ * frobenius_distance(cell_.velocity_gradient(), 0.0);
}

void Simulation::refresh_time_step(bool contacts) {
  if (contacts) critical_ = ContactTimeStep::critical_step(particles_, list_, law_);
  const std::size_t i = lightest_;
  const Vec3& in = particles_.inertia[i];
  const double a = particles_.semi_axes[i].x;
  critical_.impact = ContactTimeStep::impact_critical_step(
      impact_u_, particles_.mass[i], particles_.radius[i], a * a / std::min(in.x, std::min(in.y, in.z)), law_,
      settings_.material.young, settings_.material.density, time_scale_.t0, time_scale_.l0);
  const double dt = auto_step_.step(critical_, critical_.impact, time_scale_.t0);
  dt_pending_ = false;
  if (dt == time_scale_.dt) return;
  time_scale_.dt = dt;
  time_scale_.ct = dt / time_scale_.t0;
  update_damping();
}

void Simulation::set_thread_governor(std::optional<ThreadGovernor> g) {
  governor_ = g;
  if (governor_) governor_->limit_to_chunks(chunk_count(particles_.size()));
}

bool Simulation::step(bool measure) {
  if (!governor_) return advance(measure);
  // the governor's count for this step only: the caller's is restored (a
  // node that builds its next governor from omp_get_max_threads() must not
  // inherit a capped count)
  struct RestoreThreads {  // also when advance() throws
    int count;
    ~RestoreThreads() { omp_set_num_threads(count); }
  } restore{omp_get_max_threads()};
  omp_set_num_threads(governor_->threads());
  if (governor_->max_threads() == 1) return advance(measure);
  using Clock = std::chrono::steady_clock;
  const std::int64_t builds = list_.rebuild_count();
  const Clock::time_point t = Clock::now();
  const bool ok = advance(measure);
  // a step that rebuilt the list is counted, not timed (thread_governor.h)
  governor_->record_step(std::chrono::duration<double>(Clock::now() - t).count(), list_.rebuild_count() == builds);
  return ok;
}

bool Simulation::advance(bool measure) {
  if (!failure_.empty()) return false;
  const bool check = steps_ % settings_.check_interval == 0;
  measure = measure || check || !energy_.has_reference;
  if (list_.stale(last_max_disp2_, cell_)) list_.build(particles_, cell_);

  contact_forces_.set_motion_clock(motion_clock_, sleep_apart_);
  // The tangential increments of this evaluation span the last step (its dt).
  const ContactSums cs =
      contact_forces_.compute(particles_, cell_, list_, law_, time_scale_.dt, measure, force_, torque_);
  // Contacts basis: the step from t to t+dt from the overlaps at t.
  if (settings_.time_step_basis == TimeStepBasis::Contacts) {
    // dt_crit is refreshed every check_interval steps and whenever the
    // stress (the virial) has changed by 5 % since the last refresh: K ~ sigma^(1/3),
    // so dt_crit has then moved by less than 1 % (contact_time_step.h).
    const double w = frobenius_distance(cs.virial, 0.0);
    const bool refresh = dt_pending_ || steps_ % settings_.check_interval == 0 ||
                         std::fabs(w - refresh_virial_) > 0.05 * refresh_virial_ || (refresh_virial_ == 0.0 && w > 0.0);
    if (refresh) refresh_virial_ = w;
    refresh_time_step(refresh);
  }
  const double dt = time_scale_.dt;
  // Boundary power -sum_c F . (L d) = -sum_ab L_ab W_ba with W = sum d (x) F.
  const Mat3& l = cell_.velocity_gradient();
  double power = 0.0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) power -= l.m[a][b] * cs.virial.m[b][a];
  const double volume = cell_.volume();
  last_virial_ = cs.virial;
  spheroid_stats_.add(cs.spheroid);
  last_force_volume_ = volume;

  const Mat3 h_inverse_before = cell_.h_inverse();
  cell_.deform(dt);
  const IntegrationSums is = integrator_.advance(particles_, cell_, force_, torque_, list_.frac_at_build(), measure,
                                                 &contact_forces_.thread_runs(), &contact_forces_.phase_times(),
                                                 contact_forces_.shared_chunks());
  contact_forces_.thread_runs().end_step();
  last_max_disp2_ = is.max_displacement2;
  if (settings_.time_step_basis == TimeStepBasis::Contacts) impact_u_ = impact_speed(is.max_speed2);
  if (list_.has_spheroids()) {
    // Motion clock: bound on the growth of any pair's gap along a fixed
    // normal in this step (ContactForces::set_motion_clock).
    // ||F_step - I||_F with F_step = H(t+dt) H(t)^-1, plus the rounding of
    // both positions (fractional coordinates in [0, 1) rounded and wrapped
    // each step: < eps |H| each, doubled for safety).
    const double dev = frobenius_distance(cell_.h() * h_inverse_before, 1.0);
    const double increment = 2.0 * std::sqrt(is.max_speed2) * dt +
                             2.0 * max_elongation_ * std::sqrt(is.max_spin2) * dt + 2.0 * max_bounding_ * dev +
                             4.0 * std::numeric_limits<double>::epsilon() * frobenius_distance(cell_.h(), 0.0);
    // Kahan summation: late small increments are not lost to a large clock.
    const double y = increment - motion_clock_carry_;
    const double t = motion_clock_ + y;
    motion_clock_carry_ = (t - motion_clock_) - y;
    motion_clock_ = t;
  }

  if (energy_.has_reference) {
    energy_.boundary_work += power * dt;
    energy_.damping += is.damping_dissipation + cs.viscous_dissipation;
    energy_.friction += cs.friction_dissipation;
  }
  if (measure) {
    energy_.kinetic_translational = is.kinetic_translational;
    energy_.kinetic_rotational = is.kinetic_rotational;
    energy_.elastic = cs.elastic_energy;
    if (!energy_.has_reference) {
      energy_.kinetic_reference = energy_.kinetic();
      energy_.elastic_reference = energy_.elastic;
      energy_.has_reference = true;
    }
    last_contacts_ = cs;
    last_integration_ = is;
    last_volume_ = volume;
    last_time_ = time_;
    last_step_ = steps_;
  }
  time_ += dt;
  ++steps_;
  // Overlap and finiteness are known every step; the energy balance only on
  // measured steps (it needs the kinetic energy).
  if (measure || !is.finite || cs.max_overlap_ratio > settings_.limits.max_overlap_ratio) {
    failure_ = monitor_.check(is.finite, cs.max_overlap_ratio, energy_);
    if (!failure_.empty()) return false;
  }
  return true;
}

std::int64_t Simulation::run(std::int64_t n) {
  std::int64_t k = 0;
  while (k < n && step(false)) ++k;
  return k;
}

Measures Simulation::measures() const {
  if (last_step_ < 0) throw std::logic_error("measures(): no measured step yet");
  Measures m;
  m.time = last_time_;
  m.step = last_step_;
  m.volume = last_volume_;
  const ContactSums& cs = last_contacts_;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) m.stress.m[a][b] = 0.5 * (cs.virial.m[a][b] + cs.virial.m[b][a]) / last_volume_;
  m.principal_stress = principal_values(m.stress);
  m.p = m.stress.trace() / 3.0;
  const double s1 = m.principal_stress.x, s3 = m.principal_stress.z;
  // asin argument clamped: with a tensile s3 the ratio leaves [-1, 1].
  m.phi = (s1 + s3) > 0.0 ? std::asin(std::min(1.0, (s1 - s3) / (s1 + s3))) : 0.0;
  m.q = m.stress.m[2][2] - std::min(m.stress.m[0][0], m.stress.m[1][1]);
  const Vec3 e = cell_.log_strain();
  m.strain = {-e.x, -e.y, -e.z};
  m.volumetric_strain = -cell_.log_volume_strain();
  m.void_ratio = last_volume_ / particles_.solid_volume() - 1.0;

  // Force and moment indices from the resultant contact forces and moments.
  const std::size_t n = particles_.size();
  double sum_fp = 0, sum_fp2 = 0, sum_mp = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double f2 = norm2(force_[i]);
    sum_fp2 += f2;
    sum_fp += std::sqrt(f2);
    sum_mp += norm(torque_[i]);
  }
  const double nc = static_cast<double>(cs.contacts), np = static_cast<double>(n);
  if (cs.contacts > 0 && cs.sum_force > 0) {
    m.ufr = (sum_fp / np) / (cs.sum_force / nc);
    m.iuf = std::sqrt((sum_fp2 / np) / (cs.sum_force2 / nc));
  }
  const Vec3& ps = m.principal_stress;
  const double oct = std::sqrt(ps.x * ps.x + ps.y * ps.y + ps.z * ps.z) / std::sqrt(3.0);
  if (oct > 0) {
    m.moment_index = sum_mp / (last_volume_ * oct);
    m.inertia_index = last_integration_.sum_inertia_moment / (last_volume_ * oct);
  }
  // Coordination with iterative idle removal.
  std::vector<std::pair<std::int32_t, std::int32_t>> contacts;
  contacts.reserve(static_cast<std::size_t>(cs.contacts));
  const PairData& pd = list_.pairs();
  const auto& off = list_.offsets();
  for (std::size_t i = 0; i < n; ++i)
    for (std::int32_t k = off[i]; k < off[i + 1]; ++k)
      if (pd.half_overlap[k] > 0.0) contacts.emplace_back(static_cast<std::int32_t>(i), pd.partner[k]);
  const Coordination c = mechanical_coordination(n, contacts, particles_.mass);
  m.coordination_number = c.mechanical;
  m.raw_coordination_number = 2.0 * nc / np;
  m.idle_mass_fraction = c.idle_mass_fraction;
  m.contacts = cs.contacts;
  m.sliding_contacts = cs.sliding;
  m.max_overlap_ratio = cs.max_overlap_ratio;
  m.spheroid_contact_fallbacks = static_cast<std::int64_t>(spheroid_stats_.fallbacks);
  m.spheroid_contact_failures = static_cast<std::int64_t>(spheroid_stats_.failures);
  m.energy = energy_;
  return m;
}

Mat3 Simulation::current_stress() const {
  Mat3 s;
  if (last_force_volume_ <= 0.0) return s;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) s.m[a][b] = 0.5 * (last_virial_.m[a][b] + last_virial_.m[b][a]) / last_force_volume_;
  return s;
}

SimulationState Simulation::state() const {
  SimulationState s;
  state_into(s);
  return s;
}

void Simulation::state_into(SimulationState& s, bool sorted_contacts) const {
  s.particles = particles_;  // copy-assignment: each array keeps its storage when large enough
  s.h = cell_.h();
  s.h_reference = cell_.h_reference();
  s.velocity_gradient = cell_.velocity_gradient();
  list_.histories_into(particles_, s.contacts, sorted_contacts);
  s.time = time_;
  s.step = steps_;
  s.time_step = time_scale_.dt;
  s.contact_critical_step = critical_.dt;
  s.contact_refresh_virial = refresh_virial_;
  s.energy = energy_;
  s.settings = settings_;
}

std::string describe_time_step(const Simulation& sim) {
  const SimulationSettings& s = sim.settings();
  char text[128];
  if (s.time_step_basis == TimeStepBasis::Contacts)
    std::snprintf(text, sizeof text, "dt from the contacts (safety %g, at most %g T0)", s.time_step_safety,
                  s.time_step_max_ratio);
  else
    std::snprintf(text, sizeof text, "dt = %.4g s (c_t = %.3g)", sim.dt(), sim.time_scale().ct);
  return text;
}

}  // namespace vt::dem
