// Verlet neighbour list with a skin, built from bin (cell) lists in the
// periodic cell's fractional coordinates (DESIGN §4).
//
// Half list: particle i (storage index) lists the partners j with
// id[j] > id[i], sorted by ascending partner id, in CSR form. The pair's
// orientation is therefore fixed by the stable ids (i = lower id), and so is
// the per-pair data kept with each entry: the tangential spring (contact
// history), keyed by the id pair and carried over on every rebuild.
// Entries are in list order: by owner storage index, then ascending partner
// id. For a pair that is listed, its place in that order depends only on the
// pair (the storage order never changes during a run), not on which other
// pairs the list holds. Forces are summed per particle in list order over
// the entries it is part of (the pair loop adds them in that order,
// ContactForces), so results do not depend on when the list was rebuilt or
// on the number of threads.
//
// Spheroids: the pair test uses the bounding radius (semi_axes.x = major
// semi-axis a; = R for spheres). When the particles include spheroids
// (has_spheroids()), every entry also carries a SpheroidPairState: the
// warm-start cache of the common-normal solver (spheroid_contact.h), keyed
// and carried over like the spring, and the time the pair sleeps to.
//
// Rebuild criterion: 2 max_p |H (s_p - s_p,build)| + ||H H_build^-1 - I||_F
// * cutoff_max > skin, i.e. no pair can have closed the skin since the build,
// with the affine part of the motion included.
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"
#include "virtual_triaxial/dem/spheroid_contact.h"
#include "virtual_triaxial/dem/vec3.h"

namespace vt::dem {

/// Result of the last force evaluation of one list entry, read by the
/// measures, the servo's axis stiffness, the contact time step and the
/// list's keep rule. Half a cache line, aligned: the pair loop writes it for
/// every contact at every step (session 37: 32 bytes instead of a 64-byte
/// line holding the moment too, which only a gather of every particle's
/// sums read; without it one thread is 2.6-2.8 % faster at 12 000 spheres
/// and spheroids and 4.8 % at 10^5 spheres).
struct alignas(32) PairState {
  Vec3 force;                ///< total contact force on j [N]; zero when not in contact
  double half_overlap = 0;   ///< delta/2 [m]; 0 when not in contact
};
static_assert(sizeof(PairState) == 32, "PairState: half a cache line per list entry");

/// Per-entry state of a pair that involves a spheroid (only kept when the
/// particles include spheroids): one cache line.
struct alignas(64) SpheroidPairState {
  SpheroidContactCache cache;  ///< warm start of the contact solver
  /// The pair was found apart with gap g < 0 along some fixed normal when the
  /// motion clock (ContactForces::set_motion_clock) read C0; it stays apart
  /// while the clock reads below wake = C0 - g/2 (0: awake) [m]. Always
  /// finite and >= 0 (the pair loop sets it to 0 when the pair leaves reach).
  double wake = 0.0;
};
static_assert(sizeof(SpheroidPairState) == 64, "SpheroidPairState: one cache line per list entry");

/// Read-only view of one field of PairData::state, indexed by list entry
/// (pd.force[e], pd.half_overlap[e] read as if they were arrays).
template <class T, T PairState::*Field>
class PairField {
 public:
  explicit PairField(const std::vector<PairState>* v) : v_(v) {}
  PairField(const PairField&) = delete;
  PairField& operator=(const PairField&) = delete;
  const T& operator[](std::size_t e) const { return (*v_)[e].*Field; }
  std::size_t size() const { return v_->size(); }

 private:
  const std::vector<PairState>* v_;
};

/// Per-entry pair data, indexed by list entry.
struct PairData {
  std::vector<std::int32_t> partner;  ///< storage index of j
  std::vector<Vec3> spring;           ///< tangential force on j [N]
  std::vector<PairState> state;       ///< last evaluation (force, overlap)
  std::vector<std::uint8_t> active;   ///< 1: in contact at the last evaluation (= half_overlap != 0)
  std::vector<SpheroidPairState> spheroid;  ///< empty unless the particles include spheroids
  // Read-only views of the fields of `state`.
  PairField<Vec3, &PairState::force> force{&state};              ///< force on j [N]
  PairField<double, &PairState::half_overlap> half_overlap{&state};  ///< delta/2 [m]

