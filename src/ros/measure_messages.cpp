// dem::Measures -> state messages. See measure_messages.h.
#include "virtual_triaxial/ros/measure_messages.h"

namespace vt::ros {

std_msgs::Header make_header(const TickStamp& s) {
  std_msgs::Header h;
  h.stamp.fromSec(s.time);
  h.frame_id = "cell";
  return h;
}

virtual_triaxial::Stress to_stress_msg(const dem::Measures& m, const TickStamp& s, double control_period,
                                       double young, const dem::Vec3& stiffness) {
  virtual_triaxial::Stress msg;
  msg.header = make_header(s);
  msg.tick = s.tick;
  msg.time = s.time;
  msg.control_period = control_period;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) msg.stress[static_cast<std::size_t>(3 * r + c)] = m.stress(r, c);
  for (int i = 0; i < 3; ++i) {
    msg.principal[static_cast<std::size_t>(i)] = m.principal_stress[i];
    msg.stiffness[static_cast<std::size_t>(i)] = stiffness[i];
  }
  msg.p = m.p;
  msg.q = m.q;
  msg.phi = m.phi;
  msg.sigma_bar_p = m.p / young;
  return msg;
}

virtual_triaxial::Strain to_strain_msg(const dem::Measures& m, const TickStamp& s, const dem::Vec3& rates,
                                       double t0) {
  virtual_triaxial::Strain msg;
  msg.header = make_header(s);
  msg.tick = s.tick;
  msg.time = s.time;
  for (int i = 0; i < 3; ++i) {
    const auto k = static_cast<std::size_t>(i);
    msg.strain[k] = m.strain[i];
    msg.strain_rate[k] = rates[i];
    msg.strain_rate_dimensionless[k] = rates[i] * t0;
  }
  msg.volumetric = m.volumetric_strain;
  return msg;
}

virtual_triaxial::MomentIndex to_moment_index_msg(const dem::Measures& m, const TickStamp& s) {
  virtual_triaxial::MomentIndex msg;
  msg.header = make_header(s);
  msg.tick = s.tick;
  msg.time = s.time;
  msg.moment_index = m.moment_index;
  msg.ufr = m.ufr;
  msg.iuf = m.iuf;
  msg.inertia_index = m.inertia_index;
  return msg;
}

virtual_triaxial::KineticEnergy to_kinetic_energy_msg(const dem::Measures& m, const TickStamp& s) {
  virtual_triaxial::KineticEnergy msg;
  msg.header = make_header(s);
  msg.tick = s.tick;
  msg.time = s.time;
  const dem::EnergyBudget& e = m.energy;
  msg.translational = e.kinetic_translational;
  msg.rotational = e.kinetic_rotational;
  msg.boundary_work = e.boundary_work;
  msg.elastic = e.elastic;
  msg.damping = e.damping;
  msg.friction = e.friction;
  msg.balance_error = e.balance_error();
  msg.relative_balance_error = e.relative_balance_error();
  return msg;
}

virtual_triaxial::Fabric to_fabric_msg(const dem::Measures& m, const TickStamp& s) {
  virtual_triaxial::Fabric msg;
  msg.header = make_header(s);
  msg.tick = s.tick;
  msg.time = s.time;
  msg.void_ratio = m.void_ratio;
  msg.coordination_number = m.coordination_number;
  msg.raw_coordination_number = m.raw_coordination_number;
  msg.idle_mass_fraction = m.idle_mass_fraction;
  msg.contacts = static_cast<std::uint64_t>(m.contacts);
  msg.sliding_contacts = static_cast<std::uint64_t>(m.sliding_contacts);
  return msg;
}

dem::Measures measures_from_messages(const virtual_triaxial::Stress& stress, const virtual_triaxial::Strain& strain,
                                     const virtual_triaxial::MomentIndex& moment,
                                     const virtual_triaxial::KineticEnergy& energy,
                                     const virtual_triaxial::Fabric& fabric, std::int64_t step) {
  dem::Measures m;
  m.time = stress.time;
  m.step = step;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m.stress(r, c) = stress.stress[static_cast<std::size_t>(3 * r + c)];
  for (int i = 0; i < 3; ++i) {
    const auto k = static_cast<std::size_t>(i);
    m.principal_stress[i] = stress.principal[k];
    m.strain[i] = strain.strain[k];
  }
  m.p = stress.p;
  m.q = stress.q;
  m.phi = stress.phi;
  m.volumetric_strain = strain.volumetric;
  m.void_ratio = fabric.void_ratio;
  m.ufr = moment.ufr;
  m.iuf = moment.iuf;
  m.moment_index = moment.moment_index;
  m.inertia_index = moment.inertia_index;
  m.coordination_number = fabric.coordination_number;
  m.raw_coordination_number = fabric.raw_coordination_number;
  m.idle_mass_fraction = fabric.idle_mass_fraction;
  m.contacts = static_cast<std::int64_t>(fabric.contacts);
  m.sliding_contacts = static_cast<std::int64_t>(fabric.sliding_contacts);
  dem::EnergyBudget& e = m.energy;
  e.kinetic_translational = energy.translational;
  e.kinetic_rotational = energy.rotational;
  e.boundary_work = energy.boundary_work;
  e.elastic = energy.elastic;
  e.damping = energy.damping;
  e.friction = energy.friction;
  e.elastic_reference = energy.balance_error - e.balance_error();  // balance_error() is linear in it
  return m;
}

}  // namespace vt::ros
