// Contact force evaluation over the neighbour list: spheres (below) and,
// when the particles include spheroids, the spheroid path (further below).
//
// For each listed pair (i = lower id, j = partner):
//   d = minimum-image branch vector x_j - x_i, n = d/|d|,
//   delta = R_i + R_j - |d| (overlap), R* = R_i R_j / (R_i + R_j) (eq. 104);
//   relative velocity of the contact point of j w.r.t. i
//     v_c = v_j - v_i + L d - (l_i w_i + l_j w_j) x n,  l = R - delta/2,
//   (v are fluctuating velocities, L d the affine part of the relative motion);
//   its tangential part times dt drives the Hertz-Mindlin spring (eq. 113).
// Per-pair results are stored in the list. The per-particle resultant force
// and moment (about the centroid) add each particle's contacts in list order
// (NeighborList), whichever way they are made:
//   - one thread: the pair loop, which visits the pairs in list order, adds
//     them to both particles as it goes;
//   - several threads: thread t takes its run of chunks (thread_runs.h, cut
//     by measured speed) and sums its run's particles in its own pair loop;
//     the pairs owned in other runs whose partner is home are evaluated
//     again by it as ghosts, before and after its chunks (the pair kernel
//     itself, on its own copies of their per-entry state), so that the
//     order stays the list's (split_sums.h); no gather of every particle.
// Same terms, same order, same bits (the torque terms use fused_multiply_add
// so that compiler contraction cannot differ between them). The sums
// therefore depend on the storage order (fixed during a run) but not on the
// thread count, the runs or when the list is rebuilt.
// Torques: contact point at x_i + l_i n, so T_i = l_i (n x F_i), T_j = l_j (n x F_i).
// With viscous contact damping (set_viscous_damping) each contact's force
// also holds its dashpots, evaluated with the same v_c (so they enter the
// stress, the torques and the sums like the springs).
//
// Spheroids (chapter 4; used only when NeighborList::has_spheroids(), so a
// sample of spheres never runs this code): pairs whose bounding spheres
// (radius max(a, b) = a, prolate) overlap go through the common-normal
// solver (spheroid_contact.h; warm-started from the pair's cache kept with
// its spring; the warm one-step case 16 pairs at a time,
// spheroid_warm_lanes.h; fallbacks and failures counted in
// ContactSums::spheroid). A pair
// with a spheroid gives overlap delta, normal n and contact point c
// (relative to x_i); sphere-sphere pairs of a mixed sample take the closed
// form (no solver). Hertz-Mindlin (hertz_mindlin.h) with R* from the average
// radii R_i = (a_i + 2 b_i)/3 (eq. 104; R for a sphere), applied at c:
//   v_c = v_j - v_i + L d + w_j x (c - d) - w_i x c        [m/s]
//   T_i = c x F_on_i,  T_j = (c - d) x F_on_j               [N m]
// (both normal and tangential parts: normal forces give moments on
// spheroids). max_overlap_ratio is then delta / min(b_i, b_j). Summation
// order and chunking as for spheres, so results are deterministic.
//
// Code: the pair kernels are src/dem/sphere_pairs.cpp and
// src/dem/spheroid_pairs.cpp (what they share: src/dem/pair_kernel.h);
// compute() (contact_forces.cpp) runs them over chunks and makes the sums.
//
// Performance notes (bench/triax_bench.cpp measures them): the pairs of a
// 512-particle chunk are first tested for contact in one branch-free pass,
// then only the contacts are evaluated, 16 at a time for spheres: their
// inputs gathered into arrays, the contact law (hertz_mindlin.h, written
// with selects instead of jumps) run by one loop the compiler vectorises
// (AVX2/AVX-512 with -march=native), the results stored and summed one by
// one in list order (1.3x faster than one contact at a time at 12 000
// particles; the same bits). The per-pair results (force and half overlap)
// sit in half a cache line per entry (PairState); partner data and
// pair states are prefetched in software; Vec3 results are stored one
// component at a time (a whole-Vec3 store went through a stack slot, a
// store-forwarding stall). There is no gather of each particle's sums from
// the pair states after the pair loop (sessions 7-36 kept one for A/B: its
// scattered reads of other particles' pair states were the step's largest
// cost growth with N, and it cost 12 % even where they fit the L2 cache;
// session 37 removed it with the moments it needed in the states); on several
// threads the pairs that cross the runs are evaluated twice (ghosts,
// split_sums.h: no pair state is read by another thread; against the
// completions from the pair states that sessions 16-35 made after a
// barrier, at 12 000 dense particles on two threads with the host's two
// vCPUs far apart 0.889 of the time for spheres and 0.915 for spheroids,
// near 1.020 and 1.011, session 36).
// The order of every sum is the one of the plain loops (list order for the
// chunk sums and per particle), so the results do not depend on these
// choices.
// Spheroid path: the support data of every particle (b^2, a^2 - b^2 and the
// symmetry axis e = q (1,0,0), SpheroidSupport) and its Hertz radius
// (eq. 104) are computed once per evaluation, not once per pair; the
// separation certificate is evaluated at the warm start, and a solve reuses
// those support values (SpheroidStart); a pair found apart sleeps until the
// motion clock says it may touch (set_motion_clock: on the bench about 1.9
// of the 3.2 pairs in reach per particle sleep). The warm solves and the contact
// law run 16 pairs at a time as SIMD (spheroid_warm_lanes.h,
// spheroid_pairs.cpp). Several threads take the thread runs as for
// spheres (support data included, a barrier after it) and the same ghosts
// (their copies include the solver caches and wake times).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/hertz_mindlin.h"
#include "virtual_triaxial/dem/neighbor_list.h"
#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"
#include "virtual_triaxial/dem/phase_times.h"
#include "virtual_triaxial/dem/pair_body.h"
#include "virtual_triaxial/dem/spheroid_contact.h"
#include "virtual_triaxial/dem/split_sums.h"
#include "virtual_triaxial/dem/viscous_contact_damping.h"

