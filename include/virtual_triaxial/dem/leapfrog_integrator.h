// Leapfrog (central-difference) integration with mass-proportional damping,
// eq. 2 of the dissertation, applied to the fluctuating velocity:
//
//   v(t+dt/2) = v(t-dt/2) (1 - a dt/2)/(1 + a dt/2) + dt/(1 + a dt/2) F(t)/m
//   w(t+dt/2) = w(t-dt/2) (1 - a dt/2)/(1 + a dt/2) + dt/(1 + a dt/2) M(t)/I
//
// with a = alpha_i from MassDamping (same alpha for rotation, eq. 27-29), and
// then the position update of eq. 131 in fractional coordinates:
//   s(t+dt) = s(t) + H(t+dt)^-1 v(t+dt/2) dt        (the cell carries L x).
// Spheres need only omega (no orientation integration).
// With Cundall's local damping (set_local_damping, local_damping.h; then
// alpha = 0) F and M above are the locally damped force and moment, and the
// damping dissipation of the step is (F - F_d) . v_mid dt + (M - M_d) . w_mid dt,
// by the same identity.
//
// Spheroids (chapter 4; only when the particles include any): Euler's
// equations in the body frame (eq. 43) with the rotational damping moment
// alpha I omega = alpha L (eq. 29, same alpha as for translation), by the
// rigid-body leapfrog of rigid_rotation.h:
//   L(t+dt/2) = L(t-dt/2) (1 - a dt/2)/(1 + a dt/2) + dt/(1 + a dt/2) M(t),
//   q(t+dt)   = exact torque-free rotation of q(t) over dt with L(t+dt/2),
// L = R I_body R^T omega [kg m^2/s]. The stored state is (q, omega) with
// omega(t+dt/2) = I_world(q(t+dt))^-1 L(t+dt/2) [rad/s], so a sample file
// (orientation, angular velocity) restarts bit for bit. Rotational energy
// and damping: E_rot = L_mid . I_world(q(t))^-1 L_mid / 2 with L_mid the
// mean of the two half-step momenta; dissipation a dt L_mid . w_mid, the
// same exact identity as for spheres (the drift keeps E_rot exactly).
// Spheres of a mixed sample keep the scalar update below.
//
// Exact discrete identity used by the energy budget: with
// v_mid = (v(t-dt/2) + v(t+dt/2))/2,
//   m/2 (|v+|^2 - |v-|^2) = F . v_mid dt - a m |v_mid|^2 dt,
// so the damping dissipation of the step is a m |v_mid|^2 dt (and likewise
// a I |w_mid|^2 dt for rotation). v_mid is also the integer-time velocity used
// for the kinetic energy.
#pragma once

#include <cstdint>
#include <vector>

#include "virtual_triaxial/dem/handoff_stores.h"
#include "virtual_triaxial/dem/local_damping.h"
#include "virtual_triaxial/dem/particles.h"
#include "virtual_triaxial/dem/periodic_cell.h"
#include "virtual_triaxial/dem/phase_times.h"
#include "virtual_triaxial/dem/rigid_rotation.h"
#include "virtual_triaxial/dem/thread_runs.h"

namespace vt::dem {

/// Sums over particles of one integration step.
struct IntegrationSums {
  double damping_dissipation = 0;   ///< [J], this step
  double kinetic_translational = 0; ///< 1/2 m |v_mid|^2 [J] (measure steps only)
  double kinetic_rotational = 0;    ///< 1/2 I |w_mid|^2 [J] (measure steps only)
  double sum_inertia_moment = 0;    ///< sum |I dw/dt| [N m] (measure steps only)
  double max_displacement2 = 0;     ///< max |H (s - s_build)|^2 [m^2]
  double max_speed2 = 0;            ///< max |v(t+dt/2)|^2, fluctuating velocity [m^2/s^2]
  double max_spin2 = 0;             ///< max |w(t+dt/2)|^2 [rad^2/s^2]
  bool finite = true;
  void add(const IntegrationSums& o);
};

/// A thread's copies of the arrays its streamed chunks are stepped in
/// (LeapfrogIntegrator::advance_streamed), indexed as the particles.
struct HandoffScratch {
  std::vector<Vec3> vel, omg, frac;
};

class LeapfrogIntegrator {
 public:
  /// Per-particle damping coefficients alpha [1/s]; dt [s].
  void set_coefficients(const Particles& p, const std::vector<double>& alpha, double dt);
  /// Cundall's local damping (local_damping.h) on every particle's force and
  /// moment; a coefficient of 0 (the default) turns it off, and the loop is
  /// then the one without it (a separate instantiation).
  void set_local_damping(const LocalDamping& d) { local_ = d; }
  const std::vector<double>& alpha() const { return alpha_; }
  /// True when the particles given to set_coefficients include spheroids.
  bool has_spheroids() const { return spheroids_; }

