#include "virtual_triaxial/dem/axis_stiffness.h"

#include <algorithm>
#include <cstdint>

#include "virtual_triaxial/dem/axis_stiffness_term.h"

namespace vt::dem {

Vec3 axis_stiffness(const Simulation& sim) {
  if (const ContactSums* cs = sim.last_evaluation_sums()) return (1.0 / sim.last_measured_volume()) * cs->axis_stiffness_sum;
  return axis_stiffness_of_list(sim);
}

Vec3 axis_stiffness_of_list(const Simulation& sim) {
  const Particles& p = sim.particles();
  const NeighborList& list = sim.neighbor_list();
  const PairData& pd = list.pairs();
  const auto& off = list.offsets();
  const double kt_ratio = HertzMindlin(sim.settings().material).tangential_ratio();  // eq. 114
  const std::int32_t* owner = list.owners().data();
  const std::int32_t entries = off.empty() ? 0 : off.back();
  // The contacts of each block of entries are listed first without a jump
  // per entry (in contact or not is a coin flip for the branch predictor),
  // from the one-byte contact flags (PairData::active: 1 for every entry
  // with half_overlap > 0; the pair state is half a cache line per entry); their
  // inputs (branch d, force, overlap) are gathered one by one, the
  // factors of each term, d_i^2 and K_n n_i^2 + K_t (1 - n_i^2), computed by
  // one loop without jumps (SIMD: the square root and both divisions 8
  // contacts at a time), and the terms summed in list order: the same
  // terms, with the same roundings, in the same order as a plain loop over
  // the entries (checked bit for bit, test_axis_stiffness). The servo takes
  // this every control tick.
  constexpr std::int32_t kBlock = 256;
  std::int32_t contact[kBlock];
  double dx[kBlock], dy[kBlock], dz[kBlock], fx[kBlock], fy[kBlock], fz[kBlock], hov[kBlock];
  double sq[3][kBlock], stiff[3][kBlock];
  bool skip[kBlock];
  const PeriodicCell& cell = sim.cell();
  Vec3 m{};
  for (std::int32_t e0 = 0; e0 < entries; e0 += kBlock) {
    const std::int32_t e1 = std::min(entries, e0 + kBlock);
    std::int32_t nc = 0;
    for (std::int32_t e = e0; e < e1; ++e) {
      contact[nc] = e;
      nc += pd.active[e] != 0 ? 1 : 0;
    }
    for (std::int32_t k = 0; k < nc; ++k) {
      const std::int32_t e = contact[k];
      const Vec3 d = cell.branch(p.frac[static_cast<std::size_t>(owner[e])],
                                 p.frac[static_cast<std::size_t>(pd.partner[e])]);
      const Vec3& f = pd.force[e];
      dx[k] = d.x; dy[k] = d.y; dz[k] = d.z;
      fx[k] = f.x; fy[k] = f.y; fz[k] = f.z;
      hov[k] = pd.half_overlap[e];
    }
    for (std::int32_t k = 0; k < nc; ++k) {
      // per axis a (written out: Vec3::operator[] would put a jump in the loop)
      const AxisStiffnessTerm t = axis_stiffness_term({dx[k], dy[k], dz[k]}, {fx[k], fy[k], fz[k]}, hov[k], kt_ratio);
      sq[0][k] = t.d2.x;
      sq[1][k] = t.d2.y;
      sq[2][k] = t.d2.z;
      stiff[0][k] = t.stiffness.x;
      stiff[1][k] = t.stiffness.y;
      stiff[2][k] = t.stiffness.z;
      // no term: not in contact after all (a restored history flags its
      // entry active with half_overlap -1 until the next evaluation), or
      // coincident centres (no direction)
      skip[k] = t.none;
    }
    for (std::int32_t k = 0; k < nc; ++k) {
      if (skip[k]) continue;
      m.x += sq[0][k] * stiff[0][k];
      m.y += sq[1][k] * stiff[1][k];
      m.z += sq[2][k] * stiff[2][k];
    }
  }
  const double v = sim.cell().volume();
  return (1.0 / v) * m;
}

}  // namespace vt::dem
