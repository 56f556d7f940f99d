#include "virtual_triaxial/dem/measures.h"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace vt::dem {

Vec3 principal_values(const Mat3& s) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = 0.5 * (s.m[i][j] + s.m[j][i]);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(m, Eigen::EigenvaluesOnly);
  const Eigen::Vector3d ev = es.eigenvalues();  // ascending
  return {ev(2), ev(1), ev(0)};
}

Coordination mechanical_coordination(std::size_t n_particles,
                                     const std::vector<std::pair<std::int32_t, std::int32_t>>& contacts,
                                     const std::vector<double>& mass) {
  // Section 4.5: particles with fewer than 3 contacts are idle; their
  // contacts are idle too; repeat until no more particles are removed.
  std::vector<std::int32_t> degree(n_particles, 0);
  for (const auto& c : contacts) {
    ++degree[static_cast<std::size_t>(c.first)];
    ++degree[static_cast<std::size_t>(c.second)];
  }
  std::vector<char> idle(n_particles, 0);
  std::vector<char> contact_alive(contacts.size(), 1);
  bool changed = true;
  while (changed) {
    changed = false;
    for (std::size_t i = 0; i < n_particles; ++i)
      if (!idle[i] && degree[i] < 3) {
        idle[i] = 1;
        changed = true;
      }
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      if (!contact_alive[k]) continue;
      const auto a = static_cast<std::size_t>(contacts[k].first), b = static_cast<std::size_t>(contacts[k].second);
      if (idle[a] || idle[b]) {
        contact_alive[k] = 0;
        --degree[a];
        --degree[b];
      }
    }
  }
  Coordination r;
  double idle_mass = 0, total_mass = 0;
  for (std::size_t i = 0; i < n_particles; ++i) {
    total_mass += mass[i];
    if (idle[i]) idle_mass += mass[i];
    else ++r.active_particles;
  }
  for (char a : contact_alive) r.active_contacts += a;
  r.mechanical = r.active_particles > 0 ? 2.0 * static_cast<double>(r.active_contacts) / static_cast<double>(r.active_particles) : 0.0;
  r.idle_mass_fraction = total_mass > 0 ? idle_mass / total_mass : 0.0;
  return r;
}

}  // namespace vt::dem
