#include "virtual_triaxial/dem/specimen_snapshot.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "virtual_triaxial/dem/contact_forces.h"
#include "virtual_triaxial/dem/measures.h"

namespace vt::dem {

namespace {

/// Relative margin of the sliding test: the Coulomb cap rescales F_t to
/// mu |F_n| up to a few roundings.
constexpr double kSlidingMargin = 1e-9;

Mat3 symmetric_stress(const Mat3& virial, double volume) {
  Mat3 s;
  if (!(volume > 0.0)) return s;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) s.m[a][b] = 0.5 * (virial.m[a][b] + virial.m[b][a]) / volume;
  return s;
}

SpecimenSnapshot build(const Particles& p, const PeriodicCell& cell, const NeighborList& list, double friction) {
  SpecimenSnapshot s;
  const std::size_t n = p.size();
  s.h = cell.h();
  const Vec3 e = cell.log_strain();
  s.strain = {-e.x, -e.y, -e.z};
  s.id = p.id;
  s.shape = p.shape;
  s.radius = p.radius;
  s.semi_axes = p.semi_axes;
  s.orientation = p.orientation;
  s.velocity = p.velocity;
  s.spin = p.omega;
  s.position.resize(n);
  for (std::size_t i = 0; i < n; ++i) s.position[i] = cell.h() * p.frac[i];

  const PairData& pd = list.pairs();
  const std::vector<std::int32_t>& off = list.offsets();
  if (off.size() != n + 1) throw std::logic_error("SpecimenSnapshot: the neighbour list is not built");
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;
  for (std::size_t i = 0; i < n; ++i)
    for (std::int32_t k = off[i]; k < off[i + 1]; ++k) {
      const auto e_k = static_cast<std::size_t>(k);
      if (!(pd.half_overlap[e_k] > 0.0)) continue;
      SnapshotContact c;
      c.i = static_cast<std::int32_t>(i);
      c.j = pd.partner[e_k];
      c.branch = cell.branch(p.frac[i], p.frac[static_cast<std::size_t>(c.j)]);
      c.tangential_force = pd.spring[e_k];
      c.normal_force = pd.force[e_k] - pd.spring[e_k];
      c.overlap = 2.0 * pd.half_overlap[e_k];
      const double cap = friction * norm(c.normal_force);
      c.sliding = norm(c.tangential_force) >= cap * (1.0 - kSlidingMargin) && cap > 0.0;
      s.contacts.push_back(c);
      pairs.emplace_back(c.i, c.j);
    }
  s.contact_count.assign(n, 0);
  for (const auto& c : pairs) {
    ++s.contact_count[static_cast<std::size_t>(c.first)];
    ++s.contact_count[static_cast<std::size_t>(c.second)];
  }
  s.idle = idle_particles(n, pairs);
  return s;
}

}  // namespace

SpecimenSnapshot SpecimenSnapshot::of(const Simulation& sim) {
  if (!sim.has_forces()) return from_state(sim.state());  // not stepped yet: no pair states
  SpecimenSnapshot s = build(sim.particles(), sim.cell(), sim.neighbor_list(), sim.settings().material.friction);
  s.time = sim.time();
  s.step = sim.steps();
  s.stress = sim.current_stress();
  return s;
}

SpecimenSnapshot SpecimenSnapshot::from_state(const SimulationState& state) {
  const Particles& p = state.particles;
  const SimulationSettings& st = state.settings;
  if (p.size() < 2) throw std::invalid_argument("particles: at least 2 particles are needed");
  const PeriodicCell cell(state.h, state.h_reference);
  const TimeScale ts =
      TimeScale::from(p.min_minor_semi_axis(), st.material.density, st.material.young, st.time_step_ratio);
  NeighborList list;
  list.set_skin(st.skin_ratio * ts.l0);
  list.build(p, cell);
  const std::size_t missing = list.restore(p, state.contacts);
  if (missing > 0)
    throw std::runtime_error("contacts: " + std::to_string(missing) +
                             " stored contact(s) join particles that are not within reach");
  const HertzMindlin law(st.material);
  ContactForces forces;
  std::vector<Vec3> force(p.size()), torque(p.size());
  const ContactSums cs = forces.compute(p, cell, list, law, 0.0, true, force, torque);
  SpecimenSnapshot s = build(p, cell, list, st.material.friction);
  s.time = state.time;
  s.step = state.step;
  s.stress = symmetric_stress(cs.virial, cell.volume());
  return s;
}

double SpecimenSnapshot::total_normal_force() const {
  double sum = 0.0;
  for (const SnapshotContact& c : contacts) sum += norm(c.normal_force);
  return sum;
}

}  // namespace vt::dem
