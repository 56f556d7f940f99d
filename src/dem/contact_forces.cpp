#include "virtual_triaxial/dem/contact_forces.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/split_sums.h"

namespace vt::dem {

void ContactSums::add(const ContactSums& o) {
  virial = virial + o.virial;
  elastic_energy += o.elastic_energy;
  friction_dissipation += o.friction_dissipation;
  viscous_dissipation += o.viscous_dissipation;
  max_overlap_ratio = std::max(max_overlap_ratio, o.max_overlap_ratio);
  contacts += o.contacts;
  sliding += o.sliding;
  sum_force += o.sum_force;
  sum_force2 += o.sum_force2;
  spheroid.add(o.spheroid);
}

void ContactForces::Scratch::reserve(std::size_t n) {
  if (n <= entry.size()) return;
  const std::size_t capacity = n + n / 2;  // grown rarely, so zero-filling is no cost
  entry.resize(capacity);
  separated.resize(capacity);
  branch.resize(capacity);
  dist2.resize(capacity);
}

namespace {

// Software prefetch distances (measured on the 1e5-particle bench, where the
// particle data of a partner and the pair state of a reverse entry are
// usually not in cache; no effect when everything fits in cache):
constexpr std::int32_t kPrefetchEntries = 24;   // pass 1: partner data, entries ahead
constexpr std::int32_t kPrefetchContacts = 6;   // pass 2: pair state and spring, contacts ahead
constexpr std::int32_t kPrefetchParticles = 6;  // gather: pair states, particles ahead

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
  const Vec3* axes;
  const SpheroidSupport* body;  // per particle, this evaluation
  const double* hertz_radius;   // per particle: R_i of eq. 104, this evaluation
  double clock;                 // motion clock [m] (ContactForces::set_motion_clock); +inf: no sleep
  bool sleep;                   // pairs found apart sleep
  const Shape* shape;
  SpheroidPairState* sph;
  Mat3 h, lgrad;
  HertzMindlin law;
  double dt;
  // One thread: per-particle force and torque summed right in pass 2, in
  // list order (the gather's order, see ContactForces::compute); else null.
  Vec3* force_out;
  Vec3* torque_out;
  // viscous contact damping (viscous_contact_damping.h): masses and a; unused when off
  const double* mass;
  double viscous_a;
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
  return eta_n * vn * vn + (sliding ? 0.0 : eta_t * norm2(vt));
}

/// Contacts of the sphere pair loop taken kLanes at a time: the inputs of
/// each contact gathered into arrays, the contact itself (geometry, relative
/// velocity, Hertz-Mindlin, dashpots, moment) computed by one loop without
/// jumps over the lanes, which the compiler turns into SIMD, then the
/// results stored and summed one contact at a time in list order. Unused
/// lanes of the last group repeat the group's first contact.
constexpr int kLanes = 8;
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
  std::int32_t sliding[kLanes];
};

