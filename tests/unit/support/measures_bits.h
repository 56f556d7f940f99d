// Bit patterns of doubles and of every number of a sample (dem::Measures),
// for tests that compare two runs bit for bit (a resumed run against an
// uninterrupted one, headless and on the rig).
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include "virtual_triaxial/dem/measures.h"

namespace vt::test {

inline std::vector<std::uint64_t> bits(const std::vector<double>& v) {
  std::vector<std::uint64_t> b(v.size());
  std::memcpy(b.data(), v.data(), v.size() * sizeof(double));
  return b;
}

/// Every number of a sample, as bits (the fields a runner does not fill are
/// 0 in both runs compared).
inline std::vector<std::uint64_t> bits(const dem::Measures& m) {
  std::vector<double> v = {m.time, m.p, m.q, m.phi, m.volumetric_strain, m.volume, m.void_ratio, m.ufr, m.iuf,
                           m.moment_index, m.inertia_index, m.coordination_number, m.raw_coordination_number,
                           m.idle_mass_fraction, m.max_overlap_ratio, m.energy.boundary_work, m.energy.damping,
                           m.energy.friction, m.energy.kinetic_translational, m.energy.kinetic_rotational,
                           m.energy.elastic, m.energy.kinetic_reference, m.energy.elastic_reference,
                           static_cast<double>(m.step), static_cast<double>(m.contacts),
                           static_cast<double>(m.sliding_contacts), m.energy.has_reference ? 1.0 : 0.0};
  for (int i = 0; i < 3; ++i) {
    v.push_back(m.principal_stress[i]);
    v.push_back(m.strain[i]);
    for (int j = 0; j < 3; ++j) v.push_back(m.stress(i, j));
  }
  return bits(v);
}

}  // namespace vt::test
