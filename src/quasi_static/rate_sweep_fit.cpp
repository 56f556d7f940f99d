#include "virtual_triaxial/quasi_static/rate_sweep_fit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vt::quasi_static {
namespace {

RateSweepFit solve(const std::vector<double>& x, const std::vector<double>& y, double threshold,
                   const char* name) {
  if (!(std::isfinite(threshold) && threshold > 0.0))
    throw std::invalid_argument("threshold: I_QS must be finite and > 0");
  RateSweepFit r;
  r.law = fit_power_law(x, y, name);
  if (!(r.law.b > 0.0))
    throw std::invalid_argument(std::string(name) + ": I_mom does not rise with the rate (b = " +
                                std::to_string(r.law.b) + "); no quasi-static rate can be read off");
  r.threshold = threshold;
  r.eps_prime_qs = r.law.solve_x(threshold);
  r.se_ln_eps_prime_qs = r.law.se_ln_solve_x(threshold);
  r.extrapolation_decades = std::log10(*std::min_element(x.begin(), x.end()) / r.eps_prime_qs);
  return r;
}

}  // namespace

RateSweepFit fit_rate_sweep(const std::vector<RatePoint>& points, double threshold) {
  std::vector<double> x, y;
  for (const auto& p : points) {
    x.push_back(p.eps_prime);
    y.push_back(p.mean_i_mom);
  }
  return solve(x, y, threshold, "rates");
}

RateSweepFit fit_damping_rate_product(const std::vector<DampingRatePoint>& points,
                                      double optimum_ratio, double threshold) {
  std::vector<double> x, y;
  for (const auto& p : points)
    if (p.damping_ratio >= optimum_ratio) {
      x.push_back(p.damping_ratio * p.eps_prime);
      y.push_back(p.mean_i_mom);
    }
  return solve(x, y, threshold, "ratios");
}

}  // namespace vt::quasi_static
