#include "virtual_triaxial/quasi_static/friction_line_fit.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace vt::quasi_static {
namespace {
constexpr double kPi = 3.14159265358979323846;
double rad(double deg) { return deg * kPi / 180.0; }
double deg(double r) { return r * 180.0 / kPi; }
}  // namespace

FrictionLineFit fit_friction_line(const std::vector<FrictionPoint>& points, const char* name) {
  const std::string n(name);
  const std::size_t m = points.size();
  if (m < 2) throw std::invalid_argument(n + ": the friction line needs at least 2 runs");
  double sx = 0.0, sy = 0.0;
  for (std::size_t i = 0; i < m; ++i) {
    const auto& p = points[i];
    if (!(std::isfinite(p.mean_i_mom) && p.mean_i_mom >= 0.0 && std::isfinite(p.phi_peak_deg) &&
          p.phi_peak_deg > 0.0 && p.phi_peak_deg < 90.0))
      throw std::invalid_argument(n + "[" + std::to_string(i) +
                                  "]: need a finite I_mom >= 0 and 0 < phi_peak < 90 deg");
    sx += p.mean_i_mom;
    sy += std::tan(rad(p.phi_peak_deg));
  }
  const double mx = sx / m, my = sy / m;
  double sxx = 0.0, sxy = 0.0, syy = 0.0;
  for (const auto& p : points) {
    const double dx = p.mean_i_mom - mx, dy = std::tan(rad(p.phi_peak_deg)) - my;
    sxx += dx * dx;
    sxy += dx * dy;
    syy += dy * dy;
  }
  if (!(sxx > 0.0)) throw std::invalid_argument(n + ": every run has the same I_mom");
  FrictionLineFit f;
  f.points = static_cast<int>(m);
  f.slope = sxy / sxx;
  f.tan_phi_qs = my - f.slope * mx;
  f.phi_qs_deg = deg(std::atan(f.tan_phi_qs));
  f.slope_positive = f.slope > 0.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (m > 2) {
    const double rss = std::max(syy - f.slope * sxy, 0.0);
    f.r_squared = syy > 0.0 ? 1.0 - rss / syy : 1.0;
    const double s2 = rss / static_cast<double>(m - 2);
    const double se_tan = std::sqrt(s2 * (1.0 / m + mx * mx / sxx));
    f.se_phi_qs_deg = deg(se_tan / (1.0 + f.tan_phi_qs * f.tan_phi_qs));
  } else {
    f.r_squared = nan;
    f.se_phi_qs_deg = nan;
  }
  return f;
}

FrictionLineFit fit_friction_line_above_optimum(const std::vector<FrictionPoint>& points,
                                                double optimum_ratio) {
  std::vector<FrictionPoint> kept;
  for (const auto& p : points)
    if (p.damping_ratio >= optimum_ratio) kept.push_back(p);
  return fit_friction_line(kept, "ratios above the optimum");
}

}  // namespace vt::quasi_static
