#include "virtual_triaxial/dem/axis_stiffness.h"

namespace vt::dem {

Vec3 axis_stiffness(const Simulation& sim) {
  const Particles& p = sim.particles();
  const NeighborList& list = sim.neighbor_list();
  const PairData& pd = list.pairs();
  const auto& off = list.offsets();
  const Material& mat = sim.settings().material;
  const double kt_ratio = 2.0 * (1.0 - mat.poisson) / (2.0 - mat.poisson);  // eq. 114
  Vec3 m{};
  for (std::size_t i = 0; i + 1 < off.size(); ++i)
    for (std::int32_t e = off[i]; e < off[i + 1]; ++e) {
      const double h = pd.half_overlap[e];
      if (h <= 0.0) continue;
      const Vec3 d = sim.cell().branch(p.frac[i], p.frac[static_cast<std::size_t>(pd.partner[e])]);
      const double dist = norm(d);
      if (dist <= 0.0) continue;
      const Vec3 n = (1.0 / dist) * d;
      const double kn = 1.5 * dot(pd.force[e], n) / (2.0 * h);
      const double kt = kt_ratio * kn;
      for (int a = 0; a < 3; ++a) m[a] += d[a] * d[a] * (kn * n[a] * n[a] + kt * (1.0 - n[a] * n[a]));
    }
  const double v = sim.cell().volume();
  return (1.0 / v) * m;
}

}  // namespace vt::dem
