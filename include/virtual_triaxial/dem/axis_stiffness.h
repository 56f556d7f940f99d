// Tangent stiffness of the packing per cell axis, for servo control.
//
// Under an affine strain increment deps_ii along axis i, a contact with
// branch d and normal n changes its normal overlap by -deps d_i n_i and its
// tangential displacement by deps d_i (e_i - n_i n). With the contact
// stiffnesses K_n (eq. 115-116) and K_t (eq. 114) the stress changes by
//   M_i = dsigma_ii / deps_ii = (1/V) sum_c d_i^2 (K_n n_i^2 + K_t (1 - n_i^2))   [Pa]
// (compression positive). Sliding is ignored, so M_i is an upper bound and a
// servo gain g <= 1 stays stable. K_n = 3/2 |F_n| / delta for Hertz. The
// term of one contact: axis_stiffness_term.h.
#pragma once

#include "virtual_triaxial/dem/simulation.h"

namespace vt::dem {

/// M_i for the contacts of the last force evaluation [Pa]. After a measured
/// step (step(true)) from that evaluation's contact sums
/// (ContactSums::axis_stiffness_sum, summed per chunk with the other contact
/// sums: no pass of its own, and the same on any number of threads), else by
/// a pass over the neighbour list (axis_stiffness_of_list). The two differ
/// slightly: the order of the sums, and the list pass takes the branches
/// and the volume one step on (the particles' and the cell's motion).
Vec3 axis_stiffness(const Simulation& sim);

/// M_i by a pass over the neighbour list: the pair states' forces and
/// overlaps, the branches at the current positions, summed in list order [Pa].
Vec3 axis_stiffness_of_list(const Simulation& sim);

}  // namespace vt::dem
