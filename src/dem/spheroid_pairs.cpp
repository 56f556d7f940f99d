// Pair kernel of ContactForces for particles that include spheroids
// (formulas in contact_forces.h; the contact solver in spheroid_contact.h).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "pair_kernel.h"
#include "virtual_triaxial/dem/pair_body.h"
#include "virtual_triaxial/dem/spheroid_warm_lanes.h"

namespace vt::dem::pairs {

namespace {

/// The geometry of a pair in reach and awake.
struct PairGeometry {
  double delta = 0.0;  ///< signed overlap [m]; > 0 contact
  double gap = 0.0;    ///< > 0: apart by at least this along some fixed normal [m]
  Vec3 nrm;            ///< normal i -> j (contacts)
  Vec3 cpt;            ///< contact point relative to x_i [m] (contacts)
};

/// The counters of `solved` warm solves that converged in one Newton step.
inline void count_warm_solves(SpheroidContactStats& stats, std::uint64_t solved) {
  stats.calls += solved;
  stats.solves += solved;
  stats.warm_starts += solved;
  stats.iterations += solved;
}

/// Entry e without a contact: no force or spring (its cache and wake time
/// are the caller's); returns its spheroid state.
inline SpheroidPairState& clear_contact(const PairInputs& in, std::int32_t e) {
  in.state[e] = PairState{};
  in.spring[e] = Vec3{};
  return in.sph[e];
}

/// Pairs of the spheroid pair loop taken kLawLanes at a time (PairGroup
/// below), as the sphere loop takes its contacts (sphere_pairs.cpp): the
/// inputs of each gathered into arrays, the contact law computed by one loop
/// without jumps over the lanes (SIMD), the results then stored and summed
/// one pair at a time in list order. Unused lanes of a partial group repeat
/// its first lane. One lane per pair of the warm lanes, whose kLanes is the
/// group size (spheroid_warm_lanes.h says why 16).
constexpr int kLawLanes = SpheroidWarmLanes::kLanes;
struct LawLanes {
  // inputs
  double dx[kLawLanes], dy[kLawLanes], dz[kLawLanes];  // branch d [m]
  double delta[kLawLanes], nx[kLawLanes], ny[kLawLanes], nz[kLawLanes];
  double cx[kLawLanes], cy[kLawLanes], cz[kLawLanes];  // contact point relative to x_i [m]
  double ri[kLawLanes], rj[kLawLanes];                 // R_i, R_j of eq. 104 [m]
  double rvx[kLawLanes], rvy[kLawLanes], rvz[kLawLanes];  // v_j - v_i [m/s]
  double wix[kLawLanes], wiy[kLawLanes], wiz[kLawLanes], wjx[kLawLanes], wjy[kLawLanes], wjz[kLawLanes];
  double sx[kLawLanes], sy[kLawLanes], sz[kLawLanes];  // spring [N]: in, then out
  double mi[kLawLanes] = {}, mj[kLawLanes] = {};       // viscous dashpots only (else zeros)
  double minor[kLawLanes];                             // min(b_i, b_j) [m]
  // results
  double fx[kLawLanes], fy[kLawLanes], fz[kLawLanes];     // force on j [N]
  double mjx[kLawLanes], mjy[kLawLanes], mjz[kLawLanes];  // moment on j, (c - d) x F [N m]
  double mix[kLawLanes], miy[kLawLanes], miz[kLawLanes];  // moment on i, F x c [N m]
  double energy[kLawLanes], friction[kLawLanes], power[kLawLanes], f2[kLawLanes];
  double ratio[kLawLanes];  // delta / min(b_i, b_j)
  LaneFlag sliding[kLawLanes];
  /// Copies the inputs of lane `from` into lane `to`.
  void repeat(int from, int to) {
    double* const fields[] = {dx, dy, dz, delta, nx, ny, nz, cx, cy, cz, ri, rj, rvx, rvy, rvz,
                              wix, wiy, wiz, wjx, wjy, wjz, sx, sy, sz, mi, mj, minor};
    for (double* f : fields) f[to] = f[from];
  }
};

/// Hertz-Mindlin of every lane at its contact point c (relative to x_i):
///   v_c = v_j - v_i + L d + w_j x (c - d) - w_i x c,
///   T_i = c x F_on_i = F x c,  T_j = (c - d) x F_on_j.
template <bool Viscous>
inline void spheroid_contact_lanes(LawLanes& L, const Mat3& lgrad, const HertzMindlin& law, double dt,
                                   double viscous_a) {
  for (int k = 0; k < kLawLanes; ++k) {
    const Vec3 d{L.dx[k], L.dy[k], L.dz[k]};
    const Vec3 nrm{L.nx[k], L.ny[k], L.nz[k]};
    const Vec3 cpt{L.cx[k], L.cy[k], L.cz[k]};
    const double delta = L.delta[k];
    const double ri = L.ri[k], rj = L.rj[k];
    const double r_eff = ri * rj / (ri + rj);
    const Vec3 cj = cpt - d;  // contact point relative to x_j
    const Vec3 wi{L.wix[k], L.wiy[k], L.wiz[k]}, wj{L.wjx[k], L.wjy[k], L.wjz[k]};
    const Vec3 vc = Vec3{L.rvx[k], L.rvy[k], L.rvz[k]} + lgrad * d + cross(wj, cj) - cross(wi, cpt);
    const Vec3 dt_t = dt * (vc - dot(vc, nrm) * nrm);
    Vec3 spring{L.sx[k], L.sy[k], L.sz[k]};
    const ContactResult r = law.evaluate(nrm, delta, r_eff, dt_t, spring);
    Vec3 f = r.force_on_j;
    L.power[k] = Viscous ? add_dashpots(L.mi[k], L.mj[k], viscous_a, law, delta, r_eff, nrm, vc, r.sliding, f) : 0.0;
    const Vec3 mj = cross(cj, f), mi = cross(f, cpt);
    L.sx[k] = spring.x; L.sy[k] = spring.y; L.sz[k] = spring.z;
    L.fx[k] = f.x; L.fy[k] = f.y; L.fz[k] = f.z;
    L.mjx[k] = mj.x; L.mjy[k] = mj.y; L.mjz[k] = mj.z;
    L.mix[k] = mi.x; L.miy[k] = mi.y; L.miz[k] = mi.z;
    L.energy[k] = r.elastic_energy;
    L.friction[k] = r.friction_dissipation;
    L.f2[k] = norm2(f);
    L.ratio[k] = delta / L.minor[k];
    L.sliding[k] = r.sliding ? 1 : 0;
  }
}

/// Up to kLawLanes pairs in reach and awake, queued in list order and taken
/// through geometry and law together. A lane's geometry is either known when
/// it is queued (a sphere pair by the closed form, a spheroid pair without a
/// warm cache by scalar_geometry; only contacts are queued so) or found for
/// the group by the warm lanes; then the contact law runs on all lanes (those
/// found apart compute numbers nobody reads) and the results are stored and
/// summed lane by lane, so in list order. A lane's results depend on its own
/// inputs only, whichever group takes it.
struct PairGroup {
  SpheroidWarmLanes warm{};
  LawLanes law{};
  double known[kLawLanes] = {};  ///< 1: geometry set when queued; 0: by the warm lanes
  bool contact[kLawLanes] = {};  ///< after the geometry: in contact
  double gap[kLawLanes] = {};    ///< not in contact: as PairGeometry::gap [m]
  std::int32_t entry[kLawLanes] = {};
  std::int32_t list_index[kLawLanes] = {};  ///< c: the pair's place among the pairs in reach
  std::int32_t owner[kLawLanes] = {}, partner[kLawLanes] = {};
  double minor_i[kLawLanes], minor_j[kLawLanes];  ///< b of each body [m]
  int n = 0;                                ///< lanes queued

