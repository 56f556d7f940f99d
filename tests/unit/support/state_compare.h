// Bit-for-bit comparisons of simulation states shared by the restart and
// determinism tests (test_restart, test_spheroid_restart_sleep).
#pragma once

#include <cstring>
#include <vector>

#include "virtual_triaxial/dem/simulation.h"

namespace vt::test {

/// The two vectors hold the same bytes.
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

/// Expects two states equal bit for bit: positions, velocities, spins,
/// orientations, contact histories (ids, springs, solver caches' validity),
/// cell, step, time and energy terms.
void expect_same_state(const dem::SimulationState& a, const dem::SimulationState& b);

}  // namespace vt::test
