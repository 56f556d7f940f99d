#include "virtual_triaxial/dem/leapfrog_integrator.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/huge_pages.h"
#include "virtual_triaxial/dem/lane_transpose.h"
#include "virtual_triaxial/dem/rigid_rotation.h"
#include "virtual_triaxial/dem/streaming_copy.h"

namespace vt::dem {

void IntegrationSums::add(const IntegrationSums& o) {
  damping_dissipation += o.damping_dissipation;
  kinetic_translational += o.kinetic_translational;
  kinetic_rotational += o.kinetic_rotational;
  sum_inertia_moment += o.sum_inertia_moment;
  max_displacement2 = std::max(max_displacement2, o.max_displacement2);
  max_speed2 = std::max(max_speed2, o.max_speed2);
  max_spin2 = std::max(max_spin2, o.max_spin2);
  finite = finite && o.finite;
}

void LeapfrogIntegrator::set_coefficients(const Particles& p, const std::vector<double>& alpha,
                                          double dt) {
  dt_ = dt;
  alpha_ = alpha;
  spheroids_ = p.has_spheroids();
  const std::size_t n = p.size();
  const std::size_t blocks = (n + kLanes - 1) / kLanes;
  reserve_huge(coef_, blocks);
  coef_.assign(blocks, CoefficientLanes{});
  rot_coef_.assign(spheroids_ ? blocks : 0, RotationLanes{});
  for (std::size_t i = 0; spheroids_ && i < n; ++i) {
    const SymmetricStepConstants r = SymmetricStepConstants::of(p.inertia[i], alpha[i], dt);
    RotationLanes& l = rot_coef_[i / kLanes];
    const std::size_t k = i % kLanes;
    l.kick[k] = r.kick;
    l.inv_i1[k] = r.inv_i1;
    l.inv_i2[k] = r.inv_i2;
    l.dt_inv_i2[k] = r.dt_inv_i2;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const double half = 0.5 * alpha[i] * dt;
    CoefficientLanes& c = coef_[i / kLanes];
    const std::size_t k = i % kLanes;
    c.decay[k] = (1.0 - half) / (1.0 + half);           // eq. 2, first factor
    c.kick[k] = dt / ((1.0 + half) * p.mass[i]);         // eq. 2, second factor / m
    c.kick_rot[k] = dt / ((1.0 + half) * p.inertia[i].x);  // sphere: isotropic I
    c.alpha_dt[k] = alpha[i] * dt;
    c.mass[k] = p.mass[i];
    c.inertia[k] = p.inertia[i].x;
  }
}

namespace {

/// One group's terms of IntegrationSums, per lane (filled by a lane loop),
/// added particle by particle in storage order by both lane paths.
template <std::size_t Lanes>
struct LaneTerms {
  double diss[Lanes], ekt[Lanes], ekr[Lanes], mom[Lanes], d2[Lanes], v2[Lanes], w2[Lanes], fin[Lanes];
  /// Lane k's drift (eq. 131: s(t+dt) = wrap(s(t) + H^-1 v dt), returned)
  /// and its terms: displacement since the list build, speed, spin, finiteness.
  Vec3 drift(std::size_t k, const Vec3& s_old, const Vec3& s_build, const Vec3& v_new, const Vec3& w_new,
             const Mat3& hinv, const Mat3& h, double dt) {
    const Vec3 s = PeriodicCell::wrap(s_old + hinv * (dt * v_new));
    const Vec3 ds = PeriodicCell::minimum_image(s - s_build);
    d2[k] = norm2(h * ds);
    v2[k] = norm2(v_new);
    w2[k] = norm2(w_new);
    fin[k] = v_new.x + v_new.y + v_new.z + w_new.x + w_new.y + w_new.z;
    return s;
  }
  /// Lane k into acc; moment(k): its sum_inertia_moment term (from mom[k]).
  template <bool Measure, class Moment>
  void add_to(IntegrationSums& acc, std::size_t k, const Moment& moment) const {
    acc.damping_dissipation += diss[k];
    if constexpr (Measure) {
      acc.kinetic_translational += ekt[k];
      acc.kinetic_rotational += ekr[k];
      acc.sum_inertia_moment += moment(k);
    }
    acc.max_displacement2 = std::max(acc.max_displacement2, d2[k]);
    acc.max_speed2 = std::max(acc.max_speed2, v2[k]);
    acc.max_spin2 = std::max(acc.max_spin2, w2[k]);
    if (!std::isfinite(d2[k]) || !std::isfinite(fin[k])) acc.finite = false;
  }
};

}  // namespace

template <bool Spheroids, bool Local>
IntegrationSums LeapfrogIntegrator::advance_chunk(const StepInputs& in, std::size_t i_begin, std::size_t i_end,
                                                  bool measure) const {
  const Mat3 hinv = in.hinv;
  const Mat3 h = in.h;
  const double dt = dt_;
  Vec3* vel = in.vel;
  Vec3* omg = in.omg;
  Vec3* frac = in.frac;
  const Vec3* f_in = in.f_in;
  const Vec3* t_in = in.t_in;
  const Vec3* s_build = in.s_build;
  const LocalDamping local = local_;
  IntegrationSums acc;
  for (std::size_t i = i_begin; i < i_end; ++i) {
    const Vec3 v_old = vel[i];
    const Vec3 w_old = omg[i];
    const Coefficients k = coefficients(i);
    Vec3 f = f_in[i], t = t_in[i];
    if constexpr (Local) {  // local_damping.h: velocity estimates at the force's time (YADE)
      f = local.damped(f, v_old + (0.5 * k.kick) * f);
      t = local.damped(t, Spheroids && in.shape[i] == Shape::Spheroid ? w_old : w_old + (0.5 * k.kick_rot) * t);
    }
    const Vec3 v_new = k.decay * v_old + k.kick * f;
    Vec3 w_new;
    if constexpr (Spheroids) {
      if (in.shape[i] == Shape::Spheroid) {
        // Rigid-body leapfrog (rigid_rotation.h): kick of L with the torque
        // and damping alpha L (eq. 29), exact torque-free drift of q (eq. 43).
        const Vec3 ib = in.inertia[i];
        Vec3 l_old, l_new;
        double two_e_rot;  // L_mid . I_world(q(t))^-1 L_mid = 2 x rotational energy at t
        if (ib.y == ib.z) {  // symmetric body: every spheroid
          Quaternion q = in.orient[i];
          w_new = w_old;
          const SymmetricRotationStep r = advance_symmetric_rotation(q, w_new, t, ib, rotation_constants(i));
          in.orient[i] = q;
          l_old = r.l_old;
          l_new = r.l_new;
          two_e_rot = r.two_e_rot;
        } else {
          const Quaternion q_old = in.orient[i];
          Quaternion q = q_old;
          l_old = angular_momentum_world(q_old, w_old, ib);
          l_new = l_old;
          advance_rotation(q, l_new, t, ib, alpha_[i], dt);
          in.orient[i] = q;
          w_new = angular_velocity_world(q, l_new, ib);
          const Vec3 l_mid = 0.5 * (l_old + l_new);
          two_e_rot = dot(l_mid, angular_velocity_world(q_old, l_mid, ib));
        }
        vel[i] = v_new;
        omg[i] = w_new;
        const Vec3 v_mid = 0.5 * (v_old + v_new);
        const double m = k.mass;
        acc.damping_dissipation += k.alpha_dt * (m * norm2(v_mid) + two_e_rot);
        if constexpr (Local)
          acc.damping_dissipation += dt * (dot(f_in[i] - f, v_mid) + dot(t_in[i] - t, 0.5 * (w_old + w_new)));
        if (measure) {
          acc.kinetic_translational += 0.5 * m * norm2(v_mid);
          acc.kinetic_rotational += 0.5 * two_e_rot;
          acc.sum_inertia_moment += norm(l_new - l_old) / dt;
        }
      } else {
        w_new = k.decay * w_old + k.kick_rot * t;
      }
    } else {
      w_new = k.decay * w_old + k.kick_rot * t;
    }
    if (!Spheroids || in.shape[i] != Shape::Spheroid) {
      vel[i] = v_new;
      omg[i] = w_new;
      const Vec3 v_mid = 0.5 * (v_old + v_new);
      const Vec3 w_mid = 0.5 * (w_old + w_new);
      const double m = k.mass;
      const double inert = k.inertia;
      acc.damping_dissipation += k.alpha_dt * (m * norm2(v_mid) + inert * norm2(w_mid));
      if constexpr (Local) acc.damping_dissipation += dt * (dot(f_in[i] - f, v_mid) + dot(t_in[i] - t, w_mid));
      if (measure) {
        acc.kinetic_translational += 0.5 * m * norm2(v_mid);
        acc.kinetic_rotational += 0.5 * inert * norm2(w_mid);
        acc.sum_inertia_moment += inert / dt * norm(w_new - w_old);
      }
    }
    const Vec3 s = PeriodicCell::wrap(frac[i] + hinv * (dt * v_new));
    frac[i] = s;
    const Vec3 ds = PeriodicCell::minimum_image(s - s_build[i]);
    const double d2 = norm2(h * ds);
    acc.max_displacement2 = std::max(acc.max_displacement2, d2);
    acc.max_speed2 = std::max(acc.max_speed2, norm2(v_new));
    acc.max_spin2 = std::max(acc.max_spin2, norm2(w_new));
    if (!std::isfinite(d2) || !std::isfinite(v_new.x + v_new.y + v_new.z + w_new.x + w_new.y + w_new.z))
      acc.finite = false;
  }
  return acc;
}

/// Spheres without local damping, kLanes particles at a time: the update of
/// every lane (eq. 2 kick and drift, the wrap, the displacement since the
/// list build) computed by one loop without jumps, which the compiler turns
/// into SIMD, with the same operations as advance_chunk<false, false>; then
/// the sums and maxima taken one particle at a time in storage order, so
/// every sum sees the same terms in the same order (equal to round-off: the
/// compiler may fuse multiply-adds differently in the two loops). The last,
/// partial group of a chunk takes the same two steps over its lanes.
template <bool Measure>
IntegrationSums LeapfrogIntegrator::advance_sphere_lanes(const StepInputs& in, std::size_t i_begin,
                                                         std::size_t i_end) const {
  const Mat3 hinv = in.hinv;
  const Mat3 h = in.h;
  const double dt = dt_;
  // The Vec3 arrays as doubles (x, y, z of particle i at 3i, 3i+1, 3i+2):
  // the vectoriser takes their stride-3 groups only in that form.
  double* vel = &in.vel->x;
  double* omg = &in.omg->x;
  double* frac = &in.frac->x;
  const double* f_in = &in.f_in->x;
  const double* t_in = &in.t_in->x;
  const double* s_build = &in.s_build->x;
  IntegrationSums acc;
  LaneTerms<kLanes> L;
  // Lane k of the group at i0 (a multiple of kLanes: coefficient block i0 / kLanes).
  const auto update = [&](std::size_t i0, std::size_t k) __attribute__((always_inline)) {
    const std::size_t i = i0 + k;
    const Vec3 v_old{vel[3 * i], vel[3 * i + 1], vel[3 * i + 2]};
    const Vec3 w_old{omg[3 * i], omg[3 * i + 1], omg[3 * i + 2]};
    const CoefficientLanes& c = coef_[i0 / kLanes];
    const Vec3 f{f_in[3 * i], f_in[3 * i + 1], f_in[3 * i + 2]}, t{t_in[3 * i], t_in[3 * i + 1], t_in[3 * i + 2]};
    const Vec3 v_new = c.decay[k] * v_old + c.kick[k] * f;
    const Vec3 w_new = c.decay[k] * w_old + c.kick_rot[k] * t;
    vel[3 * i] = v_new.x; vel[3 * i + 1] = v_new.y; vel[3 * i + 2] = v_new.z;
    omg[3 * i] = w_new.x; omg[3 * i + 1] = w_new.y; omg[3 * i + 2] = w_new.z;
    const Vec3 v_mid = 0.5 * (v_old + v_new);
    const Vec3 w_mid = 0.5 * (w_old + w_new);
    const double m = c.mass[k];
    const double inert = c.inertia[k];
    L.diss[k] = c.alpha_dt[k] * (m * norm2(v_mid) + inert * norm2(w_mid));
    if constexpr (Measure) {
      L.ekt[k] = 0.5 * m * norm2(v_mid);
      L.ekr[k] = 0.5 * inert * norm2(w_mid);
      L.mom[k] = norm2(w_new - w_old);  // its root in add(): std::sqrt would branch (errno)
    }
    const Vec3 s = L.drift(k, Vec3{frac[3 * i], frac[3 * i + 1], frac[3 * i + 2]},
                           Vec3{s_build[3 * i], s_build[3 * i + 1], s_build[3 * i + 2]}, v_new, w_new, hinv, h, dt);
    frac[3 * i] = s.x; frac[3 * i + 1] = s.y; frac[3 * i + 2] = s.z;
  };
  // Lane k's terms into the sums, in storage order.
  const auto add = [&](std::size_t i0, std::size_t k) {
    L.template add_to<Measure>(acc, k,
                               [&](std::size_t j) { return coef_[i0 / kLanes].inertia[j] / dt * std::sqrt(L.mom[j]); });
  };
  static_assert(kChunkSize % kLanes == 0, "chunks start at a lane block");
  std::size_t i0 = i_begin;  // a chunk's start: a multiple of kLanes
  for (; i0 + kLanes <= i_end; i0 += kLanes) {
    // The arrays are distinct (StepInputs): no lane reads what another writes.
#pragma GCC ivdep
    for (std::size_t k = 0; k < kLanes; ++k) update(i0, k);
    for (std::size_t k = 0; k < kLanes; ++k) add(i0, k);
  }
  const std::size_t tail = i_end - i0;
  for (std::size_t k = 0; k < tail; ++k) update(i0, k);
  for (std::size_t k = 0; k < tail; ++k) add(i0, k);
  return acc;
}

/// Spheroids without local damping, kLanes particles at a time: the
/// rigid-body step of advance_symmetric_rotation (rigid_rotation.h) with the
/// translation, wrap and displacement of advance_chunk<true, false>,
/// computed by one loop without jumps into per-lane results (SIMD), the
/// step angles' cos and sin by their polynomials. A lane outside what that
/// covers (a sphere of a mixed sample, a body with I2 != I3, L = 0, a half
/// step angle above 1/16 rad) is redone by advance_chunk<true, false> for
/// its particle; then every lane is stored and its terms summed one
/// particle at a time in storage order. Which particles take the lanes
/// depends only on their own state, so results do not depend on the thread
/// count; they agree with advance_chunk's to round-off.
/// A full group is copied into the lanes and back by vector shuffles
/// (lane_transpose.h: records_to_lanes, lanes_to_records), the tail of a
/// chunk lane by lane; the lane loop is a function of its own over one
/// struct: with the shuffles in the same function GCC left it scalar
/// (session 26, E7), over one struct it knows the fields do not overlap.
template <bool Measure>
IntegrationSums LeapfrogIntegrator::advance_spheroid_lanes(const StepInputs& in, std::size_t i_begin,
                                                           std::size_t i_end) const {
  const Mat3 hinv = in.hinv;
  const Mat3 h = in.h;
  const double dt = dt_;
  IntegrationSums acc;
  // One group's lanes: the old state (field by field), the new state, the
  // terms of the sums and whether the lane holds (ok: 1, else 0).
  struct Group {
    double v[3][kLanes], w[3][kLanes], f[3][kLanes], t[3][kLanes], q[4][kLanes], s[3][kLanes], s_build[3][kLanes];
    double inertia[3][kLanes], spheroid[kLanes];
    double v_new[3][kLanes], w_new[3][kLanes], q_new[4][kLanes], s_new[3][kLanes], ok[kLanes];
    LaneTerms<kLanes> L;
  };
  Group grp;
  // a symmetric top (I2 = I3; a file may hold any inertia): else the general step
  const auto set_spheroid = [&](std::size_t i0, std::size_t k) {
    grp.spheroid[k] = (in.shape[i0 + k] == Shape::Spheroid ? 1.0 : 0.0) *
                      (grp.inertia[1][k] == grp.inertia[2][k] ? 1.0 : 0.0);
  };
  // The records as 3 and 4 doubles (records_to_lanes reads 8 of them as 24 / 32 doubles).
  static_assert(sizeof(Vec3) == 3 * sizeof(double) && std::is_trivially_copyable_v<Vec3>, "Vec3: x, y, z");
  static_assert(sizeof(Quaternion) == 4 * sizeof(double) && std::is_trivially_copyable_v<Quaternion>,
                "Quaternion: w, x, y, z");
  const auto pack_group = [&](std::size_t i0) {
    lanes::records_to_lanes<3>(&in.vel[i0].x, grp.v);
    lanes::records_to_lanes<3>(&in.omg[i0].x, grp.w);
    lanes::records_to_lanes<3>(&in.f_in[i0].x, grp.f);
    lanes::records_to_lanes<3>(&in.t_in[i0].x, grp.t);
    lanes::records_to_lanes<4>(&in.orient[i0].w, grp.q);
    lanes::records_to_lanes<3>(&in.frac[i0].x, grp.s);
    lanes::records_to_lanes<3>(&in.s_build[i0].x, grp.s_build);
    lanes::records_to_lanes<3>(&in.inertia[i0].x, grp.inertia);
    for (std::size_t k = 0; k < kLanes; ++k) set_spheroid(i0, k);
  };
  const auto pack_lane = [&](std::size_t i0, std::size_t k) {
    const std::size_t i = i0 + k;
    for (int a = 0; a < 3; ++a) {
      grp.v[a][k] = in.vel[i][a];
      grp.w[a][k] = in.omg[i][a];
      grp.f[a][k] = in.f_in[i][a];
      grp.t[a][k] = in.t_in[i][a];
      grp.s[a][k] = in.frac[i][a];
      grp.s_build[a][k] = in.s_build[i][a];
      grp.inertia[a][k] = in.inertia[i][a];
    }
    const Quaternion& q = in.orient[i];
    grp.q[0][k] = q.w; grp.q[1][k] = q.x; grp.q[2][k] = q.y; grp.q[3][k] = q.z;
    set_spheroid(i0, k);
  };
  // Lanes [0, n) of g with the constants c, rk of its particles.
  const auto update = [hinv, h, dt](Group* __restrict g, const CoefficientLanes* __restrict c,
                                    const RotationLanes* __restrict rk, std::size_t n) __attribute__((noinline)) {
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3 v_old{g->v[0][k], g->v[1][k], g->v[2][k]};
      const Vec3 w_old{g->w[0][k], g->w[1][k], g->w[2][k]};
      const Vec3 f{g->f[0][k], g->f[1][k], g->f[2][k]}, t{g->t[0][k], g->t[1][k], g->t[2][k]};
      const Vec3 v_new = c->decay[k] * v_old + c->kick[k] * f;
      // advance_symmetric_rotation's parts, L = 0 and large angles left to the scalar step
      const Quaternion q{g->q[0][k], g->q[1][k], g->q[2][k], g->q[3][k]};
      const SymmetricStepConstants sk{c->decay[k], rk->kick[k], rk->inv_i1[k], rk->inv_i2[k], rk->dt_inv_i2[k], dt};
      const SymmetricKick kk = symmetric_kick(q, w_old, t, g->inertia[0][k], g->inertia[1][k], sk);
      double cp, sinc, cs, ss;
      cos_sinc_of_square_small(kk.precession2, cp, sinc);
      cos_sin_small(kk.spin, cs, ss);
      const Quaternion q_new = symmetric_drift(q, kk, cp, sinc, cs, ss);
      Vec3 w_new;
      double two_e_rot;
      symmetric_finish(q_new, kk, sk, w_new, two_e_rot);
      g->ok[k] = g->spheroid[k] * (kk.l2 > 0.0 ? 1.0 : 0.0) * (kk.precession2 <= kSmallAngle2 ? 1.0 : 0.0) *
                 (kk.spin * kk.spin <= kSmallAngle2 ? 1.0 : 0.0);
      g->v_new[0][k] = v_new.x; g->v_new[1][k] = v_new.y; g->v_new[2][k] = v_new.z;
      g->w_new[0][k] = w_new.x; g->w_new[1][k] = w_new.y; g->w_new[2][k] = w_new.z;
      g->q_new[0][k] = q_new.w; g->q_new[1][k] = q_new.x; g->q_new[2][k] = q_new.y; g->q_new[3][k] = q_new.z;
      const Vec3 v_mid = 0.5 * (v_old + v_new);
      const double m = c->mass[k];
      g->L.diss[k] = c->alpha_dt[k] * (m * norm2(v_mid) + two_e_rot);
      if constexpr (Measure) {
        g->L.ekt[k] = 0.5 * m * norm2(v_mid);
        g->L.ekr[k] = 0.5 * two_e_rot;
        g->L.mom[k] = norm2(kk.l_new - kk.l_old);  // its root in add()
      }
      const Vec3 s = g->L.drift(k, Vec3{g->s[0][k], g->s[1][k], g->s[2][k]},
                                Vec3{g->s_build[0][k], g->s_build[1][k], g->s_build[2][k]}, v_new, w_new, hinv, h, dt);
      g->s_new[0][k] = s.x; g->s_new[1][k] = s.y; g->s_new[2][k] = s.z;
    }
  };
  // Lane k's terms into the sums.
  const auto add = [&](std::size_t k) {
    grp.L.template add_to<Measure>(acc, k, [&](std::size_t j) { return std::sqrt(grp.L.mom[j]) / dt; });
  };
  // Lane k stored and summed (or its particle stepped by advance_chunk).
  const auto finish_lane = [&](std::size_t i0, std::size_t k) {
    const std::size_t i = i0 + k;
    if (grp.ok[k] == 0.0) {  // one particle's sums: added exactly as its terms
      acc.add(advance_chunk<true, false>(in, i, i + 1, Measure));
      return;
    }
    in.vel[i] = {grp.v_new[0][k], grp.v_new[1][k], grp.v_new[2][k]};
    in.omg[i] = {grp.w_new[0][k], grp.w_new[1][k], grp.w_new[2][k]};
    in.orient[i] = {grp.q_new[0][k], grp.q_new[1][k], grp.q_new[2][k], grp.q_new[3][k]};
    in.frac[i] = {grp.s_new[0][k], grp.s_new[1][k], grp.s_new[2][k]};
    add(k);
  };
  // A full group: stored by shuffles when every lane holds (the common
  // case), else lane by lane (a lane's scalar step reads its old state).
  const auto finish_group = [&](std::size_t i0) {
    bool all = true;
    for (std::size_t k = 0; k < kLanes; ++k) all = all && grp.ok[k] != 0.0;
    if (!all) {
      for (std::size_t k = 0; k < kLanes; ++k) finish_lane(i0, k);
      return;
    }
    lanes::lanes_to_records<3>(grp.v_new, &in.vel[i0].x);
    lanes::lanes_to_records<3>(grp.w_new, &in.omg[i0].x);
    lanes::lanes_to_records<4>(grp.q_new, &in.orient[i0].w);
    lanes::lanes_to_records<3>(grp.s_new, &in.frac[i0].x);
    for (std::size_t k = 0; k < kLanes; ++k) add(k);
  };
  std::size_t i0 = i_begin;  // a chunk's start: a multiple of kLanes
  for (; i0 + kLanes <= i_end; i0 += kLanes) {
    pack_group(i0);
    update(&grp, &coef_[i0 / kLanes], &rot_coef_[i0 / kLanes], kLanes);
    finish_group(i0);
  }
  const std::size_t tail = i_end - i0;
  if (tail == 0) return acc;
  for (std::size_t k = 0; k < tail; ++k) pack_lane(i0, k);
  update(&grp, &coef_[i0 / kLanes], &rot_coef_[i0 / kLanes], tail);
  for (std::size_t k = 0; k < tail; ++k) finish_lane(i0, k);
  return acc;
}

