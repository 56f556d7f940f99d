#include "virtual_triaxial/quasi_static/power_law_fit.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace vt::quasi_static {

double PowerLawFit::operator()(double x) const { return a * std::pow(x, b); }

double PowerLawFit::solve_x(double y) const {
  return std::exp(mean_ln_x + (std::log(y) - mean_ln_y) / b);
}

double PowerLawFit::se_ln_solve_x(double y) const {
  // ln x = mx + (ln y - c) / b, c and b uncorrelated in the centred line.
  const double u = (std::log(y) - mean_ln_y) / b;
  return std::sqrt(se_mean_ln_y * se_mean_ln_y + u * u * se_b * se_b) / std::fabs(b);
}

PowerLawFit fit_power_law(const std::vector<double>& x, const std::vector<double>& y,
                          const char* name) {
  const std::string n(name);
  if (x.size() != y.size()) throw std::invalid_argument(n + ": x and y differ in length");
  if (x.size() < 2) throw std::invalid_argument(n + ": a power law needs at least 2 points");
  const std::size_t m = x.size();
  double sx = 0.0, sy = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    if (!(std::isfinite(x[i]) && x[i] > 0.0 && std::isfinite(y[i]) && y[i] > 0.0))
      throw std::invalid_argument(n + "[" + std::to_string(i) +
                                  "]: x and y must be finite and > 0 for a power law");
    sx += std::log(x[i]);
    sy += std::log(y[i]);
  }
  PowerLawFit f;
  f.points = static_cast<int>(m);
  f.mean_ln_x = sx / m;
  f.mean_ln_y = sy / m;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    const double dx = std::log(x[i]) - f.mean_ln_x, dy = std::log(y[i]) - f.mean_ln_y;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  if (!(sxx > 0.0)) throw std::invalid_argument(n + ": every x is the same");
  f.b = sxy / sxx;
  f.a = std::exp(f.mean_ln_y - f.b * f.mean_ln_x);
  const double rss = syy - f.b * sxy;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (m > 2) {
    f.r_squared = syy > 0.0 ? 1.0 - rss / syy : 1.0;
    const double s2 = std::max(rss, 0.0) / static_cast<double>(m - 2);
    f.se_mean_ln_y = std::sqrt(s2 / m);
    f.se_b = std::sqrt(s2 / sxx);
  } else {
    f.r_squared = nan;
    f.se_mean_ln_y = nan;
    f.se_b = nan;
  }
  return f;
}

}  // namespace vt::quasi_static
