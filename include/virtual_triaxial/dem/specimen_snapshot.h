// The specimen at one instant, for viewers: particles and the contact network
// in the cell frame (x = H s, origin at the cell corner), SI units. Used by
// the VTK snapshots (io/vtk_snapshot_writer.h), dem_node's RViz markers and,
// through the snapshots, the section pictures (scripts/specimen_section.py).
//
// Built read-only from a Simulation: its particles, its cell and the pair
// states of the neighbour list (NeighborList::pairs()) left by the last force
// evaluation. Nothing is computed during the step for it, so a run without
// snapshots costs nothing. Positions are the current ones, forces those of
// the last evaluation (one step earlier, as in the dumps of other DEM codes;
// for the quasi-static runs here the branch vectors differ by |v| dt).
//
// Per contact (pairs with positive overlap; i the lower id, forces on j):
//   branch            x_j - x_i, minimum image, current positions     [m]
//   normal_force      F - F_t = |F_n| n (eq. 107)                     [N]
//   tangential_force  F_t, the stored Mindlin spring after the cap     [N]
//   overlap           delta = 2 half_overlap                          [m]
//   sliding           |F_t| >= mu |F_n| (1 - 1e-9): at the Coulomb cap (eq.
//                     113); the cap rescales F_t to mu |F_n| up to rounding
// Per particle: contact count and the idle flag of section 4.5
// (dem/measures.h idle_particles: iterative removal of particles with fewer
// than 3 contacts).
// from_state() gives the same picture of a saved state (a sample file) by one
// force evaluation at dt = 0: no tangential increment, the stored springs as
// they are (rotated into the tangent plane and capped, as a step would).
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/simulation.h"

namespace vt::dem {

struct SnapshotContact {
  std::int32_t i = 0, j = 0;   ///< storage indices (i: lower id)
  Vec3 branch;                 ///< [m] x_j - x_i (minimum image)
  Vec3 normal_force;           ///< [N] on j
  Vec3 tangential_force;       ///< [N] on j
  double overlap = 0;          ///< [m]
  bool sliding = false;
};

struct SpecimenSnapshot {
  double time = 0;             ///< [s]
  std::int64_t step = 0;
  Mat3 h;                      ///< cell matrix, columns = edges [m]
  Vec3 strain;                 ///< log strain of the cell, compression positive
  Mat3 stress;                 ///< [Pa] the core's Love-Weber stress of the last evaluation, compression positive
  // particles, in storage order
  std::vector<std::int64_t> id;
  std::vector<Shape> shape;
  std::vector<Vec3> position;      ///< [m] x = H s, s in [0, 1)^3
  std::vector<double> radius;      ///< [m] nominal (equal-volume)
  std::vector<Vec3> semi_axes;     ///< [m] (a, b, b)
  std::vector<Quaternion> orientation;  ///< body -> world
  std::vector<Vec3> velocity;      ///< [m/s] fluctuating (non-affine) velocity
  std::vector<Vec3> spin;          ///< [rad/s] angular velocity, world frame
  std::vector<std::int32_t> contact_count;
  std::vector<std::uint8_t> idle;  ///< 1: idle (section 4.5)
  std::vector<SnapshotContact> contacts;

  /// The snapshot of a running simulation (its last force evaluation).
  static SpecimenSnapshot of(const Simulation& sim);
  /// The snapshot of a saved state (a sample file), see the header comment.
  static SpecimenSnapshot from_state(const SimulationState& state);
  /// sum over contacts of |F_n| [N].
  double total_normal_force() const;
};

}  // namespace vt::dem
