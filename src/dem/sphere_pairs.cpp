// Sphere pair kernel of ContactForces (formulas in contact_forces.h).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "pair_kernel.h"

namespace vt::dem::pairs {

namespace {

/// Contacts of the sphere pair loop taken kLanes at a time: the inputs of
/// each contact gathered into arrays, the contact itself (geometry, relative
/// velocity, Hertz-Mindlin, dashpots, moment) computed by one loop without
/// jumps over the lanes, which the compiler turns into SIMD, then the
/// results stored and summed one contact at a time in list order. Unused
/// lanes of the last group repeat the group's first contact. Sixteen lanes,
/// two 8-double SIMD registers per field, so each group holds two
/// independent chains of the law's square roots and divisions (0.960-0.967
/// of the cost of 8 lanes on one thread, 12 000 spheres, same bits; 24 and
/// 32 lanes no better: session 33).
constexpr int kLanes = 16;
struct SphereLanes {
  // inputs
  double dx[kLanes], dy[kLanes], dz[kLanes], dist2[kLanes], ri[kLanes], rj[kLanes];
  double rvx[kLanes], rvy[kLanes], rvz[kLanes];  // v_j - v_i [m/s]
  double wix[kLanes], wiy[kLanes], wiz[kLanes], wjx[kLanes], wjy[kLanes], wjz[kLanes];
  double sx[kLanes], sy[kLanes], sz[kLanes];     // spring [N]: in, then out
  double mi[kLanes], mj[kLanes];                 // viscous dashpots only
  // results
  double fx[kLanes], fy[kLanes], fz[kLanes], mx[kLanes], my[kLanes], mz[kLanes];
  double hov[kLanes], li[kLanes], lj[kLanes], ratio[kLanes];
  double energy[kLanes], friction[kLanes], power[kLanes], f2[kLanes];
  LaneFlag sliding[kLanes];
};

/// The contact of every lane (formulas in contact_forces.h). Not inlined,
/// so which multiply-adds the compiler fuses here does not depend on the
/// code around each call (the instantiations of evaluate_pairs with the
/// same Viscous give the same bits).
template <bool Viscous>
__attribute__((noinline)) void sphere_contact_lanes(SphereLanes& L, const Mat3& lgrad, const HertzMindlin& law, double dt,
                                 double viscous_a) {
  for (int k = 0; k < kLanes; ++k) {
    const Vec3 d{L.dx[k], L.dy[k], L.dz[k]};
    const double ri = L.ri[k], rj = L.rj[k];
    const double rsum = ri + rj;
    const double dist = std::sqrt(L.dist2[k]);
    const double delta = rsum - dist;
    const Vec3 nrm = (1.0 / dist) * d;
    const double hov = 0.5 * delta;
    const double li = ri - hov, lj = rj - hov;
    const Vec3 wi{L.wix[k], L.wiy[k], L.wiz[k]}, wj{L.wjx[k], L.wjy[k], L.wjz[k]};
    const Vec3 vc = Vec3{L.rvx[k], L.rvy[k], L.rvz[k]} + lgrad * d - cross(li * wi + lj * wj, nrm);
    const Vec3 dt_t = dt * (vc - dot(vc, nrm) * nrm);
    const double r_eff = ri * rj / rsum;
    Vec3 spring{L.sx[k], L.sy[k], L.sz[k]};
    const ContactResult r = law.evaluate(nrm, delta, r_eff, dt_t, spring);
    Vec3 f = r.force_on_j;
    L.power[k] = Viscous ? add_dashpots(L.mi[k], L.mj[k], viscous_a, law, delta, r_eff, nrm, vc, r.sliding, f) : 0.0;
    const Vec3 m = -cross(nrm, f);  // n x F_on_i
    L.sx[k] = spring.x; L.sy[k] = spring.y; L.sz[k] = spring.z;
    L.fx[k] = f.x; L.fy[k] = f.y; L.fz[k] = f.z;
    L.mx[k] = m.x; L.my[k] = m.y; L.mz[k] = m.z;
    L.hov[k] = hov;
    L.li[k] = li;
    L.lj[k] = lj;
    L.ratio[k] = delta / std::min(ri, rj);
    L.energy[k] = r.elastic_energy;
    L.friction[k] = r.friction_dissipation;
    L.f2[k] = norm2(f);
    L.sliding[k] = r.sliding ? 1 : 0;
  }
}

/// Whether the pair of entry e touches: branch d = x_j - x_i (minimum
/// image) and |d|^2.
inline bool contact_test(const PairInputs& in, const Mat3& h, std::int32_t e, Vec3& d, double& dist2) {
  const std::int32_t i = in.owner[e];
  const std::int32_t j = in.partner[e];
  d = h * PeriodicCell::minimum_image(in.frac[j] - in.frac[i]);
  dist2 = norm2(d);
  const double rsum = in.rad[i] + in.rad[j];
  return dist2 < rsum * rsum;
}

/// Lane k of L: the contact of entry e (branch d, |d|^2 = dist2), its
/// radii, motion and spring.
template <bool Viscous>
inline void set_lane(SphereLanes& L, int k, const PairInputs& in, std::int32_t e, const Vec3& d, double dist2) {
  const std::int32_t i = in.owner[e];
  const std::int32_t j = in.partner[e];
  L.dx[k] = d.x; L.dy[k] = d.y; L.dz[k] = d.z;
  L.dist2[k] = dist2;
  L.ri[k] = in.rad[i];
  L.rj[k] = in.rad[j];
  set_motion<Viscous>(L, k, in, e, i, j);
}

/// Pairs owned by particles [i_begin, i_end), i.e. list entries
/// [off[i_begin], off[i_end]) in list order. Pass 1 tests every entry for
/// contact without a data-dependent branch (the test is a coin flip for the
/// branch predictor) and without a per-particle inner loop (whose exits
/// mispredict too); pass 2 evaluates the contacts found, still in list
/// order, so every sum sees the same terms in the same order as the plain
/// double loop over particles and their entries. Entries not in contact hold
/// zero force and overlap; one that was in contact at the last evaluation
/// also loses its spring. Measure = false
/// skips what only measured steps use (elastic energy, force norms, the axis
/// stiffness terms).
template <bool Measure, bool Viscous>
ContactSums evaluate_pairs(const PairInputs& in, std::int32_t i_begin, std::int32_t i_end,
                           std::int32_t* c_entry, std::int32_t* s_entry, Vec3* c_branch, double* c_dist2) {
  const Mat3 h = in.h, lgrad = in.lgrad;
  const HertzMindlin law = in.law;
  const double dt = in.dt;
  const std::int32_t e_begin = in.off[i_begin], e_end = in.off[i_end];

  // Pass 1: contact test for every listed pair.
  std::int32_t nc = 0, ns = 0;
  for (std::int32_t e = e_begin; e < e_end; ++e) {
    if (e + kPrefetchEntries < e_end) {
      const std::int32_t jp = in.partner[e + kPrefetchEntries];
      __builtin_prefetch(in.frac + jp);
      __builtin_prefetch(in.rad + jp);
      __builtin_prefetch(in.vel + jp);
      __builtin_prefetch(in.omg + jp);
    }
    Vec3 d;
    double dist2;
    const bool touching = contact_test(in, h, e, d, dist2);
    c_entry[nc] = e;
    store(c_branch[nc], d);
    c_dist2[nc] = dist2;
    nc += touching ? 1 : 0;
    // In contact at the last evaluation but not now: cleared below.
    s_entry[ns] = e;
    ns += static_cast<std::int32_t>(in.active[e]) & static_cast<std::int32_t>(!touching);
    in.active[e] = 0;  // contacts set it again in pass 2
  }
  for (std::int32_t k = 0; k < ns; ++k) {
    const std::int32_t e = s_entry[k];
    in.state[e] = PairState{};
    in.spring[e] = Vec3{};
  }

  // Pass 2: the contacts, kLanes at a time (SphereLanes), stored and summed
  // in list order.
  ChunkSums sums;
  StiffnessLanes<kLanes> stiffness;
  Vec3 sink_f, sink_t;  // the sums of particles that are not home
  SphereLanes L;
  std::int32_t lane_e[kLanes], lane_i[kLanes], lane_j[kLanes];
  for (std::int32_t c0 = 0; c0 < nc; c0 += kLanes) {
    const int lanes = static_cast<int>(std::min<std::int32_t>(kLanes, nc - c0));
    for (int k = 0; k < kLanes; ++k) {
      const std::int32_t c = c0 + (k < lanes ? k : 0);
      if (c + kPrefetchContacts < nc) {
        const std::int32_t ep = c_entry[c + kPrefetchContacts];
        __builtin_prefetch(in.state + ep, 1);
        __builtin_prefetch(in.spring + ep, 1);
        const std::int32_t jp = in.partner[ep];
        // the partner's sums (scattered reads when N is large), only when
        // this thread makes them: a prefetch for writing of another run's
        // sums takes their line from the thread that is adding to it
        if (in.home(jp)) {
          __builtin_prefetch(in.force_out + jp, 1);
          __builtin_prefetch(in.torque_out + jp, 1);
        }
      }
      const std::int32_t e = c_entry[c];
      lane_e[k] = e;
      lane_i[k] = in.owner[e];
      lane_j[k] = in.partner[e];
      set_lane<Viscous>(L, k, in, e, c_branch[c], c_dist2[c]);
    }
    sphere_contact_lanes<Viscous>(L, lgrad, law, dt, in.viscous_a);
    if constexpr (Measure) stiffness.compute(L.dx, L.dy, L.dz, L.fx, L.fy, L.fz, L.hov, law.tangential_ratio());
    for (int k = 0; k < lanes; ++k) {
      const std::int32_t e = lane_e[k], i = lane_i[k], j = lane_j[k];
      const Vec3 f{L.fx[k], L.fy[k], L.fz[k]};
      const Vec3 m{L.mx[k], L.my[k], L.mz[k]};
      const double hov = L.hov[k];
      PairState& st = in.state[e];
      store(st.force, f);
      st.half_overlap = hov;
      store(in.spring[e], Vec3{L.sx[k], L.sy[k], L.sz[k]});
      // a particle of another thread's run (the owner of a ghost, the
      // partner of a pair crossing the runs): summed there, by that
      // thread's pair loop or its ghost of this pair (split_sums.h)
      const bool home_i = in.home(i), home_j = in.home(j);
      Vec3& fi = home_i ? in.force_out[i] : sink_f;
      Vec3& ti = home_i ? in.torque_out[i] : sink_t;
      fi -= f;
      ti = fused_multiply_add(L.li[k], m, ti);
      Vec3& fj = home_j ? in.force_out[j] : sink_f;
      Vec3& tj = home_j ? in.torque_out[j] : sink_t;
      fj += f;
      tj = fused_multiply_add(L.lj[k], m, tj);
      in.active[e] = hov != 0.0 ? 1 : 0;
      sums.add<Measure, Viscous>(L, k, f, dt);
      if constexpr (Measure) sums.add_stiffness(stiffness, k);
    }
  }
  return sums.finish(nc);
}

}  // namespace

PairKernel sphere_pair_kernel(bool measure, bool viscous) {
  if (viscous) return measure ? &evaluate_pairs<true, true> : &evaluate_pairs<false, true>;
  return measure ? &evaluate_pairs<true, false> : &evaluate_pairs<false, false>;
}

}  // namespace vt::dem::pairs