/// The contact of every lane (see evaluate_pairs for the formulas).
template <bool Viscous>
inline void sphere_contact_lanes(SphereLanes& L, const Mat3& lgrad, const HertzMindlin& law, double dt,
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

/// Pairs owned by particles [i_begin, i_end), i.e. list entries
/// [off[i_begin], off[i_end]) in list order. Pass 1 tests every entry for
/// contact without a data-dependent branch (the test is a coin flip for the
/// branch predictor) and without a per-particle inner loop (whose exits
/// mispredict too); pass 2 evaluates the contacts found, still in list
/// order, so every sum sees the same terms in the same order as the plain
/// double loop over particles and their entries. Entries not in contact hold
/// zero force and moment (so the gather may add every entry); one that was in
/// contact at the last evaluation also loses its spring. Measure = false
/// skips what only measured steps use (elastic energy, force norms).
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
    const std::int32_t i = in.owner[e];
    const std::int32_t j = in.partner[e];
    const Vec3 ds = PeriodicCell::minimum_image(in.frac[j] - in.frac[i]);
    const Vec3 d = h * ds;
    const double dist2 = norm2(d);
    const double rsum = in.rad[i] + in.rad[j];
    const bool touching = dist2 < rsum * rsum;
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
  ContactSums acc;
  double vxx = 0, vxy = 0, vxz = 0, vyx = 0, vyy = 0, vyz = 0, vzx = 0, vzy = 0, vzz = 0;
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
        if (in.force_out) {  // the partner's sums (scattered reads when N is large)
          const std::int32_t jp = in.partner[ep];
          __builtin_prefetch(in.force_out + jp, 1);
          __builtin_prefetch(in.torque_out + jp, 1);
        }
      }
      const std::int32_t e = c_entry[c];
      const std::int32_t i = in.owner[e];
      const std::int32_t j = in.partner[e];
      lane_e[k] = e;
      lane_i[k] = i;
      lane_j[k] = j;
      const Vec3 d = c_branch[c];
      L.dx[k] = d.x; L.dy[k] = d.y; L.dz[k] = d.z;
      L.dist2[k] = c_dist2[c];
      L.ri[k] = in.rad[i];
      L.rj[k] = in.rad[j];
      const Vec3 rv = in.vel[j] - in.vel[i];
      L.rvx[k] = rv.x; L.rvy[k] = rv.y; L.rvz[k] = rv.z;
      const Vec3 wi = in.omg[i], wj = in.omg[j];
      L.wix[k] = wi.x; L.wiy[k] = wi.y; L.wiz[k] = wi.z;
      L.wjx[k] = wj.x; L.wjy[k] = wj.y; L.wjz[k] = wj.z;
      const Vec3 sp = in.spring[e];
      L.sx[k] = sp.x; L.sy[k] = sp.y; L.sz[k] = sp.z;
      if constexpr (Viscous) {
        L.mi[k] = in.mass[i];
        L.mj[k] = in.mass[j];
      }
    }
    sphere_contact_lanes<Viscous>(L, lgrad, law, dt, in.viscous_a);
    for (int k = 0; k < lanes; ++k) {
      const std::int32_t e = lane_e[k], i = lane_i[k], j = lane_j[k];
      const Vec3 f{L.fx[k], L.fy[k], L.fz[k]};
      const Vec3 m{L.mx[k], L.my[k], L.mz[k]};
      const double hov = L.hov[k];
      PairState& st = in.state[e];
      store(st.force, f);
      store(st.moment_axis, m);
      st.half_overlap = hov;
      store(in.spring[e], Vec3{L.sx[k], L.sy[k], L.sz[k]});
      if (in.force_out) {  // the gather's arithmetic, in the gather's order
        in.force_out[i] -= f;
        in.torque_out[i] = fused_multiply_add(L.li[k], m, in.torque_out[i]);
        in.force_out[j] += f;
        in.torque_out[j] = fused_multiply_add(L.lj[k], m, in.torque_out[j]);
      }
      in.active[e] = hov != 0.0 ? 1 : 0;
      const double dx = L.dx[k], dy = L.dy[k], dz = L.dz[k];
      vxx += dx * f.x; vxy += dx * f.y; vxz += dx * f.z;
      vyx += dy * f.x; vyy += dy * f.y; vyz += dy * f.z;
      vzx += dz * f.x; vzy += dz * f.y; vzz += dz * f.z;
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
  }
  acc.contacts = nc;
  acc.virial.m[0][0] = vxx; acc.virial.m[0][1] = vxy; acc.virial.m[0][2] = vxz;
  acc.virial.m[1][0] = vyx; acc.virial.m[1][1] = vyy; acc.virial.m[1][2] = vyz;
  acc.virial.m[2][0] = vzx; acc.virial.m[2][1] = vzy; acc.virial.m[2][2] = vzz;
  return acc;
}

