#include "virtual_triaxial/dem/energy_budget.h"

#include <cmath>

namespace vt::dem {

double EnergyBudget::scale() const {
  return std::fabs(boundary_work) + kinetic_reference + elastic_reference + damping + friction;
}

double EnergyBudget::relative_balance_error() const {
  const double s = scale();
  return s > 0.0 ? balance_error() / s : 0.0;
}

}  // namespace vt::dem