IntegrationSums LeapfrogIntegrator::advance_streamed(const StepInputs& in, std::size_t i_begin, std::size_t i_end,
                                                     bool measure, HandoffScratch& scratch) const {
  std::copy(in.vel + i_begin, in.vel + i_end, scratch.vel.begin() + static_cast<std::ptrdiff_t>(i_begin));
  std::copy(in.omg + i_begin, in.omg + i_end, scratch.omg.begin() + static_cast<std::ptrdiff_t>(i_begin));
  std::copy(in.frac + i_begin, in.frac + i_end, scratch.frac.begin() + static_cast<std::ptrdiff_t>(i_begin));
  StepInputs copy = in;
  copy.vel = scratch.vel.data();
  copy.omg = scratch.omg.data();
  copy.frac = scratch.frac.data();
  const IntegrationSums sums =
      measure ? advance_sphere_lanes<true>(copy, i_begin, i_end) : advance_sphere_lanes<false>(copy, i_begin, i_end);
  const std::size_t count = i_end - i_begin;
  streaming_copy(in.vel + i_begin, copy.vel + i_begin, count);
  streaming_copy(in.omg + i_begin, copy.omg + i_begin, count);
  streaming_copy(in.frac + i_begin, copy.frac + i_begin, count);
  return sums;
}

