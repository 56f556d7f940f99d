// What the pair kernels of ContactForces share (contact_forces.h): the
// inputs of one evaluation as plain pointers, the software prefetch
// distances, the component-wise Vec3 store and the viscous dashpots; and the
// two kernels, one per file: spheres (sphere_pairs.cpp, contacts 8 at a
// time as SIMD) and particles that include spheroids (spheroid_pairs.cpp).
// Private to src/dem.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "virtual_triaxial/dem/axis_stiffness_term.h"
#include "virtual_triaxial/dem/contact_forces.h"

namespace vt::dem::pairs {

// Software prefetch distances (measured on the 1e5-particle bench, where the
// particle data of a partner is usually not in cache; no effect when
// everything fits in cache):
constexpr std::int32_t kPrefetchEntries = 24;   // pass 1: partner data, entries ahead
constexpr std::int32_t kPrefetchContacts = 6;   // pass 2: pair state and spring, contacts ahead

/// A per-lane flag of the SIMD lane structs (a contact's sliding state): 8
/// bytes, as wide as their doubles. With a 4-byte field GCC took an 8-lane
/// loop as 16 lanes at 64-byte vectors, more than its 8 iterations, and fell
/// back to 32-byte vectors, two per field (session 28, experiments.txt E13).
using LaneFlag = std::int64_t;
static_assert(sizeof(LaneFlag) == sizeof(double), "a lane flag is as wide as a lane's double");

/// Stores v at *dst one component at a time. A whole-Vec3 assignment in the
/// pair loops was compiled as two 8-byte stores to a stack slot and a 16-byte
/// reload (a store-forwarding stall of about 15 cycles; perf showed 12-15 %
/// of the step on each of the two such stores of the sphere loop).
inline void store(Vec3& dst, const Vec3& v) {
  dst.x = v.x;
  dst.y = v.y;
  dst.z = v.z;
}

/// Everything the pair loop reads, as plain pointers and local copies (a
/// store through a double* could otherwise alias the cell matrix or the law's
/// coefficients and force a reload on every pair).
struct PairInputs {
  const Vec3* frac;
  const Vec3* vel;
  const Vec3* omg;
  const double* rad;
  const std::int32_t* off;
  const std::int32_t* owner;
  const std::int32_t* partner;
  Vec3* spring;
  PairState* state;
  std::uint8_t* active;
  // spheroid path only (null/unused for spheres)
  const PairBody* body;  // per particle, this evaluation: support (bound: a >= b, the reach) and radii
  double clock;                 // motion clock [m] (ContactForces::set_motion_clock); +inf: no sleep
  bool sleep;                   // pairs found apart sleep
  const Shape* shape;
  SpheroidPairState* sph;
  Mat3 h, lgrad;
  HertzMindlin law;
  double dt;
  // Per-particle force and torque summed right in pass 2, in list order
  // (ContactForces::compute): the arrays themselves (on several threads
  // only the particles of the thread's run: own_begin, own_span below).
  Vec3* force_out;
  Vec3* torque_out;
  // viscous contact damping (viscous_contact_damping.h): masses and a; unused when off
  const double* mass;
  double viscous_a;
  // Several threads (both kernels): particles outside [own_begin,
  // own_begin + own_span), owner or partner, take no sum here (their own
  // thread sums them, with its ghost of the pair when it is the partner's,
  // split_sums.h). One thread: every particle is home (the defaults).
  std::int32_t own_begin = 0;
  std::uint32_t own_span = UINT32_MAX;
  /// Whether particle j is summed here (in [own_begin, own_begin + own_span)).
  bool home(std::int32_t j) const { return static_cast<std::uint32_t>(j - own_begin) < own_span; }
};

/// The viscous contact dashpots (viscous_contact_damping.h) of a pair of
/// masses m_i, m_j: adds them to the force on j and returns the power they
/// take [W] (normal always; tangential while the contact sticks). A select,
/// not a jump, for sliding (the sphere contact lanes run it as SIMD).
inline double add_dashpots(double mi, double mj, double a, const HertzMindlin& law, double delta, double r_eff,
                           const Vec3& nrm, const Vec3& vc, bool sliding, Vec3& f) {
  const double eta_n = a * std::sqrt(mi * mj / (mi + mj) * law.normal_stiffness(delta, r_eff));
  const double vn = dot(vc, nrm);
  f -= (eta_n * vn) * nrm;
  const double eta_t = eta_n * std::sqrt(law.tangential_ratio());  // a sqrt(m* K_t), K_t = ratio K_n
  const Vec3 vt = vc - vn * nrm;
  Vec3 stuck = f;
  stuck -= eta_t * vt;
  f = select(sliding, f, stuck);
  const double normal_power = eta_n * vn * vn;
  double power = normal_power;
  power += eta_t * norm2(vt);  // the operations of the branching form
  return sliding ? normal_power : power;
}

/// Lane k of a kernel's lanes (fields rv*, wi*, wj*, s*, mi, mj): the motion
/// of the pair of entry e (owner i, partner j), v_j - v_i, both spins and
/// its spring; the masses for the viscous dashpots.
template <bool Viscous, class Lanes>
inline void set_motion(Lanes& L, int k, const PairInputs& in, std::int32_t e, std::int32_t i, std::int32_t j) {
  const Vec3 sp = in.spring[e];
  const Vec3 rv = in.vel[j] - in.vel[i];
  L.rvx[k] = rv.x; L.rvy[k] = rv.y; L.rvz[k] = rv.z;
  const Vec3 wi = in.omg[i], wj = in.omg[j];
  L.wix[k] = wi.x; L.wiy[k] = wi.y; L.wiz[k] = wi.z;
  L.wjx[k] = wj.x; L.wjy[k] = wj.y; L.wjz[k] = wj.z;
  L.sx[k] = sp.x; L.sy[k] = sp.y; L.sz[k] = sp.z;
  if constexpr (Viscous) {
    L.mi[k] = in.mass[i];
    L.mj[k] = in.mass[j];
  }
}

/// The axis stiffness terms (axis_stiffness_term.h) of a kernel's group of
/// kLanes contacts, computed by one loop without jumps (SIMD) on measured
/// steps: branch d, force on j and half overlap of each lane.
template <int N>
struct StiffnessLanes {
  double d2x[N], d2y[N], d2z[N], kx[N], ky[N], kz[N];
  LaneFlag none[N];
  void compute(const double* dx, const double* dy, const double* dz, const double* fx, const double* fy,
               const double* fz, const double* half_overlap, double kt_ratio) {
    for (int k = 0; k < N; ++k) {
      const AxisStiffnessTerm t =
          axis_stiffness_term({dx[k], dy[k], dz[k]}, {fx[k], fy[k], fz[k]}, half_overlap[k], kt_ratio);
      d2x[k] = t.d2.x; d2y[k] = t.d2.y; d2z[k] = t.d2.z;
      kx[k] = t.stiffness.x; ky[k] = t.stiffness.y; kz[k] = t.stiffness.z;
      none[k] = t.none ? 1 : 0;
    }
  }
};

/// A chunk's sums over its contacts, added one contact at a time in list
/// order by both kernels. The virial sum d (x) F is kept as nine plain
/// numbers (registers) until finish().
struct ChunkSums {
  ContactSums acc;
  double vxx = 0, vxy = 0, vxz = 0, vyx = 0, vyy = 0, vyz = 0, vzx = 0, vzy = 0, vzz = 0;
  /// Lane k of a kernel's lanes (fields dx, dy, dz, energy, friction, power,
  /// ratio, sliding, f2), whose force on j is f.
  template <bool Measure, bool Viscous, class Lanes>
  void add(const Lanes& L, int k, const Vec3& f, double dt) {
    // Fused multiply-adds written out: whether the compiler fuses each of
    // them otherwise depends on the code around (it once fused eight of the
    // nine), and the stress feeds the servo, so a run would follow it.
    const double dx = L.dx[k], dy = L.dy[k], dz = L.dz[k];
    vxx = std::fma(dx, f.x, vxx); vxy = std::fma(dx, f.y, vxy); vxz = std::fma(dx, f.z, vxz);
    vyx = std::fma(dy, f.x, vyx); vyy = std::fma(dy, f.y, vyy); vyz = std::fma(dy, f.z, vyz);
    vzx = std::fma(dz, f.x, vzx); vzy = std::fma(dz, f.y, vzy); vzz = std::fma(dz, f.z, vzz);
    if (Measure) acc.elastic_energy += L.energy[k];
    acc.friction_dissipation += L.friction[k];
    if constexpr (Viscous) acc.viscous_dissipation += dt * L.power[k];
    acc.max_overlap_ratio = std::max(acc.max_overlap_ratio, L.ratio[k]);
    acc.sliding += L.sliding[k];
    if (Measure) {
      acc.sum_force2 += L.f2[k];
      acc.sum_force += std::sqrt(L.f2[k]);
    }
  }
  /// Measured steps only, after add: lane k's axis stiffness term (S: its
  /// group's), so the servo's stiffness takes no pass over the list of its
  /// own (axis_stiffness.h). A call of its own, so that the unmeasured
  /// kernels do not see S at all.
  template <int N>
  void add_stiffness(const StiffnessLanes<N>& S, int k) {
    if (S.none[k] != 0) return;
    Vec3& m = acc.axis_stiffness_sum;
    m.x = std::fma(S.d2x[k], S.kx[k], m.x);
    m.y = std::fma(S.d2y[k], S.ky[k], m.y);
    m.z = std::fma(S.d2z[k], S.kz[k], m.z);
  }
  /// The sums with `contacts` contacts.
  ContactSums finish(std::int64_t contacts) {
    acc.contacts = contacts;
    acc.virial.m[0][0] = vxx; acc.virial.m[0][1] = vxy; acc.virial.m[0][2] = vxz;
    acc.virial.m[1][0] = vyx; acc.virial.m[1][1] = vyy; acc.virial.m[1][2] = vyz;
    acc.virial.m[2][0] = vzx; acc.virial.m[2][1] = vzy; acc.virial.m[2][2] = vzz;
    return acc;
  }
};

/// A pair kernel: evaluates the pairs owned by particles [i_begin, i_end)
/// (list entries off[i_begin] .. off[i_end]), stores each entry's result in
/// the list, adds to in.force_out / in.torque_out (owners and partners in
/// [own_begin, own_begin + own_span) only: PairInputs::home), and
/// returns the chunk's sums. The last four arguments are per-thread scratch
/// (ContactForces::Scratch).
using PairKernel = ContactSums (*)(const PairInputs&, std::int32_t, std::int32_t, std::int32_t*, std::int32_t*,
                                   Vec3*, double*);

/// Sphere kernel (sphere_pairs.cpp); `measure` adds the elastic energy,
/// force norms and axis stiffness terms, `viscous` the contact dashpots. One kernel for one thread
/// and for a team: the test of PairInputs::home costs nothing measurable on
/// one thread (1.004, session 21; 0.994 at 12 000 and 1.013 at 10^5 when
/// the variant without it was removed, session 22), so none is kept.
PairKernel sphere_pair_kernel(bool measure, bool viscous);

/// Kernel for particles that include spheroids (spheroid_pairs.cpp).
PairKernel spheroid_pair_kernel(bool measure, bool viscous);

}  // namespace vt::dem::pairs
