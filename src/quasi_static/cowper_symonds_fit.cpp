#include "virtual_triaxial/quasi_static/cowper_symonds_fit.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace vt::quasi_static {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kBMin = 0.02, kBMax = 3.0;

struct Linear {
  double c = 0.0, a = 0.0, rss = 0.0;
};

// Least squares of t = c + a x^b for a fixed b (x scaled by its largest
// value so that x^b stays O(1)).
Linear solve_linear(const std::vector<double>& x, const std::vector<double>& t, double b) {
  const std::size_t m = x.size();
  double su = 0.0, st = 0.0;
  std::vector<double> u(m);
  for (std::size_t i = 0; i < m; ++i) {
    u[i] = std::pow(x[i], b);
    su += u[i];
    st += t[i];
  }
  const double mu = su / m, mt = st / m;
  double suu = 0.0, sut = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    suu += (u[i] - mu) * (u[i] - mu);
    sut += (u[i] - mu) * (t[i] - mt);
  }
  Linear l;
  l.a = suu > 0.0 ? sut / suu : 0.0;
  l.c = mt - l.a * mu;
  for (std::size_t i = 0; i < m; ++i) {
    const double r = t[i] - l.c - l.a * u[i];
    l.rss += r * r;
  }
  return l;
}

}  // namespace

CowperSymondsFit fit_cowper_symonds(const std::vector<RateFrictionPoint>& points) {
  if (points.size() < 3)
    throw std::invalid_argument("rates: eq. 75 has three parameters and needs at least 3 runs");
  double xmax = 0.0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    if (!(std::isfinite(p.eps_prime) && p.eps_prime > 0.0 && std::isfinite(p.phi_peak_deg) &&
          p.phi_peak_deg > 0.0 && p.phi_peak_deg < 90.0))
      throw std::invalid_argument("rates[" + std::to_string(i) +
                                  "]: need eps' > 0 and 0 < phi_peak < 90 deg");
    for (std::size_t j = 0; j < i; ++j)
      if (points[j].eps_prime == p.eps_prime)
        throw std::invalid_argument("rates[" + std::to_string(i) + "]: repeated rate");
    xmax = std::max(xmax, p.eps_prime);
  }
  std::vector<double> x, t;
  for (const auto& p : points) {
    x.push_back(p.eps_prime / xmax);
    t.push_back(std::tan(p.phi_peak_deg * kPi / 180.0));
  }
  // Scan ln b, then golden section around the best cell.
  const int n = 400;
  const double l0 = std::log(kBMin), l1 = std::log(kBMax);
  int best = 0;
  double best_rss = 0.0;
  for (int k = 0; k <= n; ++k) {
    const double r = solve_linear(x, t, std::exp(l0 + (l1 - l0) * k / n)).rss;
    if (k == 0 || r < best_rss) { best = k; best_rss = r; }
  }
  double lo = l0 + (l1 - l0) * std::max(best - 1, 0) / n;
  double hi = l0 + (l1 - l0) * std::min(best + 1, n) / n;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 100; ++it) {
    const double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo);
    if (solve_linear(x, t, std::exp(m1)).rss < solve_linear(x, t, std::exp(m2)).rss) hi = m2;
    else lo = m1;
  }
  CowperSymondsFit f;
  f.b_phi = std::exp(0.5 * (lo + hi));
  const Linear l = solve_linear(x, t, f.b_phi);
  f.tan_phi_qs = l.c;
  f.phi_qs_deg = std::atan(l.c) * 180.0 / kPi;
  f.a_phi = l.a / std::pow(xmax, f.b_phi);   // back to unscaled eps'
  f.rss = l.rss;
  f.b_at_bound = best == 0 || best == n;
  return f;
}

}  // namespace vt::quasi_static