  PairData() = default;
  PairData(const PairData& o)
      : partner(o.partner), spring(o.spring), state(o.state), active(o.active), spheroid(o.spheroid) {}
  PairData(PairData&& o) noexcept
      : partner(std::move(o.partner)),
        spring(std::move(o.spring)),
        state(std::move(o.state)),
        active(std::move(o.active)),
        spheroid(std::move(o.spheroid)) {}
  PairData& operator=(const PairData& o) {
    partner = o.partner;
    spring = o.spring;
    state = o.state;
    active = o.active;
    spheroid = o.spheroid;
    return *this;
  }
  PairData& operator=(PairData&& o) noexcept {
    partner = std::move(o.partner);
    spring = std::move(o.spring);
    state = std::move(o.state);
    active = std::move(o.active);
    spheroid = std::move(o.spheroid);
    return *this;
  }

  std::size_t size() const { return partner.size(); }
  /// Resize every per-entry array; `spheroids` sizes the spheroid states too.
  void resize(std::size_t n, bool spheroids = false);
};

/// A contact's history as stored in sample files: ids, tangential spring
/// and, for pairs with a spheroid, the contact solver's warm-start cache
/// (needed for a bit-for-bit restart: the converged normal depends on the
/// start in its last bits).
struct ContactHistory {
  std::int64_t id_a = 0, id_b = 0;  ///< id_a < id_b; spring acts on id_b
  Vec3 spring;
  SpheroidContactCache cache{};     ///< invalid for sphere pairs
};

/// Orders histories by (id_a, id_b), the order NeighborList::histories gives.
void sort_histories(std::vector<ContactHistory>& h);

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
  /// True when the last build saw spheroids (pairs().spheroid is then sized).
  bool has_spheroids() const { return spheroids_; }
  std::int64_t rebuild_count() const { return rebuilds_; }

  const std::vector<std::int32_t>& offsets() const { return offsets_; }
  /// Owner (storage index of i, the lower id) of every entry.
  const std::vector<std::int32_t>& owners() const { return owners_; }
  PairData& pairs() { return pairs_; }
  const PairData& pairs() const { return pairs_; }

  /// Contacts with a non-zero spring or overlap, or a valid spheroid solver
  /// cache, for saving, ordered by (id_a, id_b).
  std::vector<ContactHistory> histories(const Particles& p) const;
  /// The same into `out`, reusing its storage (and the list's scratch for
  /// the sort keys): no allocation once the buffers have grown. `sorted` =
  /// false leaves them in list order, for a caller that sorts them only
  /// when it uses them (sort_histories; a runner keeping the last good
  /// state at every sample). Not for concurrent calls on one list.
  void histories_into(const Particles& p, std::vector<ContactHistory>& out, bool sorted = true) const;
  /// Restore springs after build(); unknown pairs are reported by count.
  /// Only on a list no team of threads has evaluated since its build: the
  /// threads' ghost copies of per-entry state follow on from their last
  /// evaluation (split_sums.h) and would not see it.
  std::size_t restore(const Particles& p, const std::vector<ContactHistory>& h);

 private:
  /// A history's sort key (histories_into).
  struct HistoryKey {
    std::int64_t id_a, id_b;
    std::int32_t entry;
  };
  mutable std::vector<HistoryKey> history_keys_;  ///< scratch of histories_into
  void build_bins(const Particles& p, const PeriodicCell& cell, double cutoff);
  void collect_candidates(const Particles& p, const PeriodicCell& cell,
                          std::vector<std::vector<std::int32_t>>& per_particle) const;
  void build_owners(const Particles& p);  ///< owners_ from offsets_

  double skin_ = 0.0;
  bool built_ = false;
  bool spheroids_ = false;
  std::int64_t rebuilds_ = 0;
  double cutoff_max_ = 0.0;
  std::vector<std::int32_t> offsets_;   ///< CSR offsets, size N+1
  PairData pairs_;
  std::vector<std::int32_t> owners_;
  std::vector<Vec3> frac_at_build_;
  Mat3 h_at_build_inv_;
  // bins
  int nbins_[3] = {0, 0, 0};
  std::vector<std::int32_t> bin_start_, bin_particles_;
  std::vector<std::int32_t> particle_bin_;
};

}  // namespace vt::dem