namespace vt::dem {

namespace pairs {
struct PairInputs;  // src/dem/pair_kernel.h
}

/// Sums over all contacts of one force evaluation.
struct ContactSums {
  Mat3 virial;                      ///< sum d (x) F_on_j [N m]; /V = stress, compression positive
  double elastic_energy = 0;        ///< [J] (only when measuring)
  double friction_dissipation = 0;  ///< this step [J]
  double viscous_dissipation = 0;   ///< by the contact dashpots, this step [J] (viscous_contact_damping.h)
  double max_overlap_ratio = 0;     ///< max delta / min(R_i, R_j)
  std::int64_t contacts = 0;
  std::int64_t sliding = 0;
  double sum_force = 0;             ///< sum |F_c| [N] (only when measuring)
  double sum_force2 = 0;            ///< sum |F_c|^2 [N^2] (only when measuring)
  /// sum_c d_a^2 (K_n n_a^2 + K_t (1 - n_a^2)) per axis a [N m]; /V = the
  /// axis stiffness M_a (axis_stiffness.h, axis_stiffness_term.h; only when measuring)
  Vec3 axis_stiffness_sum;
  SpheroidContactStats spheroid;   ///< contact-solver counters (pairs with a spheroid)

  void add(const ContactSums& o);
};

class ContactForces {
 public:
  /// Evaluate every pair and sum the per-particle force and torque.
  /// `measure` adds the per-contact force norms needed by UFR and I_uf, the
  /// elastic energy and the servo's axis stiffness terms.
  ContactSums compute(const Particles& p, const PeriodicCell& cell, NeighborList& list,
                      const HertzMindlin& law, double dt, bool measure,
                      std::vector<Vec3>& force, std::vector<Vec3>& torque);

  /// Spheroid path: the motion clock C [m], a running sum over the steps
  /// taken of a bound on how much the gap g(n) = h_i(n) + h_j(n) - n.d of
  /// any pair in reach can grow along any fixed unit n in one step
  /// (Simulation keeps it: 2 max|v| dt + 2 max(a - b) max|w| dt +
  /// 2 max(a) ||F_step - I||_F, as |d(n.d)| <= |dd|, |d| < a_i + a_j and
  /// |dh/dtheta| <= a - b for a turn theta of the symmetry axis). A pair in
  /// reach found apart with g < 0 sleeps (is not evaluated) until C has grown
  /// by (-g - floor)/2 or the pair leaves reach: it cannot touch before
  /// (floor = 64 eps (a_i + a_j + C) covers the rounding of g and of C; the
  /// clock also counts 4 eps |H| per step for the rounding of positions and
  /// is summed with compensation). Evaluating a pair found apart changes
  /// nothing (its solver cache follows contacts only), so sleeping gives
  /// the same states bit for bit as not
  /// sleeping (sleep = false, the default of a bare ContactForces).
  void set_motion_clock(double clock, bool sleep) {
    motion_clock_ = clock;
    sleep_ = sleep;
  }