  /// Advance velocities and positions by one step. The cell must already be
  /// deformed to t+dt. frac_at_build feeds the Verlet rebuild criterion.
  /// `runs`: the chunks per thread of the contact forces (thread_runs.h),
  /// to take and to time; null or another team: equal runs. `phases`: each
  /// thread's time in PhaseTimes::Integrate and the region's wall time are
  /// added there (phase_times.h); null: not timed. `shared_chunks`: per
  /// chunk, whether another thread's pair loop read its particles
  /// (ContactForces::shared_chunks); with `runs` on a team, spheres without
  /// local damping store those chunks as handoff() chooses
  /// (handoff_stores.h); null: plainly.
  IntegrationSums advance(Particles& p, const PeriodicCell& cell, const std::vector<Vec3>& force,
                          const std::vector<Vec3>& torque, const std::vector<Vec3>& frac_at_build,
                          bool measure, ThreadRuns* runs = nullptr, PhaseTimes* phases = nullptr,
                          const std::vector<std::uint8_t>* shared_chunks = nullptr);
  /// The choice of stores for the shared chunks (mode, statistics).
  HandoffStores& handoff() { return handoff_; }
  const HandoffStores& handoff() const { return handoff_; }

 private:
  /// Per-particle constants of eq. 2 of one particle.
  struct Coefficients {
    double decay = 0;     ///< (1 - a dt/2) / (1 + a dt/2)
    double kick = 0;      ///< dt / ((1 + a dt/2) m)
    double kick_rot = 0;  ///< dt / ((1 + a dt/2) I)
    double alpha_dt = 0;  ///< a dt
    double mass = 0;      ///< m [kg]
    double inertia = 0;   ///< I [kg m^2] (sphere)
  };
  /// The same for kLanes consecutive particles, field by field: one stream
  /// for the integrator, and each field contiguous over the lanes of
  /// advance_sphere_lanes (SIMD).
  static constexpr std::size_t kLanes = 8;
  struct CoefficientLanes {
    double decay[kLanes] = {}, kick[kLanes] = {}, kick_rot[kLanes] = {};
    double alpha_dt[kLanes] = {}, mass[kLanes] = {}, inertia[kLanes] = {};
  };
  /// The constants of advance_symmetric_rotation that coef_ lacks, for
  /// kLanes consecutive particles field by field (decay and dt are shared;
  /// kept only when the particles include spheroids).
  struct RotationLanes {
    double kick[kLanes] = {}, inv_i1[kLanes] = {}, inv_i2[kLanes] = {}, dt_inv_i2[kLanes] = {};
  };
  SymmetricStepConstants rotation_constants(std::size_t i) const {
    const RotationLanes& r = rot_coef_[i / kLanes];
    const std::size_t k = i % kLanes;
    return {coef_[i / kLanes].decay[k], r.kick[k], r.inv_i1[k], r.inv_i2[k], r.dt_inv_i2[k], dt_};
  }
  Coefficients coefficients(std::size_t i) const {
    const CoefficientLanes& c = coef_[i / kLanes];
    const std::size_t k = i % kLanes;
    return {c.decay[k], c.kick[k], c.kick_rot[k], c.alpha_dt[k], c.mass[k], c.inertia[k]};
  }
  /// Per-particle arrays of one advance() (plain pointers, no aliasing).
  struct StepInputs {
    Vec3* vel;
    Vec3* omg;
    Vec3* frac;
    Quaternion* orient;
    const Shape* shape;
    const Vec3* inertia;
    const Vec3* f_in;
    const Vec3* t_in;
    const Vec3* s_build;
    Mat3 hinv, h;
  };
  /// Particles [i_begin, i_end); Spheroids = false is the plain sphere loop.
  template <bool Spheroids, bool Local>
  IntegrationSums advance_chunk(const StepInputs& in, std::size_t i_begin, std::size_t i_end,
                                bool measure) const;
  /// advance_chunk<false, false> kLanes particles at a time (SIMD): the same
  /// operations and sums in the same order; the compiler may fuse
  /// multiply-adds differently in the two loops, so they agree to round-off.
  /// Which particles take which loop depends only on the chunk bounds, so
  /// results do not depend on the thread count.
  template <bool Measure>
  IntegrationSums advance_sphere_lanes(const StepInputs& in, std::size_t i_begin, std::size_t i_end) const;
  /// advance_sphere_lanes on a copy of the chunk's velocities, spins and
  /// positions in `scratch`, stored back with streaming stores
  /// (streaming_copy.h): the same values.
  IntegrationSums advance_streamed(const StepInputs& in, std::size_t i_begin, std::size_t i_end, bool measure,
                                   HandoffScratch& scratch) const;
  /// advance_chunk<true, false> kLanes particles at a time (SIMD) for the
  /// lanes that hold a symmetric spheroid (I2 = I3) with L != 0 and small
  /// step angles, the particle's scalar step for the others (which depends
  /// only on the particle, not on the chunks).
  template <bool Measure>
  IntegrationSums advance_spheroid_lanes(const StepInputs& in, std::size_t i_begin, std::size_t i_end) const;

  double dt_ = 0;
  bool spheroids_ = false;
  LocalDamping local_;
  std::vector<double> alpha_;
  std::vector<CoefficientLanes> coef_;  ///< particle i: coef_[i / kLanes], lane i % kLanes
  std::vector<RotationLanes> rot_coef_;  ///< spheroids (empty without any): as coef_
  std::vector<IntegrationSums> chunk_sums_;
  HandoffStores handoff_;
  std::vector<HandoffScratch> handoff_scratch_;  ///< per thread, N particles once streaming is first used
};

}  // namespace vt::dem
