#include "virtual_triaxial/quasi_static/inertial_number.h"
#include "virtual_triaxial/quasi_static/input_checks.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace vt::quasi_static {
double fitted_inertial_threshold(QsDamping model) {
  return model == QsDamping::ND ? 5.8e-4 : 3.7e-4;
}

double inertial_number(double strain_rate, double d_avg, double density, double mean_stress) {
  require_positive(strain_rate, "strain_rate");
  require_positive(d_avg, "d_avg");
  require_positive(density, "density");
  require_positive(mean_stress, "mean_stress");
  return strain_rate * d_avg * std::sqrt(density / mean_stress);
}

double eq72_rate(const QsSample& sample, double inertial_threshold) {
  require_positive(inertial_threshold, "inertial_threshold");
  require_positive(sample.sigma_bar0, "sigma_bar0");
  require_dispersity_index(sample.dispersity_index);
  return inertial_threshold * std::sqrt(sample.sigma_bar0) / sample.dispersity_index;
}

}  // namespace vt::quasi_static
