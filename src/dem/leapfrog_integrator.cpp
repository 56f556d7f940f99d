#include "virtual_triaxial/dem/leapfrog_integrator.h"

#include <algorithm>
#include <cmath>

#include "virtual_triaxial/dem/chunked.h"

namespace vt::dem {

void IntegrationSums::add(const IntegrationSums& o) {
  damping_dissipation += o.damping_dissipation;
  kinetic_translational += o.kinetic_translational;
  kinetic_rotational += o.kinetic_rotational;
  sum_inertia_moment += o.sum_inertia_moment;
  max_displacement2 = std::max(max_displacement2, o.max_displacement2);
  finite = finite && o.finite;
}

void LeapfrogIntegrator::set_coefficients(const Particles& p, const std::vector<double>& alpha,
                                          double dt) {
  dt_ = dt;
  alpha_ = alpha;
  const std::size_t n = p.size();
  coef_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double half = 0.5 * alpha[i] * dt;
    Coefficients& c = coef_[i];
    c.decay = (1.0 - half) / (1.0 + half);           // eq. 2, first factor
    c.kick = dt / ((1.0 + half) * p.mass[i]);         // eq. 2, second factor / m
    c.kick_rot = dt / ((1.0 + half) * p.inertia[i].x);  // sphere: isotropic I
    c.alpha_dt = alpha[i] * dt;
    c.mass = p.mass[i];
    c.inertia = p.inertia[i].x;
  }
}

IntegrationSums LeapfrogIntegrator::advance(Particles& p, const PeriodicCell& cell,
                                            const std::vector<Vec3>& force,
                                            const std::vector<Vec3>& torque,
                                            const std::vector<Vec3>& frac_at_build, bool measure) {
  const std::size_t n = p.size();
  const std::int32_t nchunks = chunk_count(n);
  chunk_sums_.assign(static_cast<std::size_t>(nchunks), IntegrationSums{});
  // Local copies and plain pointers: the stores below go through double*, which
  // could otherwise alias the cell matrices and force reloads every particle.
  // The per-particle constants come from one packed array (one stream
  // instead of six). alpha dt is the same product the unpacked expression
  // alpha * dt * (...) forms first.
  const Mat3 hinv = cell.h_inverse();
  const Mat3 h = cell.h();
  const double dt = dt_;
  Vec3* vel = p.velocity.data();
  Vec3* omg = p.omega.data();
  Vec3* frac = p.frac.data();
  const Vec3* f_in = force.data();
  const Vec3* t_in = torque.data();
  const Vec3* s_build = frac_at_build.data();
  const Coefficients* coef = coef_.data();
  IntegrationSums* sums = chunk_sums_.data();

#pragma omp parallel for schedule(static, 1)
  for (std::int32_t c = 0; c < nchunks; ++c) {
    IntegrationSums acc;
    const std::size_t i_end = std::min(n, static_cast<std::size_t>(c + 1) * kChunkSize);
    for (std::size_t i = static_cast<std::size_t>(c) * kChunkSize; i < i_end; ++i) {
      const Vec3 v_old = vel[i];
      const Vec3 w_old = omg[i];
      const Coefficients& k = coef[i];
      const Vec3 v_new = k.decay * v_old + k.kick * f_in[i];
      const Vec3 w_new = k.decay * w_old + k.kick_rot * t_in[i];
      vel[i] = v_new;
      omg[i] = w_new;
      const Vec3 v_mid = 0.5 * (v_old + v_new);
      const Vec3 w_mid = 0.5 * (w_old + w_new);
      const double m = k.mass;
      const double inert = k.inertia;
      acc.damping_dissipation += k.alpha_dt * (m * norm2(v_mid) + inert * norm2(w_mid));
      if (measure) {
        acc.kinetic_translational += 0.5 * m * norm2(v_mid);
        acc.kinetic_rotational += 0.5 * inert * norm2(w_mid);
        acc.sum_inertia_moment += inert / dt * norm(w_new - w_old);
      }
      const Vec3 s = PeriodicCell::wrap(frac[i] + hinv * (dt * v_new));
      frac[i] = s;
      Vec3 ds = s - s_build[i];
      ds.x -= std::nearbyint(ds.x);
      ds.y -= std::nearbyint(ds.y);
      ds.z -= std::nearbyint(ds.z);
      const double d2 = norm2(h * ds);
      acc.max_displacement2 = std::max(acc.max_displacement2, d2);
      if (!std::isfinite(d2) || !std::isfinite(v_new.x + v_new.y + v_new.z + w_new.x + w_new.y + w_new.z))
        acc.finite = false;
    }
    sums[c] = acc;
  }
  IntegrationSums total;
  for (const IntegrationSums& s : chunk_sums_) total.add(s);
  return total;
}

}  // namespace vt::dem
