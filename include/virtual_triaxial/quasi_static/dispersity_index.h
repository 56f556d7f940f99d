// Dispersity index of an explicit particle list (Yousefi 2017, eq. 80):
//   Delta = d_avg / d_min, d_avg the mass-weighted mean nominal diameter
//   (mass ~ r^3), d_min the smallest nominal diameter [-], >= 1.
// (The PSD form, from type fractions, is io::dispersity_index(Psd).)
#pragma once

#include <vector>

namespace vt::quasi_static {

/// Throws std::invalid_argument for an empty list or a radius that is <= 0
/// or non-finite (naming its index). Radii [m].
double dispersity_index(const std::vector<double>& nominal_radii);

}  // namespace vt::quasi_static
