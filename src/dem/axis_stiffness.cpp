#include "virtual_triaxial/dem/axis_stiffness.h"

#include <algorithm>
#include <cstdint>

namespace vt::dem {

Vec3 axis_stiffness(const Simulation& sim) {
  const Particles& p = sim.particles();
  const NeighborList& list = sim.neighbor_list();
  const PairData& pd = list.pairs();
  const auto& off = list.offsets();
  const Material& mat = sim.settings().material;
  const double kt_ratio = 2.0 * (1.0 - mat.poisson) / (2.0 - mat.poisson);  // eq. 114
  const std::int32_t* owner = list.owners().data();
  const std::int32_t entries = off.empty() ? 0 : off.back();
  // The contacts of each block of entries are listed first without a jump
  // per entry (in contact or not is a coin flip for the branch predictor),
  // then summed in list order: the same terms in the same order as a plain
  // loop over the entries. The servo takes this every control tick.
  constexpr std::int32_t kBlock = 1024;
  std::int32_t contact[kBlock];
  Vec3 m{};
  for (std::int32_t e0 = 0; e0 < entries; e0 += kBlock) {
    const std::int32_t e1 = std::min(entries, e0 + kBlock);
    std::int32_t nc = 0;
    for (std::int32_t e = e0; e < e1; ++e) {
      contact[nc] = e;
      nc += pd.half_overlap[e] <= 0.0 ? 0 : 1;
    }
    for (std::int32_t k = 0; k < nc; ++k) {
      const std::int32_t e = contact[k];
      const double h = pd.half_overlap[e];
      const Vec3 d = sim.cell().branch(p.frac[static_cast<std::size_t>(owner[e])],
                                       p.frac[static_cast<std::size_t>(pd.partner[e])]);
      const double dist = norm(d);
      if (dist <= 0.0) continue;
      const Vec3 n = (1.0 / dist) * d;
      const double kn = 1.5 * dot(pd.force[e], n) / (2.0 * h);
      const double kt = kt_ratio * kn;
      for (int a = 0; a < 3; ++a) m[a] += d[a] * d[a] * (kn * n[a] * n[a] + kt * (1.0 - n[a] * n[a]));
    }
  }
  const double v = sim.cell().volume();
  return (1.0 / v) * m;
}

}  // namespace vt::dem