  /// The bodies of every lane (PairBody lines of the owners and partners;
  /// unused lanes repeat lane 0) into the warm lanes and the law's radii,
  /// in blocks of eight lanes (body_lanes, pair_body.h).
  void set_bodies(const PairBody* body) {
    static_assert(kLawLanes % kBodyLanes == 0, "body_lanes fills blocks of kBodyLanes lanes");
    for (int k = n; k < kLawLanes; ++k) {
      owner[k] = owner[0];
      partner[k] = partner[0];
    }
    double* const of_i[PairBody::kFields] = {warm.bi2, warm.ki,      warm.eix, warm.eiy,
                                             warm.eiz, warm.bound_i, law.ri,   minor_i};
    double* const of_j[PairBody::kFields] = {warm.bj2, warm.kj,      warm.ejx, warm.ejy,
                                             warm.ejz, warm.bound_j, law.rj,   minor_j};
    for (int h = 0; h < kLawLanes; h += kBodyLanes) {  // lanes [h, h + kBodyLanes)
      double* block_i[PairBody::kFields];
      double* block_j[PairBody::kFields];
      for (int f = 0; f < PairBody::kFields; ++f) {
        block_i[f] = of_i[f] + h;
        block_j[f] = of_j[f] + h;
      }
      body_lanes(body, owner + h, block_i);
      body_lanes(body, partner + h, block_j);
    }
    for (int k = 0; k < kLawLanes; ++k) law.minor[k] = std::min(minor_i[k], minor_j[k]);
  }

