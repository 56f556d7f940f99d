#include "virtual_triaxial/dem/contact_time_step.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace vt::dem {

bool parse_time_step_basis(const std::string& word, TimeStepBasis& out) {
  if (word == "reference") out = TimeStepBasis::ReferenceTime;
  else if (word == "contacts") out = TimeStepBasis::Contacts;
  else return false;
  return true;
}

const char* to_string(TimeStepBasis b) { return b == TimeStepBasis::Contacts ? "contacts" : "reference"; }

ContactTimeStep::ContactTimeStep(double safety, double max_ratio) : safety_(safety), max_ratio_(max_ratio) {
  if (!(safety > 0.0 && safety <= 1.0)) throw std::invalid_argument("time_step_safety: must lie in (0, 1]");
  if (!(max_ratio > 0.0 && std::isfinite(max_ratio)))
    throw std::invalid_argument("time_step_max_ratio: must be finite and > 0");
}

double ContactTimeStep::pair_critical_step(double k_n, double tangential_ratio, double mass_i, double mass_j,
                                           double lever2_over_inertia_i, double lever2_over_inertia_j) {
  const double inv_m = 1.0 / mass_i + 1.0 / mass_j;
  const double w_n2 = k_n * inv_m;
  const double w_t2 = tangential_ratio * k_n * (inv_m + lever2_over_inertia_i + lever2_over_inertia_j);
  return 2.0 / std::sqrt(std::max(w_n2, w_t2));
}

ContactCriticalStep ContactTimeStep::critical_step(const Particles& p, const NeighborList& list,
                                                   const HertzMindlin& law) {
  ContactCriticalStep r;
  r.dt = std::numeric_limits<double>::infinity();
  const PairData& pd = list.pairs();
  const auto& off = list.offsets();
  const auto lever2_over_inertia = [&p](std::size_t i) {
    const Vec3& in = p.inertia[i];
    const double a = p.semi_axes[i].x;
    return a * a / std::min(in.x, std::min(in.y, in.z));
  };
  // Serial min over entries: exact, so independent of any thread count.
  for (std::size_t i = 0; i + 1 < off.size(); ++i)
    for (std::int32_t e = off[i]; e < off[i + 1]; ++e) {
      const double hov = pd.half_overlap[static_cast<std::size_t>(e)];
      if (!(hov > 0.0)) continue;
      const auto j = static_cast<std::size_t>(pd.partner[static_cast<std::size_t>(e)]);
      const double ri = p.radius[i], rj = p.radius[j];
      const double k_n = law.normal_stiffness(2.0 * hov, ri * rj / (ri + rj));
      const double dt = pair_critical_step(k_n, law.tangential_ratio(), p.mass[i], p.mass[j],
                                           lever2_over_inertia(i), lever2_over_inertia(j));
      r.dt = std::min(r.dt, dt);
      ++r.contacts;
    }
  return r;
}

double ContactTimeStep::impact_critical_step(double u, double m, double r, double rot, const HertzMindlin& law,
                                             double young, double rho, double t0, double l0) {
  if (!(u > 0.0)) return std::numeric_limits<double>::infinity();
  // Dimensionless: lengths / L0, times / T0, forces / (E L0^2), masses / (rho L0^3).
  const double ut = u * t0 / l0, mt = m / (rho * l0 * l0 * l0), rt = 0.5 * r / l0, ct = law.normal_coefficient() / young;
  const double rot_t = rot * m / mt;  // (lever^2 / I) in units of 1/(rho L0^3)
  const double delta = std::pow(5.0 * (0.5 * mt) * ut * ut / (4.0 * ct * std::sqrt(rt)), 0.4);
  const double k = 1.5 * ct * std::sqrt(rt * delta);
  return t0 * pair_critical_step(k, law.tangential_ratio(), mt, mt, rot_t, rot_t);
}

double ContactTimeStep::step(const ContactCriticalStep& c, double impact, double t0) const {
  return std::min(std::min(safety_ * c.dt, safety_ * impact), max_ratio_ * t0);
}

}  // namespace vt::dem
