#include "virtual_triaxial/quasi_static/optimum_damping.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace vt::quasi_static {

OptimumDamping find_optimum_damping(std::vector<DampingPoint> points) {
  if (points.size() < 3)
    throw std::invalid_argument("ratios: an optimum needs at least 3 damping ratios");
  for (std::size_t i = 0; i < points.size(); ++i)
    if (!(std::isfinite(points[i].damping_ratio) && points[i].damping_ratio > 0.0 &&
          std::isfinite(points[i].mean_i_mom) && points[i].mean_i_mom > 0.0))
      throw std::invalid_argument("ratios[" + std::to_string(i) +
                                  "]: xi and I_mom must be finite and > 0 (xi = 0 has no log)");
  std::sort(points.begin(), points.end(),
            [](const DampingPoint& a, const DampingPoint& b) { return a.damping_ratio < b.damping_ratio; });
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i].damping_ratio == points[i - 1].damping_ratio)
      throw std::invalid_argument("ratios: repeated damping ratio " +
                                  std::to_string(points[i].damping_ratio));
  std::size_t k = 0;
  for (std::size_t i = 1; i < points.size(); ++i)
    if (points[i].mean_i_mom < points[k].mean_i_mom) k = i;
  if (k == 0 || k + 1 == points.size())
    throw std::invalid_argument(std::string("ratios: the smallest I_mom is at the ") +
                                (k == 0 ? "smallest" : "largest") +
                                " ratio; the optimum is not bracketed, extend the sweep");
  // Parabola through three points (divided differences) in ln-ln.
  const double x0 = std::log(points[k - 1].damping_ratio), y0 = std::log(points[k - 1].mean_i_mom);
  const double x1 = std::log(points[k].damping_ratio), y1 = std::log(points[k].mean_i_mom);
  const double x2 = std::log(points[k + 1].damping_ratio), y2 = std::log(points[k + 1].mean_i_mom);
  const double d01 = (y1 - y0) / (x1 - x0), d12 = (y2 - y1) / (x2 - x1);
  const double c2 = (d12 - d01) / (x2 - x0);
  if (!(c2 > 0.0)) throw std::invalid_argument("ratios: the I_mom valley is not convex");
  // y = y0 + d01 (x - x0) + c2 (x - x0)(x - x1); dy/dx = 0:
  const double xv = 0.5 * (x0 + x1) - d01 / (2.0 * c2);
  OptimumDamping o;
  o.ratio = std::exp(xv);
  o.min_i_mom = std::exp(y0 + d01 * (xv - x0) + c2 * (xv - x0) * (xv - x1));
  o.index_of_lowest = static_cast<int>(k);
  return o;
}

}  // namespace vt::quasi_static