  /// Lane k's contact geometry, known now.
  void set_geometry(int k, const PairGeometry& gm) {
    known[k] = 1.0;
    contact[k] = true;
    law.delta[k] = gm.delta;
    law.nx[k] = gm.nrm.x; law.ny[k] = gm.nrm.y; law.nz[k] = gm.nrm.z;
    law.cx[k] = gm.cpt.x; law.cy[k] = gm.cpt.y; law.cz[k] = gm.cpt.z;
  }
  /// The warm lanes' geometry into the law's inputs of the lanes not known
  /// (selects over all lanes; the outcome decides later what is read).
  void take_warm_geometry() {
    for (int k = 0; k < kLawLanes; ++k) {
      const bool w = known[k] == 0.0;
      law.delta[k] = w ? warm.delta[k] : law.delta[k];
      law.nx[k] = w ? warm.ox[k] : law.nx[k];
      law.ny[k] = w ? warm.oy[k] : law.ny[k];
      law.nz[k] = w ? warm.oz[k] : law.nz[k];
      law.cx[k] = w ? warm.cx[k] : law.cx[k];
      law.cy[k] = w ? warm.cy[k] : law.cy[k];
      law.cz[k] = w ? warm.cz[k] : law.cz[k];
    }
  }
};

/// Geometry of entry e (owner i, branch d, |d|^2 = dist2) with a spheroid,
/// one pair at a time: the separation certificate g(n) < 0 at the warm
/// start (or along d/|d|) proves the pair apart without iterating (the cache
/// is kept as it is); otherwise the common-normal solver
/// (spheroid_contact.h), warm-started from the pair's cache, which keeps the
/// result only for a contact.
PairGeometry scalar_geometry(const PairInputs& in, std::int32_t i, std::int32_t e, const Vec3& d, double dist2,
                             SpheroidContactStats& stats) {
  const SpheroidSupport& si = in.body[i].support;
  const SpheroidSupport& sj = in.body[in.partner[e]].support;
  SpheroidContactCache& cache = in.sph[e].cache;
  PairGeometry gm;
  // A solve from the warm start reuses the support values found there.
  SpheroidStart start;
  double g;  // g(n) >= delta at the probe n
  if (cache.valid) {
    start = SpheroidStart::at(si, sj, warm_start_normal(cache));
    g = start.gap(d);
  } else {
    g = spheroid_gap_bound(si, sj, d, (1.0 / std::sqrt(dist2)) * d);
  }
  if (g < 0.0) {
    gm.delta = -1.0;
    gm.gap = -g;
    return gm;
  }
  // The cache follows contacts only: a solve that finds the pair apart
  // leaves it as it was, so an apart pair's evaluation has no effect.
  // (After an apart spell the warm start may be stale; the plain Newton
  // then takes more steps or the counted fallback.)
  SpheroidContactCache trial = cache;
  const SpheroidContact sc =
      detect_spheroid_contact(si, sj, d, &trial, &stats, {}, cache.valid ? &start : nullptr);
  gm.delta = sc.overlap;
  gm.nrm = sc.normal;
  gm.cpt = sc.contact_point;
  if (gm.delta > 0.0) cache = trial;
  gm.gap = sc.converged ? -gm.delta : 0.0;  // delta = g(n*) when converged
  return gm;
}

/// Pairs owned by particles [i_begin, i_end) when the particles include
/// spheroids (in.body: PairBody of every particle, this evaluation).
/// Pass 1 keeps the pairs whose bounding spheres (radius bound = a) overlap, except
/// those asleep (found apart earlier and certified apart since by the motion
/// clock, ContactForces::set_motion_clock), and
/// drops the solver cache of every other pair (so the cache of a pair
/// depends only on its own history while in reach: a restart, which
/// rebuilds the list, continues bit for bit). Pass 2, kLawLanes pairs at a
/// time in list order (PairGroup), first their geometry: a sphere-sphere
/// pair takes the closed form (delta = R_i + R_j - |d|, n = d/|d|, contact
/// point x_i + (R_i - delta/2) n); a pair with a spheroid and a warm cache
/// goes to the warm lanes (spheroid_warm_lanes.h: the separation certificate
/// at the warm start and one Newton step, kLawLanes pairs at a time as SIMD), and
/// one those cannot settle, or without a warm cache, to scalar_geometry (the
/// certificate, then the common-normal solver of spheroid_contact.h; a
/// sphere enters it as a spheroid with a = b = R). Each pair's geometry
/// depends only on its own inputs, whichever group takes it. Then, stored
/// and summed in list order, Hertz-Mindlin
/// with R_i the average radius (a + 2b)/3 (eq. 104; R for a sphere) at the
/// contact point c (relative to x_i), as SIMD over the group:
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
      __builtin_prefetch(in.body + jp);
      __builtin_prefetch(&in.sph[e + kPrefetchEntries].wake, 1);
    }
    const std::int32_t i = in.owner[e];
    const std::int32_t j = in.partner[e];
    const Vec3 ds = PeriodicCell::minimum_image(in.frac[j] - in.frac[i]);
    const Vec3 d = h * ds;
    const double dist2 = norm2(d);
    const double reach = in.body[i].support.bound + in.body[j].support.bound;  // a_i + a_j (a >= b)
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
    // Out of reach: listed to be cleared below when it holds anything (a
    // contact, a cache or a wake time; the cache follows contacts only, so
    // has_previous implies valid). Only those entries are written.
    const std::int32_t holds = static_cast<std::int32_t>(in.active[e]) |
                               static_cast<std::int32_t>(in.sph[e].cache.valid) | (wake != 0.0 ? 1 : 0);
    s_entry[ns] = e;
    ns += holds & (in_reach ^ 1);
    in.active[e] = 0;  // contacts set it again in pass 2
  }
  // Out of reach: no contact, cache.reset() and awake (the sleep bound needs
  // |d| < a_i + a_j). An entry without a contact already holds zeros.
  for (std::int32_t k = 0; k < ns; ++k) {
    const std::int32_t e = s_entry[k];
    SpheroidPairState& sp = clear_contact(in, e);
    sp.wake = 0.0;
    sp.cache.reset();
  }

  // Pass 2: the pairs in reach and awake, in list order, kLawLanes at a time
  // (PairGroup): geometry, then the contact law, then stores and sums.
  ChunkSums sums;
  SpheroidContactStats& stats = sums.acc.spheroid;
  stats.asleep = static_cast<std::uint64_t>(slept);
  std::int64_t contacts = 0;
  PairGroup g;
  Vec3 sink_f, sink_t;  // the sums of particles that are not home
  const double tolerance = SpheroidContactOptions{}.step_tolerance;
  // A pair in reach and not in contact: cleared, and asleep on half its gap
  // less a floor for the rounding of g (~eps (a_i + a_j)) and of the clock
  // (~eps C).
  const auto part = [&](std::int32_t e, std::int32_t i, std::int32_t j, double gap) {
    SpheroidPairState& sp = clear_contact(in, e);
    const double reach = in.body[i].support.bound + in.body[j].support.bound;
    const double floor = 64.0 * std::numeric_limits<double>::epsilon() * (reach + in.clock);
    if (in.sleep && gap > floor) sp.wake = in.clock + 0.5 * (gap - floor);
  };
  const auto run_group = [&]() {
    StiffnessLanes<kLawLanes> stiffness;  // measured steps: the group's axis stiffness terms
    const int n = g.n;
    g.set_bodies(in.body);
    bool warm = false;
    for (int k = 0; k < n; ++k) warm |= g.known[k] == 0.0;
    if (warm) {
      for (int k = n; k < kLawLanes; ++k) g.warm.repeat(0, k);
      solve_spheroid_warm_lanes(g.warm, tolerance);
      g.take_warm_geometry();
      std::uint64_t solved = 0;  // counted here, added once (stats is a capture: memory)
      for (int k = 0; k < n; ++k) {
        if (g.known[k] != 0.0) continue;
        const std::int32_t e = g.entry[k];
        switch (g.warm.outcome(k)) {
          case WarmOutcome::Apart:
            g.contact[k] = false;
            g.gap[k] = g.warm.gap[k];
            break;
          case WarmOutcome::Solved:
            ++solved;
            g.contact[k] = g.warm.delta[k] > 0.0;
            g.gap[k] = -g.warm.delta[k];
            if (g.contact[k]) advance_cache(in.sph[e].cache, g.warm.normal(k));
            break;
          case WarmOutcome::Scalar: {
            const std::int32_t c = g.list_index[k];
            const PairGeometry gm = scalar_geometry(in, g.owner[k], e, c_branch[c], c_dist2[c], stats);
            g.contact[k] = gm.delta > 0.0;
            g.gap[k] = gm.gap;
            if (g.contact[k]) g.set_geometry(k, gm);
            break;
          }
        }
      }
      count_warm_solves(stats, solved);
    }
    for (int k = n; k < kLawLanes; ++k) g.law.repeat(0, k);
    spheroid_contact_lanes<Viscous>(g.law, lgrad, law, dt, in.viscous_a);
    const LawLanes& L = g.law;
    if constexpr (Measure) {
      double half_overlap[kLawLanes];  // as stored in the pair states below
      for (int k = 0; k < kLawLanes; ++k) half_overlap[k] = 0.5 * L.delta[k];
      stiffness.compute(L.dx, L.dy, L.dz, L.fx, L.fy, L.fz, half_overlap, law.tangential_ratio());
    }
    // The lanes' stores and sums through local copies of the inputs, the
    // sums and the count: through `in` and the lambda's captures they were
    // loaded and stored again at every lane, since the store through
    // in.active (a char) may alias anything that is not a local.
    const PairInputs lane_in = in;
    ChunkSums lane_sums = sums;
    std::int64_t lane_contacts = contacts;
    for (int k = 0; k < n; ++k) {
      const std::int32_t e = g.entry[k], i = g.owner[k], j = g.partner[k];
      if (!g.contact[k]) {
        part(e, i, j, g.gap[k]);
        continue;
      }
      const Vec3 f{L.fx[k], L.fy[k], L.fz[k]};
      const Vec3 mj{L.mjx[k], L.mjy[k], L.mjz[k]};
      const Vec3 mi{L.mix[k], L.miy[k], L.miz[k]};
      PairState& st = lane_in.state[e];
      store(st.force, f);
      st.half_overlap = 0.5 * L.delta[k];
      store(lane_in.spring[e], Vec3{L.sx[k], L.sy[k], L.sz[k]});
      lane_in.active[e] = 1;
      // a particle of another thread's run (the owner of a ghost, the
      // partner of a pair crossing the runs): summed there (split_sums.h)
      const bool home_i = lane_in.home(i), home_j = lane_in.home(j);
      Vec3& fi = home_i ? lane_in.force_out[i] : sink_f;
      Vec3& ti = home_i ? lane_in.torque_out[i] : sink_t;
      fi -= f;
      ti += mi;
      Vec3& fj = home_j ? lane_in.force_out[j] : sink_f;
      Vec3& tj = home_j ? lane_in.torque_out[j] : sink_t;
      fj += f;
      tj += mj;
      lane_sums.add<Measure, Viscous>(L, k, f, dt);
      if constexpr (Measure) lane_sums.add_stiffness(stiffness, k);
      ++lane_contacts;
    }
    sums = lane_sums;
    contacts = lane_contacts;
    g.n = 0;
  };
  for (std::int32_t c = 0; c < nc; ++c) {
    if (c + kPrefetchContacts < nc) {
      const std::int32_t ep = c_entry[c + kPrefetchContacts];
      const std::int32_t jp = in.partner[ep];
      __builtin_prefetch(in.body + jp);
      __builtin_prefetch(in.sph + ep, 1);
      __builtin_prefetch(in.vel + jp);
      __builtin_prefetch(in.omg + jp);
      __builtin_prefetch(in.state + ep, 1);
      __builtin_prefetch(in.spring + ep, 1);
      if (in.home(jp)) {  // never another run's sums (sphere_pairs.cpp)
        __builtin_prefetch(in.force_out + jp, 1);
        __builtin_prefetch(in.torque_out + jp, 1);
      }
    }
    const std::int32_t e = c_entry[c];
    const std::int32_t i = in.owner[e];
    const std::int32_t j = in.partner[e];
    const Vec3 d = c_branch[c];
    const int k = g.n;
    if (in.shape[i] != Shape::Spheroid && in.shape[j] != Shape::Spheroid) {
      PairGeometry gm;
      const double dist = std::sqrt(c_dist2[c]);
      gm.delta = in.rad[i] + in.rad[j] - dist;
      if (!(gm.delta > 0.0)) {
        part(e, i, j, -gm.delta);
        continue;
      }
      gm.nrm = (1.0 / dist) * d;
      gm.cpt = (in.rad[i] - 0.5 * gm.delta) * gm.nrm;
      g.set_geometry(k, gm);
    } else if (in.sph[e].cache.valid) {
      g.warm.set_pair(k, d, in.sph[e].cache);
      g.known[k] = 0.0;
    } else {
      const PairGeometry gm = scalar_geometry(in, i, e, d, c_dist2[c], stats);
      if (!(gm.delta > 0.0)) {
        part(e, i, j, gm.gap);
        continue;
      }
      g.set_geometry(k, gm);
    }
    g.entry[k] = e;
    g.list_index[k] = c;
    // the bodies and radii (eq. 104 with the average radius (a + 2b)/3; a
    // sphere keeps R exactly) when the group runs (PairGroup::set_bodies)
    g.owner[k] = i;
    g.partner[k] = j;
    LawLanes& L = g.law;
    L.dx[k] = d.x; L.dy[k] = d.y; L.dz[k] = d.z;
    set_motion<Viscous>(L, k, in, e, i, j);
    if (++g.n == kLawLanes) run_group();
  }
  if (g.n > 0) run_group();
  return sums.finish(contacts);
}

}  // namespace

PairKernel spheroid_pair_kernel(bool measure, bool viscous) {
  if (viscous) return measure ? &evaluate_pairs_spheroid<true, true> : &evaluate_pairs_spheroid<false, true>;
  return measure ? &evaluate_pairs_spheroid<true, false> : &evaluate_pairs_spheroid<false, false>;
}

}  // namespace vt::dem::pairs
