#include "virtual_triaxial/quasi_static/dispersity_index.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace vt::quasi_static {

namespace {
std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}
}  // namespace

double dispersity_index(const std::vector<double>& nominal_radii) {
  if (nominal_radii.empty()) throw std::invalid_argument("dispersity_index: no particles");
  for (std::size_t i = 0; i < nominal_radii.size(); ++i)
    if (!(std::isfinite(nominal_radii[i]) && nominal_radii[i] > 0.0))
      throw std::invalid_argument("dispersity_index: radius " + std::to_string(i) + " is " +
                                  num(nominal_radii[i]) + "; radii must be finite and > 0");
  const double r_min = *std::min_element(nominal_radii.begin(), nominal_radii.end());
  double mass = 0.0, moment = 0.0;
  for (const double r : nominal_radii) {
    const double s = r / r_min;
    const double m = s * s * s;
    mass += m;
    moment += m * s;
  }
  return moment / mass;
}

}  // namespace vt::quasi_static
