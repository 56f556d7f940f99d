#include "virtual_triaxial/dem/contact_forces.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "virtual_triaxial/dem/chunked.h"

namespace vt::dem {

void ContactSums::add(const ContactSums& o) {
  virial = virial + o.virial;
  elastic_energy += o.elastic_energy;
  friction_dissipation += o.friction_dissipation;
  max_overlap_ratio = std::max(max_overlap_ratio, o.max_overlap_ratio);
  contacts += o.contacts;
  sliding += o.sliding;
  sum_force += o.sum_force;
  sum_force2 += o.sum_force2;
}

ContactSums ContactForces::compute(const Particles& p, const PeriodicCell& cell, NeighborList& list,
                                   const HertzMindlin& law, double dt, bool measure,
                                   std::vector<Vec3>& force, std::vector<Vec3>& torque) {
  const std::size_t n = p.size();
  const std::int32_t nchunks = chunk_count(n);
  chunk_sums_.assign(static_cast<std::size_t>(nchunks), ContactSums{});
  PairData& pd = list.pairs();
  const std::vector<std::int32_t>& off = list.offsets();
  const Mat3 lgrad = cell.velocity_gradient();
  const Mat3& h = cell.h();
  const Vec3* frac = p.frac.data();
  const Vec3* vel = p.velocity.data();
  const Vec3* omg = p.omega.data();
  const double* rad = p.radius.data();

#pragma omp parallel for schedule(dynamic, 1)
  for (std::int32_t c = 0; c < nchunks; ++c) {
    ContactSums acc;
    double vxx = 0, vxy = 0, vxz = 0, vyx = 0, vyy = 0, vyz = 0, vzx = 0, vzy = 0, vzz = 0;
    const std::int32_t i_end = std::min<std::int32_t>(static_cast<std::int32_t>(n), (c + 1) * kChunkSize);
    for (std::int32_t i = c * kChunkSize; i < i_end; ++i) {
      const Vec3 si = frac[i];
      const Vec3 vi = vel[i];
      const Vec3 wi = omg[i];
      const double ri = rad[i];
      for (std::int32_t e = off[static_cast<std::size_t>(i)]; e < off[static_cast<std::size_t>(i) + 1]; ++e) {
        const std::int32_t j = pd.partner[e];
        const double rj = rad[j];
        Vec3 ds = frac[j] - si;
        ds.x -= std::nearbyint(ds.x);
        ds.y -= std::nearbyint(ds.y);
        ds.z -= std::nearbyint(ds.z);
        const Vec3 d = h * ds;
        const double dist2 = norm2(d);
        const double rsum = ri + rj;
        if (dist2 >= rsum * rsum) {
          if (pd.half_overlap[e] != 0.0) {
            pd.half_overlap[e] = 0.0;
            pd.spring[e] = Vec3{};
          }
          continue;
        }
        const double dist = std::sqrt(dist2);
        const double delta = rsum - dist;
        const Vec3 nrm = (1.0 / dist) * d;
        const double hov = 0.5 * delta;
        const double li = ri - hov, lj = rj - hov;
        const Vec3 vc = vel[j] - vi + lgrad * d - cross(li * wi + lj * omg[j], nrm);
        const Vec3 dt_t = dt * (vc - dot(vc, nrm) * nrm);
        const double r_eff = ri * rj / rsum;
        const ContactResult r = law.evaluate(nrm, delta, r_eff, dt_t, pd.spring[e]);
        pd.force[e] = r.force_on_j;
        pd.moment_axis[e] = -cross(nrm, r.force_on_j);  // n x F_on_i
        pd.half_overlap[e] = hov;
        const Vec3& f = r.force_on_j;
        vxx += d.x * f.x; vxy += d.x * f.y; vxz += d.x * f.z;
        vyx += d.y * f.x; vyy += d.y * f.y; vyz += d.y * f.z;
        vzx += d.z * f.x; vzy += d.z * f.y; vzz += d.z * f.z;
        acc.elastic_energy += r.elastic_energy;
        acc.friction_dissipation += r.friction_dissipation;
        acc.max_overlap_ratio = std::max(acc.max_overlap_ratio, delta / std::min(ri, rj));
        ++acc.contacts;
        acc.sliding += r.sliding ? 1 : 0;
        if (measure) {
          const double f2 = norm2(f);
          acc.sum_force2 += f2;
          acc.sum_force += std::sqrt(f2);
        }
      }
    }
    acc.virial.m[0][0] = vxx; acc.virial.m[0][1] = vxy; acc.virial.m[0][2] = vxz;
    acc.virial.m[1][0] = vyx; acc.virial.m[1][1] = vyy; acc.virial.m[1][2] = vyz;
    acc.virial.m[2][0] = vzx; acc.virial.m[2][1] = vzy; acc.virial.m[2][2] = vzz;
    chunk_sums_[static_cast<std::size_t>(c)] = acc;
  }

  // Gather: reverse entries (partners with smaller id) then forward entries
  // (larger id), both ascending, i.e. ascending partner id overall.
  force.resize(n);
  torque.resize(n);
  const std::vector<std::int32_t>& roff = list.reverse_offsets();
  const std::vector<std::int32_t>& rent = list.reverse_entries();
#pragma omp parallel for schedule(static, kChunkSize)
  for (std::int32_t i = 0; i < static_cast<std::int32_t>(n); ++i) {
    Vec3 f{}, t{};
    const double ri = rad[i];
    for (std::int32_t k = roff[static_cast<std::size_t>(i)]; k < roff[static_cast<std::size_t>(i) + 1]; ++k) {
      const std::int32_t e = rent[static_cast<std::size_t>(k)];
      const double hov = pd.half_overlap[e];
      if (hov == 0.0) continue;
      f += pd.force[e];
      t += (ri - hov) * pd.moment_axis[e];
    }
    for (std::int32_t e = off[static_cast<std::size_t>(i)]; e < off[static_cast<std::size_t>(i) + 1]; ++e) {
      const double hov = pd.half_overlap[e];
      if (hov == 0.0) continue;
      f -= pd.force[e];
      t += (ri - hov) * pd.moment_axis[e];
    }
    force[static_cast<std::size_t>(i)] = f;
    torque[static_cast<std::size_t>(i)] = t;
  }

  ContactSums total;
  for (const ContactSums& s : chunk_sums_) total.add(s);
  return total;
}

}  // namespace vt::dem
