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

namespace {

/// The peeling of section 4.5 (see idle_particles); `contact_alive` gets 0
/// for every removed contact.
std::vector<std::uint8_t> peel_idle(std::size_t n_particles,
                                    const std::vector<std::pair<std::int32_t, std::int32_t>>& contacts,
                                    std::vector<char>& contact_alive) {
  // Section 4.5: particles with fewer than 3 contacts are idle; their
  // contacts are idle too; repeat until no more particles are removed. The
  // particles that remain form the 3-core of the contact graph, which does
  // not depend on the order of removal, so one peeling pass with a work list
  // (O(N + C)) gives the same set as repeated sweeps.
  const std::size_t nc = contacts.size();
  std::vector<std::int32_t> degree(n_particles, 0);
  for (const auto& c : contacts) {
    ++degree[static_cast<std::size_t>(c.first)];
    ++degree[static_cast<std::size_t>(c.second)];
  }
  // Contacts of each particle (CSR).
  std::vector<std::int32_t> start(n_particles + 1, 0), incident(2 * nc);
  for (std::size_t i = 0; i < n_particles; ++i) start[i + 1] = start[i] + degree[i];
  {
    std::vector<std::int32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t k = 0; k < nc; ++k) {
      incident[static_cast<std::size_t>(fill[static_cast<std::size_t>(contacts[k].first)]++)] = static_cast<std::int32_t>(k);
      incident[static_cast<std::size_t>(fill[static_cast<std::size_t>(contacts[k].second)]++)] = static_cast<std::int32_t>(k);
    }
  }
  std::vector<std::uint8_t> idle(n_particles, 0);
  contact_alive.assign(nc, 1);
  std::vector<std::int32_t> work;
  for (std::size_t i = 0; i < n_particles; ++i)
    if (degree[i] < 3) {
      idle[i] = 1;
      work.push_back(static_cast<std::int32_t>(i));
    }
  while (!work.empty()) {
    const auto i = static_cast<std::size_t>(work.back());
    work.pop_back();
    for (std::int32_t s = start[i]; s < start[i + 1]; ++s) {
      const auto k = static_cast<std::size_t>(incident[static_cast<std::size_t>(s)]);
      if (!contact_alive[k]) continue;
      contact_alive[k] = 0;
      const auto a = static_cast<std::size_t>(contacts[k].first), b = static_cast<std::size_t>(contacts[k].second);
      --degree[a];
      --degree[b];
      const std::size_t j = a == i ? b : a;
      if (!idle[j] && degree[j] < 3) {
        idle[j] = 1;
        work.push_back(static_cast<std::int32_t>(j));
      }
    }
  }
  return idle;
}

}  // namespace

std::vector<std::uint8_t> idle_particles(std::size_t n_particles,
                                         const std::vector<std::pair<std::int32_t, std::int32_t>>& contacts) {
  std::vector<char> contact_alive;
  return peel_idle(n_particles, contacts, contact_alive);
}

Coordination mechanical_coordination(std::size_t n_particles,
                                     const std::vector<std::pair<std::int32_t, std::int32_t>>& contacts,
                                     const std::vector<double>& mass) {
  std::vector<char> contact_alive;
  const std::vector<std::uint8_t> idle = peel_idle(n_particles, contacts, contact_alive);
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
