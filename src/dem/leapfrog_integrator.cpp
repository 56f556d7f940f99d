#include "virtual_triaxial/dem/leapfrog_integrator.h"

#include <omp.h>

#include <algorithm>
#include <cmath>

#include "virtual_triaxial/dem/chunked.h"
#include "virtual_triaxial/dem/huge_pages.h"
#include "virtual_triaxial/dem/rigid_rotation.h"

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
  rot_coef_.resize(spheroids_ ? n : 0);
  for (std::size_t i = 0; spheroids_ && i < n; ++i)
    rot_coef_[i] = SymmetricStepConstants::of(p.inertia[i], alpha[i], dt);
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
          const SymmetricRotationStep r = advance_symmetric_rotation(q, w_new, t, ib, rot_coef_[i]);
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
  double diss[kLanes], ekt[kLanes], ekr[kLanes], mom[kLanes], d2[kLanes], v2[kLanes], w2[kLanes], fin[kLanes];
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
    diss[k] = c.alpha_dt[k] * (m * norm2(v_mid) + inert * norm2(w_mid));
    if constexpr (Measure) {
      ekt[k] = 0.5 * m * norm2(v_mid);
      ekr[k] = 0.5 * inert * norm2(w_mid);
      mom[k] = norm2(w_new - w_old);  // its root in add(): std::sqrt would branch (errno)
    }
    const Vec3 s = PeriodicCell::wrap(Vec3{frac[3 * i], frac[3 * i + 1], frac[3 * i + 2]} + hinv * (dt * v_new));
    frac[3 * i] = s.x; frac[3 * i + 1] = s.y; frac[3 * i + 2] = s.z;
    const Vec3 ds = PeriodicCell::minimum_image(s - Vec3{s_build[3 * i], s_build[3 * i + 1], s_build[3 * i + 2]});
    d2[k] = norm2(h * ds);
    v2[k] = norm2(v_new);
    w2[k] = norm2(w_new);
    fin[k] = v_new.x + v_new.y + v_new.z + w_new.x + w_new.y + w_new.z;
  };
  // Lane k's terms into the sums, in storage order.
  const auto add = [&](std::size_t i0, std::size_t k) {
    acc.damping_dissipation += diss[k];
    if constexpr (Measure) {
      acc.kinetic_translational += ekt[k];
      acc.kinetic_rotational += ekr[k];
      acc.sum_inertia_moment += coef_[i0 / kLanes].inertia[k] / dt * std::sqrt(mom[k]);
    }
    acc.max_displacement2 = std::max(acc.max_displacement2, d2[k]);
    acc.max_speed2 = std::max(acc.max_speed2, v2[k]);
    acc.max_spin2 = std::max(acc.max_spin2, w2[k]);
    if (!std::isfinite(d2[k]) || !std::isfinite(fin[k])) acc.finite = false;
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

IntegrationSums LeapfrogIntegrator::advance(Particles& p, const PeriodicCell& cell,
                                            const std::vector<Vec3>& force,
                                            const std::vector<Vec3>& torque,
                                            const std::vector<Vec3>& frac_at_build, bool measure,
                                            ThreadRuns* runs) {
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
#pragma omp parallel
  {
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
    const bool shared = runs && runs->threads() == team && runs->chunks() == nchunks && team > 1;
    const auto [c0, c1] = shared ? runs->run(t) : chunk_run(nchunks, t, team);
    const double start = shared ? omp_get_wtime() : 0.0;
    for (std::int32_t c = c0; c < c1; ++c) {
      const std::size_t i_begin = static_cast<std::size_t>(c) * kChunkSize;
      const std::size_t i_end = std::min(n, static_cast<std::size_t>(c + 1) * kChunkSize);
      if (local)
        sums[c] = spheroids ? advance_chunk<true, true>(in, i_begin, i_end, measure)
                            : advance_chunk<false, true>(in, i_begin, i_end, measure);
      else
        sums[c] = spheroids ? advance_chunk<true, false>(in, i_begin, i_end, measure)
              : measure   ? advance_sphere_lanes<true>(in, i_begin, i_end)
                          : advance_sphere_lanes<false>(in, i_begin, i_end);
    }
    if (shared) runs->record(t, omp_get_wtime() - start);
  }
  IntegrationSums total;
  for (const IntegrationSums& s : chunk_sums_) total.add(s);
  return total;
}

}  // namespace vt::dem