  /// Viscous contact dashpots in every contact (viscous_contact_damping.h);
  /// a default-constructed one (e = 1) turns them off, and the pair loop is
  /// then the one without dashpots (a separate instantiation).
  void set_viscous_damping(const ViscousContactDamping& d);
  /// On several threads: the pairs the last compute() evaluated twice,
  /// once by their owner's thread and once, as a ghost, by their
  /// partner's (SplitSums::ghosts); 0 otherwise.
  std::size_t ghost_pairs() const { return split_used_ ? split_.ghost_count() : 0; }
  /// On several threads: the particles with a pair owned in another run
  /// (SplitSums::cut_count); 0 otherwise.
  std::size_t cut_particles() const { return split_used_ ? split_.cut_count() : 0; }
  /// On several threads: the chunks holding a particle another thread's
  /// pair loop read in the last compute() (SplitSums::shared_chunks);
  /// null otherwise.
  const std::vector<std::uint8_t>* shared_chunks() const { return split_used_ ? &split_.shared_chunks() : nullptr; }
  /// Whether the last compute() ran on several threads (each thread's pair
  /// loop with its ghosts, split_sums.h).
  bool split_used() const { return split_used_; }
  /// The runs of chunks per thread of the pair loop, which the integrator
  /// shares (LeapfrogIntegrator::advance) and whose owner calls end_step().
  ThreadRuns& thread_runs() { return runs_; }
  const ThreadRuns& thread_runs() const { return runs_; }
  /// Seconds per thread and phase since the last reset, and the regions'
  /// wall time (phase_times.h); the integrator adds its phase and region
  /// (LeapfrogIntegrator::advance).
  PhaseTimes& phase_times() { return phases_; }
  const PhaseTimes& phase_times() const { return phases_; }

  /// Per-thread scratch kept between calls (the contacts found in a chunk),
  /// grown on demand. Implementation detail.
  struct Scratch {
    std::vector<std::int32_t> entry, separated;
    std::vector<Vec3> branch;
    std::vector<double> dist2;
    void reserve(std::size_t n);
  };

 private:
  std::vector<ContactSums> chunk_sums_;
  std::vector<Scratch> scratch_;
  std::vector<PairBody> bodies_;  ///< spheroid path: per particle, support and radii, rebuilt every call
  double motion_clock_ = 0.0;
  bool sleep_ = false;
  double viscous_a_ = 0.0;  ///< a of the contact dashpots; 0 = none
  SplitSums split_;                      ///< several threads: the ghosts
  ThreadRuns runs_;                      ///< chunks per thread (pair loop and integrator)
  PhaseTimes phases_;                    ///< where the time goes, per thread (pair loop and integrator)
  bool split_used_ = false;              ///< the last compute() used split_
  /// Several threads: each thread's ghosts (SplitSums::ghosts) as a list
  /// of their own for the pair kernel: two "owners" (0: the ghosts owned in
  /// lower runs, 1: in higher runs; off), each entry's real owner, and
  /// copies of its list data (partner and per-entry state), which follow on
  /// from the last compute() when that was a team's with the same plan
  /// (ghosts_follow_), otherwise taken from the list first (take, by the
  /// thread itself).
  struct GhostPairs {
    std::vector<std::int32_t> off, owner;
    PairData entries;
    /// Copies of the list's entries `ghosts`, the first `lower` owned in lower runs.
    void take(const NeighborList& list, const std::vector<std::int32_t>& ghosts, std::size_t lower);
    /// Points `in`'s list fields at these (off, owner, partner, per-entry state).
    void point(pairs::PairInputs& in);
  };
  std::vector<GhostPairs> ghost_pairs_;
  bool ghosts_follow_ = false;
};

}  // namespace vt::dem
