// Verlet neighbour list with a skin, built from bin (cell) lists in the
// periodic cell's fractional coordinates (DESIGN §4).
//
// Half list: particle i (storage index) lists the partners j with
// id[j] > id[i], sorted by ascending partner id, in CSR form. The pair's
// orientation is therefore fixed by the stable ids (i = lower id), and so is
// the per-pair data kept with each entry: the tangential spring (contact
// history), keyed by the id pair and carried over on every rebuild.
// A reverse index lists, for each particle, the entries where it is the
// partner, sorted by the other particle's id, so that forces can be gathered
// per particle in a canonical order (ascending partner id) whatever the list
// layout: results do not depend on when the list was rebuilt or on the
// number of threads.
//
// Rebuild criterion: 2 max_p |H (s_p - s_p,build)| + ||H H_build^-1 - I||_F
// * cutoff_max > skin, i.e. no pair can have closed the skin since the build,
// with the affine part of the motion included.
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

/// Per-entry pair data (structure of arrays, indexed by list entry).
struct PairData {
  std::vector<std::int32_t> partner;  ///< storage index of j
  std::vector<Vec3> spring;           ///< tangential force on j [N]
  std::vector<Vec3> force;            ///< total contact force on j [N] (last evaluation)
  std::vector<Vec3> moment_axis;      ///< n x F_on_i [N]; torque on i = l_i * this
  std::vector<double> half_overlap;   ///< delta/2 [m]; 0 when not in contact

  std::size_t size() const { return partner.size(); }
  void resize(std::size_t n);
};

/// A contact's history as stored in sample files: ids and tangential spring.
struct ContactHistory {
  std::int64_t id_a = 0, id_b = 0;  ///< id_a < id_b; spring acts on id_b
  Vec3 spring;
};

class NeighborList {
 public:
  /// skin [m]: extra distance beyond R_i + R_j kept in the list.
  void set_skin(double skin) { skin_ = skin; }
  double skin() const { return skin_; }

  /// Build (or rebuild) the list, carrying springs of existing pairs over.
  /// Throws std::runtime_error if the cell is too small for the cutoff.
  void build(const Particles& p, const PeriodicCell& cell);
  /// True when the rebuild criterion says the list may be stale.
  bool needs_rebuild(const Particles& p, const PeriodicCell& cell) const;
  /// Max over particles of |H (s_p - s_build)|^2, for the rebuild criterion.
  double max_displacement2(const Particles& p, const PeriodicCell& cell) const;
  /// Rebuild criterion given max_p |H (s_p - s_build)|^2 computed elsewhere.
  bool stale(double max_disp2, const PeriodicCell& cell) const;
  /// Fractional positions at the last build (for fused displacement checks).
  const std::vector<Vec3>& frac_at_build() const { return frac_at_build_; }
  bool built() const { return built_; }
  std::int64_t rebuild_count() const { return rebuilds_; }

  const std::vector<std::int32_t>& offsets() const { return offsets_; }
  const std::vector<std::int32_t>& reverse_offsets() const { return rev_offsets_; }
  const std::vector<std::int32_t>& reverse_entries() const { return rev_entries_; }
  PairData& pairs() { return pairs_; }
  const PairData& pairs() const { return pairs_; }

  /// Contacts with a non-zero spring or overlap, for saving.
  std::vector<ContactHistory> histories(const Particles& p) const;
  /// Restore springs after build(); unknown pairs are reported by count.
  std::size_t restore(const Particles& p, const std::vector<ContactHistory>& h);

 private:
  void build_bins(const Particles& p, const PeriodicCell& cell, double cutoff);
  void collect_candidates(const Particles& p, const PeriodicCell& cell,
                          std::vector<std::vector<std::int32_t>>& per_particle) const;
  void build_reverse(const Particles& p);

  double skin_ = 0.0;
  bool built_ = false;
  std::int64_t rebuilds_ = 0;
  double cutoff_max_ = 0.0;
  std::vector<std::int32_t> offsets_;   ///< CSR offsets, size N+1
  PairData pairs_;
  std::vector<std::int32_t> rev_offsets_, rev_entries_;
  std::vector<Vec3> frac_at_build_;
  Mat3 h_at_build_inv_;
  // bins
  int nbins_[3] = {0, 0, 0};
  std::vector<std::int32_t> bin_start_, bin_particles_;
  std::vector<std::int32_t> particle_bin_;
};

}  // namespace vt::dem
