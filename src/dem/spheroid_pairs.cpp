// Pair kernel of ContactForces for particles that include spheroids
// (formulas in contact_forces.h; the contact solver in spheroid_contact.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "pair_kernel.h"

namespace vt::dem::pairs {

namespace {

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

}  // namespace

PairKernel spheroid_pair_kernel(bool measure, bool viscous) {
  if (viscous) return measure ? &evaluate_pairs_spheroid<true, true> : &evaluate_pairs_spheroid<false, true>;
  return measure ? &evaluate_pairs_spheroid<true, false> : &evaluate_pairs_spheroid<false, false>;
}

}  // namespace vt::dem::pairs