/// Pairs owned by particles [i_begin, i_end) when the particles include
/// spheroids (in.body: SpheroidSupport of every particle, this evaluation).
/// Pass 1 keeps the pairs whose bounding spheres (radius a) overlap, except
/// those asleep (found apart earlier and certified apart since by the motion
/// clock, ContactForces::set_motion_clock), and
/// drops the solver cache of every other pair (so the cache of a pair
/// depends only on its own history while in reach: a restart, which
/// rebuilds the list, continues bit for bit). Pass 2, in list order: a
/// sphere-sphere pair takes the closed form (delta = R_i + R_j - |d|,
/// n = d/|d|, contact point x_i + (R_i - delta/2) n); any pair with a
/// spheroid is first tested with the separation certificate g(n) < 0 at
/// its warm start (or along d/|d|), which proves it apart without iterating, and
/// otherwise takes the common-normal solver (spheroid_contact.h, warm-started
/// from the pair's cache; a sphere enters it as a spheroid with a = b = R).
/// Then Hertz-Mindlin with R_i the average radius (a + 2b)/3 (eq. 104; R for
/// a sphere) at the contact point c (relative to x_i):
///   v_c = v_j - v_i + L d + w_j x (c - d) - w_i x c,
///   T_i = c x F_on_i,  T_j = (c - d) x F_on_j,
/// so normal forces give moments on spheroids.
template <bool Measure, bool Viscous>
ContactSums evaluate_pairs_spheroid(const PairInputs& in, std::int32_t i_begin, std::int32_t i_end,
                                    std::int32_t* c_entry, std::int32_t* s_entry, Vec3* c_branch,
                                    double* c_dist2) {
  const Mat3 h = in.h, lgrad = in.lgrad;
  const HertzMindlin law = in.law;
  const double dt = in.dt;
  const std::int32_t e_begin = in.off[i_begin], e_end = in.off[i_end];

  // Pass 1: bounding-sphere test for every listed pair; pairs asleep (see
  // ContactForces::set_motion_clock) skip pass 2.
  std::int32_t nc = 0, ns = 0;
  std::int64_t slept = 0;
  for (std::int32_t e = e_begin; e < e_end; ++e) {
    if (e + kPrefetchEntries < e_end) {
      const std::int32_t jp = in.partner[e + kPrefetchEntries];
      __builtin_prefetch(in.frac + jp);
      __builtin_prefetch(in.axes + jp);
      __builtin_prefetch(in.body + jp);
    }
    const std::int32_t i = in.owner[e];
    const std::int32_t j = in.partner[e];
    const Vec3 ds = PeriodicCell::minimum_image(in.frac[j] - in.frac[i]);
    const Vec3 d = h * ds;
    const double dist2 = norm2(d);
    const double reach = in.axes[i].x + in.axes[j].x;
    // Both tests are coin flips for the branch predictor, so they are
    // combined as integers (&, no short-circuit branch).
    const std::int32_t in_reach = dist2 < reach * reach ? 1 : 0;
    // asleep: certified apart until the motion clock reads `wake`
    const double wake = in.sph[e].wake;
    const std::int32_t asleep = in.clock < wake ? 1 : 0;
    c_entry[nc] = e;
    store(c_branch[nc], d);
    c_dist2[nc] = dist2;
    nc += in_reach & (asleep ^ 1);
    slept += in_reach & asleep;
    // Out of reach: cache.reset() and awake (the sleep bound needs |d| <
    // a_i + a_j); wake >= 0 is finite, so the product is wake or +0.
    in.sph[e].wake = wake * static_cast<double>(in_reach);
    SpheroidContactCache& cache = in.sph[e].cache;
    cache.valid = static_cast<bool>(static_cast<std::int32_t>(cache.valid) & in_reach);
    cache.has_previous = static_cast<bool>(static_cast<std::int32_t>(cache.has_previous) & in_reach);
    s_entry[ns] = e;
    ns += static_cast<std::int32_t>(in.active[e]) & (in_reach ^ 1);
    in.active[e] = 0;  // contacts set it again in pass 2
  }
  for (std::int32_t k = 0; k < ns; ++k) {
    const std::int32_t e = s_entry[k];
    in.state[e] = PairState{};
    in.spring[e] = Vec3{};
    in.sph[e].torque_i = Vec3{};
  }

  // Pass 2: the pairs in reach and awake, in list order.
  ContactSums acc;
  acc.spheroid.asleep = static_cast<std::uint64_t>(slept);
  std::int64_t contacts = 0;
  double vxx = 0, vxy = 0, vxz = 0, vyx = 0, vyy = 0, vyz = 0, vzx = 0, vzy = 0, vzz = 0;
  for (std::int32_t c = 0; c < nc; ++c) {
    if (c + kPrefetchContacts < nc) {
      const std::int32_t ep = c_entry[c + kPrefetchContacts];
      __builtin_prefetch(in.body + in.partner[ep]);
      __builtin_prefetch(in.state + ep, 1);
      __builtin_prefetch(in.sph + ep, 1);
      if (in.force_out) {
        __builtin_prefetch(in.force_out + in.partner[ep], 1);
        __builtin_prefetch(in.torque_out + in.partner[ep], 1);
      }
    }
    const std::int32_t e = c_entry[c];
    const std::int32_t i = in.owner[e];
    const std::int32_t j = in.partner[e];
    const Vec3 d = c_branch[c];
    const bool sph_i = in.shape[i] == Shape::Spheroid, sph_j = in.shape[j] == Shape::Spheroid;
    double delta;
    Vec3 nrm, cpt;  // normal i -> j; contact point relative to x_i [m]
    double gap = 0.0;  // > 0: apart by at least this along some fixed normal [m]
    if (!sph_i && !sph_j) {
      const double dist = std::sqrt(c_dist2[c]);
      delta = in.rad[i] + in.rad[j] - dist;
      nrm = (1.0 / dist) * d;
      cpt = (in.rad[i] - 0.5 * delta) * nrm;
      gap = -delta;
    } else {
      const SpheroidSupport& si = in.body[i];
      const SpheroidSupport& sj = in.body[j];
      SpheroidContactCache& cache = in.sph[e].cache;
      // Separation certificate at the warm start (or along the centre line):
      // g(n) < 0 proves delta < 0, so no solve; the cache is kept as it is.
      // A solve from the warm start reuses the support values found there.
      SpheroidStart start;
      double g;  // g(n) >= delta at the probe n
      if (cache.valid) {
        start = SpheroidStart::at(si, sj, warm_start_normal(cache));
        g = start.gap(d);
      } else {
        g = spheroid_gap_bound(si, sj, d, (1.0 / std::sqrt(c_dist2[c])) * d);
      }
      if (g < 0.0) {
        delta = -1.0;
        gap = -g;
      } else {
        // The cache follows contacts only: a solve that finds the pair apart
        // leaves it as it was, so an apart pair's evaluation has no effect.
        // (After an apart spell the warm start may be stale; the plain
        // Newton then takes more steps or the counted fallback.)
        SpheroidContactCache trial = cache;
        const SpheroidContact sc =
            detect_spheroid_contact(si, sj, d, &trial, &acc.spheroid, {}, cache.valid ? &start : nullptr);
        delta = sc.overlap;
        nrm = sc.normal;
        cpt = sc.contact_point;
        if (delta > 0.0) cache = trial;
        gap = sc.converged ? -delta : 0.0;  // delta = g(n*) when converged
      }
    }
    SpheroidPairState& sp = in.sph[e];
    PairState& st = in.state[e];
    if (!(delta > 0.0)) {  // in reach, not in contact
      st = PairState{};
      in.spring[e] = Vec3{};
      sp.torque_i = Vec3{};
      // Sleep on half the gap, less a floor for the rounding of g (~eps
      // (a_i + a_j)) and of the clock (~eps C).
      const double floor = 64.0 * std::numeric_limits<double>::epsilon() * (in.axes[i].x + in.axes[j].x + in.clock);
      if (in.sleep && gap > floor) sp.wake = in.clock + 0.5 * (gap - floor);
      continue;
    }
    // eq. 104 with the average radius (a + 2b)/3; a sphere keeps R exactly
    const double ri = in.hertz_radius[i], rj = in.hertz_radius[j];
    const double r_eff = ri * rj / (ri + rj);
    const Vec3 cj = cpt - d;  // contact point relative to x_j
    const Vec3 vc = in.vel[j] - in.vel[i] + lgrad * d + cross(in.omg[j], cj) - cross(in.omg[i], cpt);
    const Vec3 dt_t = dt * (vc - dot(vc, nrm) * nrm);
    const ContactResult r = law.evaluate(nrm, delta, r_eff, dt_t, in.spring[e]);
    Vec3 f = r.force_on_j;
    if constexpr (Viscous)
      acc.viscous_dissipation +=
          dt * add_dashpots(in.mass[i], in.mass[j], in.viscous_a, law, delta, r_eff, nrm, vc, r.sliding, f);
    st.force = f;
    st.moment_axis = cross(cj, f);  // here: the moment on j (see SpheroidPairState)
    st.half_overlap = 0.5 * delta;
    in.active[e] = 1;
    sp.torque_i = cross(f, cpt);  // c x (-F_on_j)
    if (in.force_out) {  // the gather's arithmetic, in the gather's order
      in.force_out[i] -= f;
      in.torque_out[i] += sp.torque_i;
      in.force_out[j] += f;
      in.torque_out[j] += st.moment_axis;
    }
    ++contacts;
    vxx += d.x * f.x; vxy += d.x * f.y; vxz += d.x * f.z;
    vyx += d.y * f.x; vyy += d.y * f.y; vyz += d.y * f.z;
    vzx += d.z * f.x; vzy += d.z * f.y; vzz += d.z * f.z;
    if (Measure) acc.elastic_energy += r.elastic_energy;
    acc.friction_dissipation += r.friction_dissipation;
    acc.max_overlap_ratio = std::max(acc.max_overlap_ratio, delta / std::min(in.axes[i].y, in.axes[j].y));
    acc.sliding += r.sliding ? 1 : 0;
    if (Measure) {
      const double f2 = norm2(f);
      acc.sum_force2 += f2;
      acc.sum_force += std::sqrt(f2);
    }
  }
  acc.contacts = contacts;
  acc.virial.m[0][0] = vxx; acc.virial.m[0][1] = vxy; acc.virial.m[0][2] = vxz;
  acc.virial.m[1][0] = vyx; acc.virial.m[1][1] = vyy; acc.virial.m[1][2] = vyz;
  acc.virial.m[2][0] = vzx; acc.virial.m[2][1] = vzy; acc.virial.m[2][2] = vzz;
  return acc;
}