IntegrationSums LeapfrogIntegrator::advance(Particles& p, const PeriodicCell& cell,
                                            const std::vector<Vec3>& force,
                                            const std::vector<Vec3>& torque,
                                            const std::vector<Vec3>& frac_at_build, bool measure,
                                            ThreadRuns* runs, PhaseTimes* phases,
                                            const std::vector<std::uint8_t>* shared_chunks) {
  const std::size_t n = p.size();
  const std::int32_t nchunks = chunk_count(n);
  chunk_sums_.assign(static_cast<std::size_t>(nchunks), IntegrationSums{});
  // Local copies and plain pointers: the stores below go through double*, which
  // could otherwise alias the cell matrices and force reloads every particle.
  // The per-particle constants come from one packed array (one stream
  // instead of six). alpha dt is the same product the unpacked expression
  // alpha * dt * (...) forms first.
  const StepInputs in{p.velocity.data(), p.omega.data(),   p.frac.data(),  p.orientation.data(),
                      p.shape.data(),    p.inertia.data(), force.data(),   torque.data(),
                      frac_at_build.data(), cell.h_inverse(), cell.h()};
  IntegrationSums* sums = chunk_sums_.data();
  const bool spheroids = spheroids_;
  const bool local = local_.coefficient() > 0.0;

  // One run of consecutive chunks per thread: the runs of the sphere pair
  // loop and its sums when given (thread_runs.h, contact_forces.cpp), so the
  // forces are read where they were summed and the time spent counts
  // toward the cut; else equal runs (chunk_run).
  if (phases) phases->ensure_threads(omp_get_max_threads());
  // The chunks another thread's pair loop read, stored plainly (and timed,
  // for the choice) or streamed (handoff_stores.h): spheres without local
  // damping on a team with the pair loop's runs.
  const bool handoff_possible = runs && runs->threads() > 1 && runs->chunks() == nchunks && shared_chunks &&
                                shared_chunks->size() == static_cast<std::size_t>(nchunks) && !spheroids &&
                                !local;
  const bool stream = handoff_possible && handoff_.streaming();
  if (handoff_possible) {
    handoff_.ensure_threads(runs->threads());
    if (handoff_scratch_.size() < static_cast<std::size_t>(runs->threads()))
      handoff_scratch_.resize(static_cast<std::size_t>(runs->threads()));
    for (std::size_t k = 0; stream && k < static_cast<std::size_t>(runs->threads()); ++k) {
      HandoffScratch& s = handoff_scratch_[k];
      if (s.vel.size() == n) continue;
      s.vel.resize(n);
      s.omg.resize(n);
      s.frac.resize(n);
    }
  }
  HandoffStores* handoff = &handoff_;
  HandoffScratch* scratch = handoff_scratch_.data();
  int team_formed = 0;  // the team the region got (OpenMP may give fewer threads than planned)
  const double region_start = phases ? omp_get_wtime() : 0.0;
#pragma omp parallel
  {
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
    if (t == 0) team_formed = team;
    const bool shared = runs && runs->threads() == team && runs->chunks() == nchunks && team > 1;
    const auto [c0, c1] = shared ? runs->run(t) : chunk_run(nchunks, t, team);
    const double start = shared || phases ? omp_get_wtime() : 0.0;
    const bool handoff_here = handoff_possible && shared;
    double mark = start;  // the end of the last chunk timed (handoff_here implies shared: start is set)
    for (std::int32_t c = c0; c < c1; ++c) {
      const std::size_t i_begin = static_cast<std::size_t>(c) * kChunkSize;
      const std::size_t i_end = std::min(n, static_cast<std::size_t>(c + 1) * kChunkSize);
      const bool shared_chunk = handoff_here && (*shared_chunks)[static_cast<std::size_t>(c)] != 0;
      if (stream && shared_chunk) {
        sums[c] = advance_streamed(in, i_begin, i_end, measure, scratch[t]);
        handoff->count_streamed(t);
        continue;
      }
      if (local)
        sums[c] = spheroids ? advance_chunk<true, true>(in, i_begin, i_end, measure)
                            : advance_chunk<false, true>(in, i_begin, i_end, measure);
      else
        sums[c] = spheroids ? (measure ? advance_spheroid_lanes<true>(in, i_begin, i_end)
                                       : advance_spheroid_lanes<false>(in, i_begin, i_end))
              : measure   ? advance_sphere_lanes<true>(in, i_begin, i_end)
                          : advance_sphere_lanes<false>(in, i_begin, i_end);
      if (handoff_here && !stream) {
        const double now = omp_get_wtime();
        handoff->record(t, shared_chunk, now - mark, i_end - i_begin);
        mark = now;
      }
    }
    if (stream) streaming_fence();
    const double busy = shared || phases ? omp_get_wtime() - start : 0.0;
    if (shared) runs->record(t, busy);
    if (phases) phases->add(t, PhaseTimes::Integrate, busy);
  }
  if (phases) phases->add_region(PhaseTimes::IntegrationRegion, omp_get_wtime() - region_start);
  if (handoff_possible && team_formed == runs->threads()) handoff_.end_step();
  IntegrationSums total;
  for (const IntegrationSums& s : chunk_sums_) total.add(s);
  return total;
}

}  // namespace vt::dem