using PairKernel = ContactSums (*)(const PairInputs&, std::int32_t, std::int32_t, std::int32_t*, std::int32_t*,
                                   Vec3*, double*);

template <bool Viscous>
PairKernel pair_kernel(bool spheroids, bool measure) {
  if (spheroids)
    return measure ? &evaluate_pairs_spheroid<true, Viscous> : &evaluate_pairs_spheroid<false, Viscous>;
  return measure ? &evaluate_pairs<true, Viscous> : &evaluate_pairs<false, Viscous>;
}

}  // namespace

void ContactForces::set_viscous_damping(const ViscousContactDamping& d) { viscous_a_ = d.coefficient(); }

ContactSums ContactForces::compute(const Particles& p, const PeriodicCell& cell, NeighborList& list,
                                   const HertzMindlin& law, double dt, bool measure,
                                   std::vector<Vec3>& force, std::vector<Vec3>& torque) {
  const std::size_t n = p.size();
  const std::int32_t nchunks = chunk_count(n);
  chunk_sums_.assign(static_cast<std::size_t>(nchunks), ContactSums{});
  PairData& pd = list.pairs();
  const bool spheroids = list.has_spheroids();
  if (spheroids && pd.spheroid.size() != pd.size())
    throw std::logic_error("contact forces: neighbour list without spheroid pair states");
  if (spheroids) {
    bodies_.resize(n);
    hertz_radius_.resize(n);
  }
  PairInputs in{p.frac.data(),     p.velocity.data(),     p.omega.data(),
                    p.radius.data(),   list.offsets().data(), list.owners().data(),
                    pd.partner.data(), pd.spring.data(),      pd.state.data(),
                    pd.active.data(),  p.semi_axes.data(),    bodies_.data(),
                    hertz_radius_.data(),
                    sleep_ ? motion_clock_ : std::numeric_limits<double>::infinity(), sleep_,
                    p.shape.data(),    pd.spheroid.data(),    cell.h(),
                    cell.velocity_gradient(),                 law,
                    dt,                nullptr,               nullptr,
                    p.mass.data(),     viscous_a_};
  ContactSums* sums = chunk_sums_.data();
  force.resize(n);
  torque.resize(n);
  const std::size_t state_bytes =
      pd.size() * (sizeof(PairState) + (spheroids ? sizeof(SpheroidPairState) : std::size_t{0}));
  const bool scatter = omp_get_max_threads() == 1 && state_bytes >= pair_loop_bytes_;
  pair_loop_sums_ = scatter;
  if (scatter) {
    std::fill(force.begin(), force.end(), Vec3{});
    std::fill(torque.begin(), torque.end(), Vec3{});
    in.force_out = force.data();
    in.torque_out = torque.data();
  }
  if (static_cast<int>(scratch_.size()) < omp_get_max_threads())
    scratch_.resize(static_cast<std::size_t>(omp_get_max_threads()));
  Scratch* scratch = scratch_.data();

  const std::int32_t* goff = list.gather_offsets().data();
  const std::int32_t* gcode = list.gather_codes().data();
  const PairState* ps = pd.state.data();
  const double* rad = p.radius.data();
  Vec3* fout = force.data();
  Vec3* tout = torque.data();
  const std::int32_t ni = static_cast<std::int32_t>(n);

  const PairKernel kernel =
      viscous_a_ > 0.0 ? pair_kernel<true>(spheroids, measure) : pair_kernel<false>(spheroids, measure);

  // Gather of sphere i, over its gather slots in list order (see below).
  const auto gather_sphere = [&](std::int32_t i) {
    const std::int32_t ip = std::min(i + kPrefetchParticles, ni);
    for (std::int32_t k = goff[ip]; k < goff[std::min(ip + 1, ni)]; ++k) __builtin_prefetch(ps + (gcode[k] >> 2));
    Vec3 f{}, t{};
    const double ri = rad[i];
    for (std::int32_t g = goff[i]; g < goff[i + 1]; ++g) {
      const std::int32_t code = gcode[g];
      const PairState& s = ps[code >> 2];
      // +F on the partner, -F on the owner: f + (+-1) F rounds as f +- F
      const double sign = 1.0 - static_cast<double>(code & 2);
      f = fused_multiply_add(sign, s.force, f);
      t = fused_multiply_add(ri - s.half_overlap, s.moment_axis, t);
    }
    fout[i] = f;
    tout[i] = t;
  };
  SplitSums* split = &split_;
  ThreadRuns* runs = &runs_;
  split_used_ = !scatter && !spheroids && omp_get_max_threads() > 1;

  // One parallel region: pair evaluation, barrier, sums (on one thread the
  // pair loop sums per particle itself, in the same order: no gather).
#pragma omp parallel
  {
    Scratch& mine = scratch[omp_get_thread_num()];
    if (spheroids) {
      // Support data of every particle (symmetry axis e = q (1,0,0)): one
      // rotation per particle instead of one per particle and pair.
      const Vec3* axes = p.semi_axes.data();
      const Quaternion* orient = p.orientation.data();
      const Shape* shape = p.shape.data();
      SpheroidSupport* body = bodies_.data();
      double* hertz_r = hertz_radius_.data();
#pragma omp for schedule(static, kChunkSize)
      for (std::int32_t i = 0; i < static_cast<std::int32_t>(n); ++i) {
        body[i] = SpheroidSupport::of(Spheroid::from_semi_axes(axes[i], orient[i]));
        hertz_r[i] = shape[i] == Shape::Spheroid ? (axes[i].x + 2.0 * axes[i].y) / 3.0 : rad[i];
      }
      // (implicit barrier)
    }
    const auto evaluate_chunk = [&](std::int32_t c) {
      const std::int32_t i_begin = c * kChunkSize;
      const std::int32_t i_end = std::min<std::int32_t>(ni, i_begin + kChunkSize);
      mine.reserve(static_cast<std::size_t>(in.off[i_end] - in.off[i_begin]));
      sums[c] = kernel(in, i_begin, i_end, mine.entry.data(), mine.separated.data(), mine.branch.data(),
                       mine.dist2.data());
    };
    if (scatter) {
      // One thread, chunks in ascending order: the pair loop visits every
      // pair in list order, the order of the per-particle sums.
      for (std::int32_t c = 0; c < nchunks; ++c) evaluate_chunk(c);
    } else if (spheroids) {
      // chunk costs vary with the solves and the sleeping pairs: dealt out
#pragma omp for schedule(dynamic, 1)
      for (std::int32_t c = 0; c < nchunks; ++c) evaluate_chunk(c);
    } else if (omp_get_num_threads() == 1) {
      // One thread asked for the gather (set_pair_loop_sum_threshold): pair loop, then gather
      for (std::int32_t c = 0; c < nchunks; ++c) evaluate_chunk(c);
      for (std::int32_t i = 0; i < ni; ++i) gather_sphere(i);
    } else {
      // Spheres: each thread takes its run of consecutive chunks (the run of
      // the integrator too) and sums in its own buffers (split_sums.h).
#pragma omp single
      {
        runs->prepare(nchunks, n, omp_get_num_threads());
        split->prepare(list, n, *runs);
      }
      // (implicit barrier: the plan is ready)
      const int t = omp_get_thread_num();
      const auto [c0, c1] = runs->run(t);
      const double start = omp_get_wtime();
      const std::int32_t i0 = c0 * kChunkSize, i1 = std::min(ni, c1 * kChunkSize);
      Vec3* fb = split->force(t);
      Vec3* tb = split->torque(t);
      std::fill(fb + i0, fb + i1, Vec3{});
      std::fill(tb + i0, tb + i1, Vec3{});
      for (const std::int32_t j : split->foreign(t)) {
        fb[j] = Vec3{};
        tb[j] = Vec3{};
      }
      PairInputs own = in;
      own.force_out = fb;
      own.torque_out = tb;
      for (std::int32_t c = c0; c < c1; ++c) {
        const std::int32_t b = c * kChunkSize, e = std::min<std::int32_t>(ni, b + kChunkSize);
        mine.reserve(static_cast<std::size_t>(in.off[e] - in.off[b]));
        sums[c] = kernel(own, b, e, mine.entry.data(), mine.separated.data(), mine.branch.data(), mine.dist2.data());
      }
      const double evaluated = omp_get_wtime();
#pragma omp barrier
      const double summing = omp_get_wtime();
      // every pair state is final: the sole particles' sums are the buffers',
      // the others gather (below, same bits)
      for (std::int32_t i = i0; i < i1; ++i) {
        if (split->sole(i)) {
          fout[i] = fb[i];
          tout[i] = tb[i];
        } else {
          gather_sphere(i);
        }
      }
      runs->record(t, (evaluated - start) + (omp_get_wtime() - summing));
    }
    // (spheroids: implicit barrier, every pair state is final)

    // Gather, per particle, over its gather slots in list order: entries of
    // owners stored before it (force added), its own entries (force
    // subtracted), entries of owners stored after it (force added). No
    // contact test: entries not in contact hold zero force and moment (see
    // evaluate_pairs), and f + 0, t + l * 0 leave f and t unchanged bit for
    // bit (a sum that starts at +0 and only adds or subtracts is never -0),
    // so the loop has no unpredictable branch, and the sums equal those of
    // the one-thread pair loop, which adds the contacts only.
    if (scatter) {
      // the pair loop has made the sums
    } else if (spheroids) {
      // The moment on the partner is in the pair state (one line for the
      // entries of other particles), the one on the owner in the spheroid
      // pair state (own entries: consecutive in the list).
      const SpheroidPairState* sps = pd.spheroid.data();
#pragma omp for schedule(static, kChunkSize)
      for (std::int32_t i = 0; i < ni; ++i) {
        const std::int32_t ip = std::min(i + kPrefetchParticles, ni);
        for (std::int32_t k = goff[ip]; k < goff[std::min(ip + 1, ni)]; ++k) __builtin_prefetch(ps + (gcode[k] >> 2));
        Vec3 f{}, t{};
        std::int32_t g = goff[i];
        const std::int32_t g_end = goff[i + 1];
        for (; g < g_end && (gcode[g] & 2) == 0; ++g) {  // owners stored before i
          const std::int32_t e = gcode[g] >> 2;
          f += ps[e].force;
          t += ps[e].moment_axis;  // moment on j
        }
        for (; g < g_end && (gcode[g] & 2) != 0; ++g) {  // own entries
          const std::int32_t e = gcode[g] >> 2;
          f -= ps[e].force;
          t += sps[e].torque_i;
        }
        for (; g < g_end; ++g) {  // owners stored after i
          const std::int32_t e = gcode[g] >> 2;
          f += ps[e].force;
          t += ps[e].moment_axis;
        }
        fout[i] = f;
        tout[i] = t;
      }
    }
  }

  ContactSums total;
  for (const ContactSums& s : chunk_sums_) total.add(s);
  return total;
}

}  // namespace vt::dem
